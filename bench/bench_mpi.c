/* bench_mpi.c - figures of the MPI-distributed generate (docs/mpi.md): strong scaling from
 * one process to two ranks on this machine's 2 cores, memory per rank, and the bytes
 * the ranks communicate per level (tile edges point-to-point, and the level allgathers
 * of the steps that are not distributed). It drives the CLI as a user would
 * (`mpirun -np 2 planetgen generate ... --json R`) and reads the JSON reports.
 *
 * Rows: 1 process x 1 thread, 1 process x 2 threads (OpenMP), 2 ranks x 1 thread. Each
 * for --pits off (everything distributed) and for the default pits (Gain-pit, final
 * breach and depression counts, distributed; see docs/mpi.md). Times are rank 0's
 * synthesis stage (pg_planet_synth_run) and the whole command; the exemplar is prepared
 * once beforehand (cache) and is not in "synthesis". Memory per rank: peak RSS, and the
 * peak private memory (Private_Clean + Private_Dirty of /proc/self/smaps_rollup, sampled
 * by the CLI every 0.1 s and at every stage end): RSS counts the exemplar's cache file,
 * which the ranks of a machine map together, in every rank; private memory does not.
 *
 * --acceptance: the memory and speed gates of docs/mpi.md ("Memory per rank") on a
 * 6 x 8^2 x 512^2 planet (100 Mpx, tiled, default pits, warm exemplar cache, exemplar
 * face 512 unless --face-size E), with 1, 2 and 4 ranks of 1 thread (--oversubscribe):
 * whether all outputs are the same bytes; each rank's peak private memory against
 * 1.15 x (the single process's private memory less its exemplar) / N; the wall time of
 * the whole command with 2 ranks over 1 process (gate <= 0.65). It prints figures and
 * verdicts and never fails on them. It needs about 5 GB of memory and several minutes.
 *
 * usage: bench_mpi [TILES TILE_SIZE]   (default 4 256: the default planet's size, with
 *        the exemplar face fixed at 512)
 *        bench_mpi --acceptance [TILES TILE_SIZE] [--face-size E]   (default 8 512)
 * Needs mpirun (openmpi-bin) on the PATH. */
#include "bench_util.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_SCALES 16
#define MAX_RANKS 8
#define PRIVATE_GATE 1.15 /* peak private per rank <= 1.15 x single's (less exemplar) / N */
#define WALL_GATE 0.65    /* 2 ranks x 1 thread <= 0.65 x 1 process x 1 thread */

typedef struct figures {
    double synth, total, wall, rss[MAX_RANKS], priv[MAX_RANKS], dirty[MAX_RANKS], shared[MAX_RANKS],
        halo[MAX_SCALES], gather[MAX_SCALES], pits_bytes;
    int nrss, nscales;
} figures;

/* The numbers of the array after "key": in json; returns how many (at most max). */
static int json_array(const char *json, const char *key, double *out, int max) {
    char k[128];
    snprintf(k, sizeof k, "\"%s\":", key);
    const char *p = strstr(json, k);
    if (!p || !(p = strchr(p, '['))) return 0;
    int n = 0;
    p++;
    while (n < max) {
        char *end;
        double v = strtod(p, &end);
        if (end == p) break;
        out[n++] = v;
        p = end;
        while (*p == ',' || *p == ' ' || *p == '\n')
            p++;
    }
    return n;
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* One generate run into work/OUT: 1 process, or `ranks` ranks under mpirun. */
static int run(const char *cli, int ranks, int threads, const char *size, const char *extra,
               const char *work, const char *outname, figures *fig) {
    char cmd[4096], json[1024];
    snprintf(json, sizeof json, "%s/report.json", work);
    snprintf(cmd, sizeof cmd, "rm -rf %s/%s %s", work, outname, json);
    if (system(cmd) != 0) return 1;
    const char *common = "generate -q --output-layout tiled";
    if (ranks == 1)
        snprintf(cmd, sizeof cmd,
                 "OMP_NUM_THREADS=%d '%s' %s %s %s --cache-dir %s/cache -o %s/%s --json %s",
                 threads, cli, common, size, extra, work, work, outname, json);
    else
        snprintf(cmd, sizeof cmd,
                 "mpirun --oversubscribe -np %d -x OMP_NUM_THREADS=%d '%s' %s %s %s --cache-dir "
                 "%s/cache -o %s/%s --json %s",
                 ranks, threads, cli, common, size, extra, work, work, outname, json);
    double t0 = now();
    if (system(cmd) != 0) {
        fprintf(stderr, "bench_mpi: failed: %s\n", cmd);
        return 1;
    }
    double wall = now() - t0;
    char *s = pg_bench_slurp(json);
    if (!s) return 1;
    memset(fig, 0, sizeof *fig);
    fig->wall = wall;
    fig->synth = pg_bench_json_number(s, "synth_seconds");
    fig->total = pg_bench_json_number(s, "seconds_total");
    fig->nrss = json_array(s, "peak_rss_bytes_per_rank", fig->rss, MAX_RANKS);
    json_array(s, "peak_private_bytes_per_rank", fig->priv, MAX_RANKS);
    json_array(s, "peak_private_dirty_bytes_per_rank", fig->dirty, MAX_RANKS);
    json_array(s, "peak_shared_bytes_per_rank", fig->shared, MAX_RANKS);
    if (!fig->nrss) { /* one process: the report's own figures, after its stages' */
        const char *top = strstr(s, "\"seconds_total\":");
        fig->rss[0] = pg_bench_json_number(top, "peak_rss_bytes");
        fig->priv[0] = pg_bench_json_number(top, "peak_private_bytes");
        fig->dirty[0] = pg_bench_json_number(top, "peak_private_dirty_bytes");
        fig->shared[0] = pg_bench_json_number(top, "peak_shared_bytes");
        fig->nrss = 1;
    }
    fig->nscales = json_array(s, "halo_bytes_per_scale", fig->halo, MAX_SCALES);
    json_array(s, "allgather_bytes_per_scale", fig->gather, MAX_SCALES);
    fig->pits_bytes = pg_bench_json_number(s, "pits_bytes");
    free(s);
    return 0;
}

static void print_mb(const char *what, const double *v, int n) {
    printf("%s", what);
    for (int q = 0; q < n; q++)
        printf(" %.0f", v[q] / 1e6);
    printf(" MB");
}

static void print_row(int ranks, int threads, const figures *f, const figures *base) {
    printf("  %d rank%s x %d thread%s  synthesis %6.2f s (x%.2f)  command %6.2f s ", ranks,
           ranks > 1 ? "s" : " ", threads, threads > 1 ? "s" : " ", f->synth,
           base->synth / f->synth, f->total);
    print_mb(" peak RSS/rank", f->rss, f->nrss);
    print_mb("  peak private/rank", f->priv, f->nrss);
    printf("\n");
}

static void print_bytes(const figures *f) {
    printf("  bytes sent per level, all ranks (scale 0 = finest): tile edges | level allgathers\n");
    for (int s = f->nscales - 1; s >= 0; s--)
        printf("    scale %d: %10.0f | %10.0f\n", s, f->halo[s], f->gather[s]);
    if (f->pits_bytes > 0)
        printf("  distributed pit removal and counts, all levels: %.0f bytes\n", f->pits_bytes);
}

/* The bytes of the exemplar cache file(s) in work/cache: what a process maps. */
static double cache_bytes(const char *work) {
    char cmd[1200], buf[64] = "";
    snprintf(cmd, sizeof cmd, "cat %s/cache/*.pgsx 2>/dev/null | wc -c", work);
    FILE *p = popen(cmd, "r");
    if (!p) return 0;
    if (!fgets(buf, sizeof buf, p)) buf[0] = 0;
    pclose(p);
    return strtod(buf, NULL);
}

static int same_dirs(const char *work, const char *a, const char *b) {
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "diff -rq %s/%s %s/%s >/dev/null", work, a, work, b);
    return system(cmd) == 0;
}

/* The acceptance gates (header comment). */
static int acceptance(const char *cli, const char *size, const char *face, const char *work) {
    char extra[128];
    snprintf(extra, sizeof extra, "--face-size %s", face);
    figures f1, fn[3];
    const int nps[3] = {1, 2, 4};
    printf("acceptance: planet %s, tiled, default pits, exemplar face %s, 1 thread per rank; "
           "load average %.1f at the start\n",
           size, face, pg_bench_loadavg());
    if (run(cli, 1, 1, size, extra, work, "warm", &f1)) return 1; /* fills the cache */
    /* written back: a page of the cache file still dirty in the page cache counts as
     * Private_Dirty in the process that maps it */
    if (system("sync") != 0) return 1;
    const double ex = cache_bytes(work);
    for (int i = 0; i < 3; i++) {
        char name[16];
        snprintf(name, sizeof name, "np%d", nps[i]);
        if (run(cli, nps[i], 1, size, extra, work, name, &fn[i])) return 1;
        printf("  %d rank%s: wall %.2f s (command %.2f s) ", nps[i], nps[i] > 1 ? "s" : " ",
               fn[i].wall, fn[i].total);
        print_mb(" peak RSS/rank", fn[i].rss, fn[i].nrss);
        print_mb("  peak private/rank", fn[i].priv, fn[i].nrss);
        print_mb("  shared/rank", fn[i].shared, fn[i].nrss);
        printf("\n");
    }
    printf("  load average %.1f at the end\n", pg_bench_loadavg());
    int same = same_dirs(work, "np1", "np2") && same_dirs(work, "np1", "np4") &&
               same_dirs(work, "np1", "warm");
    printf("  outputs of 1, 2 and 4 ranks byte-identical: %s\n", same ? "yes" : "NO");
    /* the single process maps the whole cache file alone, so its exemplar is private
     * there; what it wrote (private dirty) is its private memory less the exemplar */
    const double single = fn[0].priv[0], less = fn[0].dirty[0];
    printf("  single process: peak private %.0f MB, exemplar cache file %.0f MB, private less "
           "the exemplar (its peak private dirty) %.0f MB\n",
           single / 1e6, ex / 1e6, less / 1e6);
    for (int i = 1; i < 3; i++) {
        double worst = 0, gate = PRIVATE_GATE * less / nps[i];
        for (int q = 0; q < fn[i].nrss; q++)
            worst = fn[i].priv[q] > worst ? fn[i].priv[q] : worst;
        printf("  %d ranks: peak private per rank up to %.0f MB against %.2f x %.0f / %d = %.0f "
               "MB: %s (%.2fx the gate)\n",
               nps[i], worst / 1e6, PRIVATE_GATE, less / 1e6, nps[i], gate / 1e6,
               worst <= gate ? "within" : "OVER", worst / gate);
    }
    double r = fn[1].wall / fn[0].wall;
    printf("  wall time 2 ranks x 1 thread / 1 process x 1 thread: %.2f / %.2f s = %.2f "
           "(gate <= %.2f): %s\n",
           fn[1].wall, fn[0].wall, r, WALL_GATE, r <= WALL_GATE ? "within" : "OVER");
    return 0;
}

int main(int argc, char **argv) {
    char cli[4096], size[64], work[] = "/tmp/planetgen-bench-mpi";
    const char *slash = strrchr(argv[0], '/');
    snprintf(cli, sizeof cli, "%.*splanetgen", slash ? (int)(slash - argv[0] + 1) : 0, argv[0]);
    int acc = 0, npos = 0;
    const char *pos[2] = {NULL, NULL}, *face = "512";
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--acceptance"))
            acc = 1;
        else if (!strcmp(argv[i], "--face-size") && i + 1 < argc)
            face = argv[++i];
        else if (npos < 2)
            pos[npos++] = argv[i];
    }
    snprintf(size, sizeof size, "--tiles %s --tile-size %s",
             npos == 2 ? pos[0]
             : acc     ? "8"
                       : "4",
             npos == 2 ? pos[1]
             : acc     ? "512"
                       : "256");
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    char cmd[512];
    snprintf(cmd, sizeof cmd, "mkdir -p %s", work);
    if (system(cmd) != 0) return 1;
    if (acc) return acceptance(cli, size, face, work);
    figures warm, f11, f12, f21;
    const char *fixed = "--face-size 512";
    char modes[2][64];
    snprintf(modes[0], sizeof modes[0], "%s --pits off", fixed);
    snprintf(modes[1], sizeof modes[1], "%s", fixed);
    if (run(cli, 1, 2, size, modes[0], work, "out", &warm)) return 1; /* fills the cache */
    for (int m = 0; m < 2; m++) {
        printf("planet %s %s (exemplar face 512)\n", size, m ? "(default pits)" : "--pits off");
        if (run(cli, 1, 1, size, modes[m], work, "out", &f11) ||
            run(cli, 1, 2, size, modes[m], work, "out", &f12) ||
            run(cli, 2, 1, size, modes[m], work, "out", &f21))
            return 1;
        print_row(1, 1, &f11, &f11);
        print_row(1, 2, &f12, &f11);
        print_row(2, 1, &f21, &f11);
        print_bytes(&f21);
    }
    return 0;
}
