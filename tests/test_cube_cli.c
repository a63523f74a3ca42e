/* test_cube_cli.c - `planetgen grid` end to end: a good run prints the counts and
 * distortion and writes the documented JSON keys; bad input exits 2 with one line
 * on stderr naming the option at fault. */
#include "pg_test.h"

#include <stdio.h>
#include <string.h>

static void expect_bad(const char *args, const char *option) {
    char out[4096], err[4096];
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    print_message("planetgen %s -> exit %d: %s", args, rc, err);
    assert_int_equal(rc, 2);
    assert_non_null(strstr(err, option));
    char *nl = strchr(err, '\n');
    assert_true(nl && nl[1] == '\0'); /* exactly one line */
}

static void test_bad_input(void **state) {
    (void)state;
    expect_bad("grid --tile-size 100", "--tile-size");   /* not a power of two */
    expect_bad("grid --tile-size 8", "--tile-size");     /* below 16 */
    expect_bad("grid --tile-size 16384", "--tile-size"); /* above 8192 */
    expect_bad("grid --tiles 0", "--tiles");
    expect_bad("grid --tiles -3", "--tiles");
    expect_bad("grid --projection mercator", "--projection");
    expect_bad("grid --planet 6378137,1", "--planet"); /* flattening 1 */
    expect_bad("grid --planet 6378137,-0.01", "--planet");
    expect_bad("grid --planet 0,0.003", "--planet"); /* radius 0 */
    expect_bad("grid --planet -5,0", "--planet");
    expect_bad("grid --planet venus", "--planet");
}

static void test_good_run(void **state) {
    (void)state;
    char dir[1024], args[2048], out[8192], err[4096];
    pg_test_scratch_dir("cube_cli", dir, sizeof dir);
    snprintf(
        args, sizeof args,
        "grid --projection gnomonic --tiles 2 --tile-size 64 --planet wgs84 --json '%s/g.json'",
        dir);
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(out, "6 x 2 x 2 = 24 tiles"));
    assert_non_null(strstr(out, "6 x 128 x 128 = 98304"));
    assert_non_null(strstr(out, "ratio"));
    char path[1200], json[16384];
    snprintf(path, sizeof path, "%s/g.json", dir);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    size_t n = fread(json, 1, sizeof json - 1, f);
    fclose(f);
    json[n] = '\0';
    const char *keys[] = {"\"area_ratio\"", "\"texel_area_min_m2\"", "\"texel_area_max_m2\"",
                          "\"max_angle_deviation_deg\"", "\"mean_texel_km\""};
    for (size_t i = 0; i < sizeof keys / sizeof *keys; i++)
        assert_non_null(strstr(json, keys[i]));
    double ratio = 0;
    const char *p = strstr(json, "\"area_ratio\"");
    assert_int_equal(sscanf(p, "\"area_ratio\": %lf", &ratio), 1);
    assert_true(ratio > 4.5 && ratio < 5.3); /* gnomonic, coarse grid */
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_good_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
