/* test_world.c - `planetgen generate --layout world` (docs/generate.md, "Layout world"):
 * a new planet from plate tectonics and climate, amplified by example.
 *  - bad values of the world options exit 2 with one line naming the option, and write
 *    nothing;
 *  - one small planet end to end: the macro fields are in the planet directory, and the
 *    realism report (planetgen inspect --json) shows the land where the plates put it
 *    (land fraction within 0.03 of --land-fraction), no copy of Earth (earth_copy_fraction
 *    <= 0.05), ice at the poles and not at the equator, no depression, and a
 *    mountain_belt_fraction from world.exr;
 *  - guidance through the library: a two-zone macro world (one hemisphere cold, the other
 *    hot) gets at least 90% of its material from exemplar texels of the matching zone of
 *    Earth's own climate (the same climate model on Earth's relief). */
#include "pg_test.h"

#include "planetgen/pg_climate.h"
#include "planetgen/pg_planet_synth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static char out[16384], err[16384];
static char json[1 << 20];

static void expect_bad(const char *args, const char *needle, const char *outdir) {
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 2 || !strstr(err, needle))
        fail_msg("'%s': exit %d, stderr '%s' (wanted exit 2 and '%s')", args, rc, err, needle);
    assert_int_equal(pg_test_count_files(outdir), 0);
    struct stat sb;
    assert_true(stat(outdir, &sb) != 0);
}

static void test_bad_options(void **state) {
    (void)state;
    char dir[512], o[600], args[1024];
    pg_test_scratch_dir("world-bad", dir, sizeof dir);
    snprintf(o, sizeof o, "%s/o", dir);
    static const char *const bad[][2] = {{"--plates 1", "--plates"},
                                         {"--plates 65", "--plates"},
                                         {"--land-fraction 0", "--land-fraction"},
                                         {"--land-fraction 1.5", "--land-fraction"},
                                         {"--axial-tilt -1", "--axial-tilt"},
                                         {"--axial-tilt 91", "--axial-tilt"},
                                         {"--temperature-offset 100", "--temperature-offset"},
                                         {"--temperature-offset x", "--temperature-offset"}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(args, sizeof args, "generate --layout world %s -o %s", bad[k][0], o);
        expect_bad(args, bad[k][1], o);
    }
}

static void cli(const char *args) {
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("planetgen %s: exit %d: %s", args, rc, err);
}

static void test_small_world(void **state) {
    (void)state;
    const char *build = getenv("PG_BUILD_DIR");
    char dir[512], args[2048], path[700];
    pg_test_scratch_dir("world", dir, sizeof dir);
    snprintf(args, sizeof args,
             "generate -q --no-glb --layout world --seed 1 --land-fraction 0.3 --tiles 2 "
             "--tile-size 256 --cache-dir %s/synth-cache -o %s/p",
             build, dir);
    cli(args);
    const char *files[] = {"plates.png", "climate.png", "world.exr", "relief.png", "height.exr"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
        snprintf(path, sizeof path, "%s/p/%s", dir, files[k]);
        if (!pg_test_file_nonempty(path)) fail_msg("%s missing", path);
    }
    snprintf(path, sizeof path, "%s/r.json", dir);
    snprintf(args, sizeof args, "inspect -q %s/p --cache-dir %s/synth-cache --json %s", dir, build,
             path);
    cli(args);
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("cannot open %s", path);
    size_t n = fread(json, 1, sizeof json - 1, f);
    json[n] = 0;
    fclose(f);
    const char *earth = strstr(json, "\"earth\": {");
    assert_non_null(earth);
    double land = pg_test_json_number(json, "land_fraction"),
           copy = pg_test_json_number(json, "earth_copy_fraction");
    double ieq = pg_test_json_number(json, "ice_equator_fraction"),
           ipol = pg_test_json_number(json, "ice_polar_fraction"),
           epol = pg_test_json_number(earth, "ice_polar_fraction"),
           dep = pg_test_json_number(json, "depressions"),
           belt = pg_test_json_number(json, "mountain_belt_fraction");
    print_message("land %.4f copy %.4f ice equator %.4f polar %.4f (Earth %.4f) depressions %g "
                  "mountain belts %.3f\n",
                  land, copy, ieq, ipol, epol, dep, belt);
    assert_true(fabs(land - 0.3) <= 0.03);
    assert_true(copy <= 0.05);
    assert_true(ieq <= 0.01);
    assert_true(ipol >= 0.5 * epol);
    assert_true(dep == 0);
    assert_true(isfinite(belt)); /* the macro world's world.exr is read */
}

/* ---- guidance through the library ---- */

#define WN 64

static pg_synth_exemplar *ex;

static int setup(void **state) {
    (void)state;
    ex = pg_test_default_exemplar();
    return ex ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    pg_synth_exemplar_free(ex);
    return 0;
}

/* Earth's own coarse climate, as layout world sees it. */
static float *exemplar_temperature(void) {
    pg_climate c;
    pg_error e = {0};
    assert_int_equal(pg_planet_world_exemplar_climate(ex, WN, &c, &e), PG_OK);
    float *t = c.temperature_c;
    c.temperature_c = NULL;
    pg_climate_free(&c);
    return t;
}

/* The two-zone world: land everywhere, the northern hemisphere (z > 0) cold and dry, the
 * southern hot and wet. */
static void two_zones(float *elev, float *temp, float *prec) {
    pg_cube_grid g;
    pg_error e = {0};
    assert_int_equal(pg_cube_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, 1, WN, &e), PG_OK);
    for (int64_t id = 0; id < 6 * WN * WN; id++) {
        double d[3];
        pg_cube_texel_dir(&g, id, d);
        bool cold = d[2] > 0;
        elev[id] = 400;
        temp[id] = cold ? -30.0f : 26.0f;
        prec[id] = cold ? 150.0f : 2000.0f;
    }
}

static void test_two_zone_guidance(void **state) {
    (void)state;
    size_t nw = (size_t)6 * WN * WN;
    float *elev = malloc(nw * sizeof(float)), *temp = malloc(nw * sizeof(float)),
          *prec = malloc(nw * sizeof(float));
    assert_true(elev && temp && prec);
    two_zones(elev, temp, prec);
    pg_planet_world w = {WN, elev, temp, prec};
    pg_guide guide;
    pg_types_map types;
    pg_error e = {0};
    assert_int_equal(pg_planet_world_guide(&w, 512, &guide, &e), PG_OK);
    assert_int_equal(pg_planet_world_types(&w, 512, &types, &e), PG_OK);
    pg_planet_synth_params p;
    pg_planet_synth_params_default(&p);
    p.tiles = 1;
    p.tile_size = 128;
    p.synth.seed = 5;
    p.layout = PG_LAYOUT_WORLD;
    p.world = &w;
    p.guide = &guide;
    p.types = &types;
    p.pit_stats = false;
    pg_planet out;
    uint32_t *coords;
    if (pg_planet_synth_run(ex, &p, &out, &coords, NULL, &e)) fail_msg("%s", e.msg);
    float *et = exemplar_temperature();
    const int64_t n = out.n;
    const int E = ex->face_size, b = E / WN;
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, 1, (int)n, &e), PG_OK);
    size_t match[2] = {0, 0}, total[2] = {0, 0};
    for (int64_t id = 0; id < 6 * n * n; id++) {
        double d[3];
        pg_cube_texel_dir(&g, id, d);
        if (fabs(d[2]) < 0.1) continue; /* the boundary between the zones */
        int cold = d[2] > 0;
        uint32_t q = coords[id];
        int f = pg_synth_face(q), u = pg_synth_u(q), v = pg_synth_v(q);
        float t = et[((size_t)f * WN + v / b) * WN + u / b];
        total[cold]++;
        match[cold] += cold ? t < 0.0f : t > 10.0f;
    }
    double fc = (double)match[1] / total[1], fh = (double)match[0] / total[0];
    print_message("material from the matching zone: cold %.3f, hot %.3f\n", fc, fh);
    assert_true(fc >= 0.9);
    assert_true(fh >= 0.9);
    (void)E;
    free(et);
    free(coords);
    pg_planet_free(&out);
    pg_guide_free(&guide);
    pg_types_map_free(&types);
    free(elev), free(temp), free(prec);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_options),
        cmocka_unit_test(test_small_world),
        cmocka_unit_test_setup_teardown(test_two_zone_guidance, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
