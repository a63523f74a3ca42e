/* test_install.c - the installed library is usable without the source tree: `cmake
 * --install` of this build into a fresh prefix gives libplanetgen.a, the public headers
 * (each compiles on its own, none of the library-internal ones is there), the CLI and
 * planetgen.pc; examples/generate_small.c, compiled with nothing but
 * `cc $(pkg-config --cflags --libs planetgen)`, runs and writes a planet that loads and
 * has land and sea (examples/README.md). */
#include "pg_test.h"

#include "planetgen/pg_planet.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdarg.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char scratch[2048], prefix[2100], pcdir[2200], out[16384];

/* Run a shell command, capturing stdout and stderr into out; the exit code, or -1. */
static int sh(const char *fmt, ...) {
    char cmd[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    char full[8400];
    snprintf(full, sizeof full, "( %s ) 2>&1", cmd);
    FILE *p = popen(full, "r");
    if (!p) return -1;
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = '\0';
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int exists(const char *dir, const char *name) {
    char path[8192];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    struct stat s;
    return stat(path, &s) == 0;
}

/* Install once, into build/test-scratch/install/prefix; find its pkgconfig directory. */
static int install(void **state) {
    (void)state;
    pg_test_scratch_dir("install", scratch, sizeof scratch);
    snprintf(prefix, sizeof prefix, "%s/prefix", scratch);
    if (sh("cmake --install '%s' --prefix '%s'", getenv("PG_BUILD_DIR"), prefix) != 0) {
        fprintf(stderr, "cmake --install failed:\n%s\n", out);
        return -1;
    }
    const char *libdirs[] = {"lib", "lib64", "lib/x86_64-linux-gnu"};
    for (int i = 0; i < 3; i++) {
        snprintf(pcdir, sizeof pcdir, "%s/%s/pkgconfig", prefix, libdirs[i]);
        if (exists(pcdir, "planetgen.pc")) return 0;
    }
    fprintf(stderr, "no planetgen.pc under %s\n", prefix);
    return -1;
}

static void test_installed_tree(void **state) {
    (void)state;
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/..", pcdir);
    assert_true(exists(dir, "libplanetgen.a"));
    snprintf(dir, sizeof dir, "%s/bin", prefix);
    assert_true(exists(dir, "planetgen"));
    assert_int_equal(sh("'%s/bin/planetgen' --version", prefix), 0);
    snprintf(dir, sizeof dir, "%s/include/planetgen", prefix);
    assert_true(exists(dir, "planetgen.h"));
    /* exactly the public headers: the same names as the source's include/planetgen */
    assert_int_equal(sh("cd '%s/include/planetgen' && ls *.h | sort > /tmp/pg_inst_%d && "
                        "cd '%s/include/planetgen' && ls *.h | sort | diff - /tmp/pg_inst_%d; "
                        "r=$?; rm -f /tmp/pg_inst_%d; exit $r",
                        prefix, (int)getpid(), pg_test_source_dir(), (int)getpid(), (int)getpid()),
                     0);
    assert_false(exists(dir, "pg_planet_meta.h"));
    assert_false(exists(dir, "pg_planet_synth_testing.h"));
    /* no test knob reaches the installed API */
    assert_int_equal(sh("grep -rl 'independent_tiles\\|PG_MPI_TEST' '%s/include'", prefix), 1);
}

/* Every installed header compiles alone, as strict C11, with only the prefix on the
 * include path: none depends on the source tree or on being included after another. */
static void test_headers_standalone(void **state) {
    (void)state;
    int rc = sh("for h in '%s'/include/planetgen/*.h; do "
                "  printf '#include <planetgen/%%s>\\n' \"$(basename \"$h\")\" | "
                "  cc -std=c11 -Wall -Wextra -Werror -fsyntax-only -I'%s/include' -x c - "
                "  || { echo \"$h\"; exit 1; }; "
                "done",
                prefix, prefix);
    if (rc != 0) fail_msg("a header does not compile alone:\n%s", out);
}

/* Share of the planet's texels above its sea level. */
static double land_share(const pg_planet *p, float *lo, float *hi) {
    size_t nn = (size_t)p->n * (size_t)p->n, land = 0;
    *lo = INFINITY, *hi = -INFINITY;
    for (int f = 0; f < 6; f++)
        for (size_t i = 0; i < nn; i++) {
            float h = p->height[f][i];
            assert_true(isfinite(h));
            land += h > p->sea_level;
            if (h < *lo) *lo = h;
            if (h > *hi) *hi = h;
        }
    return (double)land / (6.0 * (double)nn);
}

static void test_example(void **state) {
    (void)state;
    const char *src = pg_test_source_dir();
    int rc = sh("PKG_CONFIG_PATH='%s' pkg-config --cflags --libs planetgen", pcdir);
    if (rc != 0 || !strstr(out, "-lplanetgen")) fail_msg("pkg-config: %s", out);
    rc = sh("cc -Wall -Wextra -Werror '%s/examples/generate_small.c' -o '%s/generate_small' "
            "$(PKG_CONFIG_PATH='%s' pkg-config --cflags --libs planetgen)",
            src, scratch, pcdir);
    if (rc != 0) fail_msg("building the example against the installed library failed:\n%s", out);
    rc = sh("cd '%s' && ./generate_small planet", scratch);
    if (rc != 0) fail_msg("generate_small exited %d:\n%s", rc, out);
    print_message("%s", out);
    assert_non_null(strstr(out, "planet 6 x 2^2 x 64^2 (n = 128)"));

    char dir[4096];
    snprintf(dir, sizeof dir, "%s/planet", scratch);
    assert_true(exists(dir, "planet.json") && exists(dir, "height.exr"));
    pg_planet p = {0};
    pg_error err = {0};
    if (pg_planet_load(dir, &p, &err) != PG_OK) fail_msg("%s", err.msg);
    assert_int_equal(p.tiles, 2);
    assert_int_equal(p.tile_size, 64);
    assert_int_equal(p.n, 128);
    float lo, hi;
    double land = land_share(&p, &lo, &hi);
    print_message("loaded: land %.3f, heights %.0f to %.0f m\n", land, lo, hi);
    /* an Earth-like planet: both land and sea, and relief on each */
    assert_true(land > 0.05 && land < 0.95);
    assert_true(lo < p.sea_level - 500.0f && hi > p.sea_level + 500.0f);
    /* the albedo is an image, not a constant */
    float amin = 1, amax = 0;
    for (size_t i = 0; i < (size_t)p.n * p.n * 3; i++) {
        float a = p.albedo[0][i];
        assert_true(a >= 0.0f && a <= 1.0f);
        if (a < amin) amin = a;
        if (a > amax) amax = a;
    }
    assert_true(amax - amin > 0.1f);
    pg_planet_free(&p);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_installed_tree),
        cmocka_unit_test(test_headers_standalone),
        cmocka_unit_test(test_example),
    };
    return cmocka_run_group_tests(tests, install, NULL);
}
