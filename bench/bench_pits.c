/* bench_pits.c - speed of pit removal on the default relief and on a planet.
 *
 * Flat: the default relief (Marble's 10800 x 5400 tiles, calibrated to metres by
 * pg_exemplar_load; --synthetic uses a fractal DEM of the same size instead). Planet:
 * that relief resampled onto a 6 x N^2 cube sphere (default N = 2048). For fill,
 * breach and hybrid (all with epsilon; fill also plain) it prints seconds and
 * Mcells/s with 1 thread and with 2, checks that both give identical heights, and
 * counts the depressions before and after. Figures only; nothing is asserted.
 *
 * Hard DEM (--hard FILE): Marble's relief as its raw grey levels (0..247) in a float
 * EXR, map edges as outlets and no sea level, so the oceans are basins to fill and
 * every grey level is a flat: the case integer DEMs give. FILE is written first when
 * it does not exist. For each method it prints the algorithm's seconds with 1 and 2
 * threads and their ratio, and the cost of counting the depressions before and after
 * with the removal (pg_pits_remove_counted: what `planetgen pits` does without
 * --no-stats; 1 thread, wall and CPU time) as a fraction of the removal.
 *
 * Side by side, in the same run (bench/run sets these up; see its header):
 *   PG_BENCH_BEFORE=BIN    a bench_pits built from an earlier revision with this same
 *                          file: it runs first with the same options, and every row
 *                          prints its time beside today's with the ratio;
 *   PG_BENCH_RICHDEM=BIN   bench/richdem_pits.cpp built against RichDEM: run on the
 *                          hard DEM's file, it times Barnes et al. 2014's improved
 *                          Priority-Flood and Lindsay 2016's complete breaching, and
 *                          the fill and breach rows print planetgen / RichDEM ratios.
 *                          Without it the rows print the reference figures of
 *                          docs/pits.md ("Hard DEM").
 *
 * usage: bench_pits [--synthetic] [--n N] [--flat-only|--planet-only|--hard FILE]
 *                   [--no-stats] [--only PREFIX] [--repeat N] [--rows]
 *        (--only "fill (plain)": only the methods whose name starts so; --repeat N:
 *        N passes, each figure the minimum over them; with PG_BENCH_BEFORE each pass
 *        runs the earlier revision first, so both sides alternate and get the same
 *        treatment on a machine whose speed drifts; --rows: print
 *        only "ROW <section> | <method> | <threads> <seconds>" lines, for a later
 *        revision to compare against)
 *        bench_pits --synth [--images DIR]   (Gain-pit's share of a 1024^2 flat
 *        synthesis; DIR gets shaded reliefs of both runs, depressions in red) */
#include "pg_marble.h"
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

/* Rows of figures: every timed figure has a key "<section> | <method> | <threads>".
 * A run with --rows prints only these; a run with PG_BENCH_BEFORE reads an earlier
 * revision's rows and prints each beside today's. */
typedef struct rows {
    char (*key)[128];
    double *sec;
    size_t n, cap;
} rows;

typedef struct bctx {
    int rows_only, stats;
    int repeat; /* passes (--repeat): each figure is its minimum over them */
    int last;   /* this is the last pass: print */
    const char *only;
    rows before, now;
    rows now_cpu, now_ok; /* CPU seconds' minimum; 1 while every pass agreed, else 0 */
    rows before_hash;     /* 53 bits of each result's FNV-1a hash, exact in a double */
    double richdem_fill, richdem_breach; /* seconds, 0 when not run */
} bctx;

static void rows_add(rows *r, const char *key, double sec) {
    if (r->n == r->cap) {
        r->cap = r->cap ? 2 * r->cap : 64;
        r->key = realloc(r->key, r->cap * sizeof *r->key);
        r->sec = realloc(r->sec, r->cap * sizeof *r->sec);
    }
    size_t len = strlen(key) < sizeof r->key[0] - 1 ? strlen(key) : sizeof r->key[0] - 1;
    memcpy(r->key[r->n], key, len);
    r->key[r->n][len] = 0;
    r->sec[r->n++] = sec;
}

/* Adds a row, or keeps the smaller of two figures under one key (--repeat). */
static void rows_add_min(rows *r, const char *key, double sec) {
    for (size_t i = 0; i < r->n; i++)
        if (!strncmp(r->key[i], key, sizeof r->key[0] - 1)) {
            if (sec < r->sec[i]) r->sec[i] = sec;
            return;
        }
    rows_add(r, key, sec);
}

static double rows_find(const rows *r, const char *key) {
    for (size_t i = 0; i < r->n; i++)
        if (!strcmp(r->key[i], key)) return r->sec[i];
    return 0;
}

/* Records a figure and sets *sec to its minimum over the passes so far; returns
 * " (before X s, Y x)" for printing, or "" without one. */
static const char *figure(bctx *b, const char *section, const char *method, int threads,
                          double *sec, char *buf, size_t size) {
    char key[128];
    snprintf(key, sizeof key, "%s | %s | %d", section, method, threads);
    rows_add_min(&b->now, key, *sec);
    *sec = rows_find(&b->now, key);
    buf[0] = 0;
    if (b->rows_only) {
        if (b->last) printf("ROW %s %.4f\n", key, *sec);
        return buf;
    }
    double was = rows_find(&b->before, key);
    if (was > 0) snprintf(buf, size, " (before %.2f s, %.2fx)", was, was / *sec);
    return buf;
}

/* The minimum of a CPU time over the passes so far. */
static double cpu_min(bctx *b, const char *key, double cpu) {
    rows_add_min(&b->now_cpu, key, cpu);
    return rows_find(&b->now_cpu, key);
}

/* Whether a check held on every pass so far. */
static int held(bctx *b, const char *key, int ok) {
    rows_add_min(&b->now_ok, key, ok ? 2 : 1); /* rows_find gives 0 for "absent" */
    return rows_find(&b->now_ok, key) == 2;
}

static void count(bctx *b, const char *section, const char *what, const pg_pits_topo *t,
                  const float *h, const pg_pits_opts *o, double *sec) {
    pg_pits_stats st;
    pg_error err = {0};
    double t0 = omp_get_wtime();
    if (pg_pits_stats_compute(t, h, o, NULL, &st, &err)) {
        printf("  stats failed: %s\n", err.msg);
        return;
    }
    *sec = omp_get_wtime() - t0;
    char buf[96], name[64];
    snprintf(name, sizeof name, "count depressions %s", what);
    const char *was = figure(b, section, name, omp_get_max_threads(), sec, buf, sizeof buf);
    if (!b->rows_only && b->last)
        printf("  %-30s %llu depressions, %llu cells, volume %.6g (%.2f s%s)\n", name,
               (unsigned long long)st.depressions, (unsigned long long)st.depression_cells,
               st.depression_volume_m3, *sec, was);
}

/* One method with 1 and 2 threads: seconds, identity of the results, and the cost of
 * counting depressions before and after relative to the removal. */
static void bench_method(bctx *b, const char *section, const run *r, const pg_pits_topo *t,
                         const float *dem, pg_pits_opts o, float *out[2], double stats_before) {
    const size_t n = t->ncells;
    o.method = r->m;
    o.epsilon = r->eps;
    o.descent = r->descent;
    double sec[2], cpu[2];
    for (int th = 1; th <= 2; th++) {
        memcpy(out[th - 1], dem, sizeof(float) * n);
        omp_set_num_threads(th);
        pg_error err = {0};
        double t0 = omp_get_wtime(), c0 = cpu_seconds();
        if (pg_pits_remove(t, out[th - 1], &o, NULL, &err)) {
            printf("  %s failed: %s\n", r->name, err.msg);
            return;
        }
        sec[th - 1] = omp_get_wtime() - t0;
        cpu[th - 1] = cpu_seconds() - c0;
    }
    char b1[96], b2[96], key[128], ck[160];
    uint64_t hash = 0xcbf29ce484222325u;
    const unsigned char *bytes = (const unsigned char *)out[0];
    for (size_t i = 0; i < n * sizeof(float); i++)
        hash = (hash ^ bytes[i]) * 0x100000001b3u;
    double hash53 = (double)(hash >> 11);
    snprintf(key, sizeof key, "%s | %s", section, r->name);
    if (b->rows_only && b->last) printf("HASH %s %.0f\n", key, hash53);
    double was_hash = rows_find(&b->before_hash, key);
    snprintf(ck, sizeof ck, "%s | same", key);
    const int same_before = held(b, ck, was_hash == hash53);
    snprintf(ck, sizeof ck, "%s | 1 and 2", key);
    const int identical = held(b, ck, !memcmp(out[0], out[1], sizeof(float) * n));
    const char *same = !b->before_hash.n ? ""
                       : same_before     ? "; same bytes as before: yes"
                                         : "; same bytes as before: NO";
    const char *w1 = figure(b, section, r->name, 1, &sec[0], b1, sizeof b1);
    const char *w2 = figure(b, section, r->name, 2, &sec[1], b2, sizeof b2);
    snprintf(ck, sizeof ck, "%s | 1", key);
    cpu[0] = cpu_min(b, ck, cpu[0]);
    snprintf(ck, sizeof ck, "%s | 2", key);
    cpu[1] = cpu_min(b, ck, cpu[1]);
    const double sec_1 = sec[0], cpu_1 = cpu[0];
    if (!b->rows_only && b->last) {
        size_t up = 0, down = 0;
        for (size_t i = 0; i < n; i++) {
            up += out[0][i] > dem[i];
            down += out[0][i] < dem[i];
        }
        printf("  %-30s raised %zu lowered %zu cells; identical for 1 and 2 threads: %s%s\n",
               r->name, up, down, identical ? "yes" : "NO", same);
        printf("  %-30s 1 thread %6.2f s%s %5.1f Mcells/s (cpu %.2f s)\n", "", sec[0], w1,
               n / 1e6 / sec[0], cpu[0]);
        printf("  %-30s 2 threads %5.2f s%s (cpu %.2f s); 2 vs 1 thread %.2fx\n", "", sec[1], w2,
               cpu[1], sec[0] / sec[1]);
    }
    if (b->stats) { /* what `planetgen pits` runs without --no-stats, on 1 thread */
        float *c = malloc(sizeof(float) * n);
        omp_set_num_threads(1);
        pg_pits_stats before, after;
        pg_error err = {0};
        memcpy(c, dem, sizeof(float) * n);
        double t0 = omp_get_wtime(), c0 = cpu_seconds();
#ifdef PG_PITS_HAVE_REMOVE_COUNTED
        pg_status s = pg_pits_remove_counted(t, c, &o, NULL, NULL, &before, &after, &err);
#else /* an earlier revision (PG_BENCH_BEFORE): counting around the removal, as its CLI */
        pg_status s = pg_pits_stats_compute(t, c, &o, NULL, &before, &err);
        if (!s) s = pg_pits_remove(t, c, &o, NULL, &err);
        if (!s) s = pg_pits_stats_compute(t, c, &o, NULL, &after, &err);
#endif
        double sec = omp_get_wtime() - t0, cs = cpu_seconds() - c0;
        snprintf(ck, sizeof ck, "%s | counted same", key);
        const int same = held(b, ck, !s && !memcmp(c, out[0], sizeof(float) * n));
        free(c);
        char b3[96], m3[160];
        snprintf(m3, sizeof m3, "%s, counted", r->name);
        const char *w3 = figure(b, section, m3, 1, &sec, b3, sizeof b3);
        snprintf(ck, sizeof ck, "%s | counted", key);
        cs = cpu_min(b, ck, cs);
        if (s)
            printf("  %-30s counted removal failed: %s\n", "", err.msg);
        else if (!b->rows_only && b->last)
            printf("  %-30s with the counts (1 thread): %.2f s%s (cpu %.2f s), same result: %s;\n"
                   "  %-30s counts %llu depressions before, %llu after; counting costs %.2fx the "
                   "removal (cpu %.2fx; goal <= 0.5x)\n",
                   "", sec, w3, cs, same ? "yes" : "NO", "", (unsigned long long)before.depressions,
                   (unsigned long long)after.depressions, (sec - sec_1) / sec_1,
                   (cs - cpu_1) / cpu_1);
    }
    (void)stats_before;
}

static void bench(bctx *b, const char *label, const pg_pits_topo *t, const float *dem,
                  const pg_pits_opts *base, const run *runs, size_t nruns) {
    size_t n = t->ncells;
    if (!b->rows_only && b->last)
        printf("%s: %llu cells (%.1f Mcells)\n", label, (unsigned long long)n, n / 1e6);
    double before = 0;
    omp_set_num_threads(2);
    if (b->stats) count(b, label, "before", t, dem, base, &before);
    float *out[2] = {malloc(sizeof(float) * n), malloc(sizeof(float) * n)};
    for (size_t r = 0; r < nruns; r++)
        if (!b->only || !strncmp(runs[r].name, b->only, strlen(b->only)))
            bench_method(b, label, &runs[r], t, dem, *base, out, before);
    free(out[0]);
    free(out[1]);
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

/* The hard DEM: Marble's relief as raw grey levels, written to path when missing. */
static float *hard_dem(const char *path, int *w, int *h) {
    pg_image img;
    pg_error err = {0};
    FILE *f = fopen(path, "rb");
    if (f) {
        fclose(f);
    } else {
        if (pg_exemplar_assemble_relief(PG_MARBLE_RELIEF_DIR, PG_MARBLE_RELIEF_ROWS,
                                        PG_MARBLE_RELIEF_COLS, &img, &err) ||
            pg_image_write_exr(path, &img, NULL, &err)) {
            printf("hard DEM: %s\n", err.msg);
            return NULL;
        }
        pg_image_free(&img);
        printf("hard DEM: wrote %s\n", path);
    }
    if (pg_image_read(path, 0, &img, &err) || img.channels != 1) {
        printf("hard DEM: %s: %s\n", path, err.msg[0] ? err.msg : "not one channel");
        return NULL;
    }
    *w = img.width, *h = img.height;
    float *d = img.data;
    img.data = NULL;
    pg_image_free(&img);
    return d;
}

/* Reference figures (docs/pits.md, "Hard DEM"): RichDEM c5a183a on this DEM, on the
 * 2-core machine the project's figures come from, printed when RichDEM is not built. */
#define REF_RICHDEM_FILL 4.94
#define REF_RICHDEM_BREACH 21.3

static void richdem_run(bctx *b, const char *bin, const char *file) {
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "'%s' '%s' fill breach 2>/dev/null", bin, file);
    FILE *p = popen(cmd, "r");
    char line[256], name[64];
    double s;
    while (p && fgets(line, sizeof line, p))
        if (sscanf(line, "richdem %63s %lf", name, &s) == 2) {
            if (!strcmp(name, "fill")) b->richdem_fill = s;
            if (!strcmp(name, "breach")) b->richdem_breach = s;
        }
    if (p) pclose(p);
    if (!b->richdem_fill || !b->richdem_breach)
        printf("RichDEM: %s did not report both times\n", bin);
}

static void richdem_ratios(const bctx *b, const rows *now) {
    int measured = b->richdem_fill > 0;
    double rf = measured ? b->richdem_fill : REF_RICHDEM_FILL;
    double rb = measured ? b->richdem_breach : REF_RICHDEM_BREACH;
    const char *how = measured ? "measured in this run" : "reference figures, docs/pits.md";
    double fill = rows_find(now, "hard DEM | fill (plain) | 1");
    double breach = rows_find(now, "hard DEM | breach (eps, descent tree) | 1");
    printf("RichDEM (%s): Barnes 2014 improved fill %.2f s, Lindsay 2016 complete breaching "
           "%.2f s\n",
           how, rf, rb);
    if (fill > 0)
        printf("  fill (plain), 1 thread: %.2f s = %.2fx RichDEM's fill (goal >= 1.5x)\n", fill,
               rf / fill);
    if (breach > 0)
        printf("  breach (eps, descent tree), 1 thread: %.2f s = %.2fx RichDEM's breaching (goal "
               ">= 4x)\n",
               breach, rb / breach);
}

/* Runs an earlier revision's bench_pits with the same options and keeps its rows. */
static void before_run(bctx *b, const char *bin, int argc, char **argv) {
    char cmd[8192];
    size_t k = (size_t)snprintf(cmd, sizeof cmd, "'%s' --rows", bin);
    for (int i = 1; i < argc && k < sizeof cmd; i++) {
        if (!strcmp(argv[i], "--repeat")) { /* an earlier revision may not know it */
            i++;
            continue;
        }
        k += (size_t)snprintf(cmd + k, sizeof cmd - k, " '%s'", argv[i]);
    }
    if (b->last) printf("before: %s\n", cmd);
    fflush(stdout);
    FILE *p = popen(cmd, "r");
    char line[512];
    while (p && fgets(line, sizeof line, p)) {
        char *sp = strrchr(line, ' ');
        if (!sp) continue;
        *sp = 0;
        if (!strncmp(line, "ROW ", 4)) rows_add_min(&b->before, line + 4, atof(sp + 1));
        if (!strncmp(line, "HASH ", 5)) rows_add_min(&b->before_hash, line + 5, atof(sp + 1));
    }
    if (p) pclose(p);
    if (b->last) printf("before: %zu rows\n", b->before.n);
}

/* the hybrid: Lindsay's flood with no limits, as `planetgen pits --method hybrid
 * --epsilon` runs it */
static const run HARD_RUNS[] = {{"fill (plain)", PG_PITS_FILL, false, false},
                                {"fill (eps)", PG_PITS_FILL, true, false},
                                {"breach (eps, descent tree)", PG_PITS_BREACH, true, true},
                                {"breach (eps)", PG_PITS_BREACH, true, false},
                                {"hybrid (eps, Lindsay)", PG_PITS_HYBRID, true, false}};

int main(int argc, char **argv) {
    int synthetic = 0, flat = 1, planet = 1, hard = 1, synth = 0;
    bctx b = {.stats = 1, .repeat = 1, .last = 1};
    const char *images = NULL; /* --synth: write shaded reliefs of both runs here */
    const char *hard_path = getenv("PG_BENCH_HARD");
    if (!hard_path) hard_path = "bench/out/hard_relief.exr";
    long N = 2048;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--synthetic"))
            synthetic = 1;
        else if (!strcmp(argv[i], "--flat-only"))
            planet = hard = 0;
        else if (!strcmp(argv[i], "--planet-only"))
            flat = hard = 0;
        else if (!strcmp(argv[i], "--hard") && i + 1 < argc)
            hard_path = argv[++i], flat = planet = 0;
        else if (!strcmp(argv[i], "--no-stats"))
            b.stats = 0;
        else if (!strcmp(argv[i], "--rows"))
            b.rows_only = 1;
        else if (!strcmp(argv[i], "--n") && i + 1 < argc)
            N = atol(argv[++i]);
        else if (!strcmp(argv[i], "--only") && i + 1 < argc)
            b.only = argv[++i];
        else if (!strcmp(argv[i], "--repeat") && i + 1 < argc && atoi(argv[i + 1]) >= 1)
            b.repeat = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--synth"))
            synth = 1, flat = planet = hard = 0;
        else if (!strcmp(argv[i], "--images") && i + 1 < argc)
            images = argv[++i];
        else {
            fprintf(stderr, "usage: bench_pits [--synthetic] [--n N] "
                            "[--flat-only|--planet-only|--hard FILE] [--no-stats] [--only PREFIX] "
                            "[--repeat N] [--rows]\n");
            return 2;
        }
    }
    const char *before_bin = getenv("PG_BENCH_BEFORE"), *richdem = getenv("PG_BENCH_RICHDEM");
    if (!b.rows_only) {
        double load[3] = {0};
        FILE *lf = fopen("/proc/loadavg", "r");
        if (lf) {
            if (fscanf(lf, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3) load[0] = -1;
            fclose(lf);
        }
        printf("bench_pits: %d OpenMP threads available, load average %.2f %.2f %.2f\n",
               omp_get_num_procs(), load[0], load[1], load[2]);
    }
    pg_pits_topo t;
    pg_error err = {0};
    /* the inputs, read once */
    int hw = 0, hh = 0;
    float *hdem = hard ? hard_dem(hard_path, &hw, &hh) : NULL;
    int w = 10800, h = 5400;
    float *dem = NULL, *cube = NULL;
    double sea = 0;
    if (!synthetic && (flat || planet || synth)) {
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
            if (!b.rows_only)
                printf("relief: Marble %dx%d, calibrated to metres, sea level %.1f m (load %.1f "
                       "s)\n",
                       w, h, sea, omp_get_wtime() - t0);
        } else {
            printf("relief not available (%s); using the synthetic fractal\n", err.msg);
        }
    }
    if (!dem && (flat || planet || synth)) {
        dem = fractal(w, h);
        if (!b.rows_only) printf("relief: synthetic fBm %dx%d, sea level 0 m\n", w, h);
    }
    if (synth) {
        bench_synth(dem, w, 1024, images);
        free(dem);
        return 0;
    }
    if (planet) {
        cube = malloc(sizeof(float) * 6 * (size_t)N * N);
        if (pg_cube_from_equirect(PG_CUBE_EQUIANGULAR, N, NULL, dem, w, h, 1, 1, cube, &err)) {
            printf("resampling failed: %s\n", err.msg);
            return 1;
        }
    }
    if (b.repeat > 1 && !b.rows_only)
        printf("%d passes, each figure the minimum over them%s\n", b.repeat,
               before_bin && *before_bin ? "; each pass runs the earlier revision, then this one"
                                         : "");
    for (int pass = 0; pass < b.repeat; pass++) {
        b.last = pass == b.repeat - 1;
        if (before_bin && *before_bin && !b.rows_only) before_run(&b, before_bin, argc, argv);
        if (hdem) {
            pg_pits_opts o;
            pg_pits_opts_default(&o);
            o.open_edges = true; /* the map edges are the outlets; no sea level */
            pg_pits_topo_grid(&t, (uint32_t)hw, (uint32_t)hh, NULL);
            if (!b.rows_only && b.last)
                printf("hard DEM: %s, %dx%d raw grey levels, edges as outlets, no sea level\n",
                       hard_path, hw, hh);
            bench(&b, "hard DEM", &t, hdem, &o, HARD_RUNS, sizeof HARD_RUNS / sizeof *HARD_RUNS);
            if (!b.rows_only && b.last) {
                if (richdem && *richdem) richdem_run(&b, richdem, hard_path);
                richdem_ratios(&b, &b.now);
            }
        }
        pg_pits_opts o;
        pg_pits_opts_default(&o);
        o.has_sea_level = true;
        o.sea_level = sea;
        o.max_depth = 50;
        o.max_length = 100;
        if (flat) {
            pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
            o.open_edges = true;
            bench(&b, "flat", &t, dem, &o, RUNS, sizeof RUNS / sizeof *RUNS);
        }
        if (planet) {
            pg_pits_topo_cube(&t, (uint32_t)N, NULL);
            o.open_edges = false;
            char label[64];
            snprintf(label, sizeof label, "planet 6x%ld^2", N);
            bench(&b, label, &t, cube, &o, RUNS, sizeof RUNS / sizeof *RUNS);
        }
    }
    free(hdem);
    free(cube);
    free(dem);
    return 0;
}
