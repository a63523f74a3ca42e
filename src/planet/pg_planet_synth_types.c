/* pg_planet_synth_types.c - Gain, Merry & Marais 2015's type constraints in the planet
 * synthesis: the exemplar's texels classified by type (pg_types.c), the allowed types of
 * every level texel from the type map or the preset, and the fix-up after each
 * correction sub-pass that replaces a texel of a disallowed type (docs/generate.md,
 * "Method": "Types").
 *
 * The fix-up runs on the texels of the sub-pass's parity class in the same view and
 * reads only its neighbours (of the other classes) and hashed draws, so it keeps the
 * sub-pass's independence of tile size, order and thread count. */
#include "pg_hash.h"
#include "pg_huge.h"
#include "pg_planet_synth_internal.h"
#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

pg_status pg_ps_types_setup(pg_ps_ctx *c, pg_error *err) {
    c->use_types = c->p->types || pg_ps_world_types(c->p) || c->p->type_mask != PG_TYPES_ALL;
    if (!c->use_types) return PG_OK;
    const pg_synth_exemplar *ex = c->ex;
    c->etype = pg_types_exemplar(ex);
    if (!c->etype) return pg_error_set(err, PG_ERR_NOMEM, "types: out of memory");
    /* The valid lists in texel order, built in chunks at once: each chunk counts its
     * texels of each type, the counts' prefix sums place each chunk's run in the lists,
     * and the chunks fill their runs. */
    size_t ne = (size_t)ex->nfaces * ex->face_size * ex->face_size;
    enum { CHUNKS = 64 };
    size_t(*at)[PG_TYPE_COUNT] = calloc(CHUNKS, sizeof *at);
    if (!at) return pg_error_set(err, PG_ERR_NOMEM, "types: out of memory");
#pragma omp parallel for schedule(static)
    for (int k = 0; k < CHUNKS; k++)
        for (size_t i = ne * k / CHUNKS; i < ne * (k + 1) / CHUNKS; i++)
            if (c->etype[i] != PG_TYPE_EXCLUDED) at[k][c->etype[i]]++;
    for (int t = 0; t < PG_TYPE_COUNT; t++) {
        size_t sum = 0;
        for (int k = 0; k < CHUNKS; k++) {
            size_t n = at[k][t];
            at[k][t] = sum, sum += n;
        }
        c->nvalid[t] = sum;
        c->valid[t] = pg_huge_malloc((sum + 1) * sizeof(uint32_t));
        if (!c->valid[t]) return free(at), pg_error_set(err, PG_ERR_NOMEM, "types: out of memory");
    }
    const int E = ex->face_size;
#pragma omp parallel for schedule(static)
    for (int k = 0; k < CHUNKS; k++)
        for (size_t i = ne * k / CHUNKS; i < ne * (k + 1) / CHUNKS; i++) {
            int t = c->etype[i];
            if (t == PG_TYPE_EXCLUDED) continue;
            c->valid[t][at[k][t]++] =
                pg_synth_pack((int)(i / ((size_t)E * E)), (int)(i % E), (int)(i / E % E));
        }
    free(at);
    for (int m = 0; m <= PG_TYPES_ALL; m++)
        for (int t = 0; t < PG_TYPE_COUNT; t++)
            if ((m >> t) & 1) c->nallowed[m] += c->nvalid[t];
    /* the types of each block: one row of blocks per iteration */
    const int nb = E >> PS_TYPE_BLOCK_SHIFT;
    c->eblock = calloc((size_t)ex->nfaces * nb * nb, 1);
    if (!c->eblock) return pg_error_set(err, PG_ERR_NOMEM, "types: out of memory");
#pragma omp parallel for schedule(static)
    for (int fb = 0; fb < ex->nfaces * nb; fb++)
        for (int y = 0; y < 1 << PS_TYPE_BLOCK_SHIFT; y++) {
            const uint8_t *row = c->etype + ((size_t)fb * (1 << PS_TYPE_BLOCK_SHIFT) + y) * E;
            for (int x = 0; x < E; x++)
                c->eblock[(size_t)fb * nb + (x >> PS_TYPE_BLOCK_SHIFT)] |= (uint8_t)(1u << row[x]);
        }
    /* every mask in use must leave valid texels */
    uint8_t masks = 0;
    for (int t = 0; t < PG_TYPE_COUNT; t++)
        if (c->nvalid[t]) masks |= (uint8_t)(1u << t);
    if (!(c->p->type_mask & masks))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--preset: no exemplar texel has an allowed type");
    const pg_planet_world *w = pg_ps_world_types(c->p) ? c->p->world : NULL;
    for (size_t i = 0; w && i < (size_t)6 * w->n * w->n; i++) {
        uint8_t m = pg_planet_world_mask_at(w, i);
        if (!(m & masks))
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "layout world: the exemplar has none of the types its climate "
                                "allows (type mask 0x%02x)",
                                m);
    }
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
    return asin(d[2] / pg_vec3_length(d)) * (180.0 / 3.14159265358979323846);
}

/* Nearest-pixel type mask of every texel of a level (type colours are discrete). */
pg_status pg_ps_types_level(pg_ps_ctx *c, int r, int ts, pg_error *err) {
    if (!c->p->types) return PG_OK;
    const pg_types_map *m = c->p->types;
    pg_cube_grid g;
    pg_status st = pg_cube_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, c->T, ts, err);
    if (st) return st;
    int64_t first[6], last[6]; /* distributed: the rows of the owned tiles */
    for (int f = 0; f < 6; f++) {
        int y0, y1;
        pg_ps_owned_rows(c, r, f, &y0, &y1);
        first[f] = ((int64_t)f * r + y0) * r, last[f] = ((int64_t)f * r + y1) * r;
    }
#pragma omp parallel for schedule(static)
    for (int64_t id = 0; id < (int64_t)6 * r * r; id++) {
        if (id < first[id / ((int64_t)r * r)] || id >= last[id / ((int64_t)r * r)]) continue;
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

/* How many texels of the class ahead the fix-up's check prefetches its type. */
#define TYPES_AHEAD 8

/* The climate constraint of layout world: the exemplar texel q's own annual mean
 * temperature (its cell of the exemplar's coarse climate, pg_planet_synth_world.c) lies
 * within PS_CLIMATE_K of the world's at the texel (tt, whole degrees C). Always true
 * without a world climate. */
#define PS_CLIMATE_K 10.0f
#define PS_CLIMATE_N 64 /* PS_WORLD_EXEMPLAR_N */

static bool climate_ok(const pg_ps_ctx *c, int tt, uint32_t q) {
    if (!c->ttemp || !c->world_t) return true;
    /* the cell's edge, E / PS_CLIMATE_N texels, is a power of two (E >= 64: world_t
     * exists only where pg_planet_world_exemplar_climate accepted E): a shift, where two
     * divisions per checked texel were */
    const int sh = __builtin_ctz((unsigned)c->ex->face_size) - __builtin_ctz(PS_CLIMATE_N);
    const int f = pg_synth_face(q), u = pg_synth_u(q), v = pg_synth_v(q);
    const float te = c->world_t[((size_t)f * PS_CLIMATE_N + (v >> sh)) * PS_CLIMATE_N + (u >> sh)];
    return fabsf(te - (float)tt) <= PS_CLIMATE_K;
}

/* Where a hashed draw among the exemplar texels whose type m allows lands: the address
 * of its entry in the valid lists, or NULL when m allows no exemplar texel. */
static const uint32_t *draw_slot(const pg_ps_ctx *c, uint8_t m, uint32_t h) {
    m &= PG_TYPES_ALL;
    const size_t total = c->nallowed[m];
    if (!total) return NULL;
    /* h < 2^32 and total <= the exemplar's texels < 2^32: a 32-bit division, h % total */
    size_t k = (uint32_t)h % (uint32_t)total;
    for (int t = 0; t < PG_TYPE_COUNT; t++) {
        if (!((m >> t) & 1)) continue;
        if (k < c->nvalid[t]) return &c->valid[t][k];
        k -= c->nvalid[t];
    }
    return NULL;
}

/* The level height of exemplar texel q's row in the appearance table, to prefetch. */
static const void *height_addr(const pg_ps_ctx *c, int scale, uint32_t q) {
    return c->ex->app[scale] + pg_synth_texel(c->ex, q) * PG_SYNTH_MAX_DIMS;
}

/* One texel the fix-up replaces, between the stages of fixup_batch. */
typedef struct fix_texel {
    ptrdiff_t i;  /* in the view */
    uint8_t m;    /* its mask */
    bool type_ok; /* its type is allowed (only the climate failed) */
    int tt;       /* the world's temperature there */
    uint32_t q[16];
    float vq[16];
    const uint32_t *slot[16];
} fix_texel;

/* How many failing texels of a row the fix-up gathers before it weighs them. */
#define FIX_BATCH 32

/* Weighs the candidates of n gathered texels and replaces each (pg_ps_types_fixup).
 * Their valid-list entries were prefetched when they were gathered; here they are read
 * and the candidates' heights prefetched for all n, then all n are weighed: the random
 * reads of many texels overlap. Each texel reads only itself and its neighbours of the
 * other classes, so the order in which the texels of a class are replaced changes
 * nothing. */
static void fixup_batch(const pg_ps_ctx *c, int scale, pg_synth_view *v, fix_texel *b, int n) {
    for (int j = 0; j < n; j++)
        for (int k = 8; k < 16; k++) {
            b[j].q[k] = b[j].slot[k] ? *b[j].slot[k] : 0;
            __builtin_prefetch(height_addr(c, scale, b[j].q[k]));
        }
    for (int j = 0; j < n; j++) {
        const fix_texel *t = &b[j];
        const ptrdiff_t i = t->i;
        const float want = pg_synth_level_height(c->ex, scale, v->S[i]) + v->V[i];
        float best = INFINITY, best_t = INFINITY; /* both constraints; the type alone */
        uint32_t bq = 0, bq_t = 0;
        float bv = 0, bv_t = 0;
        for (int k = 0; k < 16; k++) {
            if (k < 8 && !pg_ps_type_allowed_fast(c, t->m, t->q[k])) continue;
            const float w = k < 8 ? 1 : 2;
            float d = w * fabsf(pg_synth_level_height(c->ex, scale, t->q[k]) + t->vq[k] - want);
            if (d < best_t) best_t = d, bq_t = t->q[k], bv_t = t->vq[k];
            if (d < best && climate_ok(c, t->tt, t->q[k])) best = d, bq = t->q[k], bv = t->vq[k];
        }
        if (best < INFINITY) {
            v->S[i] = bq;
            v->V[i] = bv;
        } else if (!t->type_ok) {
            v->S[i] = bq_t;
            v->V[i] = bv_t;
        }
    }
}

/* Gain et al.'s type constraint, applied to the texels of one parity class of a view
 * after their correction. A disallowed texel is replaced by the allowed candidate
 * closest in level height to what it had (so the terrain keeps its shape): the
 * coherent candidates S[p+e] - h e of its 8 neighbours first (a coherent one wins
 * unless a draw is more than twice as close), then 8 hashed draws among the valid
 * exemplar texels.
 *
 * In layout world the climate constraint joins it (docs/generate.md, "Method":
 * "Climate constraint"): a texel whose exemplar source is more than PS_CLIMATE_K warmer
 * or colder than the world there is replaced the same way by a candidate that meets
 * both constraints. When none of the 16 does, a texel of an allowed type stays as it
 * is and one of a disallowed type takes the best of the allowed type alone, as before:
 * a world warmer or colder than anything on Earth keeps the type constraint.
 *
 * A replaced texel's candidates are random reads (a neighbour's candidate: its type and
 * height; a draw: its valid-list entry, then its height), about 2200 cycles a texel when
 * taken one texel at a time (seed 7, timed with rdtsc). So the scan gathers
 * up to FIX_BATCH failing texels of a row, computing their candidates' addresses and
 * prefetching them, and fixup_batch then weighs the batch in the same fixed order per
 * texel: the same result, with the misses of many texels in flight at once. */
void pg_ps_types_fixup(const pg_ps_ctx *c, int scale, int parity, pg_synth_view *v) {
    static const int nb[8][2] = {{1, 0},  {1, 1},   {0, 1},  {-1, 1},
                                 {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
    const int h = 1 << scale, r = (int)(c->N >> scale), px = parity & 1, py = parity >> 1;
    const uint64_t seed = c->p->synth.seed;
    /* texels of one parity class read only the other class: rows run in parallel */
#pragma omp parallel for schedule(static) if ((int64_t)v->w * v->h >= 16384)
    for (int y = 0; y < v->h; y++) {
        long gy = v->gy + y;
        if ((int)(gy & 1) != py) continue;
        fix_texel batch[FIX_BATCH];
        int n = 0;
        const int x0 = (int)((v->gx & 1) != px);
        for (int x = x0; x < v->w; x += 2) {
            long gx = v->gx + x;
            ptrdiff_t i = (ptrdiff_t)y * v->stride + x;
            /* the exemplar types of the texels a few steps on: random reads */
            uint8_t m = pg_ps_mask_at(c, r, v->face, gx, gy);
            if (x + 2 * TYPES_AHEAD < v->w) {
                const uint32_t qa = v->S[i + 2 * TYPES_AHEAD];
                if (pg_ps_type_block_mixed(c, m, qa))
                    __builtin_prefetch(c->etype + pg_synth_texel(c->ex, qa));
            }
            const int tt =
                c->ttemp ? c->ttemp[((size_t)v->face * r + (size_t)gy) * r + (size_t)gx] : 0;
            const bool type_ok = pg_ps_type_allowed_fast(c, m, v->S[i]);
            if (type_ok && climate_ok(c, tt, v->S[i])) continue;
            /* gather: the 16 candidates' addresses, prefetched */
            fix_texel *t = &batch[n++];
            t->i = i, t->m = m, t->type_ok = type_ok, t->tt = tt;
            __builtin_prefetch(height_addr(c, scale, v->S[i]));
            for (int k = 0; k < 8; k++) {
                int ex = nb[k][0], ey = nb[k][1];
                ptrdiff_t j = i + (ptrdiff_t)ey * v->stride + ex;
                t->q[k] = pg_synth_view_move(c->ex, v, j, -h * ex, -h * ey);
                t->vq[k] = v->V[j];
                if (pg_ps_type_block_mixed(c, m, t->q[k]))
                    __builtin_prefetch(c->etype + pg_synth_texel(c->ex, t->q[k]));
                __builtin_prefetch(height_addr(c, scale, t->q[k]));
            }
            for (int k = 8; k < 16; k++) {
                t->slot[k] = draw_slot(c, m, pg_hash_texel(seed, scale, v->face, gx, gy, 12 + k));
                t->vq[k] = 0;
                if (t->slot[k]) __builtin_prefetch(t->slot[k]);
            }
            if (n == FIX_BATCH) fixup_batch(c, scale, v, batch, n), n = 0;
        }
        fixup_batch(c, scale, v, batch, n);
    }
}
