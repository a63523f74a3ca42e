/* bench_generate.c - whole-planet synthesis figures (docs/generate.md): the default planet
 * (6 x 4^2 x 256^2 = 6.3 Mpx) and the large one (6 x 8^2 x 512^2 = 100 Mpx): wall time,
 * Mpx/s, Gain-pit share of the time, peak RSS and peak bytes per output texel beyond the
 * prepared exemplar, each with the exemplar `planetgen generate` picks for it (faces of
 * 1024 and 2048: the large planet is magnified 2x, and both texel counts are printed).
 * Targets: >= 2 Mpx/s on 2 cores, <= 32 B/texel.
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

/* Current and peak resident set of this process, from /proc/self/status (kB lines). */
static double status_bytes(const char *key) {
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double kb = 0;
    size_t n = strlen(key);
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, key, n)) kb = atof(line + n + 1);
    if (f) fclose(f);
    return kb * 1024.0;
}

/* Reset the peak RSS (VmHWM) to the current RSS (Linux >= 4.0), so that the peak of one
 * planet's run is not the peak of loading the 10800 x 5400 source relief before it. */
static void reset_peak(void) {
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (f) {
        fputs("5", f);
        fclose(f);
    }
}

static int run(const pg_synth_exemplar *ex, int T, int S) {
    pg_planet_synth_params p;
    pg_planet_synth_params_default(&p);
    p.tiles = T;
    p.tile_size = S;
    pg_planet planet;
    pg_planet_synth_info si;
    pg_error err = {0};
    const int m = pg_planet_synth_magnification(ex, &p);
    reset_peak();
    double base = status_bytes("VmRSS:"); /* the prepared exemplar, loaded */
    double t0 = pg_synth_now(), c0 = cpu_seconds();
    if (pg_planet_synth_run(ex, &p, &planet, NULL, &si, &err) != PG_OK) {
        fprintf(stderr, "bench_generate: %s\n", err.msg);
        return 1;
    }
    double wall = pg_synth_now() - t0, cpu = cpu_seconds() - c0, px = 6.0 * T * T * (double)S * S;
    double peak = status_bytes("VmHWM:"), spx = px / ((double)m * m);
    printf("planet 6 x %d^2 x %d^2 = %.1f Mpx, exemplar 6 x %d^2, magnification %d, %d threads\n",
           T, S, px / 1e6, ex->face_size, m, omp_get_max_threads());
    printf("  wall %.2f s: synthesis %.2f s (Gain-pit %.2f s = %.0f%%), final pits %.2f s, "
           "depression counts %.2f s, render %.2f s\n",
           wall, si.synth_seconds, si.pits_seconds, 100 * si.pits_seconds / wall,
           si.final_pits_seconds, si.pit_stats_seconds, si.render_seconds);
    printf("  synthesized %.1f Mpx: %.2f Mpx/s in the synthesis (target >= 2), %.2f Mpx/s over "
           "the whole run; delivered %.2f Mpx/s\n",
           spx / 1e6, spx / 1e6 / si.synth_seconds, spx / 1e6 / wall, px / 1e6 / wall);
    printf("  CPU %.1f s = %.2f synthesized Mpx per CPU-second (the figure that survives a "
           "loaded machine)\n",
           cpu, spx / 1e6 / cpu);
    printf("  peak RSS %.0f MB, exemplar %.0f MB; beyond the exemplar %.1f B per delivered "
           "texel (target <= 32; estimate %.1f)\n",
           peak / 1e6, base / 1e6, (peak - base) / px, si.peak_bytes_estimate / px);
    printf("  depressions %llu before the final pass, %llu after\n",
           (unsigned long long)si.before.depressions, (unsigned long long)si.after.depressions);
    pg_planet_free(&planet);
    return 0;
}

/* Each planet gets the exemplar generate would use (pg_planet_synth_face_size). */
static int bench_planet(const pg_exemplar *src, const char *dir, int T, int S) {
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    ep.face_size = pg_planet_synth_face_size(T, S);
    pg_synth_exemplar *ex;
    pg_synth_prep_info pi;
    pg_error err = {0};
    if (pg_synth_prepare_exemplar(src->albedo, src->elevation, src->width, src->height,
                                  src->sea_level, &ep, dir, &ex, &pi, &err) != PG_OK) {
        fprintf(stderr, "bench_generate: %s\n", err.msg);
        return 1;
    }
    printf("exemplar 6 x %d^2 %s in %.2f s (%.0f MB)\n", ep.face_size,
           pi.from_cache ? "from cache" : "prepared", pi.seconds, pi.bytes / 1e6);
    int rc = run(ex, T, S);
    pg_synth_exemplar_free(ex);
    return rc;
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
    int rc = 0;
    if (!strcmp(which, "default") || !strcmp(which, "both")) rc |= bench_planet(&src, dir, 4, 256);
    if (!strcmp(which, "large") || !strcmp(which, "both")) rc |= bench_planet(&src, dir, 8, 512);
    pg_exemplar_free(&src);
    return rc;
}
