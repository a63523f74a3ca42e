/* pg_earthlike.c - land fraction, hypsometry and zonal climate of a planet in one
 * pass over its texels, plus the landmass census (pg_earthlike_census.c) and the shelf
 * widths along the coasts (pg_earthlike_shelf.c); see
 * pg_earthlike.h for the figures and docs/inspect.md for the report they feed.
 *
 * THE PASS. Every texel contributes its fixed-point area (pg_earthlike_geom.c) to
 *  - a table by 1-degree geodetic latitude bin x terrain type, plus the land area
 *    and the land-ice area per bin: the 10-degree bands and every derived zone
 *    (|lat| < 20, poleward of 66, 15..35, |lat| < 10) are exact unions of 1-degree
 *    bins, so each figure is a ratio of two integer sums;
 *  - a 65536-bin histogram of land heights and one of ocean heights, each over the
 *    distribution's own range [min, max] (found in a first pass): the quantile
 *    function is read off the cumulative histogram, linear inside a bin, so its
 *    error is below one bin width;
 *  - per texel row, the area-weighted moments sum w, sum w h, sum w h^2 in double (h
 *    taken from the distribution's minimum), added in row order afterwards.
 * Each thread owns its tables; they are added as integers at the end (order-free),
 * so the result is the same for any thread count. Texel rows are taken in static
 * chunks. */
#include "pg_earthlike_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define HIST_BINS 65536

typedef struct el_acc {
    uint64_t type[PG_EL_BINS][PG_TYPE_COUNT];
    uint64_t land[PG_EL_BINS], land_ice[PG_EL_BINS];
    uint64_t hist[2][HIST_BINS]; /* 0: land, 1: ocean */
} el_acc;

/* Ranges of the heights above sea level, land and ocean. */
typedef struct el_range {
    double lo[2], hi[2];
    int64_t bad; /* non-finite heights */
} el_range;

typedef struct el_pass {
    const pg_planet *p;
    const pg_earthlike_geom *g;
    el_range r;
    double scale[2];  /* histogram bins per metre */
    double (*mom)[6]; /* per row: land w, wh, wh^2, ocean w, wh, wh^2 */
} el_pass;

static void find_range(const pg_planet *p, el_range *r) {
    int64_t n = p->n, rows = PG_CUBE_NFACES * n, bad = 0;
    double llo = INFINITY, lhi = -INFINITY, olo = INFINITY, ohi = -INFINITY;
    float sea = p->sea_level;
#pragma omp parallel for schedule(static) reduction(min : llo, olo) reduction(max : lhi, ohi) \
    reduction(+ : bad)
    for (int64_t row = 0; row < rows; row++) {
        const float *h = p->height[row / n] + (row % n) * n;
        for (int64_t x = 0; x < n; x++) {
            double d = (double)h[x] - sea;
            if (!isfinite(h[x])) {
                bad++;
            } else if (h[x] > sea) {
                llo = fmin(llo, d), lhi = fmax(lhi, d);
            } else {
                olo = fmin(olo, d), ohi = fmax(ohi, d);
            }
        }
    }
    *r = (el_range){{llo, olo}, {lhi, ohi}, bad};
}

/* 8-bit sRGB by rounding, as the type-map reader of pg_types.c does. */
static uint8_t to8(float v) {
    return (uint8_t)(!(v > 0) ? 0 : v >= 1 ? 255 : v * 255.0f + 0.5f); /* NaN: 0 */
}

/* One texel row into the thread's tables and the row's moments. */
static void pass_row(const el_pass *e, int64_t row, el_acc *a) {
    int64_t n = e->g->n, y = row % n;
    int face = (int)(row / n), kind = pg_earthlike_face_kind(face);
    const float *h = e->p->height[face] + y * n, *rgb = e->p->albedo[face] + y * n * 3;
    const uint64_t *w = e->g->weight[kind] + y * n;
    const uint8_t *bin = e->g->bin[kind] + y * n;
    float sea = e->p->sea_level;
    double *m = e->mom[row];
    memset(m, 0, 6 * sizeof *m);
    for (int64_t x = 0; x < n; x++) {
        uint8_t c[3] = {to8(rgb[3 * x]), to8(rgb[3 * x + 1]), to8(rgb[3 * x + 2])};
        int t = pg_types_classify(c, h[x], sea), land = h[x] > sea, cls = !land;
        a->type[bin[x]][t] += w[x];
        if (land) {
            a->land[bin[x]] += w[x];
            if (t == PG_TYPE_ICE) a->land_ice[bin[x]] += w[x];
        }
        double rel = (double)h[x] - sea - e->r.lo[cls], wd = (double)w[x];
        int64_t hb = (int64_t)(rel * e->scale[cls]);
        a->hist[cls][hb < HIST_BINS ? hb : HIST_BINS - 1] += w[x];
        m[3 * cls] += wd, m[3 * cls + 1] += wd * rel, m[3 * cls + 2] += wd * rel * rel;
    }
}

static void add_acc(el_acc *dst, const el_acc *src) {
    uint64_t *d = (uint64_t *)dst;
    const uint64_t *s = (const uint64_t *)src;
    for (size_t i = 0; i < sizeof *dst / sizeof *d; i++)
        d[i] += s[i];
}

/* The pass over all rows; sums into *total. */
static pg_status run_pass(el_pass *e, el_acc *total, pg_error *err) {
    int nt = omp_get_max_threads();
    el_acc *acc = calloc((size_t)nt, sizeof *acc);
    if (!acc) return pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory for tables");
    int64_t rows = PG_CUBE_NFACES * e->g->n;
#pragma omp parallel num_threads(nt)
    {
        el_acc *a = &acc[omp_get_thread_num()];
#pragma omp for schedule(static)
        for (int64_t row = 0; row < rows; row++)
            pass_row(e, row, a);
    }
    memset(total, 0, sizeof *total);
    for (int t = 0; t < nt; t++)
        add_acc(total, &acc[t]);
    free(acc);
    return PG_OK;
}

/* Quantiles q[k] = F^-1((k + 1/2) / K) of a histogram over [lo, hi]. */
static void quantiles(const uint64_t *hist, double lo, double hi, double *q) {
    uint64_t total = 0;
    for (int b = 0; b < HIST_BINS; b++)
        total += hist[b];
    if (total == 0) {
        for (int k = 0; k < PG_EARTHLIKE_QUANTILES; k++)
            q[k] = NAN;
        return;
    }
    double width = (hi - lo) / HIST_BINS, cum = 0;
    int b = 0;
    for (int k = 0; k < PG_EARTHLIKE_QUANTILES; k++) {
        double t = (k + 0.5) / PG_EARTHLIKE_QUANTILES * (double)total;
        while (b < HIST_BINS - 1 && cum + (double)hist[b] < t)
            cum += (double)hist[b++];
        double frac = hist[b] ? (t - cum) / (double)hist[b] : 0;
        q[k] = lo + ((double)b + fmin(fmax(frac, 0), 1)) * width;
    }
}

/* Mean and standard deviation from the row moments of class cls, which are taken
 * about the class's lowest height lo (no cancellation for a narrow distribution far
 * from sea level; exactly 0 for a constant one). */
static void moments(double (*mom)[6], int64_t rows, int cls, double lo, double *mean, double *sd) {
    double sw = 0, swh = 0, swh2 = 0;
    for (int64_t r = 0; r < rows; r++)
        sw += mom[r][3 * cls], swh += mom[r][3 * cls + 1], swh2 += mom[r][3 * cls + 2];
    if (sw <= 0) {
        *mean = *sd = NAN;
        return;
    }
    double m = swh / sw;
    *mean = lo + m;
    *sd = sqrt(fmax(swh2 / sw - m * m, 0));
}

/* Sums over the 1-degree bins [b0, b1) and their mirror images in the other hemisphere
 * (mirror = 1) of: all area, land, land ice, and type t. */
typedef struct zone {
    double all, land, land_ice, type;
} zone;

static zone zone_sum(const el_acc *a, int b0, int b1, int mirror, int t) {
    zone z = {0, 0, 0, 0};
    for (int m = 0; m <= mirror; m++)
        for (int b = b0; b < b1; b++) {
            int k = m ? PG_EL_BINS - 1 - b : b;
            for (int s = 0; s < PG_TYPE_COUNT; s++)
                z.all += (double)a->type[k][s];
            z.land += (double)a->land[k], z.land_ice += (double)a->land_ice[k];
            z.type += (double)a->type[k][t];
        }
    return z;
}

static double desert_ratio(const el_acc *a) {
    zone sub = zone_sum(a, 90 + 15, 90 + 35, 1, PG_TYPE_DESERT);
    zone eq = zone_sum(a, 90 - 10, 90 + 10, 0, PG_TYPE_DESERT);
    if (sub.land <= 0 || eq.land <= 0 || (sub.type <= 0 && eq.type <= 0)) return NAN;
    if (eq.type <= 0) return INFINITY;
    return (sub.type / sub.land) / (eq.type / eq.land);
}

static void zonal_figures(const el_acc *a, double unit, pg_earthlike *out) {
    for (int b = 0; b < PG_EARTHLIKE_BANDS; b++) {
        double all = zone_sum(a, 10 * b, 10 * b + 10, 0, 0).all;
        out->band_area_m2[b] = all * unit;
        for (int t = 0; t < PG_TYPE_COUNT; t++)
            out->zonal[b][t] = all > 0 ? zone_sum(a, 10 * b, 10 * b + 10, 0, t).type / all : NAN;
    }
    zone eq = zone_sum(a, 90 - 20, 90 + 20, 0, PG_TYPE_ICE);
    out->ice_equator_fraction = eq.all > 0 ? eq.type / eq.all : NAN;
    zone pol = zone_sum(a, 0, 90 - 66, 1, PG_TYPE_ICE);
    out->ice_polar_fraction =
        pol.land >= 0.01 * pol.all && pol.land > 0 ? pol.land_ice / pol.land : NAN;
    out->desert_band_ratio = desert_ratio(a);
    zone all = zone_sum(a, 0, PG_EL_BINS, 0, 0);
    out->total_area_m2 = all.all * unit;
    out->land_area_m2 = all.land * unit;
    out->land_fraction = all.all > 0 ? all.land / all.all : NAN;
}

static pg_status check_planet(const pg_planet *p, pg_error *err) {
    if (p->n < 1) return pg_error_set(err, PG_ERR_BADINPUT, "earthlike: empty planet");
    if (!isfinite(p->sea_level))
        return pg_error_set(err, PG_ERR_BADINPUT, "earthlike: sea level is not finite");
    return PG_OK;
}

/* Hypsometry and zonal figures (everything but the census). */
static pg_status pass_figures(const pg_planet *p, const pg_earthlike_geom *g, pg_earthlike *out,
                              pg_error *err) {
    el_pass e = {.p = p, .g = g};
    find_range(p, &e.r);
    if (e.r.bad)
        return pg_error_set(err, PG_ERR_BADINPUT, "earthlike: %lld heights are not finite",
                            (long long)e.r.bad);
    for (int c = 0; c < 2; c++)
        e.scale[c] = e.r.hi[c] > e.r.lo[c] ? HIST_BINS / (e.r.hi[c] - e.r.lo[c]) : 0;
    int64_t rows = PG_CUBE_NFACES * g->n;
    e.mom = malloc((size_t)rows * sizeof *e.mom);
    el_acc *total = malloc(sizeof *total);
    pg_status st = e.mom && total ? run_pass(&e, total, err)
                                  : pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory");
    if (st == PG_OK) {
        zonal_figures(total, g->unit_m2, out);
        quantiles(total->hist[0], e.r.lo[0], e.r.hi[0], out->land_quantiles);
        quantiles(total->hist[1], e.r.lo[1], e.r.hi[1], out->ocean_quantiles);
        moments(e.mom, rows, 0, e.r.lo[0], &out->land_mean_m, &out->land_std_m);
        moments(e.mom, rows, 1, e.r.lo[1], &out->ocean_mean_m, &out->ocean_std_m);
    }
    free(e.mom);
    free(total);
    return st;
}

pg_status pg_earthlike_compute(const pg_planet *p, pg_earthlike *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    pg_status st = check_planet(p, err);
    if (st) return st;
    out->n = p->n;
    pg_earthlike_geom g;
    st = pg_earthlike_geom_init(&g, p, err);
    if (st) return st;
    st = pass_figures(p, &g, out, err);
    if (st == PG_OK) st = pg_earthlike_census(p, &g, out, err);
    if (st == PG_OK) st = pg_earthlike_shelf(p, &g, out, err);
    pg_earthlike_geom_free(&g);
    return st;
}
