/* test_world.c - `planetgen generate --layout world` (docs/generate.md, "Layout world"):
 * a new planet from plate tectonics and climate, amplified by example.
 *  - bad values of the world options exit 2 with one line naming the option, and write
 *    nothing;
 *  - one small planet end to end: the macro fields are in the planet directory, and the
 *    realism report (planetgen inspect --json) shows the land where the plates put it
 *    (land fraction within 0.03 of --land-fraction), no copy of Earth (earth_copy_fraction
 *    <= 0.05), ice at the poles and not at the equator, no depression, and a
 *    mountain_belt_fraction from world.exr;
 *  - the guide and type mask sampled on the cube (pg_planet_world_level) against the
 *    world's own texels, directional samples and block means;
 *  - guidance through the library: a two-zone macro world (one hemisphere cold, the other
 *    hot) gets at least 90% of its material from exemplar texels of the matching zone of
 *    Earth's own climate (the same climate model on Earth's relief), with the world
 *    sampled on the cube and with equirectangular maps. */
#include "pg_test.h"

#include "planetgen/pg_climate.h"
#include "planetgen/pg_cube.h"
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

/* The cube-native guide and mask (pg_planet_world_level) against the world itself: at
 * the world's own size each texel is its world texel exactly; finer, each is the
 * bilinear sample at the texel's direction (pg_cube_sample); coarser, the mean of the
 * world texels it covers. */
static void test_world_level_sampling(void **state) {
    (void)state;
    const int64_t n = 16;
    size_t nw = (size_t)6 * n * n;
    float *elev = malloc(nw * sizeof(float)), *temp = malloc(nw * sizeof(float)),
          *prec = malloc(nw * sizeof(float));
    assert_true(elev && temp && prec);
    for (size_t i = 0; i < nw; i++) { /* a field with every kind of texel */
        elev[i] = (float)((int)(i * 7919 % 9000) - 4000);
        temp[i] = (float)((int)(i * 104729 % 70) - 40);
        prec[i] = (float)(i * 31 % 2500);
    }
    pg_planet_world w = {n, elev, temp, prec};
    pg_error e = {0};
    const int64_t rs[3] = {n, 4 * n, n / 2};
    for (int k = 0; k < 3; k++) {
        const int64_t r = rs[k];
        float *g = malloc((size_t)6 * r * r * sizeof *g);
        uint8_t *m = malloc((size_t)6 * r * r);
        assert_true(g && m);
        /* in two calls, as distributed ranks ask for their rows */
        assert_int_equal(pg_planet_world_level(&w, r, 0, 3 * r + 1, g, m, &e), PG_OK);
        assert_int_equal(
            pg_planet_world_level(&w, r, 3 * r + 1, 6 * r, g + (3 * r + 1) * r, NULL, &e), PG_OK);
        uint8_t *m2 = malloc((size_t)6 * r * r);
        assert_non_null(m2);
        assert_int_equal(pg_planet_world_level(&w, r, 0, 6 * r, NULL, m2, &e), PG_OK);
        assert_memory_equal(m, m2, (size_t)(3 * r + 1) * r);
        pg_cube_grid grid;
        assert_int_equal(pg_cube_grid_init(&grid, PG_CUBE_DEFAULT_PROJECTION, 1, (int)r, &e),
                         PG_OK);
        for (int64_t id = 0; id < 6 * r * r; id++) {
            const int f = (int)(id / (r * r)), y = (int)(id / r % r), x = (int)(id % r);
            if (r == n) {
                assert_float_equal(g[id], elev[id], 0);
                assert_int_equal(m2[id], pg_planet_world_mask_at(&w, (size_t)id));
            } else if (r > n) {
                double d[3];
                float want;
                pg_cube_texel_dir(&grid, id, d);
                pg_cube_sample(PG_CUBE_DEFAULT_PROJECTION, n, elev, 1, d, &want);
                assert_float_equal(g[id], want, 1e-3);
            } else {
                double sum = 0;
                for (int j = 0; j < 2; j++)
                    for (int i = 0; i < 2; i++)
                        sum += elev[((size_t)f * n + 2 * y + j) * n + 2 * x + i];
                assert_float_equal(g[id], sum / 4, 1e-3);
            }
        }
        free(g), free(m), free(m2);
    }
    /* rows outside the level are refused */
    float g1[16];
    assert_int_equal(pg_planet_world_level(&w, 2, 0, 13, g1, NULL, &e), PG_ERR_BADINPUT);
    free(elev), free(temp), free(prec);
}

/* equirect: the guide and the type map as equirectangular maps given by the caller
 * (pg_planet_world_guide, pg_planet_world_types); otherwise the synthesis samples the
 * world on the cube itself, as `generate` does. */
static void two_zone_guidance(bool equirect) {
    size_t nw = (size_t)6 * WN * WN;
    float *elev = malloc(nw * sizeof(float)), *temp = malloc(nw * sizeof(float)),
          *prec = malloc(nw * sizeof(float));
    assert_true(elev && temp && prec);
    two_zones(elev, temp, prec);
    pg_planet_world w = {WN, elev, temp, prec};
    pg_guide guide = {0};
    pg_types_map types = {0};
    pg_error e = {0};
    if (equirect) {
        assert_int_equal(pg_planet_world_guide(&w, 512, &guide, &e), PG_OK);
        assert_int_equal(pg_planet_world_types(&w, 512, &types, &e), PG_OK);
    }
    pg_planet_synth_params p;
    pg_planet_synth_params_default(&p);
    p.tiles = 1;
    p.tile_size = 128;
    p.synth.seed = 5;
    p.layout = PG_LAYOUT_WORLD;
    p.world = &w;
    p.guide = equirect ? &guide : NULL;
    p.types = equirect ? &types : NULL;
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
    print_message("material from the matching zone (%s): cold %.3f, hot %.3f\n",
                  equirect ? "equirectangular maps" : "sampled on the cube", fc, fh);
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

static void test_two_zone_guidance(void **state) {
    (void)state;
    two_zone_guidance(false);
}

static void test_two_zone_guidance_equirect(void **state) {
    (void)state;
    two_zone_guidance(true);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_options),
        cmocka_unit_test(test_small_world),
        cmocka_unit_test(test_world_level_sampling),
        cmocka_unit_test_setup_teardown(test_two_zone_guidance, setup, teardown),
        cmocka_unit_test_setup_teardown(test_two_zone_guidance_equirect, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
