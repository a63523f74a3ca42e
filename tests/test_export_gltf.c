/* test_export_gltf.c - the exported globe passes the Khronos glTF-Validator with 0
 * errors and 0 warnings, for the default planet (6 x 4x4 x 256^2) and for a small
 * one, with embedded PNG, embedded JPEG and external textures, and it holds what the
 * validator counts: 6 primitives, the mesh's triangles, 6 materials. The planet
 * parameters are in the scene extras, and the 16-bit height texture decoded with
 * the documented formula matches the EXR heights. The validator
 * is installed on first use by scripts/gltf-validate (npm, project-local). */
#include "export_fixture.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Validate OUT/planet.glb; returns the validator's summary line in line. */
static void validate(const char *out, char *line, size_t size) {
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s/scripts/gltf-validate' '%s/planet.glb' 2>&1",
             pg_test_source_dir(), out);
    int rc = fixture_sh(cmd, line, size);
    printf("%s", line);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(line, "errors=0 warnings=0"));
}

static void export_cli(const char *args) {
    char out[4096], err[4096];
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) printf("%s\n%s\n", out, err);
    assert_int_equal(rc, 0);
}

static void test_default_planet(void **s) {
    (void)s;
    char dir[1024], args[4096], line[8192];
    fixture_planet_dir("export_gltf_default", 4, 256, dir, sizeof dir);
    snprintf(args, sizeof args, "export '%s' --no-previews", dir);
    export_cli(args);
    validate(dir, line, sizeof line);
    assert_non_null(strstr(line, "primitives=6 "));
    assert_non_null(strstr(line, "triangles=196608 "));
    assert_non_null(strstr(line, "materials=6 "));
}

/* The JSON chunk of a .glb (malloc'ed, NUL-terminated). */
static char *glb_json(const char *glb) {
    FILE *f = fopen(glb, "rb");
    assert_non_null(f);
    uint32_t head[5];
    assert_int_equal(fread(head, 4, 5, f), 5);
    assert_int_equal(head[0], 0x46546C67); /* "glTF" */
    assert_int_equal(head[4], 0x4E4F534A); /* "JSON" */
    char *json = malloc(head[3] + 1);
    assert_int_equal(fread(json, 1, head[3], f), head[3]);
    json[head[3]] = '\0';
    fclose(f);
    return json;
}

static double json_number(const char *json, const char *key) {
    const char *p = strstr(json, key);
    assert_non_null(p);
    return strtod(p + strlen(key), NULL);
}

/* The metadata is there, and the documented height formula, applied to the 16-bit
 * height PNG, gives back the EXR's metres to within half a quantisation step. */
static void check_metadata_and_heights(const char *out) {
    char path[1400];
    snprintf(path, sizeof path, "%s/planet.glb", out);
    char *json = glb_json(path);
    const char *keys[] = {"\"generator\":\"planetgen ",
                          "\"radius_m\":",
                          "\"flattening\":",
                          "\"projection\":\"equi-angular\"",
                          "\"tiles\":2",
                          "\"tile_size\":32",
                          "\"seed\":\"42\"",
                          "\"exemplar\":",
                          "\"heightTexture\":2}"};
    for (size_t i = 0; i < sizeof keys / sizeof *keys; i++) {
        if (!strstr(json, keys[i])) printf("missing %s in %s\n", keys[i], json);
        assert_non_null(strstr(json, keys[i]));
    }
    double scale = json_number(json, "\"heightScale\":");
    double offset = json_number(json, "\"heightOffset\":");
    free(json);
    pg_image png, exr;
    pg_error err = {0};
    snprintf(path, sizeof path, "%s/planet_height_px.png", out);
    assert_int_equal(pg_image_read(path, 0, &png, &err), PG_OK);
    assert_int_equal(png.src_type, PG_SAMPLE_UINT16);
    snprintf(path, sizeof path, "%s/height.exr", out);
    assert_int_equal(pg_image_read_exr(path, "+X", &exr, &err), PG_OK);
    assert_int_equal(png.width * png.height, exr.width * exr.height);
    double worst = 0;
    for (int i = 0; i < png.width * png.height; i++) {
        double metres = offset + scale * png.data[i] / 65535.0;
        worst = fmax(worst, fabs(metres - exr.data[i]));
    }
    printf("height PNG vs EXR: worst %.3f m (step %.3f m)\n", worst, scale / 65535);
    assert_true(worst <= 0.5 * scale / 65535 + 1e-3);
    pg_image_free(&png);
    pg_image_free(&exr);
}

static void test_small_planet_variants(void **s) {
    (void)s;
    char dir[1024], out[1200], args[4096], line[8192];
    fixture_planet_dir("export_gltf_small", 2, 32, dir, sizeof dir);
    /* default: embedded PNG */
    snprintf(args, sizeof args, "export '%s' --no-previews", dir);
    export_cli(args);
    validate(dir, line, sizeof line);
    assert_non_null(strstr(line, "primitives=6 "));
    assert_non_null(strstr(line, "triangles=49152 ")); /* 12 x 64^2: every texel a quad */
    /* JPEG albedo, a coarser mesh */
    snprintf(out, sizeof out, "%s/jpeg", dir);
    snprintf(args, sizeof args,
             "export '%s' -o '%s' --texture-format jpeg --mesh-res 8 "
             "--no-previews",
             dir, out);
    export_cli(args);
    validate(out, line, sizeof line);
    assert_non_null(strstr(line, "triangles=768 "));
    /* external textures: 18 image files next to the .glb, which stays small */
    snprintf(out, sizeof out, "%s/external", dir);
    snprintf(args, sizeof args, "export '%s' -o '%s' --external-textures --no-previews", dir, out);
    export_cli(args);
    validate(out, line, sizeof line);
    assert_int_equal(pg_test_count_files(out), 1 + 18 + 1); /* glb, images, height.exr */
    char path[1400];
    snprintf(path, sizeof path, "%s/planet_height_nz.png", out);
    assert_true(pg_test_file_nonempty(path));
    check_metadata_and_heights(out);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_small_planet_variants),
                                       cmocka_unit_test(test_default_planet)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
