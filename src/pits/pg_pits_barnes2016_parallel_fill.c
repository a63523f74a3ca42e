/* pg_pits_barnes2016_parallel_fill.c - plain depression filling in parallel, by tiles.
 *
 * Source: R. Barnes (2016), "Parallel Priority-Flood depression filling for trillion
 * cell digital elevation models on desktops or clusters", Computers & Geosciences
 * 96:56-68 (its three stages, in shared memory).
 *
 * Idea. Cut the cells into tiles (runs of whole rows: ids [lo, hi)). Stage 1, one
 * tile per thread: a Priority-Flood (Barnes et al. 2014) that sees only the tile,
 * seeded with the tile's sinks (label 1, the outlet) and with every perimeter cell
 * (a cell with a neighbour in another tile), each under its own label. Every cell
 * joins the label of the cell it was flooded from and is filled to the level of its
 * label's seed. Where two labels touch, the pair's spill height max(W(a), W(b)) is
 * an edge of a label graph; so is every pair of neighbouring perimeter cells in two
 * different tiles. Stage 2: a minimax Dijkstra over the label graph from the outlet
 * gives each label the lowest level at which its water reaches a sink. Stage 3, in
 * parallel: every cell becomes max(W(c), level(label(c))). The tile flood and the
 * solve are the shared core (pg_pits_barnes2016_core.c, also used by the MPI fill);
 * this file chooses the tiles, runs them on threads and applies the levels.
 *
 * Preconditions: plain (non-epsilon) fill; state[] holds the sinks (pits_begin's
 * marking); sinks count as outlets at any height, as in the serial flood.
 * Why it is correct (Barnes 2016, §3): the minimal fill of a cell is the minimax
 * height over paths to a sink. Inside a tile that path ends at a sink or leaves the
 * tile through a perimeter cell; the in-tile flood gives the minimax to its label's
 * seed, and the label graph composes these segments exactly (every crossing between
 * labels is an edge with its spill height). The minimal fill is unique, so the
 * result is bit-identical to the serial fill for any tiling and thread count; the
 * tests compare them on random grids with many small tiles. */
#include "pg_huge.h"
#include "pg_pits_barnes2016_core.h"

#include <omp.h>
#include <stdlib.h>

typedef struct tiling {
    const pg_pits_topo *t;
    float *h;           /* in: heights; after stage 1: W (in-tile fill) */
    const uint8_t *st;  /* sinks */
    uint32_t *label;    /* 0 = not yet reached */
    uint64_t tile_size; /* cells per tile (whole rows) */
    uint32_t ntiles;
    uint32_t bound; /* labels per tile: at least its perimeter cell count */
} tiling;

/* Stage 1 on one tile (ids [lo, hi)): its perimeter labels are 2 + tile*bound + k.
 * Cross-tile pairs go to `cross` as cell ids; they become label pairs once every tile
 * has labelled its perimeter. */
static int flood_tile(tiling *g, uint32_t tile, pits_b16_edges *ev, pits_b16_edges *cross) {
    uint64_t lo = (uint64_t)tile * g->tile_size, hi = lo + g->tile_size;
    if (hi > g->t->ncells) hi = g->t->ncells;
    /* the tile's thread zeroes its labels: first touch by a write (a read would map
     * the zero page, and the write after it costs a second fault) */
    memset(g->label + lo, 0, (hi - lo) * sizeof *g->label);
    pits_b16_tile b = {.t = g->t,
                       .h = g->h,
                       .label = g->label,
                       .st = g->st,
                       .lo = (uint32_t)lo,
                       .hi = (uint32_t)hi,
                       .wshift = -1,
                       .next_label = 2 + tile * g->bound};
    return pits_b16_flood_tile(&b, ev, cross);
}

/* Turn the cross-tile cell pairs into label pairs (perimeter labels are final). */
static void label_cross_edges(const tiling *g, pits_b16_edges *cross) {
    for (size_t k = 0; k < cross->n; k++) {
        cross->e[k].a = g->label[cross->e[k].a];
        cross->e[k].b = g->label[cross->e[k].b];
    }
}

static uint32_t choose_tiles(const pg_pits_topo *t, const pg_pits_opts *o, uint64_t *tile_size) {
    uint64_t rows = t->ncells / t->w;
    uint64_t per = o->tile_rows > 0 ? (uint64_t)o->tile_rows : rows / 16;
    if (per < 64 && o->tile_rows <= 0) per = 64;
    if (per < 1) per = 1;
    if (per > rows) per = rows;
    *tile_size = per * t->w;
    return (uint32_t)((t->ncells + *tile_size - 1) / *tile_size);
}

/* Perimeter cells of a strip of whole rows lie in its first or last row, in the
 * first or last column (cube seams), or in a face's first or last row: a strip of
 * r rows meets at most r/h + 2 faces. */
static uint32_t perimeter_bound(const pg_pits_topo *t, uint64_t tile_size) {
    uint64_t rows = tile_size / t->w;
    uint64_t b = (uint64_t)t->w * (2 * (rows / t->h) + 6) + 2 * rows;
    return (uint32_t)(b < tile_size ? b : tile_size);
}

pg_status pits_parallel_fill_barnes2016(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                        pg_pits_result *res, pg_error *err) {
    uint8_t *st = NULL;
    uint64_t nsinks = 0;
    pg_status s = pits_begin(t, h, o, &st, NULL, &nsinks, err);
    if (s) return s;
    /* labels on huge pages (pg_huge.h), zeroed by each tile's own thread (flood_tile) */
    tiling g = {t, h, st, pg_huge_alloc(t->ncells * sizeof(uint32_t)), 0, 0, 0};
    g.ntiles = choose_tiles(t, o, &g.tile_size);
    g.bound = perimeter_bound(t, g.tile_size);
    /* ev[0..ntiles) in-tile spill edges, ev[ntiles..2*ntiles) cross-tile pairs */
    pits_b16_edges *ev = calloc(2 * (size_t)g.ntiles, sizeof *ev);
    const size_t nl = 2 + (size_t)g.ntiles * g.bound;
    float *level = malloc(nl * sizeof *level);
    int oom = !g.label || !ev || !level;
    if (!oom) {
#pragma omp parallel for schedule(dynamic, 1) reduction(| : oom)
        for (int64_t tile = 0; tile < (int64_t)g.ntiles; tile++)
            oom |= flood_tile(&g, (uint32_t)tile, &ev[tile], &ev[g.ntiles + tile]);
    }
    for (uint32_t i = 0; !oom && i < g.ntiles; i++)
        label_cross_edges(&g, &ev[g.ntiles + i]);
    /* stage 2: minimax levels of all labels from the outlet */
    if (!oom) oom = pits_b16_solve(ev, 2 * g.ntiles, nl, PITS_B16_OUTLET, level);
    if (!oom) {
        const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for schedule(static)
        for (int64_t i = 0; i < n; i++)
            if (st[i] == PITS_OPEN && level[g.label[i]] > h[i]) h[i] = level[g.label[i]];
    }
    for (uint32_t i = 0; ev && i < 2 * g.ntiles; i++)
        free(ev[i].e);
    free(ev);
    free(level);
    free(g.label);
    pits_end(t, h, o, st);
    free(st);
    if (oom) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory in the parallel fill");
    if (res) res->sinks = nsinks;
    return PG_OK;
}
