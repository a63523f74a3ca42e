/* pg_pits.h - pit (closed depression) removal on flat grids and on the cube sphere.
 *
 * Example-based synthesis stitches real terrain together and leaves pits: closed
 * basins without an outlet. This module removes them (Scott & Dodgson 2021, §3) with
 * three algorithms, each in its own source file:
 *   - Priority-Flood fill, "improved" with a FIFO pit queue (Barnes, Lehman & Mulla
 *     2014), plain (minimal fill, flats stay flat) or with epsilon (nextafter: no flats);
 *   - breaching by flood order (Soille 2004, as described by Scott & Dodgson 2021 §3.2);
 *   - hybrid selective breaching (Lindsay 2016): breach when the channel is at most
 *     max_depth deep and max_length cells long, fill otherwise.
 *
 * Every algorithm walks the cells through one neighbour interface (pg_pits_topo), so
 * the same code runs on a flat 8-connected W x H grid and on the cube sphere (6 faces
 * of N x N texels, 8-connected across face seams, 7 neighbours at the 8 cube-corner
 * texels). Global cell id: grid y*W + x; cube face*N*N + y*N + x, with the faces,
 * frames and seams of pg_cube.h (+Z north).
 *
 * Sinks (cells that are outlets and are never modified): every cell at or below the
 * sea level, every cell of the optional lakes mask, no-data cells, and on flat grids
 * with open_edges every border cell. If that set is empty (a planet with no ocean),
 * the single lowest cell is the sink (ties: smallest global id) - the whole planet
 * then drains into it.
 *
 * Determinism: the flood priority is (height, global id), so the result depends only
 * on the heights, the topology and the options - never on tiling or thread count.
 *
 * Inside a synthesis (Gain-pit, Scott & Dodgson 2021 §5): after each correction pass,
 * reconstruct R, call pg_pits_correct_offsets(topo, R, offsets, ...): it computes the
 * pit-free R' and adds R' - R to the offsets, so that reconstruction yields R'. */
#ifndef PLANETGEN_PG_PITS_H
#define PLANETGEN_PG_PITS_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_cube.h"

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- topology ------------------------------------------------------------------ */

/* PG_PITS_BLOCKS: square blocks of w x w cells (one "face" each, laid one after the
 * other), whose interior takes the fast path below and whose border cells ask the
 * function `border` of the caller (the tile-local arrays of the distributed pits,
 * src/mpi/pg_mpi_ring.c, whose border neighbours lie in other blocks or in a ring of
 * cells after the blocks). Made by pg_pits_topo_blocks. */
typedef enum pg_pits_topo_kind {
    PG_PITS_GRID = 0,
    PG_PITS_CUBE = 1,
    PG_PITS_BLOCKS = 2
} pg_pits_topo_kind;

typedef int (*pg_pits_border_fn)(const void *ctx, uint32_t id, uint32_t out[8]);

/* A cell topology. Plain data, no allocation: make it with pg_pits_topo_grid/cube. */
typedef struct pg_pits_topo {
    pg_pits_topo_kind kind;
    uint32_t w, h;            /* grid: width and height; cube: w = h = N (face size) */
    uint32_t nfaces;          /* 1 for a grid, 6 for the cube */
    uint64_t ncells;          /* w*h*nfaces, < 2^32 */
    double inv_w, inv_face;   /* 1/w and 1/(w*h): division-free coordinates */
    pg_cube_grid cube;        /* cube only: the seam map of pg_cube.h (T = N, S = 1) */
    pg_pits_border_fn border; /* blocks only: the neighbours of a block's border cell */
    const void *border_ctx;
    uint32_t extra; /* blocks only: the cells after the blocks */
} pg_pits_topo;

pg_status pg_pits_topo_grid(pg_pits_topo *t, uint32_t w, uint32_t h, pg_error *err);
pg_status pg_pits_topo_cube(pg_pits_topo *t, uint32_t n, pg_error *err);
/* nblocks blocks of w x w cells (ids block * w^2 + y * w + x) and `extra` more cells
 * after them whose neighbours nobody asks; border(ctx, id, out) gives a border cell's
 * neighbours (any ids below ncells). pg_pits_remove, pg_pits_remove_counted,
 * pg_pits_correct_offsets and pg_pits_stats_compute ask every reachable cell's
 * neighbours and refuse extra > 0 with PG_ERR_BADINPUT; the extra cells are for
 * callers that look only at the blocks' neighbours (the distributed pits' ring). */
pg_status pg_pits_topo_blocks(pg_pits_topo *t, uint32_t w, uint32_t nblocks, uint32_t extra,
                              pg_pits_border_fn border, const void *ctx, pg_error *err);

/* Neighbours of a cell on a face border (or the grid border): writes up to 8 ids to
 * out and returns how many (grid: 3/5/8; cube: 8, or 7 at a cube-corner texel). */
int pg_pits_neighbours_slow(const pg_pits_topo *t, uint32_t id, uint32_t out[8]);

/* The one neighbour iteration used by every algorithm: interior cells take the
 * inline fast path (same offsets on both topologies), border cells the slow one.
 * Order for interior cells: the 8 neighbours in raster order (dy, dx = -1..1). */
static inline uint32_t pg_pits__div(uint32_t n, uint32_t d, double inv_d) {
    uint32_t q = (uint32_t)((double)n * inv_d); /* exact up to one step either way */
    if ((uint64_t)q * d > n)
        q--;
    else if ((uint64_t)(q + 1) * d <= n)
        q++;
    return q;
}

/* The same for a cell whose place on its face (x, y) the caller knows, as a loop over
 * the rows does: no division. */
static inline int pg_pits_neighbours_xy(const pg_pits_topo *t, uint32_t id, uint32_t x, uint32_t y,
                                        uint32_t out[8]) {
    const uint32_t w = t->w;
    if (x - 1u < w - 2u && y - 1u < t->h - 2u) {
        out[0] = id - w - 1;
        out[1] = id - w;
        out[2] = id - w + 1;
        out[3] = id - 1;
        out[4] = id + 1;
        out[5] = id + w - 1;
        out[6] = id + w;
        out[7] = id + w + 1;
        return 8;
    }
    return pg_pits_neighbours_slow(t, id, out);
}

static inline int pg_pits_neighbours(const pg_pits_topo *t, uint32_t id, uint32_t out[8]) {
    uint32_t w = t->w, in_face = id;
    if (t->nfaces > 1) in_face = id - pg_pits__div(id, w * t->h, t->inv_face) * (w * t->h);
    uint32_t y = pg_pits__div(in_face, w, t->inv_w), x = in_face - y * w;
    return pg_pits_neighbours_xy(t, id, x, y, out);
}

/* ---- removal ------------------------------------------------------------------- */

typedef enum pg_pits_method {
    PG_PITS_FILL = 0,   /* Barnes, Lehman & Mulla 2014 improved Priority-Flood */
    PG_PITS_BREACH = 1, /* Soille 2004 breaching by flood order */
    PG_PITS_HYBRID = 2  /* Lindsay 2016 selective breaching */
} pg_pits_method;

typedef struct pg_pits_opts {
    pg_pits_method method;
    /* epsilon: every non-sink cell gets a strictly descending path to a sink (no
     * flats). Without it, paths never ascend (plain fill is the minimal fill). */
    bool epsilon;
    double max_depth;  /* hybrid: no cell lowered more than this below its original
                          height, height units (>= 0) */
    double max_length; /* hybrid: most cells one breach channel may lower (>= 0) */
    bool has_sea_level;
    double sea_level;     /* cells <= sea_level are ocean sinks */
    const uint8_t *lakes; /* optional, ncells bytes, nonzero = lake sink */
    bool open_edges;      /* grid only: border cells are outlets (GIS convention) */
    bool has_nodata;      /* cells == nodata (or NaN) are sinks, left unchanged (NaN */
    float nodata;         /* cells come back as nodata); without has_nodata, NaN cells
                             are PG_ERR_BADINPUT */
    /* Plain fill runs the tiled parallel Priority-Flood (Barnes 2016) when more than
     * one OpenMP thread is available or tile_rows > 0 (rows per tile; 0 = automatic);
     * pg_pits_remove_counted only when tile_rows > 0 (its check after is cheaper on
     * the serial flood). The result is bit-identical to the serial fill. Thread
     * count: OpenMP's. */
    int tile_rows;
    /* breach and hybrid: carve along the descent tree of the minimal epsilon-surface
     * instead of the flood tree (src/pg_pits_descent_breach.c). Its result depends on
     * no flood order, so a tiling (MPI ranks) can reproduce it bit for bit. */
    bool descent;
} pg_pits_opts;

/* Defaults: breach with epsilon, no sea level, no lakes, closed edges, no no-data,
 * max_depth = max_length = +inf. */
void pg_pits_opts_default(pg_pits_opts *o);

/* "fill" | "breach" | "hybrid" -> method; returns false for anything else. */
bool pg_pits_method_parse(const char *s, pg_pits_method *m);
const char *pg_pits_method_name(pg_pits_method m);
/* One-line citation of the paper the method implements (for --verbose). */
const char *pg_pits_method_citation(pg_pits_method m);
/* The citation of what pg_pits_remove runs with these options: the method's, or for
 * breach and hybrid with `descent`, the descent-tree form's. */
const char *pg_pits_citation(const pg_pits_opts *o);

/* What a removal did. */
typedef struct pg_pits_result {
    uint64_t raised, lowered; /* cells changed upward / downward */
    uint64_t sinks;           /* cells that acted as outlets */
    uint64_t breaches, fills; /* hybrid: channels carved / depressions filled */
    double max_raise, max_lower;
} pg_pits_result;

/* Remove every pit of h (topology t, ncells floats) in place. res may be NULL.
 * Errors: PG_ERR_BADINPUT for NaN without nodata, bad limits, lakes/topology
 * mismatch, blocks with cells after them; PG_ERR_NOMEM. */
pg_status pg_pits_remove(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                         pg_pits_result *res, pg_error *err);

/* Gain-pit step: R' = remove(recon); offsets += R' - R. recon is not modified. */
pg_status pg_pits_correct_offsets(const pg_pits_topo *t, const float *recon, float *offsets,
                                  const pg_pits_opts *o, pg_pits_result *res, pg_error *err);

/* ---- metrics ------------------------------------------------------------------- */

/* Per-cell area in m^2, for cells of unequal size (cube sphere texels). */
typedef double (*pg_pits_area_fn)(void *ctx, uint32_t id);

typedef struct pg_pits_area {
    const float *per_cell; /* ncells areas in m^2, or NULL */
    pg_pits_area_fn fn;    /* used when per_cell is NULL and fn is set */
    void *ctx;
    double constant; /* used when both are NULL (flat grid: cell size squared) */
} pg_pits_area;

typedef struct pg_pits_stats {
    uint64_t depressions;      /* 8-connected regions that a fill raises */
    uint64_t depression_cells; /* cells in them */
    double depression_area_m2;
    double depression_volume_m3; /* sum over those cells of (fill - h) * area: the water */
    double max_depth_m;          /* largest fill - h (fill: the minimal fill) */
    uint64_t sinks;
} pg_pits_stats;

/* Areas (m^2) of the n x n texels of one cube face on a sphere of the given radius,
 * as spherical quadrilaterals between the texel corners of projection p; every face
 * has the same areas (the projections share the cube's symmetry). Pass them to the
 * statistics as an area callback with pg_pits_cube_area_fn and ctx = the array. */
pg_status pg_pits_cube_face_areas(pg_cube_projection p, uint32_t n, double radius, double *areas,
                                  pg_error *err);
/* ctx: the n*n array from pg_pits_cube_face_areas; id: a global texel id. The face
 * size comes from the array's length, so ctx must be a pg_pits_cube_areas. */
typedef struct pg_pits_cube_areas {
    const double *face; /* n*n */
    uint32_t n;
} pg_pits_cube_areas;
double pg_pits_cube_area_fn(void *ctx, uint32_t id);

/* Count the depressions of h without changing it. The sinks come from o (sea level,
 * lakes, edges, nodata; method and epsilon are ignored). A depression is a connected
 * region raised by the minimal fill; its volume and depth are the water that fill
 * holds there. Drained flats are therefore not depressions, and no epsilon ulps count
 * as water. */
pg_status pg_pits_stats_compute(const pg_pits_topo *t, const float *h, const pg_pits_opts *o,
                                const pg_pits_area *area, pg_pits_stats *st, pg_error *err);

/* pg_pits_remove, and the depressions of h before (the input) and after (the result):
 * the same figures as pg_pits_stats_compute on each, at a fraction of the cost,
 * because the removal's own flood gives the minimal fill the count needs where it can
 * (a plain fill is it; the epsilon fill and Soille's breach compute it on the way) and
 * the result is checked by a linear certificate instead of a search (docs/pits.md,
 * "Metrics"). area as in pg_pits_stats_compute; res may be NULL. */
#define PG_PITS_HAVE_REMOVE_COUNTED 1 /* (for code built against several versions) */
pg_status pg_pits_remove_counted(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                 const pg_pits_area *area, pg_pits_result *res,
                                 pg_pits_stats *before, pg_pits_stats *after, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
