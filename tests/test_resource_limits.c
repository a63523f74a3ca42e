/* test_resource_limits.c - every command that allocates in proportion to its input or
 * parameters estimates its peak memory before any work and refuses, with exit 2, one
 * line showing the estimate and no output, when the estimate exceeds the available
 * memory or --max-memory; --max-memory overrides the available-memory limit.
 *
 * The available memory is provoked low through PLANETGEN_MEM_AVAILABLE (bytes), which
 * replaces /proc/meminfo's MemAvailable, so the refusal is tested on tiny inputs that
 * would otherwise run in a second. The inputs are small synthetic files written here:
 * an exemplar pair of 64 x 32, a 64 x 64 DEM and a 6 x 32^2 planet directory. The
 * commands: synth, pits (a DEM and a planet directory), export, exemplar, inspect;
 * generate's check is tested in test_generate_cli. */
#include "pg_test.h"

#include "planetgen/pg_image.h"
#include "planetgen/pg_planet.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char out[8192], err[8192];
static char dir[512], alb[600], hgt[600], dem[600], planet[600];

/* A smooth, non-constant pattern, so that the exemplar's PCA is not degenerate. */
static float pattern(int x, int y, int c) {
    unsigned h = (unsigned)x * 73856093u ^ (unsigned)y * 19349663u ^ (unsigned)c * 83492791u;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return 0.5f * (float)(x % 16) / 16.0f + 0.5f * (float)(h & 1023) / 1023.0f;
}

static void write_inputs(void) {
    pg_error e = {0};
    pg_image img;
    pg_test_scratch_dir("resource-limits", dir, sizeof dir);
    assert_int_equal(pg_image_alloc(&img, 64, 32, 3, &e), PG_OK);
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 64; x++)
            for (int c = 0; c < 3; c++)
                img.data[(y * 64 + x) * 3 + c] = pattern(x, y, c);
    snprintf(alb, sizeof alb, "%s/albedo.png", dir);
    assert_int_equal(pg_image_write_png(alb, &img, 8, &e), PG_OK);
    pg_image_free(&img);
    assert_int_equal(pg_image_alloc(&img, 64, 32, 1, &e), PG_OK);
    for (int i = 0; i < 64 * 32; i++)
        img.data[i] = 4000.0f * pattern(i % 64, i / 64, 7) - 1500.0f;
    snprintf(hgt, sizeof hgt, "%s/height.exr", dir);
    assert_int_equal(pg_image_write_exr(hgt, &img, NULL, &e), PG_OK);
    pg_image_free(&img);
    assert_int_equal(pg_image_alloc(&img, 64, 64, 1, &e), PG_OK);
    for (int i = 0; i < 64 * 64; i++)
        img.data[i] = 100.0f * pattern(i % 64, i / 64, 3);
    snprintf(dem, sizeof dem, "%s/dem.exr", dir);
    assert_int_equal(pg_image_write_exr(dem, &img, NULL, &e), PG_OK);
    pg_image_free(&img);
    pg_planet p;
    assert_int_equal(pg_planet_alloc(&p, PG_CUBE_EQUIANGULAR, 1, 32, pg_ellipsoid_wgs84(), &e),
                     PG_OK);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int i = 0; i < 32 * 32; i++) {
            p.height[f][i] = 3000.0f * pattern(i % 32, i / 32 + 32 * f, 1) - 1000.0f;
            for (int c = 0; c < 3; c++)
                p.albedo[f][i * 3 + c] = pattern(i % 32, i / 32 + 32 * f, c);
        }
    snprintf(planet, sizeof planet, "%s/planet", dir);
    mkdir(planet, 0777);
    assert_int_equal(pg_planet_save_dir(&p, planet, &e), PG_OK);
    pg_planet_free(&p);
}

static int setup(void **state) {
    (void)state;
    write_inputs();
    return 0;
}

static bool exists(const char *path) {
    struct stat sb;
    return stat(path, &sb) == 0;
}

/* args must fail with exit 2, one stderr line naming `what`, showing an estimate in GB
 * and the limit (`limit` is "available" or "--max-memory"), and leave `output` absent. */
static void expect_refused(const char *args, const char *what, const char *limit,
                           const char *output) {
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 2 || !strstr(err, what) || !strstr(err, "needs about") || !strstr(err, " GB") ||
        !strstr(err, limit))
        fail_msg("'%s': exit %d, stderr '%s' (wanted exit 2, '%s', an estimate and '%s')", args, rc,
                 err, what, limit);
    const char *nl = strchr(err, '\n');
    if (!nl || nl[1] != '\0') fail_msg("'%s': stderr is not one line: '%s'", args, err);
    if (output && exists(output)) fail_msg("'%s': left %s behind", args, output);
}

/* Refused under a 1 kB "available" memory, and under --max-memory 0.001 (1 MB). */
static void expect_both_refusals(const char *args, const char *what, const char *output) {
    char a2[4200];
    setenv("PLANETGEN_MEM_AVAILABLE", "1000", 1);
    expect_refused(args, what, "available", output);
    unsetenv("PLANETGEN_MEM_AVAILABLE");
    snprintf(a2, sizeof a2, "%s --max-memory 0.001", args);
    expect_refused(a2, what, "--max-memory", output);
}

/* --max-memory overrides a too small available memory: the run succeeds, and its JSON
 * report holds the estimate and the peak RSS of every stage. */
static void expect_override_runs(const char *args, const char *output) {
    char a2[4900], json[700];
    snprintf(json, sizeof json, "%s/override.json", dir);
    unlink(json);
    snprintf(a2, sizeof a2, "%s --max-memory 100 --json %s -q", args, json);
    setenv("PLANETGEN_MEM_AVAILABLE", "1000", 1);
    int rc = pg_test_run_cli(a2, out, sizeof out, err, sizeof err);
    unsetenv("PLANETGEN_MEM_AVAILABLE");
    if (rc != 0) fail_msg("'%s': exit %d, stderr '%s'", a2, rc, err);
    if (output && !exists(output)) fail_msg("'%s': no %s", a2, output);
    FILE *f = fopen(json, "r");
    assert_non_null(f);
    static char text[1 << 16];
    size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    const char *est = strstr(text, "\"memory_estimate_bytes\"");
    if (!est) fail_msg("'%s': no memory_estimate_bytes in %s", a2, json);
    assert_true(strtod(strchr(est, ':') + 1, NULL) > 1e6);
    if (!strstr(text, "\"stages\"") || !strstr(text, "\"seconds\"") ||
        !strstr(text, "\"peak_rss_bytes\"") || !strstr(text, "\"minor_faults\"") ||
        !strstr(text, "\"major_faults\""))
        fail_msg("'%s': %s lacks stages with seconds, peak_rss_bytes and page faults", a2, json);
    /* a stage that did work used CPU time */
    const char *cpu = strstr(text, "\"cpu_seconds\"");
    if (!cpu) fail_msg("'%s': no cpu_seconds in %s", a2, json);
    double most = 0;
    for (; cpu; cpu = strstr(cpu + 1, "\"cpu_seconds\""))
        most = fmax(most, strtod(strchr(cpu, ':') + 1, NULL));
    assert_true(most > 0);
}

static void test_synth(void **state) {
    (void)state;
    char args[4096], o[700];
    snprintf(o, sizeof o, "%s/synth", dir);
    snprintf(args, sizeof args,
             "synth --size 16 --face-size 32 --levels 2 --no-cache --albedo %s --height %s -o %s",
             alb, hgt, o);
    expect_both_refusals(args, "--size 16", o);
    char png[800];
    snprintf(png, sizeof png, "%s/albedo.png", o);
    expect_override_runs(args, png);
}

static void test_pits(void **state) {
    (void)state;
    char args[4096], o[700];
    snprintf(o, sizeof o, "%s/filled.exr", dir);
    snprintf(args, sizeof args, "pits --method fill %s -o %s", dem, o);
    expect_both_refusals(args, dem, o);
    snprintf(args, sizeof args, "pits --method fill --no-stats %s -o %s", dem, o);
    expect_both_refusals(args, dem, o);
    snprintf(args, sizeof args, "pits --stats %s", dem);
    expect_both_refusals(args, dem, NULL);
    snprintf(args, sizeof args, "pits --stats %s", planet);
    expect_both_refusals(args, planet, NULL);
    snprintf(args, sizeof args, "pits --method fill %s -o %s", dem, o);
    expect_override_runs(args, o);
    snprintf(args, sizeof args, "pits --stats %s", planet);
    expect_override_runs(args, NULL);
}

static void test_export(void **state) {
    (void)state;
    char args[4096], o[700], glb[800];
    snprintf(o, sizeof o, "%s/export", dir);
    snprintf(glb, sizeof glb, "%s/planet.glb", o);
    snprintf(args, sizeof args, "export %s -o %s --globe-size 64", planet, o);
    expect_both_refusals(args, planet, o);
    expect_override_runs(args, glb);
}

static void test_exemplar(void **state) {
    (void)state;
    char args[4096], o[700], png[800];
    snprintf(o, sizeof o, "%s/exemplar", dir);
    snprintf(png, sizeof png, "%s/relief.png", o);
    snprintf(args, sizeof args, "exemplar --albedo %s --height %s -o %s", alb, hgt, o);
    expect_both_refusals(args, "exemplar", o);
    expect_override_runs(args, png);
}

static void test_inspect(void **state) {
    (void)state;
    char args[4096], views[700], png[800];
    snprintf(views, sizeof views, "%s/views", dir);
    snprintf(png, sizeof png, "%s/north_planet.png", views);
    snprintf(args, sizeof args,
             "inspect %s --albedo %s --height %s --view-size 256 --no-cache -o %s", planet, alb,
             hgt, views);
    expect_both_refusals(args, planet, views);
    expect_override_runs(args, png);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_synth),   cmocka_unit_test(test_pits),
        cmocka_unit_test(test_export),  cmocka_unit_test(test_exemplar),
        cmocka_unit_test(test_inspect),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
