/* test_export_gltf.c - the exported globe passes the Khronos glTF-Validator with 0
 * errors and 0 warnings, for the default planet (6 x 4x4 x 256^2) and for a small
 * one, with embedded PNG, embedded JPEG and external textures, and it holds what the
 * validator counts: 6 primitives, the mesh's triangles, 6 materials. The validator
 * is installed on first use by scripts/gltf-validate (npm, project-local). */
#include "export_fixture.h"

#include <stdio.h>
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
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_small_planet_variants),
                                       cmocka_unit_test(test_default_planet)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
