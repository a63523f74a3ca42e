/* test_realism_e2e.c - the realism report end to end (docs/inspect.md): `planetgen
 * generate` then `planetgen inspect --json` on the default planet (layout world) at the
 * default size, seeds 1 to 4, and on one planet each of `--layout free` and `--layout
 * earth`. Every documented key must be present and finite, for the planet and under
 * "earth" for Earth's own figures, and the report must hold together (Earth's copy
 * figures are a copy's; layout earth, which keeps Earth's coarse levels, is detected as
 * a copy; a planet with plates reports its mountain belts).
 *
 * The reports are left in PG_BUILD_DIR/realism/ for the gate checks (tests/gate/
 * realism_gate.c), which ctest runs after this test (fixture "realism"): this test
 * asserts what holds by construction; the gates, some of which today's planets fail,
 * are separate tests so that each shows its own figure. */
#include "pg_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const keys[] = {"pole_distortion_ratio",
                                   "face_seam_ratio",
                                   "face_seam_coherence",
                                   "tile_edge_ratio",
                                   "seam_ratio",
                                   "fidelity_ratio",
                                   "completeness_ratio",
                                   "earth_copy_fraction",
                                   "land_fraction",
                                   "landmasses_1e6",
                                   "largest_landmass_share",
                                   "hypsometry_w1_m",
                                   "hypsometry_w1_land_m",
                                   "hypsometry_w1_ocean_m",
                                   "ice_equator_fraction",
                                   "ice_polar_fraction",
                                   "desert_band_ratio",
                                   "novelty",
                                   "hack_exponent",
                                   "depressions"};
#define NKEYS (sizeof keys / sizeof keys[0])

static char out[16384], err[16384];
static char json[1 << 20];

static void read_file(const char *path) {
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("cannot open %s", path);
    size_t n = fread(json, 1, sizeof json - 1, f);
    json[n] = 0;
    fclose(f);
}

/* The value of "key": at or after `from`; NaN when absent or null. */
static double number_after(const char *from, const char *key) {
    char pat[128];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = strstr(from, pat);
    if (!p) return NAN;
    char *end;
    double v = strtod(p + strlen(pat), &end);
    return end == p + strlen(pat) ? NAN : v;
}

static void cli(const char *args) {
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("planetgen %s: exit %d: %s", args, rc, err);
}

/* Generate and inspect one planet; the report goes to PG_BUILD_DIR/realism/NAME.json. */
static void make_report(const char *name, const char *gen_args) {
    const char *build = getenv("PG_BUILD_DIR");
    char dir[700], args[4096], path[800];
    snprintf(dir, sizeof dir, "%s/realism", build);
    mkdir(dir, 0755);
    snprintf(args, sizeof args,
             "generate -q --no-glb --cache-dir %s/synth-cache %s -o %s/realism/planet-%s", build,
             gen_args, build, name);
    char rm[1000];
    snprintf(rm, sizeof rm, "rm -rf '%s/realism/planet-%s'", build, name);
    if (system(rm) != 0) fail_msg("%s failed", rm);
    cli(args);
    snprintf(path, sizeof path, "%s/realism/%s.json", build, name);
    snprintf(args, sizeof args,
             "inspect -q %s/realism/planet-%s --cache-dir %s/synth-cache --json %s", build, name,
             build, path);
    cli(args);
    read_file(path);
}

/* Every key finite at the top level and under "earth"; returns the top-level values. */
static void check_keys(const char *name, double v[NKEYS]) {
    const char *earth = strstr(json, "\"earth\": {");
    assert_non_null(earth);
    for (size_t k = 0; k < NKEYS; k++) {
        v[k] = number_after(json, keys[k]);
        double e = number_after(earth, keys[k]);
        print_message("%-8s %-24s planet %10.4f  Earth %10.4f\n", name, keys[k], v[k], e);
        if (!isfinite(v[k])) fail_msg("%s: key %s is missing or not finite", name, keys[k]);
        if (!isfinite(e)) fail_msg("%s: earth.%s is missing or not finite", name, keys[k]);
    }
    /* Earth against itself: an exact copy of itself at every place */
    assert_true(number_after(earth, "pole_distortion_ratio") < 1.01);
    assert_true(number_after(earth, "earth_copy_fraction") >= 0.5);
    assert_true(number_after(earth, "hypsometry_w1_m") == 0);
    assert_true(number_after(earth, "novelty") < 0.01);
    /* a finished planet drains: the final pass left no depression; synthesis recorded
     * how much land drained into closed basins before that pass */
    assert_true(number_after(json, "depressions") == 0);
    const char *planet = strstr(json, "\"results\": {");
    assert_non_null(planet);
    double closed = number_after(planet, "closed_land_share_before_final");
    print_message("%-8s closed land before the final pass %.3f\n", name, closed);
    assert_true(closed > 0 && closed < 1);
}

static double key_of(const double v[NKEYS], const char *key) {
    for (size_t k = 0; k < NKEYS; k++)
        if (!strcmp(keys[k], key)) return v[k];
    return NAN;
}

static void test_default_planet(void **s) {
    (void)s;
    double v[NKEYS];
    make_report("default", "--seed 1");
    check_keys("default", v);
    /* a planet with plates has the mountain-belt figure (docs/inspect.md) */
    double belts = number_after(json, "mountain_belt_fraction");
    print_message("default  mountain_belt_fraction %.4f\n", belts);
    assert_true(isfinite(belts) && belts >= 0 && belts <= 1);
}

static void test_earth_planet(void **s) {
    (void)s;
    double v[NKEYS];
    make_report("earth", "--layout earth --seed 1");
    check_keys("earth", v);
    /* layout earth keeps Earth's coarse levels: a copy of Earth, and the report says so */
    assert_true(key_of(v, "earth_copy_fraction") >= 0.5);
    assert_true(key_of(v, "novelty") < 0.2);
}

static void test_free_planet(void **s) {
    (void)s;
    double v[NKEYS];
    make_report("free", "--layout free --seed 1");
    check_keys("free", v);
    /* a new arrangement: not Earth at the same place */
    assert_true(key_of(v, "earth_copy_fraction") < 0.5);
    assert_true(key_of(v, "novelty") > 0.5);
}

/* Seeds 2-4 of the default layout: with seed 1 above, the four seeds over which the
 * gates that must hold for every seed are checked (CMakeLists.txt, "realism gates"). */
static void test_seeds(void **s) {
    (void)s;
    for (int seed = 2; seed <= 4; seed++) {
        char name[64], args[128];
        snprintf(name, sizeof name, "default-s%d", seed);
        snprintf(args, sizeof args, "--seed %d", seed);
        make_report(name, args);
        double v[NKEYS];
        check_keys(name, v);
    }
}

/* No report from an earlier run may stand in for one this run fails to write: the
 * gates read these files. */
static int remove_old_reports(void **state) {
    (void)state;
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -f '%s'/realism/*.json", getenv("PG_BUILD_DIR"));
    return system(cmd) == 0 ? 0 : -1;
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_planet), cmocka_unit_test(test_earth_planet),
        cmocka_unit_test(test_free_planet), cmocka_unit_test(test_seeds)};
    return cmocka_run_group_tests(tests, remove_old_reports, NULL);
}
