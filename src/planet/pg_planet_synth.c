/* pg_planet_synth.c - level-synchronous Lefebvre-Hoppe synthesis of a whole cube-sphere
 * planet (issue 5), with Gain-pit pit removal inside the pyramid (issue 6).
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
#include "planetgen/pg_planet_synth.h"
#include "pg_planet_synth_testing.h"
#include "planetgen/pg_drainage.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pg_planet_synth_params_default(pg_planet_synth_params *p) {
    memset(p, 0, sizeof *p);
    p->tiles = 4;
    p->tile_size = 256;
    pg_synth_params_default(&p->synth);
    p->layout = PG_LAYOUT_EARTH;
    p->keep_levels = PG_PLANET_KEEP_AUTO;
    p->guide_alpha = 0.8;
    p->type_mask = PG_TYPES_ALL;
    p->pits = true;
    p->pit_skip_levels = 1;
    p->pit_method = PG_PITS_BREACH;
    p->final_pits = true;
    p->final_method = PG_PITS_BREACH;
    p->pit_stats = true;
}

static int top_scale(const pg_synth_exemplar *ex) {
    return ex->levels - 1;
}

/* The synthesis copies exemplar texels one to one, so a planet whose faces have more
 * texels than the exemplar cube's (the default: 1024 against 512) would show every
 * exemplar feature at 1/m of its size, and with layout earth (coarsest texels at the
 * same direction, m times closer in the exemplar than the synthesis spaces them) lay
 * each feature down m times per axis: the Arctic archipelago became a lattice of
 * repeated islands, Novaya Zemlya two parallel copies. So synthesize at N / m, the
 * largest power-of-two reduction that keeps at least the exemplar's face size and a
 * whole pyramid per tile, and magnify at delivery. */
int pg_planet_synth_magnification(const pg_synth_exemplar *ex, const pg_planet_synth_params *p) {
    const int64_t n = (int64_t)p->tiles * p->tile_size;
    const int need = 1 << top_scale(ex);
    int m = 1;
    while (n / (2 * m) >= ex->face_size && p->tile_size % (2 * m) == 0 &&
           (p->tile_size / (2 * m)) % need == 0)
        m *= 2;
    return m;
}

/* Layout earth keeps, unjittered, the levels whose texel spacing is at least 1/32 of a
 * face (about 280 km on the Earth), whatever the exemplar's resolution: spacing 2^s
 * exemplar texels of a face of E, so s >= log2(E) - 5. Counting the levels by number
 * instead would keep twice as fine a structure at E = 1024 as at 512 and make a larger
 * exemplar a closer copy of the Earth, not a finer planet. At least the coarsest level
 * is kept, or the layout would not be the Earth's. */
int pg_planet_synth_keep_levels(const pg_synth_exemplar *ex, const pg_planet_synth_params *p) {
    if (p->keep_levels != PG_PLANET_KEEP_AUTO) return p->keep_levels;
    int log2e = 0;
    while ((1 << (log2e + 1)) <= ex->face_size)
        log2e++;
    int keep = top_scale(ex) - (log2e - 5) + 1;
    return keep < 1 ? 1 : (keep > ex->levels ? ex->levels : keep);
}

/* The exemplar cube as fine as the planet (so nothing is magnified), within
 * [PG_PLANET_FACE_MIN, PG_PLANET_FACE_AUTO_MAX]: below 512 the 6 analysed levels do not
 * fit, and above the cap the exemplar outgrows a workstation (about 200 B per exemplar
 * texel while it is prepared: 5 GB at 2048, 20 GB at 4096) and the default source data
 * holds no finer detail (Blue Marble has 675 px per face, Marble's relief 2700). */
int pg_planet_synth_face_size(int tiles, int tile_size) {
    int64_t n = (int64_t)tiles * tile_size;
    int e = PG_PLANET_FACE_MIN;
    while (e < n && e < PG_PLANET_FACE_AUTO_MAX)
        e *= 2;
    return e;
}

/* Bytes per finest texel, by phase (see pg_planet_synth_run for the order of
 * allocations): synthesis (S, V with borders, the parent level, orient, type mask,
 * guide, Gain-pit at the next-finest level) and delivery (planet 16, S and H 8, and
 * what the final pit removal allocates, about 10). */
double pg_planet_synth_bytes(int tiles, int tile_size, const pg_planet_synth_params *p) {
    double n = (double)tiles * tile_size, px = 6.0 * n * n;
    double border = 6.0 * 4.0 * (n + 2) * 2 * 16;
    double synth = 8 * 1.25 + 1 + (p && p->types ? 1 : 0) + (p && p->guide ? 4 : 0) +
                   (p && p->pits ? 0.25 * 18 : 0);
    double deliver = 16 + 8 + (p && p->pits ? 12 : 0);
    return px * (synth > deliver ? synth : deliver) + border;
}

pg_status pg_planet_synth_check(const pg_synth_exemplar *ex, const pg_planet_synth_params *p,
                                pg_error *err) {
    if (!ex) return pg_error_set(err, PG_ERR_BADINPUT, "planet synthesis: no exemplar");
    if (p->tiles < 1 || p->tiles > 4096)
        return pg_error_set(err, PG_ERR_BADINPUT, "--tiles %d: must be in 1..4096", p->tiles);
    int S = p->tile_size, need = 1 << top_scale(ex);
    if (S < 16 || S > 8192 || (S & (S - 1)))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--tile-size %d: must be a power of two in 16..8192", S);
    if (S % need)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--tile-size %d: does not divide into the %d-level pyramid (must be "
                            "a multiple of 2^%d = %d so the coarsest level has whole texels per "
                            "tile)",
                            S, ex->levels, top_scale(ex), need);
    if ((int64_t)p->tiles * S > 65536)
        return pg_error_set(err, PG_ERR_BADINPUT, "--tiles x --tile-size %lld: too large",
                            (long long)p->tiles * S);
    if (p->keep_levels < PG_PLANET_KEEP_AUTO || p->keep_levels > ex->levels)
        return pg_error_set(err, PG_ERR_BADINPUT, "--keep-levels %d: must be in 0..%d",
                            p->keep_levels, ex->levels);
    if (p->pit_skip_levels < 0 || p->pit_skip_levels > ex->levels)
        return pg_error_set(err, PG_ERR_BADINPUT, "--pit-skip-levels %d: must be in 0..%d",
                            p->pit_skip_levels, ex->levels);
    if (!(p->guide_alpha >= 0 && p->guide_alpha <= 1))
        return pg_error_set(err, PG_ERR_BADINPUT, "--guide-weight %g: must be in [0, 1]",
                            p->guide_alpha);
    if (!(p->type_mask & PG_TYPES_ALL))
        return pg_error_set(err, PG_ERR_BADINPUT, "types: no type allowed");
    return PG_OK;
}

/* ---------------------------------- level storage ---------------------------------- */

typedef struct level {
    int r;        /* texels per face edge */
    ptrdiff_t st; /* row stride r + 2 */
    size_t fsz;   /* (r + 2)^2 */
    uint32_t *S;  /* 6 * fsz */
    float *V;
} level;

static size_t at(const level *L, int f, int x, int y) {
    return (size_t)f * L->fsz + (size_t)(y + 1) * (size_t)L->st + (size_t)(x + 1);
}

static pg_synth_view face_view(const level *L, int f) {
    size_t o = at(L, f, 0, 0);
    pg_synth_view v = {L->S + o, L->V + o, NULL, L->st, L->r, L->r, f, 0, 0};
    return v;
}

/* The face borders: for each border texel its source (a texel of a neighbouring face)
 * and the orientation from this face's frame into the source's. */
typedef struct border_map {
    size_t n, *dst, *src;
    uint8_t *orient; /* 6 * fsz, zero inside */
} border_map;

static pg_status border_build(const level *L, int tiles, int ts, border_map *b, uint8_t *orient,
                              pg_error *err) {
    pg_cube_grid g;
    pg_status st = pg_cube_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, tiles, ts, err);
    if (st) return st;
    const int r = L->r;
    b->n = 0;
    b->orient = orient;
    memset(orient, 0, 6 * L->fsz);
    for (int f = 0; f < 6; f++)
        for (int y = -1; y <= r; y++)
            for (int x = -1; x <= r; x++) {
                if (x >= 0 && x < r && y >= 0 && y < r) continue;
                int rot;
                int64_t id = pg_cube_wrap(&g, f, x, y, &rot);
                int64_t per = (int64_t)r * r;
                int sf = (int)(id / per), sy = (int)(id % per / r), sx = (int)(id % r);
                b->dst[b->n] = at(L, f, x, y);
                b->src[b->n++] = at(L, sf, sx, sy);
                orient[at(L, f, x, y)] = (uint8_t)((4 - rot) & 3);
            }
    return PG_OK;
}

static void border_refresh(const border_map *b, level *L) {
    for (size_t i = 0; i < b->n; i++) {
        L->S[b->dst[i]] = L->S[b->src[i]];
        L->V[b->dst[i]] = L->V[b->src[i]];
    }
}

/* ------------------------------------ context ------------------------------------ */

typedef struct ctx {
    const pg_synth_exemplar *ex;
    const pg_planet_synth_params *p;
    int T, S, s_top;
    int64_t N;    /* synthesized texels per face edge: Nout / m */
    int64_t Nout; /* delivered texels per face edge: tiles * tile_size */
    int m;        /* magnification from synthesized to delivered texels (a power of two) */
    int keep;     /* layout earth: levels kept without jitter (resolved from auto) */
    bool independent_tiles; /* test only (pg_planet_synth_testing.h) */
    border_map bm;
    /* types */
    bool use_types;
    uint8_t *etype; /* exemplar texel types */
    uint32_t *valid[PG_TYPE_COUNT];
    size_t nvalid[PG_TYPE_COUNT];
    uint8_t *mask; /* per level texel (6 r^2) when a type map is given */
    /* guide */
    float *guide; /* per level texel, metres */
    pg_planet_synth_info *info;
    double work_done, work_total;
} ctx;

/* ------------------------- distribution hooks (issue 10) ------------------------- */

/* Without p->dist this process owns every tile and exchanges nothing, so the
 * single-process path is unchanged. */
static bool owns(const ctx *c, int f, int tx, int ty) {
    const pg_planet_synth_dist *d = c->p->dist;
    return !d || d->owns(d->user, f, tx, ty);
}

static pg_status exchange(const ctx *c, int scale, const level *L, int width, pg_error *err) {
    const pg_planet_synth_dist *d = c->p->dist;
    if (!d) return PG_OK;
    pg_planet_level pl = {scale, L->r, c->S >> scale, c->T, (size_t)L->st, L->fsz, L->S, L->V};
    return d->exchange(d->user, &pl, width, err);
}

static pg_synth_view tile_view(const level *L, int f, int x0, int y0, int w, int h) {
    size_t o = at(L, f, x0, y0);
    pg_synth_view v = {L->S + o, L->V + o, NULL, L->st, w, h, f, x0, y0};
    return v;
}

/* Is delivered texel (x, y) of face f in one of this process's tiles? */
static bool owned_texel(const ctx *c, int f, int64_t x, int64_t y) {
    const int64_t ts = c->Nout / c->T;
    return owns(c, f, (int)(x / ts), (int)(y / ts));
}

/* Distributed pit removal for a level of r texels per face edge: the hook, when the
 * tiles divide the level (coarser levels are gathered: at most T^2 texels a face). */
static bool dist_pits(const ctx *c, int r) {
    return c->p->dist && c->p->dist->pits && r % c->T == 0;
}

/* The land/ocean agreement summed over the processes (each counts its tiles). */
static bool dist_sum(const ctx *c, int r) {
    return c->p->dist && c->p->dist->sum && r % c->T == 0;
}

/* Is texel (x, y) of face f, at a level of r texels per face edge, in an owned tile? */
static bool owned_at(const ctx *c, int r, int f, int x, int y) {
    const int ts = r / c->T;
    return owns(c, f, x / ts, y / ts);
}

static uint8_t mask_at(const ctx *c, int r, int f, long x, long y) {
    if (!c->mask) return c->p->type_mask;
    return c->mask[((size_t)f * r + (size_t)y) * r + (size_t)x];
}

static bool allowed(const ctx *c, uint8_t m, uint32_t q) {
    return (m >> c->etype[pg_synth_texel(c->ex, q)]) & 1;
}

/* A hashed draw among the exemplar texels whose type m allows. */
static uint32_t draw_valid(const ctx *c, uint8_t m, uint32_t h) {
    size_t total = 0;
    for (int t = 0; t < PG_TYPE_COUNT; t++)
        if ((m >> t) & 1) total += c->nvalid[t];
    if (!total) return 0;
    size_t k = (size_t)h % total;
    for (int t = 0; t < PG_TYPE_COUNT; t++) {
        if (!((m >> t) & 1)) continue;
        if (k < c->nvalid[t]) return c->valid[t][k];
        k -= c->nvalid[t];
    }
    return 0;
}

/* Gain et al.'s type constraint, applied to the texels of one parity class of a view
 * after their correction. A disallowed texel is replaced by the allowed candidate
 * closest in level height to what it had (so the terrain keeps its shape): the
 * coherent candidates S[p+e] - h e of its 8 neighbours first (a coherent one wins
 * unless a draw is more than twice as close), then 8 hashed draws among the valid
 * exemplar texels. */
static void types_fixup(const ctx *c, int scale, int parity, pg_synth_view *v) {
    static const int nb[8][2] = {{1, 0},  {1, 1},   {0, 1},  {-1, 1},
                                 {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
    const int h = 1 << scale, r = (int)(c->N >> scale), px = parity & 1, py = parity >> 1;
    const uint64_t seed = c->p->synth.seed;
    for (int y = 0; y < v->h; y++) {
        long gy = v->gy + y;
        if ((int)(gy & 1) != py) continue;
        for (int x = (int)((v->gx & 1) != px); x < v->w; x += 2) {
            long gx = v->gx + x;
            ptrdiff_t i = (ptrdiff_t)y * v->stride + x;
            uint8_t m = mask_at(c, r, v->face, gx, gy);
            if (allowed(c, m, v->S[i])) continue;
            float want = pg_synth_level_height(c->ex, scale, v->S[i]) + v->V[i], best = INFINITY;
            uint32_t bq = 0;
            float bv = 0;
            for (int k = 0; k < 16; k++) {
                uint32_t q;
                float vq = 0, w = 1;
                if (k < 8) {
                    int ex = nb[k][0], ey = nb[k][1];
                    ptrdiff_t j = i + (ptrdiff_t)ey * v->stride + ex;
                    q = pg_synth_view_move(c->ex, v, j, -h * ex, -h * ey);
                    vq = v->V[j];
                    if (!allowed(c, m, q)) continue;
                } else {
                    q = draw_valid(c, m, pg_synth_hash(seed, scale, v->face, gx, gy, 12 + k));
                    w = 2;
                }
                float d = w * fabsf(pg_synth_level_height(c->ex, scale, q) + vq - want);
                if (d < best) best = d, bq = q, bv = vq;
            }
            v->S[i] = bq;
            v->V[i] = bv;
        }
    }
}

/* --------------------------------- initialisation --------------------------------- */

static uint32_t exemplar_at_direction(const pg_synth_exemplar *ex, int r, int f, int x, int y) {
    const int E = ex->face_size;
    int u = (int)(((int64_t)2 * x + 1) * E / (2 * r)),
        v = (int)(((int64_t)2 * y + 1) * E / (2 * r));
    return pg_synth_pack(f, u, v);
}

/* Coarsest level: the exemplar at the same direction (layout earth), else hashed
 * random texels; with a guide, the best of 16 hashed draws by level height. */
static void init_top(ctx *c, level *L) {
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
            } else {
                int ndraw = c->guide ? 16 : 1;
                float g = c->guide ? c->guide[((size_t)f * r + y) * r + x] : 0, best = INFINITY;
                q = 0;
                for (int k = 0; k < ndraw; k++) {
                    uint32_t a = pg_synth_hash(seed, 99, f, x, y, 7 + 2 * k);
                    uint32_t b = pg_synth_hash(seed, 99, f, x, y, 8 + 2 * k);
                    uint32_t cand = pg_synth_pack((int)(a % 6u), (int)((a >> 3) % (uint32_t)E),
                                                  (int)(b % (uint32_t)E));
                    float d = fabsf(pg_synth_level_height(ex, s, cand) - g);
                    if (k == 0 || d < best) best = d, q = cand;
                }
            }
            L->S[at(L, f, x, y)] = q;
            L->V[at(L, f, x, y)] = 0;
        }
    }
}

/* ------------------------------------ one level ------------------------------------ */

/* TEST ONLY: correct one tile in a private copy whose halo continues its own edge
 * (as the flat driver does), i.e. without its neighbours. */
static void correct_tile_alone(const ctx *c, int scale, int parity, const pg_synth_view *v) {
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
    pg_synth_view t = {S + st + 1, V + st + 1, NULL, st, w, hgt, v->face, v->gx, v->gy};
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

static void correct_view(const ctx *c, int scale, int parity, pg_synth_view *v) {
    if (v->w <= 0 || v->h <= 0) return;
    if (c->independent_tiles)
        correct_tile_alone(c, scale, parity, v);
    else
        pg_synth_correct_subpass(c->ex, scale, &c->p->synth, parity, v);
    if (c->use_types) types_fixup(c, scale, parity, v);
}

/* The rectangle [x0, x1) x [y0, y1) of face f as a view. */
static pg_synth_view rect_view(const ctx *c, const level *L, int f, int x0, int y0, int x1,
                               int y1) {
    size_t o = at(L, f, x0, y0);
    pg_synth_view v = {L->S + o, L->V + o, c->bm.orient + o, L->st, x1 - x0, y1 - y0, f, x0, y0};
    return v;
}

/* One sub-pass over the planet, in two steps. Across a seam with a quarter turn (the
 * 8 seams of the polar faces) the 2 x 2 parity classes of the two faces do not
 * interleave: half the pairs straddling such a seam are in the same class, and if both
 * sides were corrected at once, each from the other's old value, they could never
 * become coherent. So step 1 corrects every tile except the outermost ring of the
 * polar faces, and step 2, after refreshing the borders, corrects that ring against
 * the new values on the other side. Both steps are order-independent, and the split
 * is fixed by the faces, not the tiles. */
/* The part of the rectangle [x0, x1) x [y0, y1) of polar face f that lies in this
 * process's tiles (all of it without dist). Sub-passes are order-independent, so
 * correcting a strip piecewise gives the same texels. */
static void correct_rect_owned(const ctx *c, int scale, int parity, const level *L, int f, int x0,
                               int y0, int x1, int y1) {
    const int ts = c->S >> scale;
    if (!c->p->dist) {
        pg_synth_view v = rect_view(c, L, f, x0, y0, x1, y1);
        correct_view(c, scale, parity, &v);
        return;
    }
    for (int ty = y0 / ts; ty * ts < y1; ty++)
        for (int tx = x0 / ts; tx * ts < x1; tx++) {
            if (!owns(c, f, tx, ty)) continue;
            int ax = tx * ts > x0 ? tx * ts : x0, ay = ty * ts > y0 ? ty * ts : y0;
            int bx = (tx + 1) * ts < x1 ? (tx + 1) * ts : x1,
                by = (ty + 1) * ts < y1 ? (ty + 1) * ts : y1;
            pg_synth_view v = rect_view(c, L, f, ax, ay, bx, by);
            correct_view(c, scale, parity, &v);
        }
}

static pg_status correct_subpass_all(ctx *c, int scale, int parity, level *L, pg_error *err) {
    const int ts = c->S >> scale, T = c->T, r = L->r;
    const int ntiles = 6 * T * T;
    const bool split = !c->independent_tiles && r > 2;
    pg_status st = exchange(c, scale, L, 1, err);
    if (st) return st;
    border_refresh(&c->bm, L);
#pragma omp parallel for schedule(dynamic, 1)
    for (int t = 0; t < ntiles; t++) {
        int f = t / (T * T), tx = t % T, ty = t / T % T;
        if (!owns(c, f, tx, ty)) continue;
        int x0 = tx * ts, y0 = ty * ts, x1 = x0 + ts, y1 = y0 + ts;
        if (split && polar(f)) {
            x0 = x0 < 1 ? 1 : x0, y0 = y0 < 1 ? 1 : y0;
            x1 = x1 > r - 1 ? r - 1 : x1, y1 = y1 > r - 1 ? r - 1 : y1;
        }
        pg_synth_view v = rect_view(c, L, f, x0, y0, x1, y1);
        correct_view(c, scale, parity, &v);
    }
    if (!split) return PG_OK;
    if ((st = exchange(c, scale, L, 1, err))) return st;
    border_refresh(&c->bm, L);
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

/* Contiguous 6 r^2 copies of the reconstructed heights R = E_s(S) + V and of V. */
/* With owned_only, the texels of other processes' tiles (stale, perhaps never
 * written) get R = Vc = 0; the pits hook exchanges what it reads of them. */
static void reconstruct(const ctx *c, int scale, const level *L, float *R, float *Vc,
                        bool owned_only) {
    const int r = L->r;
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * r; row++) {
        int f = row / r, y = row % r;
        for (int x = 0; x < r; x++) {
            size_t i = at(L, f, x, y), j = ((size_t)f * r + y) * r + x;
            if (owned_only && !owned_at(c, r, f, x, y)) {
                R[j] = 0;
                if (Vc) Vc[j] = 0;
                continue;
            }
            R[j] = pg_synth_level_height(c->ex, scale, L->S[i]) + L->V[i];
            if (Vc) Vc[j] = L->V[i];
        }
    }
}

static void store_offsets(const float *Vc, level *L) {
    const int r = L->r;
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * r; row++) {
        int f = row / r, y = row % r;
        for (int x = 0; x < r; x++)
            L->V[at(L, f, x, y)] = Vc[((size_t)f * r + y) * r + x];
    }
}

static pg_pits_opts pits_opts(const ctx *c, pg_pits_method m) {
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.method = m;
    o.epsilon = true;
    o.descent = true; /* no flood order: MPI ranks reproduce it (docs/mpi.md) */
    o.has_sea_level = true;
    o.sea_level = c->ex->sea_level;
    return o;
}

/* Gain-pit on the owned tiles through the hook: R' = remove(R) there, Vc += R' - R. */
static pg_status gainpit_dist(ctx *c, int r, const float *R, float *Vc, const pg_pits_opts *o,
                              pg_error *err) {
    size_t n = (size_t)6 * r * r;
    float *R2 = malloc(n * sizeof *R2);
    if (!R2) return pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory (pits)");
    memcpy(R2, R, n * sizeof *R2);
    const pg_planet_synth_dist *d = c->p->dist;
    pg_status st = d->pits(d->user, (uint32_t)r, c->T, R2, o, err);
    uint64_t changed = 0;
    for (int f = 0; !st && f < 6; f++)
        for (int y = 0; y < r; y++)
            for (int x = 0; x < r; x++) {
                size_t i = ((size_t)f * r + y) * r + x;
                if (R2[i] == R[i] || !owned_at(c, r, f, x, y)) continue;
                Vc[i] += R2[i] - R[i];
                changed++;
            }
    c->info->pit_cells_changed += changed;
    free(R2);
    return st;
}

/* After a correction pass: the guide blend R <- w G + (1 - w) R (as V += w (G - R)),
 * then Gain-pit (R' pit-free, V += R' - R). Distributed, Gain-pit runs through the
 * pits hook on the owned tiles; without the hook (or at levels too coarse for the
 * tiles) every process gathers the level and runs it whole (deterministic, so all
 * agree; docs/mpi.md). The texels outside the owned tiles are stale either way and
 * are refreshed by the next exchange before anything reads them. */
static pg_status after_pass(ctx *c, int scale, level *L, pg_error *err) {
    bool pits = c->p->pits && scale >= c->p->pit_skip_levels;
    if (!pits && !c->guide) return PG_OK;
    const int r = L->r;
    bool gather = pits && !dist_pits(c, r);
    pg_status xs = gather ? exchange(c, scale, L, -1, err) : PG_OK;
    if (xs) return xs;
    size_t n = (size_t)6 * r * r;
    float *R = malloc(n * sizeof *R), *Vc = malloc(n * sizeof *Vc);
    if (!R || !Vc) {
        free(R), free(Vc);
        return pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory (pits)");
    }
    reconstruct(c, scale, L, R, Vc, c->p->dist && !gather);
    pg_status st = PG_OK;
    if (c->guide) {
        float w = (float)pg_guide_weight(c->p->guide_alpha, c->s_top, scale);
#pragma omp parallel for schedule(static)
        for (size_t i = 0; i < n; i++) {
            float d = w * (c->guide[i] - R[i]);
            Vc[i] += d;
            R[i] += d;
        }
    }
    if (pits) {
        double t0 = pg_synth_now();
        pg_pits_topo topo;
        pg_pits_opts o = pits_opts(c, c->p->pit_method);
        pg_pits_result res;
        if (dist_pits(c, r)) {
            st = gainpit_dist(c, r, R, Vc, &o, err);
        } else {
            st = pg_pits_topo_cube(&topo, (uint32_t)r, err);
            if (!st) st = pg_pits_correct_offsets(&topo, R, Vc, &o, &res, err);
            if (!st) c->info->pit_cells_changed += res.raised + res.lowered;
        }
        c->info->pits_seconds += pg_synth_now() - t0;
    }
    if (!st) store_offsets(Vc, L);
    free(R);
    free(Vc);
    return st;
}

static void land_agreement(ctx *c, int scale, const level *L) {
    const int r = L->r;
    uint64_t agree = 0;
#pragma omp parallel for schedule(static) reduction(+ : agree)
    for (int row = 0; row < 6 * r; row++) {
        int f = row / r, y = row % r;
        for (int x = 0; x < r; x++) {
            if (dist_sum(c, r) && !owned_at(c, r, f, x, y)) continue;
            size_t i = at(L, f, x, y);
            float h = pg_synth_level_height(c->ex, scale, L->S[i]) + L->V[i];
            float he =
                pg_synth_level_height(c->ex, scale, exemplar_at_direction(c->ex, r, f, x, y));
            agree += (h > c->ex->sea_level) == (he > c->ex->sea_level);
        }
    }
    double total = (double)agree;
    if (dist_sum(c, r)) total = c->p->dist->sum(c->p->dist->user, total);
    c->info->land_agreement = total / (6.0 * r * r);
}

static void progress(ctx *c, double units) {
    c->work_done += units;
    if (c->p->progress) c->p->progress(c->p->progress_user, c->work_done / c->work_total);
}

static pg_status run_level(ctx *c, int scale, level *L, pg_error *err) {
    const pg_planet_synth_params *p = c->p;
    double units = (double)L->r * L->r / ((double)c->N * c->N);
    for (int pass = 0; pass < p->synth.passes; pass++) {
        pg_status st = PG_OK;
        for (int sp = 0; sp < 4 && !st; sp++)
            st = correct_subpass_all(c, scale, pg_synth_subpass_order[sp], L, err);
        if (!st) st = after_pass(c, scale, L, err);
        if (st) return st;
        progress(c, units / p->synth.passes);
    }
    if (p->layout == PG_LAYOUT_EARTH && c->keep > 0 && scale == c->s_top - c->keep + 1) {
        /* distributed: each process counts its tiles and the hook sums the counts
         * (without it, the coarse level is gathered) */
        pg_status st = dist_sum(c, L->r) ? PG_OK : exchange(c, scale, L, -1, err);
        if (st) return st;
        land_agreement(c, scale, L);
    }
    return PG_OK;
}

/* ------------------------------------- setup ------------------------------------- */

static pg_status types_setup(ctx *c, pg_error *err) {
    c->use_types = c->p->types || c->p->type_mask != PG_TYPES_ALL;
    if (!c->use_types) return PG_OK;
    const pg_synth_exemplar *ex = c->ex;
    c->etype = pg_types_exemplar(ex);
    if (!c->etype) return pg_error_set(err, PG_ERR_NOMEM, "types: out of memory");
    size_t ne = (size_t)ex->nfaces * ex->face_size * ex->face_size;
    for (size_t i = 0; i < ne; i++)
        c->nvalid[c->etype[i]]++;
    for (int t = 0; t < PG_TYPE_COUNT; t++) {
        c->valid[t] = malloc((c->nvalid[t] + 1) * sizeof(uint32_t));
        if (!c->valid[t]) return pg_error_set(err, PG_ERR_NOMEM, "types: out of memory");
        c->nvalid[t] = 0;
    }
    const int E = ex->face_size;
    for (size_t i = 0; i < ne; i++) {
        int t = c->etype[i];
        c->valid[t][c->nvalid[t]++] =
            pg_synth_pack((int)(i / ((size_t)E * E)), (int)(i % E), (int)(i / E % E));
    }
    /* every mask in use must leave valid texels */
    uint8_t masks = 0;
    for (int t = 0; t < PG_TYPE_COUNT; t++)
        if (c->nvalid[t]) masks |= (uint8_t)(1u << t);
    if (!(c->p->type_mask & masks))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--preset: no exemplar texel has an allowed type");
    if (c->p->types) {
        const pg_types_map *m = c->p->types;
        for (size_t i = 0; i < (size_t)m->width * m->height; i++)
            if (!(m->mask[i] & masks)) {
                char names[128] = "";
                for (int t = 0; t < PG_TYPE_COUNT; t++)
                    if ((m->mask[i] >> t) & 1) {
                        strncat(names, names[0] ? ", " : "", sizeof names - strlen(names) - 1);
                        strncat(names, pg_types_name(t), sizeof names - strlen(names) - 1);
                    }
                return pg_error_set(err, PG_ERR_BADINPUT,
                                    "--types: the exemplar has no texel of type %s", names);
            }
    }
    return PG_OK;
}

static double sphere_lat(const double d[3]) {
    double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return asin(d[2] / n) * (180.0 / 3.14159265358979323846);
}

/* Nearest-pixel type mask of every texel of a level (type colours are discrete). */
static pg_status types_level(ctx *c, int r, int ts, pg_error *err) {
    if (!c->p->types) return PG_OK;
    const pg_types_map *m = c->p->types;
    pg_cube_grid g;
    pg_status st = pg_cube_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, c->T, ts, err);
    if (st) return st;
#pragma omp parallel for schedule(static)
    for (int64_t id = 0; id < (int64_t)6 * r * r; id++) {
        double d[3];
        pg_cube_texel_dir(&g, id, d);
        double lat = sphere_lat(d), lon = atan2(d[1], d[0]) * (180.0 / 3.14159265358979323846);
        int i = (int)floor((lon + 180.0) / 360.0 * m->width),
            j = (int)floor((90.0 - lat) / 180.0 * m->height);
        i = i < 0 ? 0 : (i >= m->width ? m->width - 1 : i);
        j = j < 0 ? 0 : (j >= m->height ? m->height - 1 : j);
        c->mask[id] = m->mask[(size_t)j * m->width + i];
    }
    return PG_OK;
}

static pg_status guide_level(ctx *c, int r, pg_error *err) {
    if (!c->p->guide) return PG_OK;
    const pg_guide *g = c->p->guide;
    int samples = (int)ceil((double)g->width / (4.0 * r));
    if (samples < 1) samples = 1;
    if (samples > 8) samples = 8;
    return pg_cube_from_equirect(PG_CUBE_DEFAULT_PROJECTION, r, NULL, g->metres, g->width,
                                 g->height, 1, samples, c->guide, err);
}

static void ctx_free(ctx *c) {
    free(c->bm.dst);
    free(c->bm.src);
    free(c->bm.orient);
    free(c->etype);
    for (int t = 0; t < PG_TYPE_COUNT; t++)
        free(c->valid[t]);
    free(c->mask);
    free(c->guide);
}

static pg_status level_alloc(level *L, int r) {
    L->r = r;
    L->st = r + 2;
    L->fsz = (size_t)(r + 2) * (r + 2);
    L->S = malloc(6 * L->fsz * sizeof *L->S);
    L->V = malloc(6 * L->fsz * sizeof *L->V);
    return L->S && L->V ? PG_OK : PG_ERR_NOMEM;
}

static void level_free(level *L) {
    free(L->S);
    free(L->V);
    L->S = NULL;
    L->V = NULL;
}

static pg_status ctx_init(ctx *c, const pg_synth_exemplar *ex, const pg_planet_synth_params *p,
                          pg_planet_synth_info *info, pg_error *err) {
    memset(c, 0, sizeof *c);
    c->ex = ex;
    c->p = p;
    c->T = p->tiles;
    c->m = pg_planet_synth_magnification(ex, p);
    c->S = p->tile_size / c->m;
    c->Nout = (int64_t)p->tiles * p->tile_size;
    c->N = c->Nout / c->m;
    c->s_top = top_scale(ex);
    c->keep = pg_planet_synth_keep_levels(ex, p);
    c->info = info;
    size_t nb = (size_t)6 * 4 * (c->N + 2), full = (size_t)6 * (c->N + 2) * (c->N + 2);
    c->bm.dst = malloc(nb * sizeof(size_t));
    c->bm.src = malloc(nb * sizeof(size_t));
    c->bm.orient = malloc(full);
    size_t px = (size_t)6 * c->N * c->N;
    if (p->types) c->mask = malloc(px);
    if (p->guide) c->guide = malloc(px * sizeof(float));
    if (!c->bm.dst || !c->bm.src || !c->bm.orient || (p->types && !c->mask) ||
        (p->guide && !c->guide))
        return pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory");
    for (int s = 0; s <= c->s_top; s++)
        c->work_total += 1.0 / ((double)(1 << s) * (1 << s));
    return types_setup(c, err);
}

static pg_status prepare_level(ctx *c, int scale, level *L, pg_error *err) {
    int ts = c->S >> scale;
    pg_status st = border_build(L, c->T, ts, &c->bm, c->bm.orient, err);
    if (!st) st = types_level(c, L->r, ts, err);
    if (!st) st = guide_level(c, L->r, err);
    return st;
}

static double jitter_for(const ctx *c, int scale) {
    if (c->p->layout == PG_LAYOUT_EARTH && scale > c->s_top - c->keep) return 0;
    return pg_synth_jitter_for(&c->p->synth, scale);
}

static void jitter_level(const ctx *c, int scale, level *L) {
    double r = jitter_for(c, scale);
    const int ts = c->S >> scale;
    for (int f = 0; f < 6; f++) {
        if (!c->p->dist) {
            pg_synth_view v = face_view(L, f);
            pg_synth_jitter(c->ex, scale, r, c->p->synth.seed, &v);
            continue;
        }
        for (int t = 0; t < c->T * c->T; t++) /* the jitter hashes global texel ids */
            if (owns(c, f, t % c->T, t / c->T)) {
                pg_synth_view v = tile_view(L, f, t % c->T * ts, t / c->T * ts, ts, ts);
                pg_synth_jitter(c->ex, scale, r, c->p->synth.seed, &v);
            }
    }
}

/* Upsample the parent level into the child (per owned tile with dist: a child texel
 * reads only its parent texel, and tiles nest across levels). */
static void upsample_level(const ctx *c, int s, const level *parent, level *child) {
    const int pts = c->S >> (s + 1);
    for (int f = 0; f < 6; f++) {
        if (!c->p->dist) {
            pg_synth_view pv = face_view(parent, f), cv = face_view(child, f);
            pg_synth_upsample(c->ex, s, &pv, &cv);
            continue;
        }
        for (int t = 0; t < c->T * c->T; t++)
            if (owns(c, f, t % c->T, t / c->T)) {
                int x = t % c->T * pts, y = t / c->T * pts;
                pg_synth_view pv = tile_view(parent, f, x, y, pts, pts),
                              cv = tile_view(child, f, 2 * x, 2 * y, 2 * pts, 2 * pts);
                pg_synth_upsample(c->ex, s, &pv, &cv);
            }
    }
}

/* The pyramid: the coarsest level, then upsample / jitter / correct down to scale 0.
 * On success *out holds the finest level. */
static pg_status synthesize(ctx *c, level *out, pg_error *err) {
    level cur = {0}, nxt = {0};
    const int r_top = (int)(c->N >> c->s_top);
    if (level_alloc(&cur, r_top))
        return level_free(&cur), pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory");
    pg_status st = prepare_level(c, c->s_top, &cur, err);
    double t0 = pg_synth_now();
    if (!st) {
        init_top(c, &cur);
        jitter_level(c, c->s_top, &cur);
        st = run_level(c, c->s_top, &cur, err);
    }
    c->info->level_seconds[c->info->nlevels++] = pg_synth_now() - t0;
    for (int s = c->s_top - 1; s >= 0 && !st; s--) {
        t0 = pg_synth_now();
        if (level_alloc(&nxt, cur.r * 2)) {
            st = pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory at %d^2",
                              cur.r * 2);
            break;
        }
        upsample_level(c, s, &cur, &nxt);
        level_free(&cur);
        cur = nxt;
        nxt = (level){0};
        st = prepare_level(c, s, &cur, err);
        if (!st) {
            jitter_level(c, s, &cur);
            st = run_level(c, s, &cur, err);
        }
        c->info->level_seconds[c->info->nlevels++] = pg_synth_now() - t0;
    }
    level_free(&nxt);
    if (st) {
        level_free(&cur);
        return st;
    }
    *out = cur;
    return PG_OK;
}

/* ------------------------------------ delivery ------------------------------------ */

/* Delivery at Nout = m N texels per face edge. One synthesized texel stands for one
 * exemplar texel of ground, so when the planet's faces are finer than the exemplar's
 * (m > 1) the synthesized albedo and height are magnified with a cubic B-spline (texel
 * centres aligned; the 4 x 4 taps read the level's one-texel border across face seams,
 * clamped to it). Why a B-spline and not an interpolating kernel: every tile edge of
 * the delivered planet is a synthesized-texel boundary, and an interpolating kernel
 * makes the delivered steps across such a boundary systematically larger than those
 * inside a synthesized texel, so tile edges would look like seams (default planet:
 * albedo seam ratio 1.155 bilinear, 1.19 Catmull-Rom, 1.04 B-spline; the B-spline's
 * smoothing is below the exemplar's own resolution). With m = 1 the synthesized texel
 * is delivered as it is. */
typedef struct texel_out {
    float rgb[3], h;
} texel_out;

/* Cubic B-spline weights of the taps n - 1 .. n + 2 around t = s - n, 0 <= t < 1. */
static void bspline3_weights(double t, double w[4]) {
    double u = 1 - t;
    w[0] = u * u * u / 6;
    w[1] = (3 * t * t * t - 6 * t * t + 4) / 6;
    w[2] = (3 * u * u * u - 6 * u * u + 4) / 6;
    w[3] = t * t * t / 6;
}

static void magnified_texel(const ctx *c, const level *L, int f, int64_t X, int64_t Y,
                            texel_out *o) {
    const int m = c->m, r = L->r;
    if (m == 1) {
        size_t i = at(L, f, (int)X, (int)Y), t = pg_synth_texel(c->ex, L->S[i]);
        for (int j = 0; j < 3; j++)
            o->rgb[j] = c->ex->albedo[t * 3 + j] * (1.0f / 255.0f);
        o->h = c->ex->height[t] + (L->V ? L->V[i] : 0.0f);
        return;
    }
    double sx = (X + 0.5) / m - 0.5, sy = (Y + 0.5) / m - 0.5;
    int x0 = (int)floor(sx), y0 = (int)floor(sy);
    double wx[4], wy[4], acc[4] = {0};
    bspline3_weights(sx - x0, wx);
    bspline3_weights(sy - y0, wy);
    for (int ky = 0; ky < 4; ky++)
        for (int kx = 0; kx < 4; kx++) {
            double w = wx[kx] * wy[ky];
            int x = x0 - 1 + kx, y = y0 - 1 + ky;
            x = x < -1 ? -1 : (x > r ? r : x);
            y = y < -1 ? -1 : (y > r ? r : y);
            size_t i = at(L, f, x, y);
            size_t t = pg_synth_texel(c->ex, L->S[i]);
            for (int j = 0; j < 3; j++)
                acc[j] += w * c->ex->albedo[t * 3 + j];
            acc[3] += w * (c->ex->height[t] + (L->V ? L->V[i] : 0.0f));
        }
    for (int j = 0; j < 3; j++)
        o->rgb[j] = (float)(acc[j] * (1.0 / 255.0));
    o->h = (float)acc[3];
}

/* Row `row` (face row / n, texel row row % n) of the delivered planet: heights into h,
 * albedo into rgb, when not NULL. */
/* With all false, only the texels of this process's tiles (all of them without dist). */
static void deliver_row(const ctx *c, const level *L, int64_t row, float *h, float *rgb, bool all) {
    const int64_t n = c->Nout;
    const int f = (int)(row / n);
    for (int64_t x = 0; x < n; x++) {
        if (!all && c->p->dist && !owned_texel(c, f, x, row % n)) continue;
        texel_out o;
        magnified_texel(c, L, f, x, row % n, &o);
        if (h) h[x] = o.h;
        for (int k = 0; rgb && k < 3; k++)
            rgb[x * 3 + k] = o.rgb[k];
    }
}

static void finest_heights(const ctx *c, const level *L, float *H, bool all) {
#pragma omp parallel for schedule(static)
    for (int64_t row = 0; row < 6 * c->Nout; row++)
        deliver_row(c, L, row, H + (size_t)row * c->Nout, NULL, all);
}

/* The final removal and the counts: on the whole planet in this process, or through
 * the hooks on this process's tiles (H valid there only) when there are hooks for
 * both. */
static bool dist_final(const ctx *c) {
    const pg_planet_synth_dist *d = c->p->dist;
    return dist_pits(c, (int)c->Nout) && (!c->p->pit_stats || d->stats);
}

static pg_status final_remove(const ctx *c, const pg_pits_topo *topo, float *H,
                              const pg_pits_opts *o, pg_error *err) {
    const pg_planet_synth_dist *d = c->p->dist;
    if (dist_final(c)) return d->pits(d->user, (uint32_t)c->Nout, c->T, H, o, err);
    return pg_pits_remove(topo, H, o, NULL, err);
}

static pg_status final_stats(const ctx *c, const pg_pits_topo *topo, const float *H,
                             const pg_pits_opts *o, const pg_pits_area *area, pg_pits_stats *out,
                             pg_error *err) {
    const pg_planet_synth_dist *d = c->p->dist;
    if (dist_final(c)) return d->stats(d->user, (uint32_t)c->Nout, c->T, H, o, area, out, err);
    return pg_pits_stats_compute(topo, H, o, area, out, err);
}

/* whole: H holds every texel, not only this process's tiles. closed receives the
 * closed-land share of H before the final pass (pg_drainage.h), a whole-planet measure:
 * taken with the depression counts (pit_stats) when H is whole, NaN otherwise. */
static pg_status final_pits(ctx *c, float *H, bool whole, double *closed, pg_error *err) {
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
    if (!st && p->pit_stats) st = final_stats(c, &topo, H, &o, &area, &c->info->before, err);
    double t1 = pg_synth_now();
    if (!st && p->pits && p->final_pits) st = final_remove(c, &topo, H, &o, err);
    double t2 = pg_synth_now();
    if (!st && p->pit_stats) st = final_stats(c, &topo, H, &o, &area, &c->info->after, err);
    c->info->final_pits_seconds = t2 - t1;
    c->info->pit_stats_seconds = (t1 - t0) + (pg_synth_now() - t2);
    return st;
}

/* Albedo (magnified), the heights H, and per delivered texel the exemplar coordinate of
 * its synthesized texel (coords, types). */
static void render(const ctx *c, const level *L, const float *H, pg_planet *out, uint32_t *coords) {
    const int64_t n = c->Nout;
    const int r = L->r, m = c->m;
    uint64_t ok = 0;
#pragma omp parallel for schedule(static) reduction(+ : ok)
    for (int64_t row = 0; row < 6 * n; row++) {
        int f = (int)(row / n);
        int64_t y = row % n;
        deliver_row(c, L, row, NULL, out->albedo[f] + (size_t)y * n * 3, false);
        if (!c->p->dist)
            memcpy(out->height[f] + (size_t)y * n, H + (size_t)row * n, (size_t)n * sizeof *H);
        for (int64_t x = 0; x < n; x++) {
            if (c->p->dist) {
                if (!owned_texel(c, f, x, y)) continue;
                out->height[f][(size_t)y * n + x] = H[(size_t)row * n + x];
            }
            uint32_t q = L->S[at(L, f, (int)(x / m), (int)(y / m))];
            if (coords) coords[(size_t)row * n + x] = q;
            if (c->use_types)
                ok += (mask_at(c, r, f, (long)(x / m), (long)(y / m)) >>
                       c->etype[pg_synth_texel(c->ex, q)]) &
                      1;
        }
    }
    c->info->allowed_fraction = c->use_types ? (double)ok / (6.0 * n * n) : 1.0;
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
    memset(out, 0, sizeof *out);
    if (coords_out) *coords_out = NULL;
    pg_status st = pg_planet_synth_check(ex, p, err);
    if (st) return st;
    info->peak_bytes_estimate = pg_planet_synth_bytes(p->tiles, p->tile_size, p);
    info->s_top = top_scale(ex);
    ctx c;
    st = ctx_init(&c, ex, p, info, err);
    c.independent_tiles = testing && testing->independent_tiles;
    level L = {0};
    double t0 = pg_synth_now();
    if (!st) st = synthesize(&c, &L, err);
    info->synth_seconds = pg_synth_now() - t0;
    size_t px = (size_t)6 * c.Nout * c.Nout;
    float *H = NULL;
    bool whole = false;
    double closed = NAN;
    if (!st && !(H = malloc(px * sizeof *H)))
        st = pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory (heights)");
    if (!st) {
        /* Distributed without the pits hooks: the final pit removal and the depression
         * counts are whole-planet steps, run by every process on the whole level
         * (docs/mpi.md); otherwise the magnification needs the two texel rings around
         * this process's tiles, and the hooks exchange what the pits need. */
        bool all = !dist_final(&c) && ((p->pits && p->final_pits) || p->pit_stats);
        whole = !p->dist || all;
        st = exchange(&c, 0, &L, all ? -1 : 2, err);
        if (!st) {
            border_refresh(&c.bm, &L); /* the magnification reads across face seams */
            finest_heights(&c, &L, H, whole);
        }
    }
    if (!st) {
        free(L.V); /* S stays for the albedo */
        L.V = NULL;
        st = final_pits(&c, H, whole, &closed, err);
    }
    t0 = pg_synth_now();
    if (!st)
        st = pg_planet_alloc(out, PG_CUBE_DEFAULT_PROJECTION, p->tiles, p->tile_size,
                             pg_ellipsoid_sphere(), err);
    if (!st && coords_out && !(*coords_out = malloc(px * sizeof(uint32_t))))
        st = pg_error_set(err, PG_ERR_NOMEM, "planet synthesis: out of memory (coords)");
    if (!st) {
        out->seed = p->synth.seed;
        out->sea_level = ex->sea_level;
        out->closed_land_share_before_final = closed;
        render(&c, &L, H, out, coords_out ? *coords_out : NULL);
    }
    info->render_seconds = pg_synth_now() - t0;
    free(H);
    level_free(&L);
    ctx_free(&c);
    if (st) {
        pg_planet_free(out);
        if (coords_out) free(*coords_out), *coords_out = NULL;
    }
    return st;
}
