/* bench_mpi_pits.c - memory and time of the distributed pit removal and depression
 * counts per rank (docs/mpi.md, "Pit removal across ranks"), for 1, 2 and 4 ranks on
 * one cube level, as generate's final pass meets it: each rank holds only its own
 * tiles of a planet-sized height array (an address range reserved without memory,
 * MAP_NORESERVE, of which the rank writes only its tiles), and calls
 * pg_mpi_pits_remove (breach along the descent tree, epsilon: generate's default
 * final pass), then pg_mpi_pits_stats.
 *
 * Figures per rank: the cells it owns, the peak resident memory the call added
 * (VmHWM after the call, its peak reset through /proc/self/clear_refs just before,
 * less VmRSS before, with the heap trimmed before each call: the call's own buffers,
 * its heaps and what it touched of the planet array), and that peak per owned cell. The terrain is
 * rolling relief with hashed noise and an ocean, so it has pits everywhere (the hard case: every
 * tile floods, the breach carves everywhere).
 *
 * usage: bench_mpi_pits [N TILES [RANKS...]]   (default 2048 8 1 2 4: a 6 x 2048^2
 *        level in 6 x 8^2 tiles of 256^2). Needs mpirun (openmpi-bin) on the PATH;
 *        runs the ranks with --oversubscribe. */
#define _GNU_SOURCE
#include "planetgen/pg_mpi.h"

#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* A field of /proc/self/status in kB, or -1. */
static double status_kb(const char *key) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double v = -1;
    size_t k = strlen(key);
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, key, k) && line[k] == ':') v = atof(line + k + 1);
    if (f) fclose(f);
    return v;
}

/* Reset VmHWM to the current RSS (Linux: clear_refs 5). */
static int reset_peak(void) {
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (!f) return -1;
    int ok = fputs("5", f) >= 0;
    return fclose(f) == 0 && ok ? 0 : -1;
}

static float dem(uint64_t id, uint32_t n) {
    uint64_t per = (uint64_t)n * n, f = id / per, y = id % per / n, x = id % n;
    uint32_t z = (uint32_t)(id + 1) * 2654435761u;
    z ^= z >> 15, z *= 2246822519u, z ^= z >> 13;
    double s =
        600.0 * sin(0.013 * (double)x + (double)f) * cos(0.011 * (double)y - 0.5 * (double)f) +
        150.0 * (double)f - 200.0;
    return (float)(s + (double)(z % 1000) * 0.4);
}

static int worker(uint32_t n, int T) {
    pg_mpi *m = NULL;
    pg_error err = {0};
    if (pg_mpi_init(&m, &err)) return fprintf(stderr, "worker: %s\n", err.msg), 2;
    const int nt = 6 * T * T, P = pg_mpi_size(m), me = pg_mpi_rank(m);
    const uint32_t ts = n / (uint32_t)T;
    const size_t nc = (size_t)6 * n * n;
    float *h = mmap(NULL, nc * sizeof *h, PROT_READ | PROT_WRITE,
                    MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (h == MAP_FAILED) return fprintf(stderr, "worker: mmap failed\n"), 2;
    const int t0 = pg_mpi_tile_first(nt, P, me), t1 = pg_mpi_tile_first(nt, P, me + 1);
    double owned = (double)(t1 - t0) * ts * ts;
    for (int t = t0; t < t1; t++) {
        uint64_t f = (uint64_t)t / (uint64_t)(T * T), tx = (uint64_t)t % (uint64_t)T,
                 ty = (uint64_t)t / (uint64_t)T % (uint64_t)T;
        for (uint32_t y = 0; y < ts; y++)
            for (uint32_t x = 0; x < ts; x++) {
                uint64_t id = f * n * n + (ty * ts + y) * n + tx * ts + x;
                h[id] = dem(id, n);
            }
    }
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.method = PG_PITS_BREACH, o.epsilon = true, o.descent = true;
    o.has_sea_level = true, o.sea_level = 0;
    pg_mpi_pits_info info = {0};
    pg_pits_stats st;
    pg_pits_area area = {.constant = 1.0};
    malloc_trim(0); /* what earlier calls freed is no longer resident */
    double rss0 = status_kb("VmRSS"), peak[2], secs[2];
    int bad = reset_peak();
    double t_start = now();
    bad |= pg_mpi_pits_stats(m, T, n, h, &o, &area, &st, &err) != PG_OK;
    secs[0] = now() - t_start;
    peak[0] = status_kb("VmHWM") - rss0;
    malloc_trim(0);
    rss0 = status_kb("VmRSS");
    bad |= reset_peak();
    t_start = now();
    bad |= pg_mpi_pits_remove(m, T, n, h, &o, &info, &err) != PG_OK;
    secs[1] = now() - t_start;
    peak[1] = status_kb("VmHWM") - rss0;
    if (bad) fprintf(stderr, "rank %d: %s\n", me, err.msg[0] ? err.msg : "clear_refs failed");
    for (int r = 0; r < P; r++) {
        pg_mpi_max_int(m, 0); /* one rank after the other */
        if (r == me)
            printf("  rank %d: %10.0f owned cells | stats: peak +%7.1f MB = %5.1f B/owned cell, "
                   "%6.2f s | breach: peak +%7.1f MB = %5.1f B/owned cell, %6.2f s\n",
                   me, owned, peak[0] / 1024, peak[0] * 1024 / owned, secs[0], peak[1] / 1024,
                   peak[1] * 1024 / owned, secs[1]);
        if (r == me)
            printf("          breach: W by the fill %.2f s (flood %.2f s, rank 0 solving %.2f s, "
                   "%d epsilon rounds %.2f s), then %d token rounds %.2f s\n",
                   info.flood_seconds + info.solve_seconds + info.eps_seconds, info.flood_seconds,
                   info.solve_seconds, info.eps_rounds, info.eps_seconds, info.breach_rounds,
                   info.breach_seconds - info.flood_seconds - info.solve_seconds -
                       info.eps_seconds);
        fflush(stdout);
    }
    munmap(h, nc * sizeof *h);
    pg_mpi_finalize(m);
    return bad ? 2 : 0;
}

int main(int argc, char **argv) {
    if (argc == 4 && !strcmp(argv[1], "--worker"))
        return worker((uint32_t)atoi(argv[2]), atoi(argv[3]));
    uint32_t n = argc > 2 ? (uint32_t)atoi(argv[1]) : 2048;
    int T = argc > 2 ? atoi(argv[2]) : 8;
    int ranks[8] = {1, 2, 4}, nr = 3;
    if (argc > 3) {
        nr = 0;
        for (int i = 3; i < argc && nr < 8; i++)
            ranks[nr++] = atoi(argv[i]);
    }
    printf("distributed pits, level 6 x %u^2 (%.1f Mcells) in 6 x %d^2 tiles of %u^2; breach "
           "= pg_mpi_pits_remove (descent, epsilon), stats = pg_mpi_pits_stats\n",
           n, 6.0 * n * n / 1e6, T, n / (uint32_t)T);
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    for (int i = 0; i < nr; i++) {
        char cmd[4096];
        printf("%d rank(s):\n", ranks[i]);
        fflush(stdout);
        snprintf(cmd, sizeof cmd,
                 "mpirun --oversubscribe -np %d -x OMP_NUM_THREADS=1 '%s' --worker %u %d "
                 "</dev/null",
                 ranks[i], argv[0], n, T);
        if (system(cmd) != 0) printf("  (failed)\n");
    }
    return 0;
}
