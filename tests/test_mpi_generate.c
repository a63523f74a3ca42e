/* test_mpi_generate.c - `mpirun -np N planetgen generate` (docs/mpi.md) end to end: the
 * tiled output of 1, 2 and 4 ranks is byte for byte the single-process tiled output
 * (default pits, --pits off, other final pit methods, --geotiff, a magnified planet with
 * --geotiff); a rank that
 * dies mid-run makes the job exit non-zero with its line and leaves no output; more
 * ranks than tiles and the single-file layout under mpirun exit 2 with one line; a memory
 * limit that one process exceeds is met by 4 ranks, each within its estimate.
 *
 * mpirun runs as root here, so the test sets OpenMPI's allow-run-as-root variables;
 * --oversubscribe lets 4 ranks share 2 cores. Each rank runs one OpenMP thread so that
 * the ranks do not fight over the cores (the results never depend on it). Under
 * AddressSanitizer the ranks run without LeakSanitizer (PG_MPI_RANK_ASAN below). */
#include "pg_test.h"

#include "planetgen/pg_mpi.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static char out[16384], err[16384];

/* Under ASan, LeakSanitizer is off in the ranks: OpenMPI leaves allocations behind at
 * exit from components it has unloaded, whose frames LSan cannot even name, so they
 * cannot be suppressed by library. ASan's and UBSan's other checks stay on; the
 * single-process runs of the same tests keep leak checking. */
#define PG_MPI_RANK_ASAN "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1"

/* Run `mpirun -np np planetgen ARGS` with extra environment `env` (NAME=V ...). */
static int run_mpi(int np, const char *env, const char *args) {
    char cmd[4096], outp[256], errp[256];
    snprintf(outp, sizeof outp, "/tmp/pg_mpi_out.%d", (int)getpid());
    snprintf(errp, sizeof errp, "/tmp/pg_mpi_err.%d", (int)getpid());
    snprintf(cmd, sizeof cmd,
             "env %s %s mpirun --oversubscribe -np %d -x OMP_NUM_THREADS=1 '%s' %s >%s 2>%s "
             "</dev/null",
             PG_MPI_RANK_ASAN, env ? env : "", np, pg_test_cli(), args, outp, errp);
    int st = system(cmd);
    FILE *f = fopen(errp, "r");
    size_t n = f ? fread(err, 1, sizeof err - 1, f) : 0;
    err[n] = 0;
    if (f) fclose(f);
    f = fopen(outp, "r");
    n = f ? fread(out, 1, sizeof out - 1, f) : 0;
    out[n] = 0;
    if (f) fclose(f);
    unlink(outp);
    unlink(errp);
    if (st == -1 || !WIFEXITED(st)) return -1;
    return WEXITSTATUS(st);
}

static int setup(void **state) {
    (void)state;
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    return 0;
}

static long file_size(const char *p) {
    FILE *f = fopen(p, "rb");
    if (!f) return -1;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fclose(f);
    return n;
}

static int same_bytes(const char *a, const char *b) {
    long n = file_size(a);
    if (n < 0 || n != file_size(b)) return 0;
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    int same = fa && fb;
    char ba[65536], bb[65536];
    size_t k;
    while (same && (k = fread(ba, 1, sizeof ba, fa)) > 0)
        same = fread(bb, 1, k, fb) == k && !memcmp(ba, bb, k);
    if (fa) fclose(fa);
    if (fb) fclose(fb);
    return same;
}

/* Every file of `ref` is in `dir` with the same bytes, and dir has no other file. */
static void expect_same_dir(const char *ref, const char *dir) {
    DIR *d = opendir(ref);
    assert_non_null(d);
    struct dirent *e;
    int n = 0;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        char a[1024], b[1024];
        snprintf(a, sizeof a, "%s/%s", ref, e->d_name);
        snprintf(b, sizeof b, "%s/%s", dir, e->d_name);
        if (!same_bytes(a, b)) fail_msg("%s differs from %s", b, a);
        n++;
    }
    closedir(d);
    assert_int_equal(pg_test_count_files(dir), n);
}

/* The number after "key": in the JSON report `path` (NaN when absent). */
static double report_number(const char *path, const char *key) {
    static char text[1 << 16];
    FILE *f = fopen(path, "r");
    size_t n = f ? fread(text, 1, sizeof text - 1, f) : 0;
    if (f) fclose(f);
    text[n] = 0;
    return n ? pg_test_json_number(text, key) : NAN;
}

/* Single-process tiled run of `opts` into dir/ref, then mpirun with each rank count
 * into dir/npN, each compared byte for byte, and the report's planet-wide figures
 * (summed over the ranks) equal to the single process's. */
static void expect_identical(const char *tag, const char *opts, const int *nps, int nnp) {
    char dir[512], args[2048], ref[700], got[700];
    pg_test_scratch_dir(tag, dir, sizeof dir);
    snprintf(ref, sizeof ref, "%s/ref", dir);
    snprintf(args, sizeof args,
             "generate -q --output-layout tiled --cache-dir %s/synth-cache %s -o %s --json %s.json",
             getenv("PG_BUILD_DIR"), opts, ref, ref);
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("single process: exit %d: %s", rc, err);
    /* 6 T^2 tiles, two files each, and the index */
    char idx[800];
    snprintf(idx, sizeof idx, "%s/index.json", ref);
    assert_true(pg_test_file_nonempty(idx));
    for (int i = 0; i < nnp; i++) {
        snprintf(got, sizeof got, "%s/np%d", dir, nps[i]);
        snprintf(args, sizeof args,
                 "generate -q --output-layout tiled --cache-dir %s/synth-cache %s -o %s --json "
                 "%s.json",
                 getenv("PG_BUILD_DIR"), opts, got, got);
        rc = run_mpi(nps[i], NULL, args);
        if (rc != 0) fail_msg("mpirun -np %d: exit %d: %s", nps[i], rc, err);
        expect_same_dir(ref, got);
        char rj[800], gj[800];
        snprintf(rj, sizeof rj, "%s.json", ref);
        snprintf(gj, sizeof gj, "%s.json", got);
        double a = report_number(rj, "allowed_type_fraction"),
               b = report_number(gj, "allowed_type_fraction");
        if (!(a == b))
            fail_msg("mpirun -np %d: allowed_type_fraction %g, one process %g", nps[i], b, a);
    }
}

/* The default planet's pipeline (Gain-pit at every level but the finest, final
 * epsilon-breach) on a small planet, for 1, 2 and 4 ranks. */
static void test_identical_default(void **state) {
    (void)state;
    const int nps[] = {1, 2, 4};
    expect_identical("mpi-default", "--tiles 2 --tile-size 32 --seed 5", nps, 3);
}

/* --pits off: nothing is gathered, each rank delivers only its tiles and their rings. */
static void test_identical_pits_off(void **state) {
    (void)state;
    const int nps[] = {2};
    expect_identical("mpi-pits-off", "--tiles 2 --tile-size 32 --seed 6 --pits off", nps, 1);
}

/* The other final pit removals give the same heights too. */
static void test_identical_final_fill_hybrid(void **state) {
    (void)state;
    const int nps[] = {2};
    expect_identical("mpi-fill", "--tiles 2 --tile-size 32 --seed 7 --final-pits fill", nps, 1);
    expect_identical("mpi-hybrid", "--tiles 2 --tile-size 32 --seed 7 --final-pits hybrid", nps, 1);
}

/* --geotiff: rank 0 reads the other ranks' tiles back and writes the GeoTIFF tiles and
 * their VRT mosaics (docs/export.md), the same bytes as one process. */
static void test_identical_geotiff(void **state) {
    (void)state;
    const int nps[] = {2};
    expect_identical("mpi-geotiff", "--tiles 2 --tile-size 32 --seed 5 --geotiff", nps, 1);
}

/* A magnified planet (N = 1024 > the exemplar's 512: the delivery reads two synthesized
 * texels beyond each tile), --pits off so that the width-2 exchange is what feeds it.
 * With --geotiff: rank 0 resamples the GeoTIFFs from the PNG tiles it reads back, one
 * process from the planet in memory, so the two agree only if the delivered albedo is
 * already what the PNGs store (the B-spline's blends quantised at delivery). */
static void test_identical_magnified(void **state) {
    (void)state;
    const int nps[] = {2};
    expect_identical("mpi-magnified",
                     "--tiles 2 --tile-size 512 --face-size 512 --seed 8 --pits off --geotiff", nps,
                     1);
}

/* Rank 1 dies at scale 2 (PG_MPI_TEST_FAIL_AT): non-zero exit, its line, and no file
 * left (no index.json above all: the directory is never presented as complete). */
static void test_rank_failure(void **state) {
    (void)state;
    char dir[512], args[2048], o[700];
    pg_test_scratch_dir("mpi-fail", dir, sizeof dir);
    snprintf(o, sizeof o, "%s/o", dir);
    snprintf(args, sizeof args,
             "generate -q --tiles 2 --tile-size 32 --cache-dir %s/synth-cache -o %s",
             getenv("PG_BUILD_DIR"), o);
    int rc = run_mpi(2, "PG_MPI_TEST_FAIL_AT=1:2", args);
    if (rc == 0) fail_msg("a dead rank gave exit 0: %s", err);
    if (!strstr(err, "rank 1: PG_MPI_TEST_FAIL_AT: simulated crash at scale 2"))
        fail_msg("no clear message: %s", err);
    char idx[800];
    snprintf(idx, sizeof idx, "%s/index.json", o);
    assert_false(pg_test_file_nonempty(idx));
    if (pg_test_count_files(o) != 0) fail_msg("%d files left in %s", pg_test_count_files(o), o);
}

static int planetgen_lines(const char *s) {
    int n = 0;
    for (const char *p = s; (p = strstr(p, "planetgen ")); p++)
        if (p == s || p[-1] == '\n') n++;
    return n;
}

static void test_bad_input(void **state) {
    (void)state;
    char dir[512], args[2048];
    pg_test_scratch_dir("mpi-bad", dir, sizeof dir);
    snprintf(args, sizeof args, "generate --tiles 1 --tile-size 32 -o %s/o", dir);
    int rc = run_mpi(7, NULL, args);
    if (rc != 2 || !strstr(err, "more ranks than the 6 tiles"))
        fail_msg("7 ranks, 6 tiles: exit %d, stderr '%s'", rc, err);
    assert_int_equal(planetgen_lines(err), 1);
    snprintf(args, sizeof args, "generate --tiles 1 --tile-size 32 --output-layout planet -o %s/o",
             dir);
    rc = run_mpi(2, NULL, args);
    if (rc != 2 || !strstr(err, "--output-layout planet"))
        fail_msg("planet layout under mpirun: exit %d, stderr '%s'", rc, err);
    assert_int_equal(planetgen_lines(err), 1);
    assert_int_equal(pg_test_count_files(dir), 0);
}

/* The first number after `key` in s (a JSON report or a message); -1 when absent. */
static double number_after(const char *s, const char *key) {
    const char *p = strstr(s, key);
    if (!p) return -1;
    p += strlen(key);
    while (*p && !(*p >= '0' && *p <= '9'))
        p++;
    return *p ? strtod(p, NULL) : -1;
}

/* The numbers of the JSON array after "key": (at most max). */
static int json_array(const char *json, const char *key, double *v, int max) {
    char k[128];
    snprintf(k, sizeof k, "\"%s\":", key);
    const char *p = strstr(json, k);
    if (!p || !(p = strchr(p, '['))) return 0;
    int n = 0;
    for (p++; n < max && *p && *p != ']';) {
        char *end;
        v[n] = strtod(p, &end);
        if (end == p) break;
        n++;
        for (p = end; *p == ',' || *p == ' ' || *p == '\n';)
            p++;
    }
    return n;
}

/* Beyond one process's memory: a limit (--max-memory) below the single-process estimate
 * refuses one process (exit 2, one line with the estimate, no output); the same planet
 * under the same limit per rank succeeds with 4 ranks, whose estimates are each below it
 * and whose measured peak private memory is below its estimate (docs/mpi.md, "Memory per
 * rank"). With a limit below one rank's share, mpirun refuses too, in one line from rank 0
 * naming the rank and its tiles. */
static void test_memory_per_rank(void **state) {
    (void)state;
    char dir[512], args[2048], o[700], json[700];
    pg_test_scratch_dir("mpi-memory", dir, sizeof dir);
    const char *planet = "--tiles 2 --tile-size 64 --seed 5 --layout free";
    snprintf(o, sizeof o, "%s/o1", dir);
    /* the single-process estimate, from the refusal line at a tiny limit */
    snprintf(args, sizeof args,
             "generate -q --output-layout tiled --cache-dir %s/synth-cache %s --max-memory 0.001 "
             "-o %s",
             getenv("PG_BUILD_DIR"), planet, o);
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    double single = number_after(err, "needs about");
    if (rc != 2 || !(single > 0)) fail_msg("tiny limit: exit %d, stderr '%s'", rc, err);
    const double limit = 0.6 * single; /* GB, below the single-process estimate */
    snprintf(args, sizeof args,
             "generate -q --output-layout tiled --cache-dir %s/synth-cache %s --max-memory %.4f "
             "-o %s",
             getenv("PG_BUILD_DIR"), planet, limit, o);
    rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 2 || !strstr(err, "--max-memory") || number_after(err, "needs about") != single)
        fail_msg("one process under %.3f GB: exit %d, stderr '%s'", limit, rc, err);
    assert_int_equal(planetgen_lines(err), 1);
    assert_int_equal(pg_test_count_files(dir), 0);
    /* 4 ranks, the same limit per rank */
    snprintf(o, sizeof o, "%s/o4", dir);
    snprintf(json, sizeof json, "%s/r4.json", dir);
    snprintf(args, sizeof args,
             "generate -q --cache-dir %s/synth-cache %s --max-memory %.4f -o %s --json %s",
             getenv("PG_BUILD_DIR"), planet, limit, o, json);
    rc = run_mpi(4, NULL, args);
    if (rc != 0) fail_msg("4 ranks under %.3f GB each: exit %d: %s", limit, rc, err);
    char idx[800];
    snprintf(idx, sizeof idx, "%s/index.json", o);
    assert_true(pg_test_file_nonempty(idx));
    static const char *const faces[6] = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};
    for (int f = 0; f < 6; f++) /* every tile's albedo and height, from its rank */
        for (int t = 0; t < 4; t++) {
            char tile[900];
            snprintf(tile, sizeof tile, "%s/albedo_%s_%d_%d.png", o, faces[f], t % 2, t / 2);
            if (!pg_test_file_nonempty(tile)) fail_msg("no %s", tile);
            snprintf(tile, sizeof tile, "%s/height_%s_%d_%d.exr", o, faces[f], t % 2, t / 2);
            if (!pg_test_file_nonempty(tile)) fail_msg("no %s", tile);
        }
    char r[65536];
    FILE *f = fopen(json, "r");
    assert_non_null(f);
    r[fread(r, 1, sizeof r - 1, f)] = 0;
    fclose(f);
    double est[4], priv[4], shared[4];
    assert_int_equal(json_array(r, "memory_estimate_bytes_per_rank", est, 4), 4);
    assert_int_equal(json_array(r, "peak_private_bytes_per_rank", priv, 4), 4);
    assert_int_equal(json_array(r, "peak_shared_bytes_per_rank", shared, 4), 4);
    for (int q = 0; q < 4; q++) {
        if (!(est[q] <= limit * 1e9 && priv[q] > 0 && priv[q] <= est[q]))
            fail_msg("rank %d: estimate %.0f MB, peak private %.0f MB, limit %.0f MB", q,
                     est[q] / 1e6, priv[q] / 1e6, limit * 1e3);
        /* the exemplar's cache file is mapped by every rank: shared, not private */
        if (!(shared[q] > 0.5 * priv[q]))
            fail_msg("rank %d: shared %.0f MB against private %.0f MB: is the exemplar shared?", q,
                     shared[q] / 1e6, priv[q] / 1e6);
    }
    /* below one rank's share: refused by rank 0 in one line naming the rank */
    const double tiny = 0.5 * est[0] / 1e9;
    snprintf(o, sizeof o, "%s/o4b", dir);
    snprintf(args, sizeof args, "generate -q --cache-dir %s/synth-cache %s --max-memory %.4f -o %s",
             getenv("PG_BUILD_DIR"), planet, tiny, o);
    rc = run_mpi(4, NULL, args);
    if (rc != 2 || !strstr(err, "mpirun -np 4, rank ") || !strstr(err, "--max-memory"))
        fail_msg("4 ranks under %.3f GB each: exit %d, stderr '%s'", tiny, rc, err);
    assert_int_equal(planetgen_lines(err), 1);
    assert_int_equal(pg_test_count_files(o), 0);
}

/* Ownership: balanced by count (blocks differ by at most one tile), contiguous in the
 * face-major order, and owner() inverts first(). */
static void test_ownership(void **state) {
    (void)state;
    for (int n = 6; n <= 6 * 16 * 16; n += 18)
        for (int P = 1; P <= 40 && P <= n; P++) {
            int lo = n, hi = 0;
            for (int q = 0; q < P; q++) {
                int a = pg_mpi_tile_first(n, P, q), b = pg_mpi_tile_first(n, P, q + 1);
                lo = b - a < lo ? b - a : lo;
                hi = b - a > hi ? b - a : hi;
                for (int t = a; t < b; t++)
                    assert_int_equal(pg_mpi_tile_owner(n, P, t), q);
            }
            assert_true(hi - lo <= 1);
            assert_int_equal(pg_mpi_tile_first(n, P, P), n);
        }
    /* 4 ranks on 6 x 2^2 tiles: 6 tiles each, so rank 0 has face +X and half of -X */
    assert_int_equal(pg_mpi_tile_first(24, 4, 1), 6);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ownership),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_identical_default),
        cmocka_unit_test(test_identical_pits_off),
        cmocka_unit_test(test_identical_final_fill_hybrid),
        cmocka_unit_test(test_identical_geotiff),
        cmocka_unit_test(test_identical_magnified),
        cmocka_unit_test(test_rank_failure),
        cmocka_unit_test(test_memory_per_rank),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
