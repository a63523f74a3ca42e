/* pg_pits_barnes2016_core.h - the steps of Barnes (2016) that every tiling shares (not
 * public API): the labelled flood of one tile with its spill edges, and the minimax
 * solve of the label graph. Used by the threaded fill (pg_pits_barnes2016_parallel_fill.c,
 * tiles = runs of whole rows) and by the MPI fill (src/mpi/pg_mpi_pits_barnes2016_fill.c,
 * tiles = square blocks of cube faces, one rank's tiles at a time). The paper, its
 * preconditions and why the steps compose exactly: pg_pits_barnes2016_core.c. */
#ifndef PG_PITS_BARNES2016_CORE_H
#define PG_PITS_BARNES2016_CORE_H

#include "pg_pits_internal.h"

#include <stddef.h>
#include <stdint.h>

/* Label 0 = not reached yet; label 1 = the outlet (every sink). */
enum { PITS_B16_OUTLET = 1 };

/* An edge of the label graph: water crosses from label a to label b at height w. */
typedef struct pits_b16_edge {
    uint32_t a, b;
    float w;
} pits_b16_edge;

typedef struct pits_b16_edges {
    pits_b16_edge *e;
    size_t n, cap;
    int oom;
} pits_b16_edges;

/* Append (a, b, w) with a < b; a pair a == b is no edge and is dropped. */
void pits_b16_edge_push(pits_b16_edges *v, uint32_t a, uint32_t b, float w);
/* Sort by (a, b, w) and keep each pair's lowest w: the graph's answer is the same. */
void pits_b16_edges_compact(pits_b16_edges *v);

/* One tile. Its cells lie in the ids [lo, hi): with w = 0 all of them (a run of whole
 * rows), else those whose column (id mod w) is in [c0, c1) (a block of a cube face,
 * whose rows are w = N ids apart). */
typedef struct pits_b16_tile {
    const pg_pits_topo *t;
    float *h;          /* in: heights; out: the tile's own fill W (sinks untouched) */
    uint32_t *label;   /* the tile's cells: 0 on entry; out: the label each joined */
    const uint8_t *st; /* sinks: st[id] != PITS_OPEN (pits_begin's marking) ... */
    double sea;        /* ... or, with st NULL, h[id] <= sea */
    uint32_t lo, hi;
    uint32_t w, c0, c1;
    int wshift;          /* log2(w) when w is a power of two, else -1 */
    uint32_t next_label; /* perimeter labels: next_label, next_label + 1, ...; 0: 2 + id */
} pits_b16_tile;

static inline int pits_b16_inside(const pits_b16_tile *g, uint32_t id) {
    if (id < g->lo || id >= g->hi) return 0;
    if (!g->w) return 1;
    uint32_t col = g->wshift >= 0 ? id & (g->w - 1) : id % g->w;
    return col >= g->c0 && col < g->c1;
}

static inline int pits_b16_sink(const pits_b16_tile *g, uint32_t id) {
    return g->st ? g->st[id] != PITS_OPEN : g->h[id] <= g->sea;
}

/* A cell's height as a way out: sinks take water at any height. */
static inline float pits_b16_eff(const pits_b16_tile *g, uint32_t id) {
    return pits_b16_sink(g, id) ? -INFINITY : g->h[id];
}

/* Steps 1 and 2 on one tile: the labelled Priority-Flood and its spill edges. Edges
 * between two labels of the tile go to ev; every pair of neighbouring cells in two
 * tiles goes to cross once (from the lower id) as (cell, cell, spill height), for the
 * caller to turn into labels once it knows the other side's. Returns nonzero when out
 * of memory. */
int pits_b16_flood_tile(pits_b16_tile *g, pits_b16_edges *ev, pits_b16_edges *cross);

/* Step 3: the minimax level of every label index in [0, nl) over the edges of the nev
 * vectors ev (endpoints are label indices), from `source` (the outlet's index;
 * UINT32_MAX: none, every level +inf). Returns nonzero when out of memory. */
int pits_b16_solve(const pits_b16_edges *ev, size_t nev, size_t nl, uint32_t source, float *level);

/* ---- sorted tables of labels (the MPI forms index labels by binary search) ---- */

/* Sort a[0..n) and drop repeats; returns the new count (labels: 64-bit global ids of
 * the distributed pits). */
size_t pits_sort_unique_u64(uint64_t *a, size_t n);
/* The index of v in the sorted a[0..n) (where it would go when absent). */
size_t pits_sorted_index_u64(const uint64_t *a, size_t n, uint64_t v);

#endif
