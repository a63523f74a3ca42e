/* bench_exemplar.c - figures for the foundation: exemplar load (relief assembly,
 * calibration, resampling) and preview writing, with peak memory. Prints only;
 * nothing here is asserted. Run: build/bench_exemplar [repeats] */
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_relief.h"

#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double peak_mb(void) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss / 1024.0;
}

int main(int argc, char **argv) {
    int reps = argc > 1 ? atoi(argv[1]) : 3;
    double best_load = 1e9, best_prev = 1e9;
    for (int r = 0; r < reps; r++) {
        pg_error err = {0};
        pg_exemplar_opts o;
        pg_exemplar_opts_default(&o);
        pg_exemplar ex;
        double t0 = now_s();
        if (pg_exemplar_load(&o, &ex, &err) != PG_OK) {
            fprintf(stderr, "bench_exemplar: %s\n", err.msg);
            return 1;
        }
        double t1 = now_s();
        pg_image img = {.width = ex.width, .height = ex.height, .channels = 3, .data = ex.albedo};
        pg_image rel;
        pg_image_alloc(&rel, ex.width, ex.height, 3, &err);
        pg_relief_shade(ex.elevation, ex.width, ex.height, ex.sea_level, rel.data);
        if (pg_image_write_png("/tmp/bench_albedo.png", &img, 8, &err) != PG_OK ||
            pg_image_write_png("/tmp/bench_relief.png", &rel, 8, &err) != PG_OK) {
            fprintf(stderr, "bench_exemplar: %s\n", err.msg);
            return 1;
        }
        double t2 = now_s();
        pg_image_free(&rel);
        pg_exemplar_free(&ex);
        best_load = t1 - t0 < best_load ? t1 - t0 : best_load;
        best_prev = t2 - t1 < best_prev ? t2 - t1 : best_prev;
    }
    printf(
        "exemplar load (2700x1350 albedo + 10800x5400 relief, calibrated): %.3f s (best of %d)\n",
        best_load, reps);
    printf("previews (albedo.png + relief.png, 2700x1350):                  %.3f s\n", best_prev);
    printf("peak RSS:                                                        %.0f MB\n", peak_mb());
    return 0;
}
