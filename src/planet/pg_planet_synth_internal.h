/* pg_planet_synth_internal.h - what the planet synthesis files (src/planet/pg_planet_synth*.c)
 * share: the level storage, the run's context, the distribution hooks' ownership tests,
 * and the functions one file calls in another. Not a public API; the prefix pg_ps_ marks
 * these internals.
 *
 * The files: pg_planet_synth.c (the driver: context, pyramid, delivery order),
 * pg_planet_synth_params.c (defaults, sizing, checks), pg_planet_synth_level.c (level
 * storage, face borders, the per-tile level operations), pg_planet_synth_types.c (type
 * constraints), pg_planet_synth_guide.c (guide), pg_planet_synth_world.c (layout world's
 * coarsest level), pg_planet_synth_pits.c (Gain-pit in the
 * pyramid, the final pass and the depression counts), pg_planet_synth_deliver.c
 * (magnification and the delivered planet). */
#ifndef PG_PLANET_SYNTH_INTERNAL_H
#define PG_PLANET_SYNTH_INTERNAL_H

#include "planetgen/pg_planet_synth.h"
#include "pg_span.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The rows of a level that this process touches (docs/mpi.md, "Memory per rank"): every
 * row in one process and at the levels a distributed process holds whole (the coarsest,
 * made by every process; levels the tiles do not divide; levels gathered for the pits,
 * the land agreement or a final pass without hooks); else, per face, the rows of its
 * own tiles widened by PG_PS_WINDOW_MARGIN (the exchanges' rings are at most 2 wide,
 * the reads one more), unclipped: each array clips them to its own border. */
#define PG_PS_WINDOW_MARGIN 3
typedef struct pg_ps_window {
    bool whole;
    int y0[6], y1[6]; /* per face; y0 == y1: no row */
} pg_ps_window;

/* One level of the pyramid: the six faces as (r + 2)^2 arrays of exemplar coordinates S
 * and offsets V, with a one-texel border around each face. Distributed, the arrays are
 * reserved whole and only the window's rows committed (pg_span.h). */
typedef struct pg_ps_level {
    int r;        /* texels per face edge */
    ptrdiff_t st; /* row stride r + 2 */
    size_t fsz;   /* (r + 2)^2 */
    uint32_t *S;  /* 6 * fsz */
    float *V;
    pg_ps_window win;
    pg_span sS, sV; /* distributed: the reservations behind S and V */
} pg_ps_level;

/* The face borders: for each border texel its source (a texel of a neighbouring face)
 * and the orientation from this face's frame into the source's. Distributed, only the
 * border texels within two texels of an owned tile are listed, those whose source this
 * process owns first (the first nlocal, copied by pg_ps_border_refresh); the others'
 * sources belong to other processes, whose exchange writes the border texel itself
 * (docs/mpi.md, "Memory per rank"), so no process stores a foreign face's edge. */
typedef struct pg_ps_border {
    size_t n, nlocal, *dst, *src;
    uint8_t *orient; /* 6 * fsz, zero inside; allocated per level, in the level's window */
    pg_span sorient;
} pg_ps_border;

/* The run's context: parameters resolved once, buffers that live for the whole run. */
typedef struct pg_ps_ctx {
    const pg_synth_exemplar *ex;
    /* an exemplar mapped from the cache: a shallow copy whose densely read levels point
     * to private copies on huge pages while they are synthesized (pg_synth_copy_level) */
    pg_synth_exemplar *own;
    const pg_synth_exemplar *given;
    const pg_planet_synth_params *p;
    int T, S, s_top;
    int64_t N;    /* synthesized texels per face edge: Nout / m */
    int64_t Nout; /* delivered texels per face edge: tiles * tile_size */
    int m;        /* magnification from synthesized to delivered texels (a power of two) */
    int keep;     /* layout earth: levels kept without jitter (resolved from auto) */
    bool independent_tiles; /* test only (pg_planet_synth_testing.h) */
    pg_ps_border bm;
    /* types */
    bool use_types;
    uint8_t *etype; /* exemplar texel types */
    /* The types present in each block of 2^PS_TYPE_BLOCK_SHIFT x 2^PS_TYPE_BLOCK_SHIFT
     * exemplar texels, one bit each (PG_TYPE_EXCLUDED's too). Where a mask allows every
     * type of the block, a texel's check needs no random read of etype: so for 98% of
     * the fix-up's checks on seed 7's default planet (the share depends on the masks).
     * The table (6 (E/4)^2 bytes, 384 KiB at E = 1024) stays in cache where etype
     * (6 MiB) does not. */
    uint8_t *eblock;
    uint32_t *valid[PG_TYPE_COUNT];
    size_t nvalid[PG_TYPE_COUNT];
    size_t nallowed[PG_TYPES_ALL + 1]; /* per mask: the valid texels of its types */
    uint8_t *mask;                     /* per level texel (6 r^2) when a type map is given */
    /* layout world's climate constraint: the world's temperature per level texel (whole
     * degrees C) and the exemplar texels' own (world_t below) */
    int8_t *ttemp;
    /* guide */
    float *guide;                  /* per level texel, metres */
    pg_span smask, sguide, sttemp; /* distributed: reserved at the finest level's size, each
                                      level's window opened as it comes */
    /* layout world: the exemplar's own coarse climate (pg_planet_synth_world.c) */
    float *world_t, *world_p;
    pg_planet_synth_info *info;
    double work_done, work_total;
} pg_ps_ctx;

static inline int pg_ps_top_scale(const pg_synth_exemplar *ex) {
    return ex->levels - 1;
}

/* Index of texel (x, y) of face f; x, y in -1..r (the border included). */
static inline size_t pg_ps_at(const pg_ps_level *L, int f, int x, int y) {
    return (size_t)f * L->fsz + (size_t)(y + 1) * (size_t)L->st + (size_t)(x + 1);
}

/* ------------- distribution hooks (docs/mpi.md, "What is distributed, and how") ------------- */

/* Without p->dist this process owns every tile and exchanges nothing, so the
 * single-process path is unchanged. */
static inline bool pg_ps_owns(const pg_ps_ctx *c, int f, int tx, int ty) {
    const pg_planet_synth_dist *d = c->p->dist;
    return !d || d->owns(d->user, f, tx, ty);
}

/* Does Gain-pit run after the passes of level `scale` (r texels per face edge)? Not at the
 * finest p->pit_skip_levels, nor on a level of one texel per face (the coarsest of a planet
 * with N = 32), which has no grid to drain on: the next level's pass and the final pass see
 * its texels. */
static inline bool pg_ps_gainpit_at(const pg_ps_ctx *c, int scale, int r) {
    return c->p->pits && scale >= c->p->pit_skip_levels && r >= 2;
}

/* Distributed pit removal for a level of r texels per face edge: the hook, when the
 * tiles divide the level (coarser levels are gathered: at most T^2 texels a face). */
static inline bool pg_ps_dist_pits(const pg_ps_ctx *c, int r) {
    return c->p->dist && c->p->dist->pits && r % c->T == 0;
}

/* The land/ocean agreement summed over the processes (each counts its tiles). */
static inline bool pg_ps_dist_sum(const pg_ps_ctx *c, int r) {
    return c->p->dist && c->p->dist->sum && r % c->T == 0;
}

/* Is texel (x, y) of face f, at a level of r texels per face edge, in an owned tile? */
static inline bool pg_ps_owned_at(const pg_ps_ctx *c, int r, int f, int x, int y) {
    const int ts = r / c->T;
    return pg_ps_owns(c, f, x / ts, y / ts);
}

/* The type mask at texel (x, y) of face f of a level of r texels per face edge. */
static inline uint8_t pg_ps_mask_at(const pg_ps_ctx *c, int r, int f, long x, long y) {
    if (!c->mask) return c->p->type_mask;
    return c->mask[((size_t)f * r + (size_t)y) * r + (size_t)x];
}

/* Whether mask m allows exemplar texel q's type. The mask is read through PG_TYPES_ALL,
 * so no mask allows PG_TYPE_EXCLUDED (pg_types.h). */
static inline bool pg_ps_type_allowed(const pg_ps_ctx *c, uint8_t m, uint32_t q) {
    return ((m & PG_TYPES_ALL) >> c->etype[pg_synth_texel(c->ex, q)]) & 1;
}

/* Exemplar texels a side of one block of eblock (the face size is a multiple). */
#define PS_TYPE_BLOCK_SHIFT 2

/* The types of q's block of the exemplar (pg_ps_ctx.eblock). */
static inline uint8_t pg_ps_type_block(const pg_ps_ctx *c, uint32_t q) {
    const size_t nb = (size_t)c->ex->face_size >> PS_TYPE_BLOCK_SHIFT;
    return c->eblock[((size_t)pg_synth_face(q) * nb + (pg_synth_v(q) >> PS_TYPE_BLOCK_SHIFT)) * nb +
                     (pg_synth_u(q) >> PS_TYPE_BLOCK_SHIFT)];
}

/* Whether q's block holds a type that m does not allow: only then does the check need
 * etype (and its prefetch pay). */
static inline bool pg_ps_type_block_mixed(const pg_ps_ctx *c, uint8_t m, uint32_t q) {
    return pg_ps_type_block(c, q) & (uint8_t) ~(m & PG_TYPES_ALL);
}

/* pg_ps_type_allowed, answered from q's block when the mask allows all its types: the
 * same answer, with the random read of etype only where the block is mixed. */
static inline bool pg_ps_type_allowed_fast(const pg_ps_ctx *c, uint8_t m, uint32_t q) {
    if (!pg_ps_type_block_mixed(c, m, q)) return true;
    return pg_ps_type_allowed(c, m, q);
}

/* --------------------------- pg_planet_synth_level.c --------------------------- */

pg_ps_window pg_ps_level_window(const pg_ps_ctx *c, int scale, int r);
pg_status pg_ps_rows_alloc(const pg_ps_ctx *c, const pg_ps_window *w, int r, int pad, size_t elem,
                           bool zero, void **out, pg_span *span, pg_error *err);
pg_status pg_ps_rows_open(const pg_ps_window *w, int r, int pad, size_t elem, pg_span *span,
                          pg_error *err);
void pg_ps_rows_free(void *p, pg_span *span);
pg_status pg_ps_level_alloc(const pg_ps_ctx *c, pg_ps_level *L, int scale, int r);
void pg_ps_level_free(pg_ps_level *L);
pg_status pg_ps_border_build(const pg_ps_ctx *c, const pg_ps_level *L, int ts, bool all,
                             pg_ps_border *b, pg_error *err);
void pg_ps_border_refresh(const pg_ps_border *b, pg_ps_level *L, bool whole);
void pg_ps_owned_rows(const pg_ps_ctx *c, int r, int f, int *y0, int *y1);
bool pg_ps_owned_near(const pg_ps_ctx *c, int r, int f, int x, int y, int d);
pg_status pg_ps_exchange(const pg_ps_ctx *c, int scale, const pg_ps_level *L, int width,
                         pg_error *err);
void pg_ps_init_top(pg_ps_ctx *c, pg_ps_level *L);
void pg_ps_jitter_level(const pg_ps_ctx *c, int scale, pg_ps_level *L);
void pg_ps_upsample_level(const pg_ps_ctx *c, int s, const pg_ps_level *parent, pg_ps_level *child);
pg_status pg_ps_correct_subpass_all(pg_ps_ctx *c, int scale, int parity, pg_ps_level *L,
                                    pg_error *err);
void pg_ps_land_agreement(pg_ps_ctx *c, int scale, const pg_ps_level *L);

/* --------------------------- pg_planet_synth_types.c --------------------------- */

/* Layout world without a caller's guide or type map: both come from the macro world,
 * sampled on the cube at each level (pg_planet_world_level). */
static inline bool pg_ps_world_guide(const pg_planet_synth_params *p) {
    return !p->guide && p->layout == PG_LAYOUT_WORLD && p->world;
}
static inline bool pg_ps_world_types(const pg_planet_synth_params *p) {
    return !p->types && p->layout == PG_LAYOUT_WORLD && p->world;
}

/* The climate constraint (the world's temperature per level texel) holds in layout world
 * whatever gives the type map. */
static inline bool pg_ps_world_climate(const pg_planet_synth_params *p) {
    return p->layout == PG_LAYOUT_WORLD && p->world;
}

pg_status pg_ps_types_setup(pg_ps_ctx *c, pg_error *err);
pg_status pg_ps_types_level(pg_ps_ctx *c, int r, int ts, pg_error *err);
void pg_ps_types_fixup(const pg_ps_ctx *c, int scale, int parity, pg_synth_view *v);

/* --------------------------- pg_planet_synth_guide.c --------------------------- */

pg_status pg_ps_guide_level(pg_ps_ctx *c, int r, pg_error *err);
/* The blend weight w of the level at `scale` (pg_guide_weight, as a float). */
float pg_ps_guide_w(const pg_ps_ctx *c, int scale);
void pg_ps_guide_blend(const pg_ps_ctx *c, int scale, size_t n, float *R, float *Vc,
                       const float *G);

/* --------------------------- pg_planet_synth_world.c --------------------------- */

pg_status pg_ps_world_setup(pg_ps_ctx *c, pg_error *err);
uint32_t pg_ps_world_pick(const pg_ps_ctx *c, int r, int f, int x, int y);
pg_status pg_ps_world_level(pg_ps_ctx *c, int r, pg_error *err);

/* --------------------------- pg_planet_synth_pits.c ---------------------------- */

pg_status pg_ps_after_pass(pg_ps_ctx *c, int scale, pg_ps_level *L, pg_error *err);
bool pg_ps_dist_final(const pg_ps_ctx *c);
pg_status pg_ps_final_pits(pg_ps_ctx *c, float *H, bool whole, double *closed, pg_error *err);

/* -------------------------- pg_planet_synth_deliver.c -------------------------- */

void pg_ps_finest_heights(const pg_ps_ctx *c, const pg_ps_level *L, float *H, bool all);
void pg_ps_render(const pg_ps_ctx *c, const pg_ps_level *L, const float *H, const pg_sea_ice *ice,
                  pg_planet *out, uint32_t *coords);

#endif
