/* pg_planet_synth_pits.c - pit removal in the planet synthesis: Gain-pit (Scott 2020
 * §4.2.1) after each correction pass on the whole cube level (R = E_s(S) + V made
 * pit-free, V += R' - R), preceded by the guide blend, and the final pass on the
 * delivered heights with the depression counts before and after it (docs/generate.md,
 * "Method": "Gain-pit").
 *
 * Every pass uses pit removal whose result depends on no flood order (docs/mpi.md, "Pit
 * removal across ranks"), so a distributed run computes it on each process's tiles
 * through the pits hooks and gets the single process's bits; without the hooks every
 * process runs the same deterministic pass on the gathered level. */
#include "pg_planet_synth_internal.h"
#include "planetgen/pg_drainage.h"

#include <stdlib.h>
#include <string.h>

/* The rows [y0[f], y1[f]) of each face that a pass over the level visits: every row, or
 * with owned_only the rows of this process's tiles, so that a distributed run touches
 * no other memory of the level's planet-sized arrays (docs/mpi.md, "Memory per rank"). */
typedef struct level_rows {
    int y0[6], y1[6];
    bool owned_only;
} level_rows;

static level_rows rows_of(const pg_ps_ctx *c, int r, bool owned_only) {
    level_rows lr = {.owned_only = owned_only};
    for (int f = 0; f < 6; f++) {
        lr.y0[f] = 0, lr.y1[f] = r;
        if (owned_only) pg_ps_owned_rows(c, r, f, &lr.y0[f], &lr.y1[f]);
    }
    return lr;
}

static bool row_visited(const level_rows *lr, int r, int row) {
    int f = row / r, y = row % r;
    return y >= lr->y0[f] && y < lr->y1[f];
}

/* Contiguous 6 r^2 copies of the reconstructed heights R = E_s(S) + V and of V. With
 * owned_only, the texels of other processes' tiles in the visited rows get R = Vc = 0
 * (the pits hook exchanges what it reads of them) and the other rows are not touched. */
static void reconstruct(const pg_ps_ctx *c, int scale, const pg_ps_level *L, const level_rows *lr,
                        float *R, float *Vc) {
    const int r = L->r;
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * r; row++) {
        if (!row_visited(lr, r, row)) continue;
        int f = row / r, y = row % r;
        for (int x = 0; x < r; x++) {
            size_t i = pg_ps_at(L, f, x, y), j = ((size_t)f * r + y) * r + x;
            if (lr->owned_only && !pg_ps_owned_at(c, r, f, x, y)) {
                R[j] = 0;
                if (Vc) Vc[j] = 0;
                continue;
            }
            R[j] = pg_synth_level_height(c->ex, scale, L->S[i]) + L->V[i];
            if (Vc) Vc[j] = L->V[i];
        }
    }
}

static void store_offsets(const pg_ps_ctx *c, const level_rows *lr, const float *Vc,
                          pg_ps_level *L) {
    const int r = L->r;
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * r; row++) {
        if (!row_visited(lr, r, row)) continue;
        int f = row / r, y = row % r;
        for (int x = 0; x < r; x++)
            if (!lr->owned_only || pg_ps_owned_at(c, r, f, x, y))
                L->V[pg_ps_at(L, f, x, y)] = Vc[((size_t)f * r + y) * r + x];
    }
}

static pg_pits_opts pits_opts(const pg_ps_ctx *c, pg_pits_method m) {
    pg_pits_opts o;
    pg_planet_synth_pits_opts(m, c->ex->sea_level, &o);
    return o;
}

/* Gain-pit on the owned tiles through the hook: R' = remove(R) there, Vc += R' - R. */
static pg_status gainpit_dist(pg_ps_ctx *c, const pg_ps_level *L, const level_rows *lr,
                              const float *R, float *Vc, const pg_pits_opts *o, pg_error *err) {
    const int r = L->r;
    void *buf = NULL;
    pg_span span;
    pg_status st = pg_ps_rows_alloc(c, &L->win, r, 0, sizeof(float), false, &buf, &span, err);
    float *R2 = buf;
    if (st) return st;
    for (int f = 0; f < 6; f++) /* the visited rows only: the others are never touched */
        if (lr->y0[f] < lr->y1[f])
            memcpy(R2 + ((size_t)f * r + lr->y0[f]) * r, R + ((size_t)f * r + lr->y0[f]) * r,
                   (size_t)(lr->y1[f] - lr->y0[f]) * r * sizeof *R2);
    const pg_planet_synth_dist *d = c->p->dist;
    st = d->pits(d->user, (uint32_t)r, c->T, R2, o, err);
    uint64_t changed = 0;
    for (int f = 0; !st && f < 6; f++)
        for (int y = lr->y0[f]; y < lr->y1[f]; y++)
            for (int x = 0; x < r; x++) {
                size_t i = ((size_t)f * r + y) * r + x;
                if (!pg_ps_owned_at(c, r, f, x, y) || R2[i] == R[i]) continue;
                Vc[i] += R2[i] - R[i];
                changed++;
            }
    c->info->pit_cells_changed += changed;
    pg_ps_rows_free(R2, &span);
    return st;
}

/* The guide blend alone (a level without Gain-pit): R, the blend and the stored offsets
 * fused into one pass over the visited texels, V <- V + w (G - (E_s(S) + V)), the same
 * float operations in the same order as the three passes, without their two level-sized
 * buffers (whose fresh pages cost more than the blend). */
#define GUIDE_AHEAD 8

static void guide_only(const pg_ps_ctx *c, int scale, pg_ps_level *L, const level_rows *lr) {
    const int r = L->r;
    const float w = pg_ps_guide_w(c, scale);
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * r; row++) {
        if (!row_visited(lr, r, row)) continue;
        int f = row / r, y = row % r;
        for (int x = 0; x < r; x++) {
            if (lr->owned_only && !pg_ps_owned_at(c, r, f, x, y)) continue;
            size_t i = pg_ps_at(L, f, x, y), j = ((size_t)f * r + y) * r + x;
            if (x + GUIDE_AHEAD < r) /* E_s a few texels on: a random read */
                __builtin_prefetch(c->ex->app[scale] +
                                   pg_synth_texel(c->ex, L->S[i + GUIDE_AHEAD]) *
                                       PG_SYNTH_MAX_DIMS);
            float R = pg_synth_level_height(c->ex, scale, L->S[i]) + L->V[i];
            float d = w * (c->guide[j] - R);
            L->V[i] = L->V[i] + d;
        }
    }
}

/* After a correction pass: the guide blend R <- w G + (1 - w) R (as V += w (G - R)),
 * then Gain-pit (R' pit-free, V += R' - R). Distributed, Gain-pit runs through the
 * pits hook on the owned tiles; without the hook (or at levels too coarse for the
 * tiles) every process gathers the level and runs it whole (deterministic, so all
 * agree; docs/mpi.md). The texels outside the owned tiles are stale either way and
 * are refreshed by the next exchange before anything reads them. */
pg_status pg_ps_after_pass(pg_ps_ctx *c, int scale, pg_ps_level *L, pg_error *err) {
    bool pits = pg_ps_gainpit_at(c, scale, L->r);
    if (!pits && !c->guide) return PG_OK;
    if (!pits) {
        const level_rows lr = rows_of(c, L->r, c->p->dist != NULL);
        guide_only(c, scale, L, &lr);
        return PG_OK;
    }
    const int r = L->r;
    bool gather = pits && !pg_ps_dist_pits(c, r);
    pg_status xs = gather ? pg_ps_exchange(c, scale, L, -1, err) : PG_OK;
    if (xs) return xs;
    /* planet-sized in one process; distributed, only the level's window */
    void *rb = NULL, *vb = NULL;
    pg_span rs = {0}, vs = {0};
    pg_status st = pg_ps_rows_alloc(c, &L->win, r, 0, sizeof(float), false, &rb, &rs, err);
    if (!st) st = pg_ps_rows_alloc(c, &L->win, r, 0, sizeof(float), false, &vb, &vs, err);
    float *R = rb, *Vc = vb;
    if (st) {
        pg_ps_rows_free(R, &rs), pg_ps_rows_free(Vc, &vs);
        return st;
    }
    const level_rows lr = rows_of(c, r, c->p->dist && !gather);
    reconstruct(c, scale, L, &lr, R, Vc);
    for (int f = 0; c->guide && f < 6; f++) {
        size_t a = ((size_t)f * r + lr.y0[f]) * r, b = ((size_t)f * r + lr.y1[f]) * r;
        if (a < b) pg_ps_guide_blend(c, scale, b - a, R + a, Vc + a, c->guide + a);
    }
    if (pits) {
        double t0 = pg_synth_now();
        pg_pits_topo topo;
        pg_pits_opts o = pits_opts(c, c->p->pit_method);
        pg_pits_result res;
        if (pg_ps_dist_pits(c, r)) {
            st = gainpit_dist(c, L, &lr, R, Vc, &o, err);
        } else {
            st = pg_pits_topo_cube(&topo, (uint32_t)r, err);
            if (!st) st = pg_pits_correct_offsets(&topo, R, Vc, &o, &res, err);
            if (!st) c->info->pit_cells_changed += res.raised + res.lowered;
        }
        c->info->pits_seconds += pg_synth_now() - t0;
    }
    if (!st) store_offsets(c, &lr, Vc, L);
    pg_ps_rows_free(R, &rs);
    pg_ps_rows_free(Vc, &vs);
    return st;
}

/* The final removal and the counts: on the whole planet in this process, or through
 * the hooks on this process's tiles (H valid there only) when there are hooks for
 * both. */
bool pg_ps_dist_final(const pg_ps_ctx *c) {
    const pg_planet_synth_dist *d = c->p->dist;
    return pg_ps_dist_pits(c, (int)c->Nout) && (!c->p->pit_stats || d->stats);
}

static pg_status final_remove(const pg_ps_ctx *c, const pg_pits_topo *topo, float *H,
                              const pg_pits_opts *o, pg_error *err) {
    const pg_planet_synth_dist *d = c->p->dist;
    if (pg_ps_dist_final(c)) return d->pits(d->user, (uint32_t)c->Nout, c->T, H, o, err);
    return pg_pits_remove(topo, H, o, NULL, err);
}

static pg_status final_stats(const pg_ps_ctx *c, const pg_pits_topo *topo, const float *H,
                             const pg_pits_opts *o, const pg_pits_area *area, pg_pits_stats *out,
                             pg_error *err) {
    const pg_planet_synth_dist *d = c->p->dist;
    if (pg_ps_dist_final(c))
        return d->stats(d->user, (uint32_t)c->Nout, c->T, H, o, area, out, err);
    return pg_pits_stats_compute(topo, H, o, area, out, err);
}

/* whole: H holds every texel, not only this process's tiles. closed receives the
 * closed-land share of H before the final pass (pg_drainage.h), a whole-planet measure:
 * taken with the depression counts (pit_stats) when H is whole, NaN otherwise. */
pg_status pg_ps_final_pits(pg_ps_ctx *c, float *H, bool whole, double *closed, pg_error *err) {
    const pg_planet_synth_params *p = c->p;
    pg_pits_topo topo;
    pg_status st = pg_pits_topo_cube(&topo, (uint32_t)c->Nout, err);
    if (st) return st;
    pg_pits_opts o = pits_opts(c, p->final_method);
    pg_pits_area area = {0};
    area.constant = 4.0 * 3.14159265358979323846 * PG_ELLIPSOID_SPHERE_RADIUS_M *
                    PG_ELLIPSOID_SPHERE_RADIUS_M / (6.0 * (double)c->Nout * (double)c->Nout);
    double t0 = pg_synth_now();
    if (p->pit_stats && whole)
        st = pg_drainage_closed_land_share(H, c->Nout, PG_CUBE_DEFAULT_PROJECTION, NULL,
                                           c->ex->sea_level, closed, err);
    if (!st && p->pit_stats && p->pits && p->final_pits && !pg_ps_dist_final(c)) {
        /* in one process the removal's own floods give the counts (pg_pits_remove_counted:
         * the same figures and the same result as counting around pg_pits_remove) */
        double t1 = pg_synth_now();
        st = pg_pits_remove_counted(&topo, H, &o, &area, NULL, &c->info->before, &c->info->after,
                                    err);
        double t2 = pg_synth_now();
        c->info->final_pits_seconds = t2 - t1;
        c->info->pit_stats_seconds = t1 - t0;
        return st;
    }
    if (!st && p->pit_stats) st = final_stats(c, &topo, H, &o, &area, &c->info->before, err);
    double t1 = pg_synth_now();
    if (!st && p->pits && p->final_pits) st = final_remove(c, &topo, H, &o, err);
    double t2 = pg_synth_now();
    if (!st && p->pit_stats) st = final_stats(c, &topo, H, &o, &area, &c->info->after, err);
    c->info->final_pits_seconds = t2 - t1;
    c->info->pit_stats_seconds = (t1 - t0) + (pg_synth_now() - t2);
    return st;
}
