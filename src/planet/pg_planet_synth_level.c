/* pg_planet_synth_level.c - one level of the planet synthesis and the operations on it:
 * the level storage (six faces with a one-texel border), the face borders refreshed
 * across the seams through the integer seam maps of pg_cube.h (EarthGen's adjacency
 * map, made exact), the coarsest level's initialisation and the land/ocean agreement of
 * layout earth, upsampling and jitter, and the correction sub-pass over all tiles with
 * the polar-ring split (docs/generate.md, "Method": "Level-synchronous", "Quarter-turn
 * seams", "Pyramid", "Layout earth").
 *
 * Every operation works per owned tile when the distribution hooks are set (docs/mpi.md,
 * "What is distributed, and how"): a tile's texels depend only on values the hooks'
 * exchange provides, so every process computes the same bits as a single one. */
#include "pg_hash.h"
#include "pg_huge.h"
#include "pg_planet_synth_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------- level storage ---------------------------------- */

pg_ps_window pg_ps_level_window(const pg_ps_ctx *c, int scale, int r) {
    const pg_planet_synth_params *p = c->p;
    pg_ps_window w = {.whole = true};
    for (int f = 0; f < 6; f++)
        w.y0[f] = 0, w.y1[f] = r;
    if (!p->dist || scale == c->s_top || r % c->T != 0) return w;
    if (pg_ps_gainpit_at(c, scale, r) && !pg_ps_dist_pits(c, r)) return w;
    if (p->layout == PG_LAYOUT_EARTH && c->keep > 0 && scale == c->s_top - c->keep + 1 &&
        !pg_ps_dist_sum(c, r))
        return w;
    if (scale == 0 && !pg_ps_dist_final(c) && ((p->pits && p->final_pits) || p->pit_stats))
        return w;
    w.whole = false;
    for (int f = 0; f < 6; f++) {
        pg_ps_owned_rows(c, r, f, &w.y0[f], &w.y1[f]);
        if (w.y0[f] < w.y1[f]) w.y0[f] -= PG_PS_WINDOW_MARGIN, w.y1[f] += PG_PS_WINDOW_MARGIN;
    }
    return w;
}

/* Open the window's rows of a 6-face array of r + 2 pad texels per edge. */
pg_status pg_ps_rows_open(const pg_ps_window *w, int r, int pad, size_t elem, pg_span *span,
                          pg_error *err) {
    const size_t side = (size_t)r + 2 * (size_t)pad, row = side * elem, face = side * row;
    pg_status st = PG_OK;
    for (int f = 0; f < 6 && !st; f++) {
        int a = w->whole ? -pad : w->y0[f], b = w->whole ? r + pad : w->y1[f];
        a = a < -pad ? -pad : a, b = b > r + pad ? r + pad : b;
        if (a < b)
            st = pg_span_open(span, (size_t)f * face + (size_t)(a + pad) * row,
                              (size_t)(b - a) * row, err);
    }
    return st;
}

/* A 6-face array of level r with pad border texels around each face: malloc'd whole in
 * one process (zeroed with zero), reserved with the window's rows opened (zeroed)
 * when distributed. */
pg_status pg_ps_rows_alloc(const pg_ps_ctx *c, const pg_ps_window *w, int r, int pad, size_t elem,
                           bool zero, void **out, pg_span *span, pg_error *err) {
    const size_t side = (size_t)r + 2 * (size_t)pad, bytes = 6 * side * side * elem;
    *span = (pg_span){0};
    *out = NULL;
    if (!c->p->dist) {
        *out = zero ? pg_huge_calloc(bytes, 1) : pg_huge_malloc(bytes);
        return *out ? PG_OK
                    : pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory at %d^2", r);
    }
    pg_status st = pg_span_reserve(span, bytes, err);
    if (!st) st = pg_ps_rows_open(w, r, pad, elem, span, err);
    if (st) pg_span_free(span);
    *out = span->base;
    return st;
}

void pg_ps_rows_free(void *p, pg_span *span) {
    if (span->base)
        pg_span_free(span);
    else
        free(p);
}

pg_status pg_ps_level_alloc(const pg_ps_ctx *c, pg_ps_level *L, int scale, int r) {
    L->r = r;
    L->st = r + 2;
    L->fsz = (size_t)(r + 2) * (r + 2);
    L->win = pg_ps_level_window(c, scale, r);
    void *S = NULL, *V = NULL;
    pg_error e = {0};
    pg_status st = pg_ps_rows_alloc(c, &L->win, r, 1, sizeof *L->S, false, &S, &L->sS, &e);
    if (!st) st = pg_ps_rows_alloc(c, &L->win, r, 1, sizeof *L->V, false, &V, &L->sV, &e);
    L->S = S, L->V = V;
    return st;
}

void pg_ps_level_free(pg_ps_level *L) {
    pg_ps_rows_free(L->S, &L->sS);
    pg_ps_rows_free(L->V, &L->sV);
    L->S = NULL;
    L->V = NULL;
}

static pg_synth_view face_view(const pg_ps_level *L, int f) {
    size_t o = pg_ps_at(L, f, 0, 0);
    pg_synth_view v = {L->S + o, L->V + o, NULL, L->st, L->r, L->r, f, 0, 0, L->r};
    return v;
}

static pg_synth_view tile_view(const pg_ps_level *L, int f, int x0, int y0, int w, int h) {
    size_t o = pg_ps_at(L, f, x0, y0);
    pg_synth_view v = {L->S + o, L->V + o, NULL, L->st, w, h, f, x0, y0, L->r};
    return v;
}

/* ------------------------------ face borders, exchange ------------------------------ */

/* Does this process own a texel of face f within Chebyshev distance d of (x, y) (a
 * texel of the face or of its border)? Always, without distribution. */
bool pg_ps_owned_near(const pg_ps_ctx *c, int r, int f, int x, int y, int d) {
    if (!c->p->dist) return true;
    const int ts = r / c->T;
    int xa = x - d < 0 ? 0 : x - d, xb = x + d >= r ? r - 1 : x + d;
    int ya = y - d < 0 ? 0 : y - d, yb = y + d >= r ? r - 1 : y + d;
    for (int ty = ya / ts; ty <= yb / ts; ty++)
        for (int tx = xa / ts; tx <= xb / ts; tx++)
            if (pg_ps_owns(c, f, tx, ty)) return true;
    return false;
}

/* The rows [*y0, *y1) of face f, at a level of r texels per face edge, that hold this
 * process's tiles (every row without distribution; an empty range when it owns none of
 * the face). Per-texel fields (type mask, guide) are computed on these rows only. */
void pg_ps_owned_rows(const pg_ps_ctx *c, int r, int f, int *y0, int *y1) {
    *y0 = 0, *y1 = r;
    if (!c->p->dist) return;
    const int ts = r / c->T;
    int lo = c->T, hi = -1;
    for (int ty = 0; ty < c->T; ty++)
        for (int tx = 0; tx < c->T; tx++)
            if (pg_ps_owns(c, f, tx, ty)) {
                lo = ty < lo ? ty : lo;
                hi = ty > hi ? ty : hi;
            }
    *y0 = hi < 0 ? 0 : lo * ts;
    *y1 = hi < 0 ? 0 : (hi + 1) * ts;
}

/* all: every border texel, for a level gathered whole. */
pg_status pg_ps_border_build(const pg_ps_ctx *c, const pg_ps_level *L, int ts, bool all,
                             pg_ps_border *b, pg_error *err) {
    pg_cube_grid g;
    pg_status st = pg_cube_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, c->T, ts, err);
    if (st) return st;
    const int r = L->r;
    pg_ps_rows_free(b->orient, &b->sorient); /* a fresh zeroed map per level, in its window */
    void *o = NULL;
    st = pg_ps_rows_alloc(c, &L->win, r, 1, 1, true, &o, &b->sorient, err);
    b->orient = o;
    if (st) return st;
    size_t nfar = 0, cap = (size_t)6 * 4 * (r + 1);
    b->n = b->nlocal = 0;
    for (int f = 0; f < 6; f++)
        for (int y = -1; y <= r; y++)
            for (int x = -1; x <= r; x++) {
                if (x >= 0 && x < r && y >= 0 && y < r) continue;
                if (!all && !pg_ps_owned_near(c, r, f, x, y, 2)) continue;
                int rot;
                int64_t id = pg_cube_wrap(&g, f, x, y, &rot);
                int64_t per = (int64_t)r * r;
                int sf = (int)(id / per), sy = (int)(id % per / r), sx = (int)(id % r);
                size_t dst = pg_ps_at(L, f, x, y), src = pg_ps_at(L, sf, sx, sy);
                b->orient[dst] = (uint8_t)((4 - rot) & 3);
                if (all || !c->p->dist || pg_ps_owned_at(c, r, sf, sx, sy)) {
                    b->dst[b->nlocal] = dst, b->src[b->nlocal++] = src;
                } else { /* listed from the end, moved after the local ones below */
                    nfar++;
                    b->dst[cap - nfar] = dst, b->src[cap - nfar] = src;
                }
            }
    for (size_t k = 0; k < nfar; k++)
        b->dst[b->nlocal + k] = b->dst[cap - nfar + k],
                           b->src[b->nlocal + k] = b->src[cap - nfar + k];
    b->n = b->nlocal + nfar;
    return PG_OK;
}

/* Copy the border texels from their sources: the local ones, or all of them after the
 * level was gathered whole (whole). */
void pg_ps_border_refresh(const pg_ps_border *b, pg_ps_level *L, bool whole) {
    size_t n = whole ? b->n : b->nlocal;
    for (size_t i = 0; i < n; i++) {
        L->S[b->dst[i]] = L->S[b->src[i]];
        L->V[b->dst[i]] = L->V[b->src[i]];
    }
}

pg_status pg_ps_exchange(const pg_ps_ctx *c, int scale, const pg_ps_level *L, int width,
                         pg_error *err) {
    const pg_planet_synth_dist *d = c->p->dist;
    if (!d) return PG_OK;
    pg_planet_level pl = {scale, L->r, c->S >> scale, c->T, (size_t)L->st, L->fsz, L->S, L->V};
    return d->exchange(d->user, &pl, width, err);
}

/* -------------------------------- the coarsest level -------------------------------- */

static uint32_t exemplar_at_direction(const pg_synth_exemplar *ex, int r, int f, int x, int y) {
    const int E = ex->face_size;
    int u = (int)(((int64_t)2 * x + 1) * E / (2 * r)),
        v = (int)(((int64_t)2 * y + 1) * E / (2 * r));
    return pg_synth_pack(f, u, v);
}

/* Coarsest level: the exemplar at the same direction (layout earth), the best feature
 * match with the macro world (layout world, pg_planet_synth_world.c), else hashed
 * random texels; with a guide, the best of 16 hashed draws by level height. */
void pg_ps_init_top(pg_ps_ctx *c, pg_ps_level *L) {
    const pg_synth_exemplar *ex = c->ex;
    const int r = L->r, s = c->s_top, E = ex->face_size;
    const uint64_t seed = c->p->synth.seed;
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * r; row++) {
        int f = row / r, y = row % r;
        for (int x = 0; x < r; x++) {
            uint32_t q;
            if (c->p->layout == PG_LAYOUT_EARTH) {
                q = exemplar_at_direction(ex, r, f, x, y);
            } else if (c->p->layout == PG_LAYOUT_WORLD) {
                q = pg_ps_world_pick(c, r, f, x, y);
            } else {
                int ndraw = c->guide ? 16 : 1;
                float g = c->guide ? c->guide[((size_t)f * r + y) * r + x] : 0, best = INFINITY;
                q = 0;
                for (int k = 0; k < ndraw; k++) {
                    uint32_t a = pg_hash_texel(seed, 99, f, x, y, 7 + 2 * k);
                    uint32_t b = pg_hash_texel(seed, 99, f, x, y, 8 + 2 * k);
                    uint32_t cand = pg_synth_pack((int)(a % 6u), (int)((a >> 3) % (uint32_t)E),
                                                  (int)(b % (uint32_t)E));
                    float d = fabsf(pg_synth_level_height(ex, s, cand) - g);
                    if (k == 0 || d < best) best = d, q = cand;
                }
            }
            L->S[pg_ps_at(L, f, x, y)] = q;
            L->V[pg_ps_at(L, f, x, y)] = 0;
        }
    }
}

void pg_ps_land_agreement(pg_ps_ctx *c, int scale, const pg_ps_level *L) {
    const int r = L->r;
    uint64_t agree = 0;
#pragma omp parallel for schedule(static) reduction(+ : agree)
    for (int row = 0; row < 6 * r; row++) {
        int f = row / r, y = row % r;
        for (int x = 0; x < r; x++) {
            if (pg_ps_dist_sum(c, r) && !pg_ps_owned_at(c, r, f, x, y)) continue;
            size_t i = pg_ps_at(L, f, x, y);
            float h = pg_synth_level_height(c->ex, scale, L->S[i]) + L->V[i];
            float he =
                pg_synth_level_height(c->ex, scale, exemplar_at_direction(c->ex, r, f, x, y));
            agree += (h > c->ex->sea_level) == (he > c->ex->sea_level);
        }
    }
    double total = (double)agree;
    if (pg_ps_dist_sum(c, r)) total = c->p->dist->sum(c->p->dist->user, total);
    c->info->land_agreement = total / (6.0 * r * r);
}

/* ------------------------------- upsampling and jitter ------------------------------- */

static double jitter_for(const pg_ps_ctx *c, int scale) {
    if (c->p->layout == PG_LAYOUT_EARTH && scale > c->s_top - c->keep) return 0;
    return pg_synth_jitter_for(&c->p->synth, scale);
}

void pg_ps_jitter_level(const pg_ps_ctx *c, int scale, pg_ps_level *L) {
    double r = jitter_for(c, scale);
    const int ts = c->S >> scale;
    for (int f = 0; f < 6; f++) {
        if (!c->p->dist) {
            pg_synth_view v = face_view(L, f);
            pg_synth_jitter(c->ex, scale, r, c->p->synth.seed, &v);
            continue;
        }
        for (int t = 0; t < c->T * c->T; t++) /* the jitter hashes global texel ids */
            if (pg_ps_owns(c, f, t % c->T, t / c->T)) {
                pg_synth_view v = tile_view(L, f, t % c->T * ts, t / c->T * ts, ts, ts);
                pg_synth_jitter(c->ex, scale, r, c->p->synth.seed, &v);
            }
    }
}

/* Upsample the parent level into the child (per owned tile with dist: a child texel
 * reads only its parent texel, and tiles nest across levels). */
void pg_ps_upsample_level(const pg_ps_ctx *c, int s, const pg_ps_level *parent,
                          pg_ps_level *child) {
    const int pts = c->S >> (s + 1);
    for (int f = 0; f < 6; f++) {
        if (!c->p->dist) {
            pg_synth_view pv = face_view(parent, f), cv = face_view(child, f);
            pg_synth_upsample(c->ex, s, &pv, &cv);
            continue;
        }
        for (int t = 0; t < c->T * c->T; t++)
            if (pg_ps_owns(c, f, t % c->T, t / c->T)) {
                int x = t % c->T * pts, y = t / c->T * pts;
                pg_synth_view pv = tile_view(parent, f, x, y, pts, pts),
                              cv = tile_view(child, f, 2 * x, 2 * y, 2 * pts, 2 * pts);
                pg_synth_upsample(c->ex, s, &pv, &cv);
            }
    }
}

/* ------------------------------------ correction ------------------------------------ */

/* TEST ONLY: correct one tile in a private copy whose halo continues its own edge
 * (as the flat driver does), i.e. without its neighbours. */
static void correct_tile_alone(const pg_ps_ctx *c, int scale, int parity, const pg_synth_view *v) {
    const int w = v->w, hgt = v->h, st = w + 2, h = 1 << scale;
    uint32_t *S = malloc(sizeof *S * (size_t)st * (hgt + 2));
    float *V = malloc(sizeof *V * (size_t)st * (hgt + 2));
    if (!S || !V) {
        free(S), free(V);
        return;
    }
    for (int y = -1; y <= hgt; y++)
        for (int x = -1; x <= w; x++) {
            int cx = x < 0 ? 0 : (x >= w ? w - 1 : x), cy = y < 0 ? 0 : (y >= hgt ? hgt - 1 : y);
            ptrdiff_t src = (ptrdiff_t)cy * v->stride + cx, dst = (ptrdiff_t)(y + 1) * st + x + 1;
            S[dst] = pg_synth_offset(c->ex, v->S[src], h * (x - cx), h * (y - cy));
            V[dst] = v->V[src];
        }
    pg_synth_view t = {S + st + 1, V + st + 1, NULL, st, w, hgt, v->face, v->gx, v->gy, v->face_r};
    pg_synth_correct_subpass(c->ex, scale, &c->p->synth, parity, &t);
    for (int y = 0; y < hgt; y++)
        for (int x = 0; x < w; x++) {
            v->S[(ptrdiff_t)y * v->stride + x] = t.S[(ptrdiff_t)y * st + x];
            v->V[(ptrdiff_t)y * v->stride + x] = t.V[(ptrdiff_t)y * st + x];
        }
    free(S);
    free(V);
}

static bool polar(int f) {
    return f == PG_CUBE_FACE_PZ || f == PG_CUBE_FACE_NZ;
}

static void correct_view(const pg_ps_ctx *c, int scale, int parity, pg_synth_view *v) {
    if (v->w <= 0 || v->h <= 0) return;
    if (c->independent_tiles)
        correct_tile_alone(c, scale, parity, v);
    else
        pg_synth_correct_subpass(c->ex, scale, &c->p->synth, parity, v);
    if (c->use_types) pg_ps_types_fixup(c, scale, parity, v);
}

/* The rectangle [x0, x1) x [y0, y1) of face f as a view. */
static pg_synth_view rect_view(const pg_ps_ctx *c, const pg_ps_level *L, int f, int x0, int y0,
                               int x1, int y1) {
    size_t o = pg_ps_at(L, f, x0, y0);
    pg_synth_view v = {L->S + o, L->V + o, c->bm.orient + o, L->st, x1 - x0, y1 - y0, f, x0,
                       y0,       L->r};
    return v;
}

/* The part of the rectangle [x0, x1) x [y0, y1) of polar face f that lies in this
 * process's tiles (all of it without dist). Sub-passes are order-independent, so
 * correcting a strip piecewise gives the same texels. */
static void correct_rect_owned(const pg_ps_ctx *c, int scale, int parity, const pg_ps_level *L,
                               int f, int x0, int y0, int x1, int y1) {
    const int ts = c->S >> scale;
    if (!c->p->dist) {
        pg_synth_view v = rect_view(c, L, f, x0, y0, x1, y1);
        correct_view(c, scale, parity, &v);
        return;
    }
    for (int ty = y0 / ts; ty * ts < y1; ty++)
        for (int tx = x0 / ts; tx * ts < x1; tx++) {
            if (!pg_ps_owns(c, f, tx, ty)) continue;
            int ax = tx * ts > x0 ? tx * ts : x0, ay = ty * ts > y0 ? ty * ts : y0;
            int bx = (tx + 1) * ts < x1 ? (tx + 1) * ts : x1,
                by = (ty + 1) * ts < y1 ? (ty + 1) * ts : y1;
            pg_synth_view v = rect_view(c, L, f, ax, ay, bx, by);
            correct_view(c, scale, parity, &v);
        }
}

/* One sub-pass over the planet, in two steps. Across a seam with a quarter turn (the
 * 8 seams of the polar faces) the 2 x 2 parity classes of the two faces do not
 * interleave: half the pairs straddling such a seam are in the same class, and if both
 * sides were corrected at once, each from the other's old value, they could never
 * become coherent. So step 1 corrects every tile except the outermost ring of the
 * polar faces, and step 2, after refreshing the borders, corrects that ring against
 * the new values on the other side. Both steps are order-independent, and the split
 * is fixed by the faces, not the tiles. */
pg_status pg_ps_correct_subpass_all(pg_ps_ctx *c, int scale, int parity, pg_ps_level *L,
                                    pg_error *err) {
    const int ts = c->S >> scale, T = c->T, r = L->r;
    const int ntiles = 6 * T * T;
    const bool split = !c->independent_tiles && r > 2;
    pg_status st = pg_ps_exchange(c, scale, L, 1, err);
    if (st) return st;
    pg_ps_border_refresh(&c->bm, L, false);
#pragma omp parallel for schedule(dynamic, 1)
    for (int t = 0; t < ntiles; t++) {
        int f = t / (T * T), tx = t % T, ty = t / T % T;
        if (!pg_ps_owns(c, f, tx, ty)) continue;
        int x0 = tx * ts, y0 = ty * ts, x1 = x0 + ts, y1 = y0 + ts;
        if (split && polar(f)) {
            x0 = x0 < 1 ? 1 : x0, y0 = y0 < 1 ? 1 : y0;
            x1 = x1 > r - 1 ? r - 1 : x1, y1 = y1 > r - 1 ? r - 1 : y1;
        }
        pg_synth_view v = rect_view(c, L, f, x0, y0, x1, y1);
        correct_view(c, scale, parity, &v);
    }
    if (!split) return PG_OK;
    if ((st = pg_ps_exchange(c, scale, L, 1, err))) return st;
    pg_ps_border_refresh(&c->bm, L, false);
    /* the rings of the two polar faces: 4 strips each (bottom, top, left, right) */
#pragma omp parallel for schedule(static)
    for (int k = 0; k < 8; k++) {
        int f = k < 4 ? PG_CUBE_FACE_PZ : PG_CUBE_FACE_NZ, side = k & 3;
        if (side == 0) correct_rect_owned(c, scale, parity, L, f, 0, 0, r, 1);
        if (side == 1) correct_rect_owned(c, scale, parity, L, f, 0, r - 1, r, r);
        if (side == 2) correct_rect_owned(c, scale, parity, L, f, 0, 1, 1, r - 1);
        if (side == 3) correct_rect_owned(c, scale, parity, L, f, r - 1, 1, r, r - 1);
    }
    return PG_OK;
}
