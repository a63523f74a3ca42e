/* bench_pits.c - speed of pit removal on the default relief and on a planet.
 *
 * Flat: the default relief (Marble's 10800 x 5400 tiles, calibrated to metres by
 * pg_exemplar_load; --synthetic uses a fractal DEM of the same size instead). Planet:
 * that relief resampled onto a 6 x N^2 cube sphere (default N = 2048). For fill,
 * breach and hybrid (all with epsilon; fill also plain) it prints seconds and
 * Mcells/s with 1 thread and with 2, checks that both give identical heights, and
 * counts the depressions before and after. Figures only; nothing is asserted.
 *
 * usage: bench_pits [--synthetic] [--n N] [--flat-only|--planet-only] [--no-stats]
 *                   [--only PREFIX]   (e.g. --only "fill (plain)")
 *        bench_pits --synth [--images DIR]   (Gain-pit's share of a 1024^2 flat
 *        synthesis; DIR gets shaded reliefs of both runs, depressions in red) */
#include "planetgen/pg_cube.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_image.h"
#include "planetgen/pg_pits.h"
#include "planetgen/pg_pits_gainpit.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double hashf(uint32_t a, uint32_t b) {
    uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 13;
    return (h & 0xFFFFFF) / 16777216.0;
}

/* Value-noise fBm, 8 octaves, on a W x H grid; sea at 0 m. */
static float *fractal(int w, int h) {
    float *d = malloc(sizeof(float) * (size_t)w * h);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double v = 0, amp = 3000;
            for (int o = 0; o < 8; o++) {
                int cell = 512 >> o;
                int cx = x / cell, cy = y / cell;
                double fx = (double)(x % cell) / cell, fy = (double)(y % cell) / cell;
                double a = hashf(o, (uint32_t)(cy * 100003 + cx)),
                       b = hashf(o, (uint32_t)(cy * 100003 + cx + 1)),
                       c = hashf(o, (uint32_t)((cy + 1) * 100003 + cx)),
                       e = hashf(o, (uint32_t)((cy + 1) * 100003 + cx + 1));
                double top = a + (b - a) * fx, bot = c + (e - c) * fx;
                v += amp * (top + (bot - top) * fy - 0.5);
                amp *= 0.5;
            }
            d[(size_t)y * w + x] = (float)v;
        }
    return d;
}

/* CPU seconds of the whole process (all threads): on a loaded machine this shows
 * the work done, where the wall clock also shows the waiting. */
static double cpu_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

typedef struct run {
    const char *name;
    pg_pits_method m;
    bool eps, descent;
} run;

static const run RUNS[] = {{"fill (plain)", PG_PITS_FILL, false, false},
                           {"fill (eps)", PG_PITS_FILL, true, false},
                           {"breach (eps)", PG_PITS_BREACH, true, false},
                           {"hybrid (eps, 50 m, 100 cells)", PG_PITS_HYBRID, true, false},
                           {"breach (eps, descent tree)", PG_PITS_BREACH, true, true},
                           {"hybrid (eps, descent tree)", PG_PITS_HYBRID, true, true}};

static void count(const char *what, const pg_pits_topo *t, const float *h, const pg_pits_opts *o) {
    pg_pits_stats st;
    pg_error err = {0};
    double t0 = omp_get_wtime();
    if (pg_pits_stats_compute(t, h, o, NULL, &st, &err)) {
        printf("  stats failed: %s\n", err.msg);
        return;
    }
    printf("  %-34s %llu depressions, %llu cells, volume %.4g m^3-per-cell-area (%.1f s)\n", what,
           (unsigned long long)st.depressions, (unsigned long long)st.depression_cells,
           st.depression_volume_m3, omp_get_wtime() - t0);
}

static void bench(const char *label, const pg_pits_topo *t, const float *dem, double sea, int stats,
                  const char *only) {
    size_t n = t->ncells;
    printf("%s: %llu cells (%.1f Mcells)\n", label, (unsigned long long)n, n / 1e6);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.has_sea_level = true;
    o.sea_level = sea;
    o.open_edges = t->kind == PG_PITS_GRID;
    if (stats) count("before", t, dem, &o);
    float *a = malloc(sizeof(float) * n), *b = malloc(sizeof(float) * n);
    for (size_t r = 0; r < sizeof RUNS / sizeof *RUNS; r++) {
        if (only && strncmp(RUNS[r].name, only, strlen(only))) continue;
        o.method = RUNS[r].m;
        o.epsilon = RUNS[r].eps;
        o.descent = RUNS[r].descent;
        o.max_depth = 50;
        o.max_length = 100;
        double sec[2], cpu[2];
        float *out[2] = {a, b};
        for (int th = 1; th <= 2; th++) {
            memcpy(out[th - 1], dem, sizeof(float) * n);
            omp_set_num_threads(th);
            pg_error err = {0};
            double t0 = omp_get_wtime(), c0 = cpu_seconds();
            if (pg_pits_remove(t, out[th - 1], &o, NULL, &err)) {
                printf("  %s failed: %s\n", RUNS[r].name, err.msg);
                return;
            }
            sec[th - 1] = omp_get_wtime() - t0;
            cpu[th - 1] = cpu_seconds() - c0;
        }
        size_t up = 0, down = 0;
        for (size_t i = 0; i < n; i++) {
            up += a[i] > dem[i];
            down += a[i] < dem[i];
        }
        printf("  %-30s raised %zu lowered %zu cells\n", RUNS[r].name, up, down);
        printf("  %-30s 1 thread %6.2f s %6.1f Mcells/s (cpu %.2f s) | 2 threads %6.2f s %6.1f "
               "Mcells/s (cpu %.2f s) | identical: %s\n",
               RUNS[r].name, sec[0], n / 1e6 / sec[0], cpu[0], sec[1], n / 1e6 / sec[1], cpu[1],
               memcmp(a, b, sizeof(float) * n) ? "NO" : "yes");
        if (stats) count("after", t, a, &o);
    }
    free(a);
    free(b);
}

/* A hill-shaded grey image of h (cell size `cell` metres, lit from the north-west)
 * with the cells a fill would raise (depressions) tinted red; written as PNG. */
static void write_shaded(const char *path, const float *h, int n, double cell) {
    pg_pits_topo t;
    pg_pits_topo_grid(&t, (uint32_t)n, (uint32_t)n, NULL);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.method = PG_PITS_FILL;
    o.epsilon = false;
    o.open_edges = true;
    o.has_sea_level = true;
    o.sea_level = 0;
    float *f = malloc(sizeof(float) * n * n);
    memcpy(f, h, sizeof(float) * n * n);
    pg_pits_remove(&t, f, &o, NULL, NULL);
    pg_image img;
    if (pg_image_alloc(&img, n, n, 3, NULL) == PG_OK) {
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++) {
                int xl = x > 0 ? x - 1 : x, xr = x < n - 1 ? x + 1 : x;
                int yu = y > 0 ? y - 1 : y, yd = y < n - 1 ? y + 1 : y;
                double dx = (h[y * n + xr] - h[y * n + xl]) / ((xr - xl) * cell);
                double dy = (h[yd * n + x] - h[yu * n + x]) / ((yd - yu) * cell);
                double shade = (1 + (dx + dy) * -0.7071 * 8) / sqrt(1 + 64 * (dx * dx + dy * dy));
                float g = (float)fmin(1, fmax(0, 0.15 + 0.75 * shade));
                int pit = f[y * n + x] > h[y * n + x], sea = h[y * n + x] <= 0;
                float *px = &img.data[((size_t)y * n + x) * 3];
                px[0] = pit ? 0.6f + 0.4f * g : sea ? 0.3f * g : g;
                px[1] = pit ? 0.2f * g : sea ? 0.4f * g : g;
                px[2] = pit ? 0.2f * g : sea ? 0.7f * g : g;
            }
        pg_image_write_png(path, &img, 8, NULL);
        pg_image_free(&img);
    }
    free(f);
}

/* The cost of Gain-pit inside the synthesis: a 256^2 crop of the relief (Himalaya)
 * as a toroidal exemplar, a flat N x N synthesis with and without the hook. */
static void bench_synth(const float *dem, int w, int n, const char *images) {
    enum { E = 256 };
    float *h = malloc(sizeof(float) * E * E), *rgb = malloc(sizeof(float) * E * E * 3);
    int x0 = w * (80 + 180) / 360, y0 = w / 2 * 58 / 180; /* about 80 E, 32 N */
    for (int y = 0; y < E; y++)
        for (int x = 0; x < E; x++) {
            float v = dem[(size_t)(y0 + y) * w + x0 + x];
            h[y * E + x] = v;
            for (int c = 0; c < 3; c++)
                rgb[(y * E + x) * 3 + c] = 0.2f + 0.1f * c + 1e-4f * v;
        }
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    ep.face_size = E;
    ep.levels = 5;
    pg_synth_exemplar *ex = NULL;
    pg_synth_prep_info info;
    pg_error err = {0};
    if (pg_synth_prepare_torus(rgb, h, E, 0.0f, &ep, "", &ex, &info, &err)) {
        printf("synthesis: exemplar failed: %s\n", err.msg);
        return;
    }
    pg_synth_params p;
    pg_synth_params_default(&p);
    for (int with = 0; with < 2; with++) {
        pg_pits_gainpit gp;
        pg_pits_gainpit_init(&gp);
        pg_synth_result r;
        double t0 = omp_get_wtime();
        if (pg_synth_flat(ex, n, &p, with ? pg_pits_gainpit_hook : NULL, &gp, &r, &err)) {
            printf("synthesis failed: %s\n", err.msg);
            break;
        }
        double sec = omp_get_wtime() - t0;
        printf("synthesis %dx%d (exemplar 256^2 relief crop, %d levels) %s Gain-pit: %.2f s", n, n,
               ep.levels, with ? "with" : "without", sec);
        if (with)
            printf(", pit removal %.2f s = %.1f%% (%llu passes)", gp.seconds,
                   100 * gp.seconds / sec, (unsigned long long)gp.runs);
        printf("\n");
        if (images) { /* the raw synthesized heights, before any final pass */
            float *hh = malloc(sizeof(float) * n * n);
            pg_synth_render(ex, r.coords, r.offset, (size_t)n * n, NULL, hh);
            char path[1024];
            snprintf(path, sizeof path, "%s/pits_gainpit_%s.png", images, with ? "on" : "off");
            write_shaded(path, hh, n, 40075017.0 / w);
            printf("  wrote %s\n", path);
            free(hh);
        }
        pg_synth_result_free(&r);
    }
    pg_synth_exemplar_free(ex);
    free(h);
    free(rgb);
}

int main(int argc, char **argv) {
    int synthetic = 0, flat = 1, planet = 1, stats = 1, synth = 0;
    const char *only = NULL;   /* run only the methods whose name starts with this */
    const char *images = NULL; /* --synth: write shaded reliefs of both runs here */
    long N = 2048;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--synthetic"))
            synthetic = 1;
        else if (!strcmp(argv[i], "--flat-only"))
            planet = 0;
        else if (!strcmp(argv[i], "--planet-only"))
            flat = 0;
        else if (!strcmp(argv[i], "--no-stats"))
            stats = 0;
        else if (!strcmp(argv[i], "--n") && i + 1 < argc)
            N = atol(argv[++i]);
        else if (!strcmp(argv[i], "--only") && i + 1 < argc)
            only = argv[++i];
        else if (!strcmp(argv[i], "--synth"))
            synth = 1, flat = planet = 0;
        else if (!strcmp(argv[i], "--images") && i + 1 < argc)
            images = argv[++i];
        else {
            fprintf(stderr, "usage: bench_pits [--synthetic] [--n N] [--flat-only|--planet-only] "
                            "[--no-stats] [--only PREFIX]\n");
            return 2;
        }
    }
    int w = 10800, h = 5400;
    float *dem = NULL;
    double sea = 0;
    pg_error err = {0};
    if (!synthetic) {
        pg_exemplar_opts eo;
        pg_exemplar_opts_default(&eo);
        eo.grid_width = w;
        pg_exemplar ex;
        double t0 = omp_get_wtime();
        if (pg_exemplar_load(&eo, &ex, &err) == PG_OK) {
            dem = ex.elevation;
            ex.elevation = NULL;
            sea = ex.sea_level;
            pg_exemplar_free(&ex);
            printf("relief: Marble %dx%d, calibrated to metres, sea level %.1f m (load %.1f s)\n",
                   w, h, sea, omp_get_wtime() - t0);
        } else {
            printf("relief not available (%s); using the synthetic fractal\n", err.msg);
        }
    }
    if (!dem) {
        dem = fractal(w, h);
        printf("relief: synthetic fBm %dx%d, sea level 0 m\n", w, h);
    }
    if (synth) bench_synth(dem, w, 1024, images);
    pg_pits_topo t;
    if (flat) {
        pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
        bench("flat", &t, dem, sea, stats, only);
    }
    if (planet) {
        float *cube = malloc(sizeof(float) * 6 * (size_t)N * N);
        if (pg_cube_from_equirect(PG_CUBE_EQUIANGULAR, N, NULL, dem, w, h, 1, 1, cube, &err)) {
            printf("resampling failed: %s\n", err.msg);
            return 1;
        }
        pg_pits_topo_cube(&t, (uint32_t)N, NULL);
        char label[64];
        snprintf(label, sizeof label, "planet 6x%ld^2", N);
        bench(label, &t, cube, sea, stats, only);
        free(cube);
    }
    free(dem);
    return 0;
}
