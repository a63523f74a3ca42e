/* test_mpi_pits.c - the distributed Barnes (2016) depression fill (pg_mpi_pits_fill)
 * gives, on every rank's tiles, exactly the serial fill of pg_pits_remove, for 1, 2
 * and 4 ranks and tiles of several sizes, on a cube-sphere DEM full of pits: the plain
 * fill, with epsilon the minimal epsilon-surface (reached in rounds of ring
 * exchanges, which must take more than one round on these DEMs), breach and hybrid
 * along the descent tree (rounds of tokens), and the depression statistics
 * (pg_mpi_pits_stats: the same counts as pg_pits_stats_compute), also with every
 * global id above 2^32.
 *
 * The test program is its own MPI worker: the cmocka tests run
 * `mpirun -np N THIS --worker n T seed eps`; each rank builds the same DEM, fills it both
 * ways and counts differing cells in its tiles; rank 0 prints the totals and the worker
 * exits 0 only when nothing differs and the fill raised cells (so the DEM had pits).
 * Under ASan the workers run without LeakSanitizer, as in test_mpi_generate.c: OpenMPI
 * leaves allocations behind in components it has unloaded. */
#include "pg_test.h"

#include "planetgen/pg_mpi.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *self;
static char out[8192];

/* Rolling terrain with hashed noise: an ocean below 0, many closed pits above. Seeds
 * from 100 on: the same terraced in steps of 60 m, whose flats give the descent tree
 * many ties of W that only the global ids decide. */
static float dem(uint32_t id, uint32_t n, uint32_t seed) {
    uint32_t per = n * n, f = id / per, y = id % per / n, x = id % n;
    uint32_t z = (id + 1) * 2654435761u ^ seed * 2246822519u;
    z ^= z >> 15, z *= 2246822519u, z ^= z >> 13;
    double s = 600.0 * sin(0.21 * x + f) * cos(0.17 * y - 0.5 * f) + 150.0 * f - 200.0;
    s += (double)(z % 1000) * 0.4;
    return (float)(seed >= 100 ? floor(s / 60.0) * 60.0 : s);
}

/* The distributed DEM as generate hands it over: each rank's own tiles hold the heights;
 * the cells of other ranks hold nothing the functions may use (they exchange their
 * rings themselves). Natively those cells get poison (NaN, sea and mountain values):
 * the results must not change. Under valgrind (PG_EXEC_WRAPPER set by
 * scripts/valgrind-suite) they stay undefined, so memcheck reports any read of them. */
static void fill_owned(pg_mpi *m, float *h, uint32_t n, int T, uint32_t seed) {
    const int nt = 6 * T * T, P = pg_mpi_size(m), me = pg_mpi_rank(m);
    const uint32_t ts = n / (uint32_t)T, per = n * n;
    const int t0 = pg_mpi_tile_first(nt, P, me), t1 = pg_mpi_tile_first(nt, P, me + 1);
    const char *w = getenv("PG_EXEC_WRAPPER");
    const int poison = !(w && *w);
    static const float bad[] = {NAN, -1e6f, 9e3f, -INFINITY};
    for (uint32_t id = 0; id < 6 * per; id++) {
        uint32_t f = id / per, y = id % per / n, x = id % n;
        int t = (int)(f * (uint32_t)(T * T) + y / ts * (uint32_t)T + x / ts);
        if (t >= t0 && t < t1)
            h[id] = dem(id, n, seed);
        else if (poison)
            h[id] = bad[id % 4];
    }
}

/* mode 0: plain fill, 1: fill with epsilon, 2: breach, 3: hybrid (descent tree, epsilon) */
static int worker(uint32_t n, int T, uint32_t seed, int mode) {
    pg_mpi *m = NULL;
    pg_error err = {0};
    if (pg_mpi_init(&m, &err)) {
        fprintf(stderr, "worker: %s\n", err.msg);
        return 2;
    }
    const size_t nc = (size_t)6 * n * n;
    float *h = malloc(nc * sizeof *h), *ref = malloc(nc * sizeof *ref);
    for (size_t i = 0; i < nc; i++)
        ref[i] = dem((uint32_t)i, n, seed);
    fill_owned(m, h, n, T, seed);
    pg_pits_topo topo;
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    const pg_pits_method methods[] = {PG_PITS_FILL, PG_PITS_FILL, PG_PITS_BREACH, PG_PITS_HYBRID};
    o.method = methods[mode];
    o.epsilon = mode > 0;
    o.descent = mode >= 2;
    o.max_depth = 150; /* hybrid: some channels too deep, some too long */
    o.max_length = 6;
    o.has_sea_level = true;
    o.sea_level = 0;
    pg_mpi_pits_info info = {0};
    int rc = pg_pits_topo_cube(&topo, n, &err) || pg_pits_remove(&topo, ref, &o, NULL, &err) ||
             pg_mpi_pits_remove(m, T, n, h, &o, &info, &err);
    if (rc) fprintf(stderr, "worker: %s\n", err.msg);
    const int nt = 6 * T * T, P = pg_mpi_size(m), me = pg_mpi_rank(m);
    const uint32_t ts = n / (uint32_t)T;
    double diff = 0, raised = 0, lowered = 0;
    for (int t = pg_mpi_tile_first(nt, P, me); !rc && t < pg_mpi_tile_first(nt, P, me + 1); t++)
        for (uint32_t y = 0; y < ts; y++)
            for (uint32_t x = 0; x < ts; x++) {
                uint32_t f = (uint32_t)t / (uint32_t)(T * T), tx = (uint32_t)t % (uint32_t)T,
                         ty = (uint32_t)t / (uint32_t)T % (uint32_t)T;
                uint32_t id = f * n * n + (ty * ts + y) * n + tx * ts + x;
                diff += memcmp(&h[id], &ref[id], sizeof(float)) != 0;
                raised += ref[id] > dem(id, n, seed);
                lowered += ref[id] < dem(id, n, seed);
            }
    rc = pg_mpi_max_int(m, rc);
    diff = pg_mpi_sum_double(m, diff);
    raised = pg_mpi_sum_double(m, raised);
    lowered = pg_mpi_sum_double(m, lowered);
    double labels = info.labels;
    if (me == 0)
        printf("ranks %d tiles %d mode %d: differing cells %.0f, raised cells %.0f, lowered "
               "cells %.0f, labels %.0f, epsilon rounds %d, breach rounds %d, max label %llu\n",
               P, nt, mode, diff, raised, lowered, labels, info.eps_rounds, info.breach_rounds,
               (unsigned long long)info.max_label);
    /* the depression statistics of the original DEM, serial and distributed */
    int stats_ok = 1;
    if (mode == 0 && !rc) {
        for (size_t i = 0; i < nc; i++)
            ref[i] = dem((uint32_t)i, n, seed);
        fill_owned(m, h, n, T, seed);
        pg_pits_stats a, b;
        pg_pits_area area = {.constant = 2.5};
        rc = pg_pits_stats_compute(&topo, ref, &o, &area, &a, &err) ||
             pg_mpi_pits_stats(m, T, n, h, &o, &area, &b, &err);
        rc = pg_mpi_max_int(m, rc);
        stats_ok =
            !rc && a.depressions == b.depressions && a.depressions > 0 &&
            a.depression_cells == b.depression_cells && a.max_depth_m == b.max_depth_m &&
            a.sinks == b.sinks &&
            fabs(a.depression_volume_m3 - b.depression_volume_m3) <= 1e-9 * a.depression_volume_m3;
        if (me == 0)
            printf("stats: serial %llu depressions %llu cells deepest %.4f volume %.6g, "
                   "distributed %llu %llu %.4f %.6g sinks %llu %llu: %s\n",
                   (unsigned long long)a.depressions, (unsigned long long)a.depression_cells,
                   a.max_depth_m, a.depression_volume_m3, (unsigned long long)b.depressions,
                   (unsigned long long)b.depression_cells, b.max_depth_m, b.depression_volume_m3,
                   (unsigned long long)a.sinks, (unsigned long long)b.sinks,
                   stats_ok ? "same" : "DIFFERENT");
    }
    /* the statistics of the breached result: no depression, found by the certificate
     * in every rank (pg_mpi_pits_stats), by the search in the single process */
    if (mode == 2 && !rc) {
        pg_pits_stats a, b;
        pg_pits_area area = {.constant = 2.5};
        rc = pg_pits_stats_compute(&topo, ref, &o, &area, &a, &err) ||
             pg_mpi_pits_stats(m, T, n, h, &o, &area, &b, &err);
        rc = pg_mpi_max_int(m, rc);
        stats_ok = !rc && a.depressions == 0 && b.depressions == 0 && b.depression_cells == 0 &&
                   b.max_depth_m == 0 && b.depression_volume_m3 == 0 && a.sinks == b.sinks &&
                   b.sinks > 0;
        if (me == 0)
            printf("stats after breach: serial %llu depressions %llu sinks, distributed %llu "
                   "%llu: %s\n",
                   (unsigned long long)a.depressions, (unsigned long long)a.sinks,
                   (unsigned long long)b.depressions, (unsigned long long)b.sinks,
                   stats_ok ? "same" : "DIFFERENT");
    }
    free(h), free(ref);
    pg_mpi_finalize(m);
    return rc ? 2 : (diff == 0 && raised + lowered > 0 && stats_ok ? 0 : 1);
}

/* Under scripts/valgrind-suite every rank runs under memcheck too (PG_EXEC_WRAPPER). */
static int run_workers(int np, uint32_t n, int T, uint32_t seed, int mode, const char *env) {
    char cmd[4096], outp[256];
    const char *wrap = getenv("PG_EXEC_WRAPPER");
    snprintf(outp, sizeof outp, "/tmp/pg_mpi_pits.%d", (int)getpid());
    snprintf(cmd, sizeof cmd,
             "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 mpirun --oversubscribe -np %d -x "
             "OMP_NUM_THREADS=1 %s %s '%s' --worker %u %d %u %d >%s "
             "2>&1 </dev/null",
             np, env, wrap && *wrap ? wrap : "", self, n, T, seed, mode, outp);
    int st = system(cmd);
    FILE *f = fopen(outp, "r");
    size_t k = f ? fread(out, 1, sizeof out - 1, f) : 0;
    out[k] = 0;
    if (f) fclose(f);
    unlink(outp);
    return st == -1 || !WIFEXITED(st) ? -1 : WEXITSTATUS(st);
}

/* min_rounds 3: round 2 changed cells (ring values from round 1 mattered), round 3
 * confirmed; one round alone would have left those cells wrong. The same for the
 * breach's token rounds. */
static void expect_same_env(int np, uint32_t n, int T, uint32_t seed, int min_rounds,
                            const char *env) {
    static const char *names[] = {"fill", "fill eps", "breach", "hybrid"};
    for (int mode = 0; mode < 4; mode++) {
        int rc = run_workers(np, n, T, seed, mode, env);
        if (rc != 0 || !strstr(out, "differing cells 0"))
            fail_msg("mpirun -np %d, n %u, T %d, %s %s: exit %d: %s", np, n, T, names[mode], env,
                     rc, out);
        const char *ml = strstr(out, "max label ");
        if (*env && (!ml || strtoull(ml + 10, NULL, 10) <= 0xFFFFFFFFull))
            fail_msg("%s: the labels stayed below 2^32: %s", env, out);
        print_message("%s", out);
        const char *r = strstr(out, mode >= 2 ? "breach rounds " : "epsilon rounds ");
        if (mode && (!r || atoi(r + (mode >= 2 ? 14 : 15)) < min_rounds))
            fail_msg("mpirun -np %d, %s: expected %d rounds at least: %s", np, names[mode],
                     min_rounds, out);
    }
}

static void expect_same(int np, uint32_t n, int T, uint32_t seed, int min_rounds) {
    expect_same_env(np, n, T, seed, min_rounds, "");
}

static void test_one_rank(void **state) {
    (void)state;
    expect_same(1, 48, 3, 1, 1);
}

static void test_two_ranks(void **state) {
    (void)state;
    expect_same(2, 48, 3, 2, 1);
    expect_same(2, 64, 1, 3, 1); /* whole faces as tiles: only seam pairs cross */
}

static void test_four_ranks(void **state) {
    (void)state;
    expect_same(4, 64, 4, 4, 3);
    expect_same(4, 32, 8, 5, 3); /* tiles of 4 x 4 texels: most cells on a perimeter */
}

/* 64-bit global ids (docs/mpi.md, "Pit removal across ranks"): terraced planets (flats:
 * many ties that the ids decide) with every global cell id moved above 2^32
 * (pg_mpi_testing.h) give the serial bits and counts. First a base that makes the ids
 * cross 2^32 inside the planet (a tie-break cut to 32 bits flips there: 18 cells
 * differ), then ids B + 2^32 c: cut to 32 bits they would all be B mod 2^32, so a
 * truncated label, tie-break id, ring parent or cross-rank label pair merges them
 * (labels: 208 cells differ; region labels: 176 depressions instead of 175). */
static void test_ids_above_2_32(void **state) {
    (void)state;
    expect_same_env(2, 48, 3, 102, 1, "-x PG_MPI_TEST_ID_BASE=4294960000");
    expect_same_env(4, 32, 8, 105, 3, "-x PG_MPI_TEST_ID_BASE=12884914233:4294967296");
}

/* The preconditions are refused, not silently broken. */
static void test_preconditions(void **state) {
    (void)state;
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    pg_error err = {0};
    float h[6 * 4 * 4] = {0};
    pg_mpi_pits_info info = {0};
    o.method = PG_PITS_BREACH;
    o.has_sea_level = true;
    assert_int_equal(pg_mpi_pits_fill(NULL, 1, 4, h, &o, &info, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "fill method"));
    /* a rank whose cells exceed its 32-bit local ids is refused before anything is
     * allocated or read (h is not even a planet here): 6 x 65536^2 cells on one rank */
    o.method = PG_PITS_FILL;
    err = (pg_error){0};
    assert_int_equal(pg_mpi_pits_fill(NULL, 64, 65536, h, &o, &info, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "local ids of one rank: use more ranks"));
    o.method = PG_PITS_BREACH, o.descent = true, o.epsilon = true;
    err = (pg_error){0};
    assert_int_equal(pg_mpi_pits_remove(NULL, 64, 65536, h, &o, &info, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "25769803776 cells"));
}

static int setup(void **state) {
    (void)state;
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    return 0;
}

int main(int argc, char **argv) {
    if (argc == 6 && !strcmp(argv[1], "--worker"))
        return worker((uint32_t)atoi(argv[2]), atoi(argv[3]), (uint32_t)atoi(argv[4]),
                      atoi(argv[5]));
    self = argv[0];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_preconditions),  cmocka_unit_test(test_one_rank),
        cmocka_unit_test(test_two_ranks),      cmocka_unit_test(test_four_ranks),
        cmocka_unit_test(test_ids_above_2_32),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
