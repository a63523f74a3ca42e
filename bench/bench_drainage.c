/* bench_drainage.c - the drainage measures (pg_drainage.h) and their speed on a planet
 * directory or on the Earth, plus the rivers preview.
 *
 * Planet: loaded with pg_planet_load. Earth (--earth): the default exemplar reprojected
 * onto a 6 x N^2 cube (default N = 1024, default projection, WGS84), then breached
 * with epsilon (pg_pits, sea level = the exemplar's), because the raw relief has
 * thousands of pits (its closed-land share is printed first). Prints the figures and the seconds of
 * pg_drainage_planet (and of pg_drainage_closed_land_share on the same heights); with --png, writes
 * the rivers over a shaded relief (pg_relief_shade) of --width x width/2 pixels. Figures only;
 * nothing is asserted.
 *
 * usage: bench_drainage PLANET_DIR [--png OUT.png] [--width W]
 *        bench_drainage --earth [--n N] [--png OUT.png] [--width W] */
#include "planetgen/pg_drainage.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_image.h"
#include "planetgen/pg_pits.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_relief.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* CPU seconds of the whole process (all threads): on a shared machine this shows the
 * work, where the wall clock also shows the waiting. */
static double cpu_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct args {
    const char *dir, *png;
    int earth, width;
    int64_t n;
} args;

static int parse(int argc, char **argv, args *a) {
    *a = (args){NULL, NULL, 0, 2048, 1024};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--earth"))
            a->earth = 1;
        else if (!strcmp(argv[i], "--png") && i + 1 < argc)
            a->png = argv[++i];
        else if (!strcmp(argv[i], "--width") && i + 1 < argc)
            a->width = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--n") && i + 1 < argc)
            a->n = atoll(argv[++i]);
        else if (argv[i][0] != '-' && !a->dir)
            a->dir = argv[i];
        else
            return 0;
    }
    return (a->earth || a->dir) && a->width >= 2 && a->n >= 16 && a->n % 16 == 0;
}

static float *height_field(const pg_planet *p) {
    size_t nn = (size_t)p->n * (size_t)p->n;
    float *h = malloc(6 * nn * sizeof *h);
    for (int f = 0; h && f < PG_CUBE_NFACES; f++)
        memcpy(h + f * nn, p->height[f], nn * sizeof *h);
    return h;
}

/* The Earth at N texels per face edge, breached with epsilon. */
static pg_status earth(pg_planet *p, int64_t n, pg_error *err) {
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo);
    pg_exemplar ex;
    pg_status s = pg_exemplar_load(&eo, &ex, err);
    if (s) return s;
    s = pg_planet_alloc(p, PG_CUBE_DEFAULT_PROJECTION, (int)(n / 16), 16, pg_ellipsoid_wgs84(),
                        err);
    if (!s) s = pg_planet_from_exemplar(p, &ex, 2, err);
    pg_exemplar_free(&ex);
    if (s) return s;
    float *h = height_field(p);
    if (!h) return pg_error_set(err, PG_ERR_NOMEM, "bench: out of memory");
    pg_pits_topo t;
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.has_sea_level = true;
    o.sea_level = p->sea_level;
    double raw = NAN;
    s = pg_drainage_closed_land_share(h, n, p->projection, &p->ellipsoid, p->sea_level, &raw, err);
    printf("closed land share of the raw relief: %.4f\n", raw);
    double t0 = omp_get_wtime();
    if (!s) s = pg_pits_topo_cube(&t, (uint32_t)n, err);
    if (!s) s = pg_pits_remove(&t, h, &o, NULL, err);
    printf("pits (breach, epsilon): %.2f s\n", omp_get_wtime() - t0);
    size_t nn = (size_t)n * (size_t)n;
    for (int f = 0; !s && f < PG_CUBE_NFACES; f++)
        memcpy(p->height[f], h + f * nn, nn * sizeof *h);
    free(h);
    return s;
}

static void print_stats(const pg_drainage_stats *st) {
    printf("land: %llu texels, %.4g km^2; mouths %llu, pits %llu\n",
           (unsigned long long)st->land_cells, st->land_area_km2, (unsigned long long)st->mouths,
           (unsigned long long)st->pits);
    printf("rivers: %llu texels, %.4g km; drainage density %.5f km^-1\n",
           (unsigned long long)st->river_cells, st->river_length_km, st->drainage_density_per_km);
    printf("Hack: h = %.3f, c = %.3f, r^2 = %.3f over %llu basins\n", st->hack_exponent,
           st->hack_coefficient, st->hack_r2, (unsigned long long)st->hack_basins);
    printf("largest basin %.4g km^2 = %.4f of land; closed land share %.4f\n",
           st->largest_basin_km2, st->largest_basin_land_share, st->closed_land_share);
}

static pg_status preview(const pg_planet *p, const float *acc, const args *a, pg_error *err) {
    int w = a->width, h = w / 2;
    float *hc = height_field(p), *eq = malloc((size_t)w * h * sizeof *eq);
    pg_image img = {0};
    pg_status s = hc && eq ? pg_image_alloc(&img, w, h, 3, err)
                           : pg_error_set(err, PG_ERR_NOMEM, "bench: out of memory");
    if (!s) s = pg_cube_to_equirect(p->projection, p->n, &p->ellipsoid, hc, 1, eq, w, h, err);
    if (!s) {
        pg_relief_shade(eq, w, h, p->sea_level, img.data);
        double t0 = omp_get_wtime();
        pg_drainage_opts o;
        pg_drainage_opts_default(&o);
        pg_drainage_terrain t = pg_planet_drainage_terrain(p);
        s = pg_drainage_draw_rivers(&t, acc, o.river_threshold_km2, img.data, w, h, err);
        printf("rivers preview %d x %d: %.2f s\n", w, h, omp_get_wtime() - t0);
    }
    if (!s) s = pg_image_write_png(a->png, &img, 8, err);
    pg_image_free(&img);
    free(hc), free(eq);
    return s;
}

static pg_status run(const args *a, pg_error *err) {
    pg_planet p = {0};
    pg_status s = a->earth ? earth(&p, a->n, err) : pg_planet_load(a->dir, &p, err);
    if (s) return s;
    printf("%s: N = %lld, %d threads\n", a->earth ? "Earth" : a->dir, (long long)p.n,
           omp_get_max_threads());
    pg_drainage_stats st;
    float *acc = NULL;
    double t0 = omp_get_wtime(), c0 = cpu_seconds();
    pg_drainage_terrain terrain = pg_planet_drainage_terrain(&p);
    s = pg_drainage_planet(&terrain, NULL, &st, &acc, err);
    double t1 = omp_get_wtime(), c1 = cpu_seconds();
    if (!s) {
        print_stats(&st);
        printf("pg_drainage_planet: %.3f s wall, %.3f s CPU\n", t1 - t0, c1 - c0);
    }
    float *h = s ? NULL : height_field(&p);
    double share = 0;
    t0 = omp_get_wtime(), c0 = cpu_seconds();
    if (h)
        s = pg_drainage_closed_land_share(h, p.n, p.projection, &p.ellipsoid, p.sea_level, &share,
                                          err);
    if (h && !s)
        printf("pg_drainage_closed_land_share: %.4f in %.3f s wall, %.3f s CPU\n", share,
               omp_get_wtime() - t0, cpu_seconds() - c0);
    free(h);
    if (!s && a->png) s = preview(&p, acc, a, err);
    free(acc);
    pg_planet_free(&p);
    return s;
}

int main(int argc, char **argv) {
    args a;
    if (!parse(argc, argv, &a)) {
        fprintf(stderr,
                "usage: bench_drainage PLANET_DIR|--earth [--n N] [--png OUT] [--width W]\n");
        return 2;
    }
    pg_error err = {0};
    if (run(&a, &err)) {
        fprintf(stderr, "bench_drainage: %s\n", err.msg);
        return 1;
    }
    return 0;
}
