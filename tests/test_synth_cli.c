/* test_synth_cli.c - `planetgen synth` end to end: bad input exits 2 with a one-line
 * message naming the problem, before any output is written; a small run writes the
 * three outputs. */
#include "pg_test.h"

#include "planetgen/pg_image.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char out[8192], err[8192];

static void expect_bad(const char *args, const char *needle) {
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 2 || !strstr(err, needle))
        fail_msg("'%s': exit %d, stderr '%s' (wanted exit 2 and '%s')", args, rc, err, needle);
}

static void test_bad_size(void **state) {
    (void)state;
    char dir[512], args[1024];
    pg_test_scratch_dir("synth-cli-bad", dir, sizeof dir);
    snprintf(args, sizeof args, "synth --size 100 -o %s/o", dir);
    expect_bad(args, "power of two");
    assert_int_equal(pg_test_count_files(dir), 0);
    expect_bad("synth --size 1048576", "GB"); /* too large: the estimate is shown */
    expect_bad("synth", "--size is required");
}

static void test_bad_seed_and_jitter(void **state) {
    (void)state;
    expect_bad("synth --size 64 --seed abc", "--seed");
    expect_bad("synth --size 64 --seed 12x", "not an integer");
    expect_bad("synth --size 64 --jitter 1.5", "--jitter");
    expect_bad("synth --size 64 --jitter -0.1", "--jitter");
}

/* A constant exemplar has no appearance variance: the PCA is degenerate. */
static void test_constant_exemplar(void **state) {
    (void)state;
    char dir[512], a[600], h[600], args[2048];
    pg_test_scratch_dir("synth-cli-const", dir, sizeof dir);
    pg_image img;
    pg_error e = {0};
    assert_int_equal(pg_image_alloc(&img, 256, 128, 3, &e), PG_OK);
    for (int i = 0; i < 256 * 128 * 3; i++)
        img.data[i] = 0.5f;
    snprintf(a, sizeof a, "%s/albedo.png", dir);
    assert_int_equal(pg_image_write_png(a, &img, 8, &e), PG_OK);
    pg_image_free(&img);
    assert_int_equal(pg_image_alloc(&img, 256, 128, 1, &e), PG_OK);
    for (int i = 0; i < 256 * 128; i++)
        img.data[i] = 100.0f;
    snprintf(h, sizeof h, "%s/height.exr", dir);
    assert_int_equal(pg_image_write_exr(h, &img, NULL, &e), PG_OK);
    pg_image_free(&img);
    snprintf(args, sizeof args, "synth --size 64 --albedo %s --height %s --no-cache -o %s/o", a, h,
             dir);
    expect_bad(args, "degenerate");
}

static void test_small_run_writes_outputs(void **state) {
    (void)state;
    char dir[512], args[1024], p[600];
    pg_test_scratch_dir("synth-cli-ok", dir, sizeof dir); /* exits if PG_BUILD_DIR is unset */
    /* the prepared default exemplar is shared with test_synth_quality through this cache */
    snprintf(args, sizeof args, "synth --size 64 --seed 3 -o %s/o --cache-dir %s/synth-cache", dir,
             getenv("PG_BUILD_DIR"));
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("exit %d: %s", rc, err);
    const char *names[] = {"albedo.png", "height.exr", "coords.png"};
    for (int i = 0; i < 3; i++) {
        snprintf(p, sizeof p, "%s/o/%s", dir, names[i]);
        assert_true(pg_test_file_nonempty(p));
    }
    pg_image img;
    pg_error e = {0};
    snprintf(p, sizeof p, "%s/o/height.exr", dir);
    assert_int_equal(pg_image_read_exr(p, NULL, &img, &e), PG_OK);
    assert_int_equal(img.width, 64);
    float lo = img.data[0], hi = img.data[0];
    for (int i = 0; i < 64 * 64; i++) {
        lo = img.data[i] < lo ? img.data[i] : lo;
        hi = img.data[i] > hi ? img.data[i] : hi;
    }
    assert_true(hi - lo > 10.0f); /* real terrain, not a constant */
    assert_true(lo > -12000 && hi < 10000);
    pg_image_free(&img);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_size),
        cmocka_unit_test(test_bad_seed_and_jitter),
        cmocka_unit_test(test_constant_exemplar),
        cmocka_unit_test(test_small_run_writes_outputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
