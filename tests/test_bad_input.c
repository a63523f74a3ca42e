/* test_bad_input.c - the rows of the README's bad-input table that no other test
 * covered: each input gets exit 2, one stderr line naming the file or option, and no
 * output. The inputs are small files written here (a DEM, a planet directory of
 * 6 x 32^2, an exemplar pair that cannot be calibrated). */
#include "pg_test.h"

#include "planetgen/pg_image.h"
#include "planetgen/pg_planet.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static char out[8192], err[8192];
static char dir[512];

/* args gives exit 2 and one stderr line containing needle; `absent`, when given,
 * does not exist afterwards. */
static void expect_bad(const char *args, const char *needle, const char *absent) {
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 2 || !strstr(err, needle))
        fail_msg("'%s': exit %d, stderr '%s' (wanted exit 2 and '%s')", args, rc, err, needle);
    const char *nl = strchr(err, '\n');
    if (!nl || nl[1] != '\0') fail_msg("'%s': stderr is not one line: '%s'", args, err);
    struct stat sb;
    if (absent && stat(absent, &sb) == 0) fail_msg("'%s': left %s behind", args, absent);
}

static void write_image(const char *path, int w, int h, int c, int bits, float (*f)(int, int)) {
    pg_image img;
    pg_error e = {0};
    assert_int_equal(pg_image_alloc(&img, w, h, c, &e), PG_OK);
    for (int i = 0; i < w * h * c; i++)
        img.data[i] = f((i / c) % w, (i / c) / w);
    if (bits)
        assert_int_equal(pg_image_write_png(path, &img, bits, &e), PG_OK);
    else
        assert_int_equal(pg_image_write_exr(path, &img, NULL, &e), PG_OK);
    pg_image_free(&img);
}

static float ramp(int x, int y) {
    return (float)((x * 7 + y * 13) % 97) / 97.0f;
}

static float white(int x, int y) {
    (void)x, (void)y;
    return 1.0f;
}

/* A planet directory of 6 x 32^2 texels at path. */
static void write_planet(const char *path) {
    pg_error e = {0};
    pg_planet p;
    assert_int_equal(pg_planet_alloc(&p, PG_CUBE_EQUIANGULAR, 1, 32, pg_ellipsoid_wgs84(), &e),
                     PG_OK);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int i = 0; i < 32 * 32; i++) {
            p.height[f][i] = 1000.0f * ramp(i % 32, i / 32 + f);
            for (int c = 0; c < 3; c++)
                p.albedo[f][3 * i + c] = ramp(i % 32 + c, i / 32);
        }
    mkdir(path, 0777);
    assert_int_equal(pg_planet_save_dir(&p, path, &e), PG_OK);
    pg_planet_free(&p);
}

static void write_text(const char *path, const char *text) {
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static int setup(void **state) {
    (void)state;
    pg_test_scratch_dir("bad-input", dir, sizeof dir);
    return 0;
}

/* pits: the output format comes from -o's extension; a float DEM or one of more than
 * 16 bits cannot become a 16-bit PNG; a DEM has one channel; -o and exactly one input
 * are required; --stats takes no other input; --lakes needs a flat DEM. */
static void test_pits_arguments(void **state) {
    (void)state;
    char dem[600], rgb[600], planet[600], o[600], args[4096];
    snprintf(dem, sizeof dem, "%s/dem.exr", dir);
    write_image(dem, 32, 32, 1, 0, ramp);
    snprintf(rgb, sizeof rgb, "%s/rgb.png", dir);
    write_image(rgb, 32, 32, 3, 8, ramp);
    snprintf(planet, sizeof planet, "%s/planet", dir);
    write_planet(planet);
    snprintf(o, sizeof o, "%s/out", dir);
    mkdir(o, 0777);
    char jpg[700];
    snprintf(jpg, sizeof jpg, "%s/out.jpg", o);
    snprintf(args, sizeof args, "pits --method fill %s -o %s", dem, jpg);
    expect_bad(args, "write .exr or .tif (float) or .png (16-bit)", jpg);
    char png[700];
    snprintf(png, sizeof png, "%s/out.png", o);
    snprintf(args, sizeof args, "pits --method fill %s -o %s", dem, png);
    expect_bad(args, "a float DEM cannot be written as PNG", png);
    snprintf(args, sizeof args, "pits --method fill %s -o %s/out.exr", rgb, o);
    expect_bad(args, "3 channels, expected 1", NULL);
    snprintf(args, sizeof args, "pits --method fill %s", dem);
    expect_bad(args, "-o OUT is required", NULL);
    snprintf(args, sizeof args, "pits --method fill -o %s/out.exr", o);
    expect_bad(args, "expected one input DEM", NULL);
    snprintf(args, sizeof args, "pits --method fill %s %s -o %s/out.exr", dem, dem, o);
    expect_bad(args, "expected one input DEM", NULL);
    snprintf(args, sizeof args, "pits --stats %s %s", dem, dem);
    expect_bad(args, "--stats takes no other input", NULL);
    snprintf(args, sizeof args, "pits --stats %s --lakes %s", planet, dem);
    expect_bad(args, "--lakes: not supported with a planet directory", NULL);
    assert_int_equal(pg_test_count_files(o), 0);
}

/* A damaged planet.json: not JSON, a field missing or absurd; face images whose size
 * is not the one planet.json states. Read by export, inspect and pits --stats alike
 * (pg_planet_load), checked here through export and pits. */
static void test_damaged_planet_json(void **state) {
    (void)state;
    char planet[600], meta[700], args[4096], o[700];
    snprintf(planet, sizeof planet, "%s/damaged", dir);
    snprintf(meta, sizeof meta, "%s/planet.json", planet);
    snprintf(o, sizeof o, "%s/damaged-out", dir);
    write_planet(planet);
    /* keep the good planet.json to derive the damaged ones */
    FILE *f = fopen(meta, "r");
    assert_non_null(f);
    static char good[8192];
    size_t n = fread(good, 1, sizeof good - 1, f);
    good[n] = '\0';
    fclose(f);

    write_text(meta, "{ \"tiles\": 1, ");
    snprintf(args, sizeof args, "export %s -o %s", planet, o);
    expect_bad(args, "not valid JSON", o);

    static char edited[8192];
    const char *t = strstr(good, "\"tile_size\"");
    assert_non_null(t);
    /* tile_size 32 -> 64: the faces are 32 x 32, planet.json says 64 x 64 */
    snprintf(edited, sizeof edited, "%.*s\"tile_size\": 64%s", (int)(t - good), good,
             strchr(t, ','));
    write_text(meta, edited);
    snprintf(args, sizeof args, "pits --stats %s", planet);
    expect_bad(args, "but planet.json says 64x64", NULL);

    /* tile_size 48: not a power of two */
    snprintf(edited, sizeof edited, "%.*s\"tile_size\": 48%s", (int)(t - good), good,
             strchr(t, ','));
    write_text(meta, edited);
    snprintf(args, sizeof args, "export %s -o %s", planet, o);
    expect_bad(args, "tile_size missing or not a power of two", o);

    /* radius_m removed */
    const char *r = strstr(good, "\"radius_m\"");
    assert_non_null(r);
    snprintf(edited, sizeof edited, "%.*s%s", (int)(r - good), good, strchr(r, ',') + 1);
    write_text(meta, edited);
    snprintf(args, sizeof args, "pits --stats %s", planet);
    expect_bad(args, "radius_m missing", NULL);
}

/* An exemplar whose grey relief cannot be calibrated: an all-white albedo shows no
 * water to fit sea level to. The message says which options replace the calibration. */
static void test_uncalibratable_relief(void **state) {
    (void)state;
    char alb[600], hgt[600], o[600], args[4096];
    snprintf(alb, sizeof alb, "%s/white.png", dir);
    write_image(alb, 64, 32, 3, 8, white);
    snprintf(hgt, sizeof hgt, "%s/grey.png", dir);
    write_image(hgt, 64, 32, 1, 8, ramp);
    snprintf(o, sizeof o, "%s/calib-out", dir);
    snprintf(args, sizeof args, "exemplar --albedo %s --height %s -o %s", alb, hgt, o);
    expect_bad(args, "cannot calibrate the relief", o);
    assert_non_null(strstr(err, "--sea-level and --height-scale"));
}

/* Wrong positional arguments and out-of-range level options of the other commands. */
static void test_command_arguments(void **state) {
    (void)state;
    char planet[600], args[4096];
    snprintf(planet, sizeof planet, "%s/args-planet", dir);
    write_planet(planet);
    expect_bad("export", "expected one planet directory", NULL);
    snprintf(args, sizeof args, "export %s %s", planet, planet);
    expect_bad(args, "unexpected argument", NULL);
    expect_bad("inspect", "expected one planet directory", NULL);
    snprintf(args, sizeof args, "generate --keep-levels 9 -o %s/g", dir);
    expect_bad(args, "--keep-levels", NULL);
    snprintf(args, sizeof args, "generate --pit-skip-levels 9 -o %s/g", dir);
    expect_bad(args, "--pit-skip-levels", NULL);
    snprintf(args, sizeof args, "synth --size 64 --face-size 100 -o %s/s", dir);
    expect_bad(args, "--face-size", NULL);
    expect_bad("grid --tiles 70000", "--tiles: 70000 is out of range", NULL);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pits_arguments),
        cmocka_unit_test(test_damaged_planet_json),
        cmocka_unit_test(test_uncalibratable_relief),
        cmocka_unit_test(test_command_arguments),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
