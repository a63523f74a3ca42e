/* test_generate_cli.c - `planetgen generate` end to end: each bad input of docs/generate.md exits
 * 2 with a one-line message naming the problem (and writes nothing), and a small planet
 * run writes the planet directory, the previews, the globe and a JSON report with the quality
 * figures (pits after the final pass: 0). */
#include "pg_test.h"

#include "planetgen/pg_image.h"
#include "planetgen/pg_planet_synth.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char out[65536], err[65536];

static void expect_bad(const char *args, const char *needle) {
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 2 || !strstr(err, needle))
        fail_msg("'%s': exit %d, stderr '%s' (wanted exit 2 and '%s')", args, rc, err, needle);
}

/* Write a w x h RGB PNG filled by fn(x, y, rgb). */
static void write_png(const char *path, int w, int h, void (*fn)(int, int, float *)) {
    pg_image img;
    pg_error e = {0};
    assert_int_equal(pg_image_alloc(&img, w, h, 3, &e), PG_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            fn(x, y, img.data + ((size_t)y * w + x) * 3);
    assert_int_equal(pg_image_write_png(path, &img, 8, &e), PG_OK);
    pg_image_free(&img);
}

static void grey_ramp(int x, int y, float *c) {
    (void)y;
    c[0] = c[1] = c[2] = (float)(x % 64) / 63.0f;
}

static void types_with_magenta(int x, int y, float *c) {
    c[0] = 0, c[1] = 0, c[2] = 1;                      /* ocean */
    if (x < 10 && y < 5) c[0] = 1, c[1] = 0, c[2] = 1; /* magenta names no type */
}

/* Seven vertical bands: the six type colours, then black (any). */
static void type_bands(int x, int y, float *c) {
    (void)y;
    static const float pal[7][3] = {{0, 0, 1}, {1, 1, 1},      {1, 1, 0},
                                    {0, 1, 0}, {0, 0.502f, 0}, {0.502f, 0.502f, 0.502f},
                                    {0, 0, 0}};
    memcpy(c, pal[x * 7 / 140], sizeof pal[0]);
}

/* The whole of a small text file (a JSON report) into a static buffer. */
static const char *slurp(const char *path) {
    static char buf[65536];
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("cannot open %s", path);
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = 0;
    if (n == sizeof buf - 1 && fgetc(f) != EOF) fail_msg("%s: longer than %zu bytes", path, n);
    fclose(f);
    return buf;
}

static void test_type_map_colours(void **state) {
    (void)state;
    char dir[512], f[600];
    pg_test_scratch_dir("generate-cli-typemap", dir, sizeof dir);
    snprintf(f, sizeof f, "%s/types.png", dir);
    write_png(f, 140, 70, type_bands);
    pg_types_map m;
    pg_error e = {0};
    assert_int_equal(pg_types_map_load(f, &m, &e), PG_OK);
    for (int t = 0; t < 7; t++) {
        uint8_t want = t < PG_TYPE_COUNT ? (uint8_t)(1u << t) : PG_TYPES_ALL;
        assert_int_equal(m.mask[35 * 140 + t * 20 + 10], want);
    }
    pg_types_map_free(&m);
}

static void test_bad_sizes(void **state) {
    (void)state;
    char dir[512], args[1024];
    pg_test_scratch_dir("generate-cli-bad", dir, sizeof dir);
    snprintf(args, sizeof args, "generate --tile-size 16 -o %s/o", dir);
    expect_bad(args, "pyramid");
    snprintf(args, sizeof args, "generate --tile-size 100 -o %s/o", dir);
    expect_bad(args, "power of two");
    snprintf(args, sizeof args, "generate --tiles 64 --tile-size 4096 -o %s/o", dir);
    expect_bad(args, "GB"); /* T*S too large: the estimate is shown */
    snprintf(args, sizeof args, "generate --tiles 4 --max-memory 0.01 -o %s/o", dir);
    expect_bad(args, "--max-memory");
    expect_bad("generate --preset moon", "--preset");
    expect_bad("generate --layout flat", "--layout");
    expect_bad("generate --final-pits magic", "--final-pits");
    assert_int_equal(pg_test_count_files(dir), 0);
}

static void test_bad_maps(void **state) {
    (void)state;
    char dir[512], f[600], args[2048];
    pg_test_scratch_dir("generate-cli-maps", dir, sizeof dir);
    snprintf(args, sizeof args, "generate --guide %s/missing.png -o %s/o", dir, dir);
    expect_bad(args, "--guide");
    snprintf(f, sizeof f, "%s/square.png", dir);
    write_png(f, 64, 64, grey_ramp);
    snprintf(args, sizeof args, "generate --guide %s -o %s/o", f, dir);
    expect_bad(args, "2:1");
    snprintf(args, sizeof args, "generate --types %s -o %s/o", f, dir);
    expect_bad(args, "2:1");
    snprintf(f, sizeof f, "%s/types.png", dir);
    write_png(f, 128, 64, types_with_magenta);
    snprintf(args, sizeof args, "generate --types %s -o %s/o", f, dir);
    expect_bad(args, "#ff00ff");
    assert_non_null(strstr(err, "name no type"));
}

/* An all-ocean exemplar: the desert preset leaves no valid exemplar texel. */
static void ocean_albedo(int x, int y, float *c) {
    c[0] = 0.02f, c[1] = 0.05f + 0.05f * (float)((x * 7 + y * 13) % 11) / 10.0f, c[2] = 0.3f;
}

/* An exemplar that is all ocean (256 x 128, depths -3000..-3500 m) in dir. */
static void ocean_exemplar(const char *name, char *dir, size_t dsize, char *a, char *h) {
    pg_test_scratch_dir(name, dir, dsize);
    snprintf(a, 600, "%s/albedo.png", dir);
    write_png(a, 256, 128, ocean_albedo);
    pg_image img;
    pg_error e = {0};
    assert_int_equal(pg_image_alloc(&img, 256, 128, 1, &e), PG_OK);
    for (int i = 0; i < 256 * 128; i++)
        img.data[i] = -3000.0f - 500.0f * (float)((i * 31) % 17) / 16.0f;
    snprintf(h, 600, "%s/height.exr", dir);
    assert_int_equal(pg_image_write_exr(h, &img, NULL, &e), PG_OK);
    pg_image_free(&img);
}

static void test_preset_without_texels(void **state) {
    (void)state;
    char dir[512], a[600], h[600], args[2048];
    ocean_exemplar("generate-cli-preset", dir, sizeof dir, a, h);
    snprintf(args, sizeof args,
             "generate --layout free --tiles 1 --tile-size 32 --preset desert --albedo %s "
             "--height %s --no-cache -o %s/o",
             a, h, dir);
    expect_bad(args, "no exemplar texel");
}

/* layout world (the default) takes its hypsometry from the exemplar's land and ocean */
static void test_world_exemplar_without_land(void **state) {
    (void)state;
    char dir[512], a[600], h[600], args[2048];
    ocean_exemplar("generate-cli-world-ocean", dir, sizeof dir, a, h);
    snprintf(args, sizeof args,
             "generate --tiles 1 --tile-size 32 --albedo %s --height %s --no-cache -o %s/o", a, h,
             dir);
    expect_bad(args, "the exemplar has no land");
}

static void test_small_planet(void **state) {
    (void)state;
    char dir[512], args[2048], path[700];
    pg_test_scratch_dir("generate-cli-run", dir, sizeof dir);
    snprintf(args, sizeof args,
             "generate --tiles 2 --tile-size 64 --seed 3 --cache-dir %s/synth-cache -o %s/p "
             "--json %s/r.json",
             getenv("PG_BUILD_DIR"), dir, dir);
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("exit %d: %s", rc, err);
    /* the default layout is world: its macro fields are written too */
    const char *files[] = {"planet.json",   "height.exr",  "albedo_+X.png",
                           "albedo_-Z.png", "albedo.png",  "relief.png",
                           "plates.png",    "climate.png", "world.exr"};
    for (int i = 0; i < 9; i++) {
        snprintf(path, sizeof path, "%s/p/%s", dir, files[i]);
        if (!pg_test_file_nonempty(path)) fail_msg("missing %s", path);
    }
    snprintf(path, sizeof path, "%s/r.json", dir);
    const char *json = slurp(path);
    const char *after = strstr(json, "\"pits_after\"");
    assert_non_null(after);
    assert_non_null(strstr(after, "\"depressions\": 0"));
    assert_non_null(strstr(json, "\"land_agreement\""));
    /* planet.json says how the planet was made */
    snprintf(path, sizeof path, "%s/p/planet.json", dir);
    json = slurp(path);
    const char *gen = strstr(json, "\"generation\"");
    if (!gen) fail_msg("planet.json has no generation record: %s", json);
    assert_non_null(strstr(gen, "\"layout\": \"world\""));
    assert_non_null(strstr(gen, "\"plates\": 14"));
    assert_non_null(strstr(gen, "\"land_fraction\": 0.29"));
}

/* The smallest planet the options allow (one tile of 32^2 per face): its pyramid's coarsest level
 * has one texel per face, which Gain-pit skips; every layout delivers it drained, and -v names
 * the pit removal that ran. */
static void test_smallest_planet(void **state) {
    (void)state;
    const char *layouts[] = {"free", "world", "earth"};
    for (int i = 0; i < 3; i++) {
        char dir[512], args[2048], path[700];
        snprintf(path, sizeof path, "generate-cli-n32-%s", layouts[i]);
        pg_test_scratch_dir(path, dir, sizeof dir);
        snprintf(args, sizeof args,
                 "generate -v --layout %s --tiles 1 --tile-size 32 --cache-dir %s/synth-cache "
                 "--no-glb -o %s/p --json %s/r.json",
                 layouts[i], getenv("PG_BUILD_DIR"), dir, dir);
        int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
        if (rc != 0) fail_msg("layout %s: exit %d: %s", layouts[i], rc, err);
        /* -v names the pit removal that runs: breaching along the descent tree */
        if (!strstr(out, "Gain-pit (Scott 2020 4.2.1): breaching along the descent tree") &&
            !strstr(err, "Gain-pit (Scott 2020 4.2.1): breaching along the descent tree"))
            fail_msg("layout %s: -v does not name the descent-tree breach: %s%s", layouts[i], out,
                     err);
        snprintf(path, sizeof path, "%s/p/height.exr", dir);
        if (!pg_test_file_nonempty(path)) fail_msg("missing %s", path);
        snprintf(path, sizeof path, "%s/r.json", dir);
        const char *json = slurp(path);
        const char *after = strstr(json, "\"pits_after\"");
        if (!after || !strstr(after, "\"depressions\": 0"))
            fail_msg("layout %s: not drained: %s", layouts[i], json);
    }
}

/* Ocean in the left half, land in the right (the heights are a ramp across x, written by the
 * test), so every stage of the preparation has work. */
static void land_albedo(int x, int y, float *c) {
    float land = x >= 128 ? 1.0f : 0.0f;
    c[0] = 0.02f + 0.3f * land, c[1] = 0.05f + 0.25f * land + 0.01f * (float)(y % 5),
    c[2] = 0.3f - 0.2f * land;
}

/* A cold preparation reports its own stages (docs/synthesis.md, "Exemplar preparation"): -v
 * prints them, and --json holds five times, each positive, that together take no longer than
 * the whole preparation and most of it (what falls outside them: the height range and its
 * weighting). A warm run, loaded from the cache, records none. */
static void test_cold_prep_stages(void **state) {
    (void)state;
    char dir[512], a[600], h[600], args[4096], path[700];
    pg_test_scratch_dir("generate-cli-prep-stages", dir, sizeof dir);
    snprintf(a, sizeof a, "%s/albedo.png", dir);
    write_png(a, 256, 128, land_albedo);
    pg_image img;
    pg_error e = {0};
    assert_int_equal(pg_image_alloc(&img, 256, 128, 1, &e), PG_OK);
    for (int i = 0; i < 256 * 128; i++)
        img.data[i] = -2000.0f + 3500.0f * (float)(i % 256) / 255.0f + (float)((i * 31) % 17);
    snprintf(h, sizeof h, "%s/height.exr", dir);
    assert_int_equal(pg_image_write_exr(h, &img, NULL, &e), PG_OK);
    pg_image_free(&img);
    snprintf(args, sizeof args,
             "generate -v --layout free --tiles 1 --tile-size 32 --albedo %s --height %s "
             "--cache-dir %s/cache --no-glb -o %s/o --json %s/r.json",
             a, h, dir, dir, dir);
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("exit %d: %s", rc, err);
    if (!strstr(out, "k-coherence") && !strstr(err, "k-coherence"))
        fail_msg("-v printed no preparation stages: %s%s", out, err);
    snprintf(path, sizeof path, "%s/r.json", dir);
    const char *json = slurp(path);
    const char *tot = strstr(json, "\"exemplar_prep_seconds\": ");
    const char *st = strstr(json, "\"exemplar_prep_stage_seconds\"");
    if (!tot || !st) fail_msg("no preparation record in %s", json);
    char obj[1024]; /* the stages' object alone, so that no other key can answer */
    const char *end = strchr(st, '}');
    if (!end || end - st >= (ptrdiff_t)sizeof obj) fail_msg("malformed stages: %s", st);
    memcpy(obj, st, (size_t)(end - st));
    obj[end - st] = 0;
    double total = strtod(tot + strlen("\"exemplar_prep_seconds\": "), NULL), sum = 0;
    static const char *const names[5] = {"cube", "stack", "appearance", "kcoherence",
                                         "cache_write"};
    for (int i = 0; i < 5; i++) {
        char key[40];
        snprintf(key, sizeof key, "\"%s\": ", names[i]);
        const char *k = strstr(obj, key);
        if (!k) fail_msg("stage %s missing: %s", names[i], obj);
        double s = strtod(k + strlen(key), NULL);
        if (!(s > 0.0)) fail_msg("stage %s took %g s: not timed", names[i], s);
        sum += s;
    }
    print_message("preparation %.3f s, its stages %.3f s\n", total, sum);
    if (!(sum <= total + 1e-3 && sum >= 0.8 * total))
        fail_msg("stages sum to %.4f s, the preparation took %.4f s", sum, total);
    /* warm: loaded from the cache, no stages */
    rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("exit %d: %s", rc, err);
    json = slurp(path);
    assert_non_null(strstr(json, "\"exemplar_from_cache\": true"));
    assert_null(strstr(json, "\"exemplar_prep_stage_seconds\""));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_type_map_colours),
        cmocka_unit_test(test_bad_sizes),
        cmocka_unit_test(test_bad_maps),
        cmocka_unit_test(test_preset_without_texels),
        cmocka_unit_test(test_world_exemplar_without_land),
        cmocka_unit_test(test_small_planet),
        cmocka_unit_test(test_smallest_planet),
        cmocka_unit_test(test_cold_prep_stages),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
