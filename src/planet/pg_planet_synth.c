/* pg_planet_synth.c - the driver of the level-synchronous Lefebvre-Hoppe synthesis of a
 * whole cube-sphere planet (docs/generate.md, "Method"), with Gain-pit pit removal inside
 * the pyramid: the run's context, the pyramid from the coarsest level down, the passes
 * of one level, and the order of delivery (heights, final pit pass, planet). What each
 * step does is in pg_planet_synth_level.c, _types.c, _guide.c, _pits.c and _deliver.c
 * (pg_planet_synth_internal.h lists them); sizes and checks in _params.c.
 *
 * Sources: Lefebvre & Hoppe 2005/2006 (the per-level operations, pg_synth.h); Gain,
 * Merry & Marais 2015 (height offsets V, type constraints); Scott & Dodgson 2021 §4.2
 * (guide blending with exponential weights) and Scott 2020 §4.2.1 (Gain-pit); EarthGen
 * (seed 004 §4.3.4: tiles that read their neighbours' edges through an adjacency map),
 * made exact with the integer seam maps of pg_cube.h.
 *
 * LAYOUT. Each level holds the six faces as (r + 2)^2 arrays of exemplar coordinates S
 * and offsets V, a one-texel border around each face. Tiles are rectangles of a face
 * (S >> s texels at scale s); a tile's view points into the shared face array, so its
 * halo is literally its neighbours' current edge texels. Before every sub-pass the face
 * borders are refreshed from the neighbouring faces through pg_cube_wrap, with the
 * orientation that rotates offsets into the neighbour's frame. Then all tiles of all
 * faces are corrected in parallel: a sub-pass writes one parity class and reads only
 * the other classes and the halo (pg_synth_lefebvre_hoppe.c), so the result is the same
 * for any tile size, any order and any thread count. Levels whose tiles would be smaller
 * than one texel cannot occur: S must be a multiple of 2^s_top (checked).
 *
 * Type fix-up (after each sub-pass, same parity, same tile) and the guide blend and
 * Gain-pit (after each pass, whole planet) keep that property: each reads only values
 * the sub-pass did not write, or runs on the whole planet with a deterministic
 * algorithm. */
#include "pg_huge.h"
#include "pg_planet_synth_internal.h"
#include "pg_planet_synth_testing.h"
#include "pg_span.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------- context ------------------------------------- */

static void ctx_free(pg_ps_ctx *c) {
    free(c->own);
    free(c->bm.dst);
    free(c->bm.src);
    pg_ps_rows_free(c->bm.orient, &c->bm.sorient);
    free(c->etype);
    free(c->eblock);
    for (int t = 0; t < PG_TYPE_COUNT; t++)
        free(c->valid[t]);
    pg_ps_rows_free(c->mask, &c->smask);
    pg_ps_rows_free(c->ttemp, &c->sttemp);
    pg_ps_rows_free(c->guide, &c->sguide);
    free(c->world_t);
    free(c->world_p);
}

static pg_status ctx_init(pg_ps_ctx *c, const pg_synth_exemplar *ex,
                          const pg_planet_synth_params *p, pg_planet_synth_info *info,
                          pg_error *err) {
    memset(c, 0, sizeof *c);
    c->ex = c->given = ex;
    if (ex->map && (c->own = malloc(sizeof *c->own))) {
        *c->own = *ex;
        c->ex = c->own;
    }
    c->p = p;
    c->T = p->tiles;
    c->m = pg_planet_synth_magnification(ex, p);
    c->S = p->tile_size / c->m;
    c->Nout = (int64_t)p->tiles * p->tile_size;
    c->N = c->Nout / c->m;
    c->s_top = pg_ps_top_scale(ex);
    c->keep = pg_planet_synth_keep_levels(ex, p);
    c->info = info;
    size_t nb = (size_t)6 * 4 * (c->N + 2);
    c->bm.dst = malloc(nb * sizeof(size_t));
    c->bm.src = malloc(nb * sizeof(size_t));
    /* the type mask and the guide of each level, at the finest level's size; distributed,
     * reserved with no row open: each level opens its window (prepare_level) */
    const pg_ps_window none = {.whole = false};
    void *mask = NULL, *guide = NULL, *ttemp = NULL;
    pg_status st = PG_OK;
    if (p->types || pg_ps_world_types(p))
        st = pg_ps_rows_alloc(c, &none, (int)c->N, 0, 1, false, &mask, &c->smask, err);
    if (!st && pg_ps_world_climate(p))
        st = pg_ps_rows_alloc(c, &none, (int)c->N, 0, 1, false, &ttemp, &c->sttemp, err);
    c->ttemp = ttemp;
    if (!st && (p->guide || pg_ps_world_guide(p)))
        st =
            pg_ps_rows_alloc(c, &none, (int)c->N, 0, sizeof(float), false, &guide, &c->sguide, err);
    c->mask = mask, c->guide = guide;
    if (st) return st;
    if (!c->bm.dst || !c->bm.src)
        return pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory");
    for (int s = 0; s <= c->s_top; s++)
        c->work_total += 1.0 / ((double)(1 << s) * (1 << s));
    st = pg_ps_types_setup(c, err);
    return st ? st : pg_ps_world_setup(c, err);
}

/* ------------------------------------- the pyramid ------------------------------------- */

/* The mask and the guide share one layout per level (6 r^2, no border): distributed,
 * this level's window of them is opened (what coarser levels opened stays open). */
static pg_status open_level_buffers(pg_ps_ctx *c, const pg_ps_level *L, pg_error *err) {
    pg_status st = PG_OK;
    if (c->smask.base) st = pg_ps_rows_open(&L->win, L->r, 0, 1, &c->smask, err);
    if (!st && c->sttemp.base) st = pg_ps_rows_open(&L->win, L->r, 0, 1, &c->sttemp, err);
    if (!st && c->sguide.base)
        st = pg_ps_rows_open(&L->win, L->r, 0, sizeof(float), &c->sguide, err);
    return st;
}

static pg_status prepare_level(pg_ps_ctx *c, int scale, pg_ps_level *L, pg_error *err) {
    int ts = c->S >> scale;
    pg_status st = open_level_buffers(c, L, err);
    if (!st) st = pg_ps_border_build(c, L, ts, false, &c->bm, err);
    if (!st) st = pg_ps_types_level(c, L->r, ts, err);
    if (!st) st = pg_ps_guide_level(c, L->r, err);
    if (!st) st = pg_ps_world_level(c, L->r, err);
    return st;
}

/* A level read densely (at least one synthesized texel per 4 exemplar texels: the
 * finest two of the default planet) gets its tables copied out of the mapped cache
 * file for its duration; coarser levels touch few of their pages and read the mapping.
 * Not when other processes on the machine share the mapping (dist->shared_exemplar):
 * each copy would be private to its process. */
static pg_status hold_level(pg_ps_ctx *c, int scale, int r, pg_error *err) {
    if (!c->own || 2 * (int64_t)r < c->ex->face_size) return PG_OK;
    if (c->p->dist && c->p->dist->shared_exemplar) return PG_OK;
    int16_t *app;
    uint32_t *kcoh;
    pg_status st = pg_synth_copy_level(c->given, scale, &app, &kcoh, err);
    if (st || !app) return st;
    c->own->app[scale] = app;
    if (kcoh) c->own->kcoh[scale] = kcoh;
    return PG_OK;
}

static void release_level(pg_ps_ctx *c, int scale) {
    if (!c->own) return;
    if (c->own->app[scale] != c->given->app[scale]) free(c->own->app[scale]);
    if (c->own->kcoh[scale] != c->given->kcoh[scale]) free(c->own->kcoh[scale]);
    c->own->app[scale] = c->given->app[scale];
    c->own->kcoh[scale] = c->given->kcoh[scale];
}

static void progress(pg_ps_ctx *c, double units) {
    c->work_done += units;
    if (c->p->progress) c->p->progress(c->p->progress_user, c->work_done / c->work_total);
}

static pg_status run_level(pg_ps_ctx *c, int scale, pg_ps_level *L, pg_error *err) {
    const pg_planet_synth_params *p = c->p;
    double units = (double)L->r * L->r / ((double)c->N * c->N);
    for (int pass = 0; pass < p->synth.passes; pass++) {
        pg_status st = PG_OK;
        for (int sp = 0; sp < 4 && !st; sp++)
            st = pg_ps_correct_subpass_all(c, scale, pg_synth_subpass_order[sp], L, err);
        if (!st) st = pg_ps_after_pass(c, scale, L, err);
        if (st) return st;
        progress(c, units / p->synth.passes);
    }
    if (p->layout == PG_LAYOUT_EARTH && c->keep > 0 && scale == c->s_top - c->keep + 1) {
        /* distributed: each process counts its tiles and the hook sums the counts
         * (without it, the coarse level is gathered) */
        pg_status st = pg_ps_dist_sum(c, L->r) ? PG_OK : pg_ps_exchange(c, scale, L, -1, err);
        if (st) return st;
        pg_ps_land_agreement(c, scale, L);
    }
    return PG_OK;
}

/* The pyramid: the coarsest level, then upsample / jitter / correct down to scale 0.
 * On success *out holds the finest level. */
static pg_status synthesize(pg_ps_ctx *c, pg_ps_level *out, pg_error *err) {
    pg_ps_level cur = {0}, nxt = {0};
    const int r_top = (int)(c->N >> c->s_top);
    if (pg_ps_level_alloc(c, &cur, c->s_top, r_top))
        return pg_ps_level_free(&cur),
               pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory");
    pg_status st = prepare_level(c, c->s_top, &cur, err);
    double t0 = pg_synth_now();
    if (!st) {
        pg_ps_init_top(c, &cur);
        pg_ps_jitter_level(c, c->s_top, &cur);
        st = run_level(c, c->s_top, &cur, err);
    }
    c->info->level_seconds[c->info->nlevels++] = pg_synth_now() - t0;
    for (int s = c->s_top - 1; s >= 0 && !st; s--) {
        t0 = pg_synth_now();
        if (pg_ps_level_alloc(c, &nxt, s, cur.r * 2)) {
            st = pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory at %d^2",
                              cur.r * 2);
            break;
        }
        pg_ps_upsample_level(c, s, &cur, &nxt);
        pg_ps_level_free(&cur);
        cur = nxt;
        nxt = (pg_ps_level){0};
        st = prepare_level(c, s, &cur, err);
        if (!st) {
            pg_ps_jitter_level(c, s, &cur);
            st = hold_level(c, s, cur.r, err);
            if (!st) st = run_level(c, s, &cur, err);
            release_level(c, s);
        }
        c->info->level_seconds[c->info->nlevels++] = pg_synth_now() - t0;
    }
    pg_ps_level_free(&nxt);
    if (st) {
        pg_ps_level_free(&cur);
        return st;
    }
    *out = cur;
    return PG_OK;
}

/* ---------------------------------------- the run ---------------------------------------- */

/* The rows [y0[f], y1[f]) of each face that hold this process's tiles at the delivered
 * size (every row when whole). */
static void owned_face_rows(const pg_ps_ctx *c, bool whole, int64_t *y0, int64_t *y1) {
    for (int f = 0; f < 6; f++) {
        int a = 0, b = (int)c->Nout;
        if (!whole) pg_ps_owned_rows(c, (int)c->Nout, f, &a, &b);
        y0[f] = a, y1[f] = b;
    }
}

/* The delivered heights H: the whole planet in one process; a distributed process that
 * touches only its tiles reserves the planet's range and commits only its tiles' rows
 * (pg_span.h), so its memory and its commit charge follow its tiles. */
static pg_status heights_alloc(const pg_ps_ctx *c, bool whole, float **H, pg_span *span,
                               pg_error *err) {
    const size_t n = (size_t)c->Nout, px = 6 * n * n;
    if (whole) {
        *H = pg_huge_malloc(px * sizeof **H);
        return *H ? PG_OK
                  : pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory (heights)");
    }
    int64_t y0[6], y1[6];
    owned_face_rows(c, whole, y0, y1);
    pg_status st = pg_span_reserve(span, px * sizeof **H, err);
    for (int f = 0; f < 6 && !st; f++)
        if (y1[f] > y0[f])
            st = pg_span_open(span, ((size_t)f * n + (size_t)y0[f]) * n * sizeof **H,
                              (size_t)(y1[f] - y0[f]) * n * sizeof **H, err);
    if (st) pg_span_free(span);
    *H = st ? NULL : span->base;
    return st;
}

/* The delivered planet, the same way: whole, or only this process's tiles' rows. */
static pg_status planet_alloc(const pg_ps_ctx *c, bool whole, pg_planet *out, pg_error *err) {
    const pg_planet_synth_params *p = c->p;
    if (whole)
        return pg_planet_alloc(out, PG_CUBE_DEFAULT_PROJECTION, p->tiles, p->tile_size,
                               pg_ellipsoid_sphere(), err);
    int64_t y0[6], y1[6];
    owned_face_rows(c, whole, y0, y1);
    return pg_planet_alloc_rows(out, PG_CUBE_DEFAULT_PROJECTION, p->tiles, p->tile_size,
                                pg_ellipsoid_sphere(), y0, y1, err);
}

pg_status pg_planet_synth_run(const pg_synth_exemplar *ex, const pg_planet_synth_params *p,
                              pg_planet *out, uint32_t **coords_out, pg_planet_synth_info *info,
                              pg_error *err) {
    return pg_planet_synth_run_testing(ex, p, NULL, out, coords_out, info, err);
}

pg_status pg_planet_synth_run_testing(const pg_synth_exemplar *ex, const pg_planet_synth_params *p,
                                      const pg_planet_synth_testing *testing, pg_planet *out,
                                      uint32_t **coords_out, pg_planet_synth_info *info,
                                      pg_error *err) {
    pg_planet_synth_info local;
    if (!info) info = &local;
    memset(info, 0, sizeof *info);
    info->land_agreement = NAN;
    info->sea_ice_fraction = NAN;
    memset(out, 0, sizeof *out);
    if (coords_out) *coords_out = NULL;
    pg_status st = pg_planet_synth_check(ex, p, err);
    if (st) return st;
    info->peak_bytes_estimate = pg_planet_synth_bytes(p->tiles, p->tile_size, p);
    info->s_top = pg_ps_top_scale(ex);
    pg_ps_ctx c;
    st = ctx_init(&c, ex, p, info, err);
    c.independent_tiles = testing && testing->independent_tiles;
    pg_ps_level L = {0};
    double t0 = pg_synth_now();
    if (!st) st = synthesize(&c, &L, err);
    info->synth_seconds = pg_synth_now() - t0;
    size_t px = (size_t)6 * c.Nout * c.Nout;
    /* Distributed without the pits hooks: the final pit removal and the depression
     * counts are whole-planet steps, run by every process on the whole level
     * (docs/mpi.md); otherwise the magnification needs the two texel rings around
     * this process's tiles, and the hooks exchange what the pits need. */
    bool all = false, whole = true;
    if (!st) {
        all = !pg_ps_dist_final(&c) && ((p->pits && p->final_pits) || p->pit_stats);
        whole = !p->dist || all;
    }
    float *H = NULL;
    pg_span Hs = {0};
    double closed = NAN;
    if (!st) st = heights_alloc(&c, whole, &H, &Hs, err);
    if (!st) {
        st = pg_ps_exchange(&c, 0, &L, all ? -1 : 2, err);
        if (!st && all && p->dist) st = pg_ps_border_build(&c, &L, c.S, true, &c.bm, err);
        if (!st) {
            /* the magnification reads across face seams */
            pg_ps_border_refresh(&c.bm, &L, whole);
            pg_ps_finest_heights(&c, &L, H, whole);
        }
    }
    if (!st) {
        pg_ps_rows_free(L.V, &L.sV); /* S stays for the albedo */
        L.V = NULL;
        st = pg_ps_final_pits(&c, H, whole, &closed, err);
    }
    t0 = pg_synth_now();
    if (!st) st = planet_alloc(&c, whole, out, err);
    if (!st && coords_out && !(*coords_out = pg_huge_malloc(px * sizeof(uint32_t))))
        st = pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory (coords)");
    /* layout world: the sea ice goes on as each texel is delivered */
    pg_sea_ice ice;
    const bool with_ice = p->world && p->sea_ice && p->layout == PG_LAYOUT_WORLD;
    bool ice_ready = false;
    if (!st && with_ice) {
        st = pg_sea_ice_init(&ice, p->world, ex, c.etype, p->synth.seed, c.Nout, err);
        ice_ready = !st;
    }
    if (!st) {
        out->seed = p->synth.seed;
        out->sea_level = ex->sea_level;
        out->closed_land_share_before_final = closed;
        pg_ps_render(&c, &L, H, ice_ready ? &ice : NULL, out, coords_out ? *coords_out : NULL);
    }
    if (ice_ready) pg_sea_ice_free(&ice);
    info->render_seconds = pg_synth_now() - t0;
    if (Hs.base)
        pg_span_free(&Hs);
    else
        free(H);
    pg_ps_level_free(&L);
    ctx_free(&c);
    if (st) {
        pg_planet_free(out);
        if (coords_out) free(*coords_out), *coords_out = NULL;
    }
    return st;
}
