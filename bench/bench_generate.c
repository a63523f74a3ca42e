/* bench_generate.c - whole-planet synthesis figures (issue 5): the default planet
 * (6 x 4^2 x 256^2 = 6.3 Mpx) and the large one (6 x 8^2 x 512^2 = 100 Mpx): wall time,
 * Mpx/s, Gain-pit share of the time, peak RSS and peak bytes per output texel beyond the
 * prepared exemplar. Targets: >= 2 Mpx/s on 2 cores, <= 32 B/texel.
 *
 * usage: bench_generate [default|large|both] [CACHE_DIR]   (default: both) */
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_planet_synth.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

static double cpu_seconds(void) {
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return (double)u.ru_utime.tv_sec + u.ru_utime.tv_usec * 1e-6 + (double)u.ru_stime.tv_sec +
           u.ru_stime.tv_usec * 1e-6;
}

static double rss_bytes(void) {
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return (double)u.ru_maxrss * 1024.0;
}

static int run(const pg_synth_exemplar *ex, int T, int S, double base_rss) {
    pg_planet_synth_params p;
    pg_planet_synth_params_default(&p);
    p.tiles = T;
    p.tile_size = S;
    pg_planet planet;
    pg_planet_synth_info si;
    pg_error err = {0};
    double t0 = pg_synth_now(), c0 = cpu_seconds();
    if (pg_planet_synth_run(ex, &p, &planet, NULL, &si, &err) != PG_OK) {
        fprintf(stderr, "bench_generate: %s\n", err.msg);
        return 1;
    }
    double wall = pg_synth_now() - t0, cpu = cpu_seconds() - c0, px = 6.0 * T * T * (double)S * S;
    double rss = rss_bytes();
    printf("planet 6 x %d^2 x %d^2 = %.1f Mpx, %d threads\n", T, S, px / 1e6,
           omp_get_max_threads());
    printf("  wall %.2f s: synthesis %.2f s (Gain-pit %.2f s = %.0f%%), final pits %.2f s, "
           "depression counts %.2f s, render %.2f s\n",
           wall, si.synth_seconds, si.pits_seconds, 100 * si.pits_seconds / wall,
           si.final_pits_seconds, si.pit_stats_seconds, si.render_seconds);
    printf("  %.2f Mpx/s (target >= 2); CPU %.1f s = %.2f Mpx per CPU-second (the figure that "
           "survives a loaded machine)\n",
           px / 1e6 / wall, cpu, px / 1e6 / cpu);
    printf("  peak RSS %.0f MB; beyond the exemplar %.1f B/texel (target <= 32; estimate %.1f)\n",
           rss / 1e6, (rss - base_rss) / px, si.peak_bytes_estimate / px);
    printf("  depressions %llu before the final pass, %llu after\n",
           (unsigned long long)si.before.depressions, (unsigned long long)si.after.depressions);
    pg_planet_free(&planet);
    return 0;
}

int main(int argc, char **argv) {
    const char *which = argc > 1 ? argv[1] : "both";
    char dir[512];
    if (argc > 2)
        snprintf(dir, sizeof dir, "%s", argv[2]);
    else
        pg_synth_default_cache_dir(dir, sizeof dir);
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo);
    pg_exemplar src;
    pg_error err = {0};
    if (pg_exemplar_load(&eo, &src, &err) != PG_OK) {
        fprintf(stderr, "bench_generate: %s\n", err.msg);
        return 1;
    }
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    pg_synth_exemplar *ex;
    pg_synth_prep_info pi;
    if (pg_synth_prepare_exemplar(src.albedo, src.elevation, src.width, src.height, src.sea_level,
                                  &ep, dir, &ex, &pi, &err) != PG_OK) {
        fprintf(stderr, "bench_generate: %s\n", err.msg);
        return 1;
    }
    pg_exemplar_free(&src);
    /* the baseline: the process with the prepared exemplar loaded (the source images are
     * freed, but the peak RSS keeps them: the per-texel figure is therefore conservative) */
    double base = pi.bytes;
    printf("exemplar %s in %.2f s (%.0f MB)\n", pi.from_cache ? "from cache" : "prepared",
           pi.seconds, pi.bytes / 1e6);
    int rc = 0;
    if (!strcmp(which, "default") || !strcmp(which, "both")) rc |= run(ex, 4, 256, base);
    if (!strcmp(which, "large") || !strcmp(which, "both")) rc |= run(ex, 8, 512, base);
    pg_synth_exemplar_free(ex);
    return rc;
}
