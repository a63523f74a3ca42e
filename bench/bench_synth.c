/* bench_synth.c - synthesis figures (docs/synthesis.md): exemplar preparation cold
 * and cached, end-to-end flat synthesis throughput (output texels per second over all
 * levels), where the time goes (per preparation stage, per synthesis level), and peak
 * memory per output texel.
 *
 * usage: bench_synth [N (default 2048)] [cache dir (default: a fresh temp dir)]
 * Threads: OMP_NUM_THREADS (the figure is for 2). Prints, never asserts. */
#include "bench_util.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_synth.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

static double status_mb(const char *key) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double kb = 0;
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, key, strlen(key)) == 0) kb = atof(line + strlen(key));
    if (f) fclose(f);
    return kb / 1024.0;
}

/* Reset the kernel's peak-RSS mark (VmHWM) so the synthesis peak is its own. */
static void reset_peak(void) {
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (f) {
        fputs("5", f);
        fclose(f);
    }
}

/* CPU seconds of this process (all threads): on a shared machine wall time includes
 * waiting for cores other people use; CPU time does not. */
static double cpu_seconds(void) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_utime.tv_sec + ru.ru_utime.tv_usec * 1e-6 + ru.ru_stime.tv_sec +
           ru.ru_stime.tv_usec * 1e-6;
}

static const char *stage_names[5] = {"cube reprojection", "Gaussian stack", "appearance PCA",
                                     "k-coherence PatchMatch", "cache write"};

static int prep(const pg_exemplar *src, const char *dir, pg_synth_exemplar **ex,
                pg_synth_prep_info *pi) {
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    pg_error err = {0};
    if (pg_synth_prepare_exemplar(src->albedo, src->elevation, src->width, src->height,
                                  src->sea_level, &ep, dir, ex, pi, &err) != PG_OK) {
        fprintf(stderr, "bench_synth: %s\n", err.msg);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    int n = argc > 1 ? atoi(argv[1]) : 2048;
    char dir[256];
    if (argc > 2)
        snprintf(dir, sizeof dir, "%s", argv[2]);
    else {
        snprintf(dir, sizeof dir, "/tmp/pg_bench_synth_XXXXXX");
        if (!mkdtemp(dir)) return 1;
    }
    printf("threads %d, output %d x %d, cache %s\n", omp_get_max_threads(), n, n, dir);
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo);
    pg_exemplar src;
    pg_error err = {0};
    double t0 = pg_synth_now();
    if (pg_exemplar_load(&eo, &src, &err) != PG_OK) {
        fprintf(stderr, "bench_synth: %s\n", err.msg);
        return 1;
    }
    printf("load default exemplar (%d x %d): %.2f s\n", src.width, src.height, pg_synth_now() - t0);
    pg_synth_exemplar *ex;
    pg_synth_prep_info pi;
    double c0 = cpu_seconds();
    if (prep(&src, dir, &ex, &pi)) return 1;
    printf("exemplar prep %s: %.2f s wall, %.2f s CPU (%.0f MB); load average %.1f\n",
           pi.from_cache ? "(was cached)" : "cold", pi.seconds, cpu_seconds() - c0, pi.bytes / 1e6,
           pg_bench_loadavg());
    for (int i = 0; i < 5; i++)
        printf("  %-24s %.2f s\n", stage_names[i], pi.stage_seconds[i]);
    pg_synth_exemplar_free(ex);
    if (prep(&src, dir, &ex, &pi)) return 1;
    printf("exemplar prep cached: %.2f s (from cache: %s)\n", pi.seconds,
           pi.from_cache ? "yes" : "no");
    pg_exemplar_free(&src);

    reset_peak();
    double base_mb = status_mb("VmRSS:");
    pg_synth_params sp;
    pg_synth_params_default(&sp);
    pg_synth_result r;
    t0 = pg_synth_now();
    c0 = cpu_seconds();
    if (pg_synth_flat(ex, n, &sp, NULL, NULL, &r, &err) != PG_OK) {
        fprintf(stderr, "bench_synth: %s\n", err.msg);
        return 1;
    }
    size_t count = (size_t)n * n;
    uint8_t *rgb = malloc(count * 3);
    float *h = malloc(count * sizeof(float));
    pg_synth_render(ex, r.coords, r.offset, count, rgb, h);
    double dt = pg_synth_now() - t0, dc = cpu_seconds() - c0;
    double peak_mb = status_mb("VmHWM:");
    FILE *sm = fopen("/proc/self/smaps_rollup", "r");
    char line[256];
    while (sm && fgets(line, sizeof line, sm))
        if (strncmp(line, "AnonHugePages:", 14) == 0) printf("huge pages in use: %s", line + 14);
    if (sm) fclose(sm);
    printf("synthesis + render %d x %d: %.2f s = %.2f Mpx/s (target >= 2)\n", n, n, dt,
           count / dt / 1e6);
    printf("  CPU time %.2f s = %.2f Mpx per CPU-second; load average %.1f\n", dc, count / dc / 1e6,
           pg_bench_loadavg());
    printf("  per level (coarse -> fine):");
    for (int i = 0; i < r.nlevels_run; i++)
        printf(" %.3f", r.level_seconds[i]);
    printf(" s\n");
    printf("peak RSS %.0f MB; before synthesis %.0f MB; beyond the exemplar %.1f bytes per "
           "output texel (target <= 32)\n",
           peak_mb, base_mb, (peak_mb - base_mb) * 1048576.0 / count);
    free(rgb);
    free(h);
    pg_synth_result_free(&r);
    pg_synth_exemplar_free(ex);
    return 0;
}
