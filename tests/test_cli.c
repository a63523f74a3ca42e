/* test_cli.c - the planetgen command line as a user meets it: help, version, exit
 * codes, and every bad input of the foundation issue. Each bad input must give
 * exit 2, exactly one line on stderr naming the file or option, and no files. */
#include "pg_marble.h"
#include "pg_test.h"

#include "planetgen/pg_exemplar.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char g_dir[1024]; /* scratch dir with the bad inputs */

static int count_lines(const char *s) {
    int n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

static void write_exr_with(const char *name, float bad) {
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", g_dir, name);
    pg_image img;
    pg_error err = {0};
    assert_int_equal(pg_image_alloc(&img, 64, 32, 1, &err), PG_OK);
    for (int i = 0; i < 64 * 32; i++)
        img.data[i] = (float)(i % 100) * 10.0f - 500.0f;
    img.data[5 * 64 + 7] = bad;
    assert_int_equal(pg_image_write_exr(path, &img, NULL, &err), PG_OK);
    pg_image_free(&img);
}

static int setup(void **state) {
    (void)state;
    pg_test_scratch_dir("cli_bad", g_dir, sizeof g_dir);
    const char *bm = PG_MARBLE_ALBEDO;
    char cmd[4096];
    snprintf(cmd, sizeof cmd,
             "cd '%s' && head -c 150000 '%s' > trunc.jpg && oiiotool '%s' -o full.png && "
             "head -c 300000 full.png > trunc.png && oiiotool '%s' -o full.tif && "
             "head -c 300000 full.tif > trunc.tif && echo 'not an image' > text.png && "
             ": > empty.jpg && mkdir -p adir && oiiotool --create 1x1 3 -o one.png && "
             "oiiotool --create 300x200 3 -o notglobal.png",
             g_dir, bm, bm, bm);
    return system(cmd) == 0 ? 0 : -1;
}

/* Run `planetgen ARGS` expecting a one-line usage/bad-input error mentioning `needle`
 * and no output directory left behind. */
static void expect_bad(const char *args, const char *needle) {
    char out[8192], err[8192], full[4096], outdir[1200];
    snprintf(outdir, sizeof outdir, "%s/out_should_not_exist", g_dir);
    snprintf(full, sizeof full, "%s -o '%s'", args, outdir);
    int rc = pg_test_run_cli(full, out, sizeof out, err, sizeof err);
    print_message("planetgen %s\n  -> rc=%d: %s", args, rc, err);
    assert_int_equal(rc, 2);
    assert_int_equal(count_lines(err), 1);
    assert_non_null(strstr(err, needle));
    struct stat st;
    assert_int_not_equal(stat(outdir, &st), 0);
}

static void test_help_version(void **s) {
    (void)s;
    char out[8192], err[8192];
    assert_int_equal(pg_test_run_cli("--version", out, sizeof out, err, sizeof err), 0);
    assert_non_null(strstr(out, "planetgen "));
    assert_int_equal(pg_test_run_cli("--help", out, sizeof out, err, sizeof err), 0);
    assert_non_null(strstr(out, "exemplar"));
    assert_int_equal(pg_test_run_cli("help exemplar", out, sizeof out, err, sizeof err), 0);
    assert_non_null(strstr(out, "--albedo"));
    assert_int_equal(pg_test_run_cli("exemplar --help", out, sizeof out, err, sizeof err), 0);
    assert_non_null(strstr(out, "--height-scale"));
    assert_int_equal(pg_test_run_cli("frobnicate", out, sizeof out, err, sizeof err), 2);
    assert_non_null(strstr(err, "frobnicate"));
    assert_int_equal(pg_test_run_cli("", out, sizeof out, err, sizeof err), 2);
    assert_int_equal(pg_test_run_cli("help frobnicate", out, sizeof out, err, sizeof err), 2);
}

static void test_bad_files(void **s) {
    (void)s;
    char a[2048];
#define BAD(fmt, file, needle)                                                                     \
    do {                                                                                           \
        snprintf(a, sizeof a, fmt, g_dir, file);                                                   \
        expect_bad(a, needle);                                                                     \
    } while (0)
    BAD("exemplar --albedo '%s/%s'", "missing.jpg", "missing.jpg: No such file");
    BAD("exemplar --albedo '%s/%s'", "adir", "adir: is a directory");
    BAD("exemplar --albedo '%s/%s'", "empty.jpg", "empty.jpg: empty file");
    BAD("exemplar --albedo '%s/%s'", "trunc.jpg", "trunc.jpg: corrupt or truncated");
    BAD("exemplar --albedo '%s/%s'", "trunc.png", "trunc.png: corrupt or truncated PNG");
    BAD("exemplar --albedo '%s/%s'", "trunc.tif", "trunc.tif");
    BAD("exemplar --albedo '%s/%s'", "text.png", "text.png: not a readable image");
    BAD("exemplar --albedo '%s/%s'", "one.png", "one.png: 1x1 is too small");
    BAD("exemplar --albedo '%s/%s'", "notglobal.png", "notglobal.png: 300x200 is not 2:1");
    BAD("exemplar --height '%s/%s'", "trunc.png", "trunc.png");
    BAD("exemplar --height '%s/%s'", "notglobal.png", "is not 2:1");
#undef BAD
}

static void test_nan_inf_heights(void **s) {
    (void)s;
    write_exr_with("nan.exr", NAN);
    write_exr_with("inf.exr", INFINITY);
    char a[2048];
    snprintf(a, sizeof a, "exemplar --height '%s/nan.exr'", g_dir);
    expect_bad(a, "nan.exr: NaN value at pixel (7, 5)");
    snprintf(a, sizeof a, "exemplar --height '%s/inf.exr'", g_dir);
    expect_bad(a, "inf.exr: infinite value at pixel (7, 5)");
}

static void test_bad_options(void **s) {
    (void)s;
    expect_bad("exemplar --frobnicate", "unknown option '--frobnicate'");
    expect_bad("exemplar --sea-level 99999", "--sea-level: 99999 is out of range");
    expect_bad("exemplar --sea-level abc", "--sea-level: 'abc' is not a finite number");
    expect_bad("exemplar --sea-level nan", "--sea-level: 'nan' is not a finite number");
    expect_bad("exemplar --grid-width 3", "--grid-width: 3 is out of range");
    expect_bad("exemplar --threads -1", "--threads: -1 is out of range");
    expect_bad("exemplar --albedo", "--albedo needs a value");
    expect_bad("exemplar stray", "unexpected argument 'stray'");
    expect_bad("exemplar --json /nonexistent-dir/x.json", "--json /nonexistent-dir/x.json");
}

/* The real job: previews and a JSON report, and nothing else, in the output dir. */
static void test_exemplar_success(void **s) {
    (void)s;
    char dir[1024], args[4096], out[8192], err[8192], p[1200];
    pg_test_scratch_dir("cli_ok", dir, sizeof dir);
    snprintf(args, sizeof args, "exemplar -o '%s/out' --json '%s/report.json'", dir, dir);
    assert_int_equal(pg_test_run_cli(args, out, sizeof out, err, sizeof err), 0);
    assert_non_null(strstr(out, "land fraction"));
    snprintf(p, sizeof p, "%s/out/albedo.png", dir);
    assert_true(pg_test_file_nonempty(p));
    snprintf(p, sizeof p, "%s/out/relief.png", dir);
    assert_true(pg_test_file_nonempty(p));
    snprintf(p, sizeof p, "%s/out", dir);
    assert_int_equal(pg_test_count_files(p), 2); /* no temp files left over */
    snprintf(p, sizeof p, "%s/report.json", dir);
    FILE *f = fopen(p, "r");
    assert_non_null(f);
    char js[16384];
    size_t n = fread(js, 1, sizeof js - 1, f);
    js[n] = '\0';
    fclose(f);
    const char *keys[] = {"\"inputs\"",  "\"parameters\"",     "\"stages\"",
                          "\"seconds\"", "\"peak_rss_bytes\"", "\"land_fraction\""};
    for (size_t i = 0; i < sizeof keys / sizeof *keys; i++)
        assert_non_null(strstr(js, keys[i]));
    /* a bare --json file name is written in the working directory */
    snprintf(args, sizeof args, "exemplar -q -o '%s/out4' --json rel.json", dir);
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "cd '%s' && '%s' %s", dir, pg_test_cli(), args);
    assert_int_equal(system(cmd), 0);
    snprintf(p, sizeof p, "%s/rel.json", dir);
    assert_true(pg_test_file_nonempty(p));
    /* --quiet silences stdout and the stage lines */
    snprintf(args, sizeof args, "exemplar -q -o '%s/out2'", dir);
    assert_int_equal(pg_test_run_cli(args, out, sizeof out, err, sizeof err), 0);
    assert_string_equal(out, "");
    assert_string_equal(err, "");
    /* without a terminal, progress is one line per stage */
    snprintf(args, sizeof args, "exemplar -o '%s/out3'", dir);
    assert_int_equal(pg_test_run_cli(args, out, sizeof out, err, sizeof err), 0);
    assert_non_null(strstr(err, "load exemplar done in"));
    assert_int_equal(count_lines(err), 2);
}

/* Grey albedo becomes RGB; an alpha channel is ignored with a note. */
static void test_grey_and_alpha_albedo(void **s) {
    (void)s;
    char dir[1024], cmd[4096], out[8192], err[8192];
    pg_test_scratch_dir("cli_channels", dir, sizeof dir);
    snprintf(cmd, sizeof cmd,
             "cd '%s' && oiiotool --pattern checker:width=8:height=8 64x32 1 -o grey.png", dir);
    assert_int_equal(system(cmd), 0);
    pg_image rgba;
    pg_error e = {0};
    assert_int_equal(pg_image_alloc(&rgba, 64, 32, 4, &e), PG_OK);
    for (int i = 0; i < 64 * 32; i++) {
        rgba.data[4 * i] = 0.2f, rgba.data[4 * i + 1] = 0.3f;
        rgba.data[4 * i + 2] = 0.5f, rgba.data[4 * i + 3] = 0.7f; /* unassociated */
    }
    char p[1200];
    snprintf(p, sizeof p, "%s/rgba.png", dir);
    assert_int_equal(pg_image_write_png(p, &rgba, 8, &e), PG_OK);
    pg_image_free(&rgba);
    /* --height-scale skips the calibration, which needs Blue Marble's water */
    snprintf(cmd, sizeof cmd, "exemplar --albedo '%s/grey.png' --height-scale 30 -o '%s/o1'", dir,
             dir);
    assert_int_equal(pg_test_run_cli(cmd, out, sizeof out, err, sizeof err), 0);
    snprintf(p, sizeof p, "%s/o1/albedo.png", dir);
    pg_image img;
    assert_int_equal(pg_image_read(p, 0, &img, &e), PG_OK);
    assert_int_equal(img.channels, 3); /* grey became RGB */
    for (int i = 0; i < img.width * img.height; i++) {
        assert_float_equal(img.data[3 * i], img.data[3 * i + 1], 0);
        assert_float_equal(img.data[3 * i], img.data[3 * i + 2], 0);
    }
    pg_image_free(&img);
    snprintf(cmd, sizeof cmd, "exemplar --albedo '%s/rgba.png' --height-scale 30 -o '%s/o2'", dir,
             dir);
    assert_int_equal(pg_test_run_cli(cmd, out, sizeof out, err, sizeof err), 0);
    assert_non_null(strstr(out, "alpha/extra channels ignored"));
    snprintf(p, sizeof p, "%s/o2/albedo.png", dir);
    assert_int_equal(pg_image_read(p, 0, &img, &e), PG_OK);
    assert_int_equal(img.channels, 3);
    /* the colour is kept as it is, not multiplied by alpha 0.7 */
    assert_float_equal(img.data[2] * img.unit_scale, 0.5, 1.0 / 255);
    pg_image_free(&img);
}

/* Does dir contain a staged temporary file yet? */
static int has_tmp_file(const char *dir) {
    DIR *d = opendir(dir);
    if (!d) return 0;
    struct dirent *e;
    int found = 0;
    while ((e = readdir(d)))
        if (strncmp(e->d_name, ".tmp-", 5) == 0) found = 1;
    closedir(d);
    return found;
}

/* SIGTERM / SIGINT while outputs are being written: non-zero exit, nothing left. */
static void interrupt_mid_write(int sig) {
    char dir[1024], out[1200];
    pg_test_scratch_dir(sig == SIGTERM ? "cli_sigterm" : "cli_sigint", dir, sizeof dir);
    snprintf(out, sizeof out, "%s/out", dir);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        /* a big grid makes the preview stage take seconds */
        execl(pg_test_cli(), "planetgen", "exemplar", "--grid-width", "10800", "-q", "-o", out,
              (char *)NULL);
        _exit(127);
    }
    /* Loading reaches the previews in seconds; under valgrind (scripts/valgrind-suite sets
     * PG_CLI_WRAPPER) it takes minutes, more on a loaded machine. */
    int waited_ms = 0, limit_ms = getenv("PG_CLI_WRAPPER") ? 1800000 : 120000;
    while (!has_tmp_file(out) && waited_ms < limit_ms) {
        struct timespec ts = {0, 20 * 1000 * 1000};
        nanosleep(&ts, NULL);
        waited_ms += 20;
    }
    assert_true(has_tmp_file(out)); /* we really interrupt a write in progress */
    kill(pid, sig);
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 128 + sig);
    struct stat st;
    assert_int_not_equal(stat(out, &st), 0); /* the dir we created is gone, and empty */
}

static void test_sigterm_leaves_nothing(void **s) {
    (void)s;
    interrupt_mid_write(SIGTERM);
}

static void test_sigint_leaves_nothing(void **s) {
    (void)s;
    interrupt_mid_write(SIGINT);
}

/* A full disk, emulated with a file-size limit: exit 1, one line, nothing left. */
static void test_full_disk(void **s) {
    (void)s;
    char dir[1024], cmd[4096], errp[1200], err[4096] = {0};
    pg_test_scratch_dir("cli_fulldisk", dir, sizeof dir);
    snprintf(errp, sizeof errp, "%s/stderr.txt", dir);
    snprintf(cmd, sizeof cmd, "ulimit -f 500; '%s' exemplar -q -o '%s/out' 2>'%s'", pg_test_cli(),
             dir, errp);
    int st = system(cmd);
    assert_true(WIFEXITED(st));
    assert_int_equal(WEXITSTATUS(st), 1);
    FILE *f = fopen(errp, "r");
    assert_non_null(f);
    size_t n = fread(err, 1, sizeof err - 1, f);
    err[n] = '\0';
    fclose(f);
    print_message("%s", err);
    assert_int_equal(count_lines(err), 1);
    assert_non_null(strstr(err, "albedo.png: write failed"));
    assert_null(strstr(err, ".tmp-")); /* the user is told the final name */
    char out[1200];
    snprintf(out, sizeof out, "%s/out", dir);
    struct stat sb;
    assert_int_not_equal(stat(out, &sb), 0);
}

/* An output path that cannot be created: bad input, exit 2, one line. */
static void test_unwritable_output(void **s) {
    (void)s;
    char out[8192], err[8192];
    int rc = pg_test_run_cli("exemplar -o /proc/planetgen-out", out, sizeof out, err, sizeof err);
    assert_int_equal(rc, 2);
    assert_int_equal(count_lines(err), 1);
    assert_non_null(strstr(err, "-o /proc/planetgen-out"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_help_version),          cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_nan_inf_heights),       cmocka_unit_test(test_bad_options),
        cmocka_unit_test(test_exemplar_success),      cmocka_unit_test(test_sigterm_leaves_nothing),
        cmocka_unit_test(test_sigint_leaves_nothing), cmocka_unit_test(test_full_disk),
        cmocka_unit_test(test_unwritable_output),     cmocka_unit_test(test_grey_and_alpha_albedo),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
