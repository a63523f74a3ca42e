/* pg_planet_synth_world.c - layout world's coarsest level by texture-by-numbers (Hertzmann,
 * Jacobs, Oliver, Curless and Salesin 2001, "Image Analogies", §4.3): every texel of the
 * coarsest level takes the exemplar texel whose features best match the macro world's
 * there (docs/generate.md, "Layout world").
 *
 * FEATURES. The target's come from the macro world (pg_planet_world: plate elevation and
 * its climate), averaged over the block of world texels a level texel covers. The
 * exemplar's are its own level height and the climate the SAME model (pg_climate.h,
 * Earth's parameters) computes on its relief averaged to a coarse cube of
 * PS_WORLD_EXEMPLAR_N texels a face edge, so both sides are described alike.
 *
 * THE MATCH. 256 candidates are hashed draws of (seed, level, face, x, y, k); the one with
 * the least distance
 *   4 [land differs] + 2 [ice differs] + (dh / 1500 m)^2 + (dT / 6 K)^2
 *     + ((sqrt P_e - sqrt P_t) / 10)^2
 * wins (the first on ties), so the choice is deterministic and independent of threads. */
#include "pg_hash.h"
#include "pg_planet_synth_internal.h"

#include "planetgen/pg_climate.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PS_WORLD_EXEMPLAR_N 64
#define PS_WORLD_DRAWS 256

/* The exemplar's coarse relief (metres above its sea level): block means of its heights. */
static float *exemplar_relief(const pg_synth_exemplar *ex, int64_t n) {
    const int E = ex->face_size, b = E / (int)n;
    float *h = malloc((size_t)6 * n * n * sizeof *h);
    if (!h) return NULL;
#pragma omp parallel for schedule(static)
    for (int64_t id = 0; id < 6 * n * n; id++) {
        int f = (int)(id / (n * n)), y = (int)(id / n % n), x = (int)(id % n);
        double s = 0;
        for (int v = y * b; v < (y + 1) * b; v++)
            for (int u = x * b; u < (x + 1) * b; u++)
                s += ex->height[((size_t)f * E + v) * E + u];
        h[id] = (float)(s / ((double)b * b) - ex->sea_level);
    }
    return h;
}

pg_status pg_planet_world_exemplar_climate(const pg_synth_exemplar *ex, int64_t n, pg_climate *out,
                                           pg_error *err) {
    pg_climate_init(out);
    if (ex->nfaces != 6 || n < 1 || ex->face_size % n)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "layout world: needs a cube exemplar whose face size %lld divides",
                            (long long)n);
    float *h = exemplar_relief(ex, n);
    if (!h) return pg_error_set(err, PG_ERR_NOMEM, "layout world: out of memory");
    pg_climate_params cp;
    pg_climate_params_default(&cp);
    pg_status st = pg_climate_compute(&cp, PG_CUBE_DEFAULT_PROJECTION, n, h, out, err);
    free(h);
    return st;
}

/* Area of texel (x, y) of an n-texel face on the unit sphere: two spherical triangles. */
static double texel_area(int f, int64_t n, int64_t x, int64_t y) {
    double c[4][3];
    for (int k = 0; k < 4; k++) {
        double u = 2.0 * (double)(x + (k & 1)) / (double)n - 1,
               v = 2.0 * (double)(y + (k >> 1)) / (double)n - 1;
        pg_cube_to_dir(PG_CUBE_DEFAULT_PROJECTION, f, u, v, c[k]);
    }
    return pg_cube_spherical_triangle(c[0], c[1], c[3]) +
           pg_cube_spherical_triangle(c[0], c[3], c[2]);
}

typedef struct ps_keyed {
    float h, a; /* height (m), area */
} ps_keyed;

static int keyed_cmp(const void *pa, const void *pb) {
    const ps_keyed *a = pa, *b = pb;
    return (a->h > b->h) - (a->h < b->h);
}

/* nq area-weighted quantiles of the m samples k (sorted here) into q, ascending. */
static void quantiles(ps_keyed *k, size_t m, int nq, float *q) {
    qsort(k, m, sizeof *k, keyed_cmp);
    double total = 0, below = 0;
    for (size_t i = 0; i < m; i++)
        total += k[i].a;
    size_t i = 0;
    for (int j = 0; j < nq; j++) {
        double want = total * j / (nq - 1);
        while (i + 1 < m && below + 0.5 * k[i].a < want)
            below += k[i++].a;
        q[j] = k[i].h;
    }
}

pg_status pg_planet_world_exemplar_hypsometry(const pg_synth_exemplar *ex, int64_t n, int nq,
                                              float *land_m, float *ocean_m, pg_error *err) {
    if (ex->nfaces != 6 || n < 1 || ex->face_size % n || nq < 2)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "layout world: needs a cube exemplar whose face size %lld divides",
                            (long long)n);
    float *h = exemplar_relief(ex, n);
    ps_keyed *land = malloc((size_t)6 * n * n * sizeof *land),
             *sea = malloc((size_t)6 * n * n * sizeof *sea);
    if (!h || !land || !sea) {
        free(h), free(land), free(sea);
        return pg_error_set(err, PG_ERR_NOMEM, "layout world: out of memory");
    }
    size_t nl = 0, no = 0;
    for (int64_t id = 0; id < 6 * n * n; id++) {
        ps_keyed k = {h[id], (float)texel_area((int)(id / (n * n)), n, id % n, id / n % n)};
        if (h[id] > 0)
            land[nl++] = k;
        else
            sea[no++] = k;
    }
    pg_status st = PG_OK;
    if (!nl || !no)
        st = pg_error_set(err, PG_ERR_BADINPUT, "layout world: the exemplar has no %s",
                          nl ? "ocean" : "land");
    if (!st) quantiles(land, nl, nq, land_m), quantiles(sea, no, nq, ocean_m);
    free(h), free(land), free(sea);
    return st;
}

pg_status pg_ps_world_setup(pg_ps_ctx *c, pg_error *err) {
    if (c->p->layout != PG_LAYOUT_WORLD) return PG_OK;
    pg_climate cl;
    pg_status st = pg_planet_world_exemplar_climate(c->ex, PS_WORLD_EXEMPLAR_N, &cl, err);
    if (!st) {
        c->world_t = cl.temperature_c, c->world_p = cl.precipitation_mm;
        cl.temperature_c = cl.precipitation_mm = NULL;
    }
    pg_climate_free(&cl);
    return st;
}

typedef struct ps_feat {
    float h, t, p;
} ps_feat;

/* The macro world averaged over the block level texel (f, x, y) of r covers. */
static ps_feat target(const pg_planet_world *w, int r, int f, int x, int y) {
    const int64_t n = w->n;
    int64_t x0 = (int64_t)x * n / r, x1 = ((int64_t)x + 1) * n / r;
    int64_t y0 = (int64_t)y * n / r, y1 = ((int64_t)y + 1) * n / r;
    if (x1 <= x0) x1 = x0 + 1;
    if (y1 <= y0) y1 = y0 + 1;
    double s[3] = {0, 0, 0};
    for (int64_t j = y0; j < y1; j++)
        for (int64_t i = x0; i < x1; i++) {
            size_t id = ((size_t)f * n + j) * n + i;
            s[0] += w->elevation_m[id], s[1] += w->temperature_c[id];
            s[2] += w->precipitation_mm[id];
        }
    double k = (double)(x1 - x0) * (y1 - y0);
    ps_feat t = {(float)(s[0] / k), (float)(s[1] / k), (float)(s[2] / k)};
    return t;
}

static double distance(ps_feat e, ps_feat t) {
    double d =
        4.0 * ((e.h > 0) != (t.h > 0)) + 2.0 * (pg_climate_is_ice(e.t) != pg_climate_is_ice(t.t));
    double dh = (e.h - t.h) / 1500.0, dt = (e.t - t.t) / 6.0,
           dp = (sqrt(fmax(e.p, 0)) - sqrt(fmax(t.p, 0))) / 10.0;
    return d + dh * dh + dt * dt + dp * dp;
}

uint32_t pg_ps_world_pick(const pg_ps_ctx *c, int r, int f, int x, int y) {
    const pg_synth_exemplar *ex = c->ex;
    const int E = ex->face_size, b = E / PS_WORLD_EXEMPLAR_N, s = c->s_top;
    const uint64_t seed = c->p->synth.seed;
    const ps_feat t = target(c->p->world, r, f, x, y);
    double best = INFINITY;
    uint32_t q = 0, cand[PS_WORLD_DRAWS];
    size_t cell[PS_WORLD_DRAWS];
    /* the draws first, their level heights prefetched (random reads), then the match */
    for (int k = 0; k < PS_WORLD_DRAWS; k++) {
        uint32_t a = pg_hash_texel(seed, s, f, x, y, 64 + 2 * k);
        uint32_t bb = pg_hash_texel(seed, s, f, x, y, 65 + 2 * k);
        int ef = (int)(a % 6u), u = (int)((a >> 3) % (uint32_t)E), v = (int)(bb % (uint32_t)E);
        cell[k] = ((size_t)ef * PS_WORLD_EXEMPLAR_N + v / b) * PS_WORLD_EXEMPLAR_N + u / b;
        cand[k] = pg_synth_pack(ef, u, v);
        __builtin_prefetch(ex->app[s] + pg_synth_texel(ex, cand[k]) * PG_SYNTH_MAX_DIMS);
    }
    for (int k = 0; k < PS_WORLD_DRAWS; k++) {
        ps_feat e = {pg_synth_level_height(ex, s, cand[k]) - ex->sea_level, c->world_t[cell[k]],
                     c->world_p[cell[k]]};
        double d = distance(e, t);
        if (d < best) best = d, q = cand[k];
    }
    return q;
}

/* The guide, the type mask and the temperature of level r from the macro world, in one
 * pass over the rows this process owns (pg_planet_world_level_climate), one call for
 * each run of consecutive owned rows (the whole planet in one without MPI: each call
 * interleaves the world's fields afresh); whichever the params give as maps of their
 * own is left to pg_ps_guide_level and pg_ps_types_level. */
pg_status pg_ps_world_level(pg_ps_ctx *c, int r, pg_error *err) {
    const bool guide = pg_ps_world_guide(c->p), types = pg_ps_world_types(c->p),
               temp = c->ttemp != NULL;
    if (!guide && !types && !temp) return PG_OK;
    pg_status st = PG_OK;
    int64_t run0 = -1, run1 = -1; /* the run of global rows [run0, run1) not yet done */
    for (int f = 0; f <= 6 && !st; f++) {
        int y0 = 0, y1 = 0;
        if (f < 6) pg_ps_owned_rows(c, r, f, &y0, &y1);
        const int64_t a = (int64_t)f * r + y0, b = (int64_t)f * r + y1;
        if (f < 6 && y0 < y1 && a == run1) { /* continues the run */
            run1 = b;
            continue;
        }
        if (run0 < run1) {
            const size_t o = (size_t)run0 * r;
            st = pg_planet_world_level_climate(
                c->p->world, r, run0, run1, guide ? c->guide + o : NULL, types ? c->mask + o : NULL,
                temp ? c->ttemp + o : NULL, err);
        }
        run0 = a, run1 = y0 < y1 ? b : a;
    }
    return st;
}
