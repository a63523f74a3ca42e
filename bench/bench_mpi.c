/* bench_mpi.c - figures of the MPI-distributed generate (docs/mpi.md): strong scaling from
 * one process to two ranks on this machine's 2 cores, peak RSS per rank, and the bytes
 * the ranks communicate per level (tile edges point-to-point, and the level allgathers
 * of the steps that are not distributed). It drives the CLI as a user would
 * (`mpirun -np 2 planetgen generate ... --json R`) and reads the JSON reports.
 *
 * Rows: 1 process x 1 thread, 1 process x 2 threads (OpenMP), 2 ranks x 1 thread. Each
 * for --pits off (everything distributed) and for the default pits (Gain-pit, final
 * breach and depression counts replicated on every rank after an allgather; see
 * docs/mpi.md). Times are rank 0's synthesis stage (pg_planet_synth_run) and the whole
 * command; the exemplar is prepared once beforehand (cache) and is not in "synthesis".
 *
 * usage: bench_mpi [TILES TILE_SIZE]   (default 4 256: the default planet's size, with
 *        the exemplar face fixed at 512). Needs mpirun (openmpi-bin) on the PATH. */
#include "bench_util.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SCALES 16

typedef struct figures {
    double synth, total, rss[8], halo[MAX_SCALES], gather[MAX_SCALES], pits_bytes;
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

static int run(const char *cli, int ranks, int threads, const char *size, const char *extra,
               const char *work, figures *fig) {
    char cmd[4096], json[1024];
    snprintf(json, sizeof json, "%s/report.json", work);
    snprintf(cmd, sizeof cmd, "rm -rf %s/out %s", work, json);
    if (system(cmd) != 0) return 1;
    const char *common = "generate -q --output-layout tiled --face-size 512";
    if (ranks == 1)
        snprintf(cmd, sizeof cmd,
                 "OMP_NUM_THREADS=%d '%s' %s %s %s --cache-dir %s/cache -o %s/out --json %s",
                 threads, cli, common, size, extra, work, work, json);
    else
        snprintf(cmd, sizeof cmd,
                 "mpirun --oversubscribe -np %d -x OMP_NUM_THREADS=%d '%s' %s %s %s --cache-dir "
                 "%s/cache -o %s/out --json %s",
                 ranks, threads, cli, common, size, extra, work, work, json);
    if (system(cmd) != 0) {
        fprintf(stderr, "bench_mpi: failed: %s\n", cmd);
        return 1;
    }
    char *s = pg_bench_slurp(json);
    if (!s) return 1;
    memset(fig, 0, sizeof *fig);
    fig->synth = pg_bench_json_number(s, "synth_seconds");
    fig->total = pg_bench_json_number(s, "seconds_total");
    fig->nrss = json_array(s, "peak_rss_bytes_per_rank", fig->rss, 8);
    if (!fig->nrss) fig->rss[0] = pg_bench_json_number(s, "peak_rss_bytes"), fig->nrss = 1;
    fig->nscales = json_array(s, "halo_bytes_per_scale", fig->halo, MAX_SCALES);
    json_array(s, "allgather_bytes_per_scale", fig->gather, MAX_SCALES);
    fig->pits_bytes = pg_bench_json_number(s, "pits_bytes");
    free(s);
    return 0;
}

static void print_row(int ranks, int threads, const figures *f, const figures *base) {
    printf("  %d rank%s x %d thread%s  synthesis %6.2f s (x%.2f)  command %6.2f s  peak RSS/rank",
           ranks, ranks > 1 ? "s" : " ", threads, threads > 1 ? "s" : " ", f->synth,
           base->synth / f->synth, f->total);
    for (int q = 0; q < f->nrss; q++)
        printf(" %.0f", f->rss[q] / 1e6);
    printf(" MB\n");
}

static void print_bytes(const figures *f) {
    printf("  bytes sent per level, all ranks (scale 0 = finest): tile edges | level allgathers\n");
    for (int s = f->nscales - 1; s >= 0; s--)
        printf("    scale %d: %10.0f | %10.0f\n", s, f->halo[s], f->gather[s]);
    if (f->pits_bytes > 0)
        printf("  distributed pit removal and counts, all levels: %.0f bytes\n", f->pits_bytes);
}

int main(int argc, char **argv) {
    char cli[4096], size[64], work[] = "/tmp/planetgen-bench-mpi";
    const char *slash = strrchr(argv[0], '/');
    snprintf(cli, sizeof cli, "%.*splanetgen", slash ? (int)(slash - argv[0] + 1) : 0, argv[0]);
    snprintf(size, sizeof size, "--tiles %s --tile-size %s", argc > 2 ? argv[1] : "4",
             argc > 2 ? argv[2] : "256");
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    char cmd[512];
    snprintf(cmd, sizeof cmd, "mkdir -p %s", work);
    if (system(cmd) != 0) return 1;
    figures warm, f11, f12, f21;
    if (run(cli, 1, 2, size, "--pits off", work, &warm)) return 1; /* fills the cache */
    const char *modes[] = {"--pits off", ""};
    for (int m = 0; m < 2; m++) {
        printf("planet %s %s (exemplar face 512)\n", size, m ? "(default pits)" : modes[m]);
        if (run(cli, 1, 1, size, modes[m], work, &f11) ||
            run(cli, 1, 2, size, modes[m], work, &f12) ||
            run(cli, 2, 1, size, modes[m], work, &f21))
            return 1;
        print_row(1, 1, &f11, &f11);
        print_row(1, 2, &f12, &f11);
        print_row(2, 1, &f21, &f11);
        print_bytes(&f21);
    }
    return 0;
}
