/* test_export_cli.c - `planetgen export` as a user runs it: bad input exits 2 with
 * a message naming the option and writes nothing; a second export into the same
 * directory replaces the files atomically (new inode, no temporary left behind);
 * the previews exist and show a globe (orthographic renders cover the disc's share
 * of the frame) and the equirectangular maps are not blank. */
#include "export_fixture.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static void test_bad_input(void **s) {
    (void)s;
    char dir[1024];
    fixture_planet_dir("export_cli_bad", 2, 32, dir, sizeof dir);
    fixture_export_refused(dir, "--texture-format gif", "--texture-format 'gif'");
    fixture_export_refused(dir, "--mesh-res 48", "--mesh-res 48"); /* does not divide 64 texels */
    fixture_export_refused(dir, "--mesh-res 5", "--mesh-res 5");   /* not a multiple of 2 tiles */
    fixture_export_refused(dir, "--mesh-res 128", "--mesh-res 128");
    fixture_export_refused(dir, "--exaggeration -1", "--exaggeration");
    fixture_export_refused(dir, "--exaggeration 1e9", "--exaggeration");
    fixture_export_refused(dir, "--exaggeration 900", "quarter of the"); /* Earth's relief x 900 */
    char args[2048], err[4096];
    snprintf(args, sizeof args, "export '%s/nonexistent'", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, err, sizeof err), 2);
    assert_non_null(strstr(err, "not a planet output"));
}

static ino_t inode_of(const char *path) {
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    return sb.st_ino;
}

static void test_replace_and_previews(void **s) {
    (void)s;
    char dir[1024], args[4096], path[1300];
    fixture_planet_dir("export_cli", 2, 64, dir, sizeof dir);
    snprintf(args, sizeof args, "export '%s' -q", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    snprintf(path, sizeof path, "%s/planet.glb", dir);
    ino_t before = inode_of(path);
    /* planet.json, 6 albedo faces, height.exr, planet.glb, 2 maps, 4 globes */
    assert_int_equal(pg_test_count_files(dir), 8 + 1 + 2 + 4);
    snprintf(args, sizeof args, "export '%s' -q --mesh-res 32 --texture-format jpeg", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    assert_true(inode_of(path) != before);          /* renamed into place, not rewritten */
    assert_int_equal(pg_test_count_files(dir), 15); /* no temporary left */
    const char *globes[] = {"globe_north.png", "globe_south.png", "globe_lon000.png",
                            "globe_lon180.png"};
    for (int i = 0; i < 4; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, globes[i]);
        double fg = fixture_foreground_fraction(path);
        printf("%s: %.1f%% globe\n", globes[i], 100 * fg);
        /* the disc of radius 1/1.04 of the half-frame covers 72.6%; dark night-side
         * pixels may match the black background */
        assert_true(fg > 0.45 && fg < 0.74);
    }
    const char *maps[] = {"albedo.png", "relief.png"};
    for (int i = 0; i < 2; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, maps[i]);
        int w, h, ch;
        pg_error err = {0};
        assert_int_equal(pg_image_probe(path, &w, &h, &ch, &err), PG_OK);
        assert_int_equal(w, 2 * h);
        assert_true(fixture_foreground_fraction(path) > 0.3);
    }
}

/* Results do not depend on the thread count: the .glb and the previews are
 * byte-identical with 1 and 2 threads. */
static void test_thread_count_invariant(void **s) {
    (void)s;
    char dir[1024], args[4096];
    fixture_planet_dir("export_cli_threads", 2, 32, dir, sizeof dir);
    const char *files[] = {"planet.glb", "globe_north.png", "relief.png", "height.exr"};
    for (int t = 1; t <= 2; t++) {
        snprintf(args, sizeof args, "export '%s' -o '%s/t%d' --threads %d -q", dir, dir, t, t);
        assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    }
    for (int i = 0; i < 4; i++) {
        char cmd[4096];
        snprintf(cmd, sizeof cmd, "cmp -s '%s/t1/%s' '%s/t2/%s'", dir, files[i], dir, files[i]);
        assert_int_equal(fixture_sh(cmd, NULL, 0), 0);
        printf("%s identical with 1 and 2 threads\n", files[i]);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_bad_input),
                                       cmocka_unit_test(test_replace_and_previews),
                                       cmocka_unit_test(test_thread_count_invariant)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
