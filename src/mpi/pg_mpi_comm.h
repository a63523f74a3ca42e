/* pg_mpi_comm.h - the communication layer of the MPI module (not public API): the
 * pg_mpi handle, the collectives, gathers to rank 0, sorted index lists, a rank's cube
 * tiles and the one-cell ring exchange around them.
 *
 * LAYERING of src/mpi (calls go downward only; no file calls one above it):
 *   pg_mpi.c                  init and finalize, the synthesis's tile-edge exchange
 *                             and its hooks; calls the pit algorithms through
 *                             pg_mpi_pits_remove and pg_mpi_pits_stats (pg_mpi.h)
 *   pg_mpi_pits_stats_unionfind.c, pg_mpi_pits_descent_breach.c
 *                             call the fill (pg_mpi_pits_fill) and the epsilon rounds
 *   pg_mpi_pits_barnes2016_fill.c
 *                             calls the epsilon rounds
 *   pg_mpi_pits_planchon2002_eps.c
 *   pg_mpi_ring.c             a rank's tiles and the ring exchange (this header)
 *   pg_mpi_comm.c             the handle's accessors, collectives, gathers (this header)
 * The pit algorithms share the Barnes (2016) core with the threaded fill
 * (src/pits/pg_pits_barnes2016_core.h) and never call pg_mpi.c. */
#ifndef PG_MPI_COMM_H
#define PG_MPI_COMM_H

#include "planetgen/pg_mpi.h"
#include "planetgen/pg_pits.h"

#include <stddef.h>
#include <stdint.h>

/* A growing list of array indices; pg_mpi_idx_unique sorts it and drops repeats. */
typedef struct pg_mpi_idx {
    size_t *a;
    size_t n, cap;
    int oom;
} pg_mpi_idx;

void pg_mpi_idx_push(pg_mpi_idx *v, size_t i);
void pg_mpi_idx_unique(pg_mpi_idx *v);

#ifdef PG_HAVE_MPI

#include <mpi.h>

struct pg_mpi_plan; /* the synthesis's exchange plan, pg_mpi.c's own */

struct pg_mpi {
    MPI_Comm comm;
    int rank, size;
    int tiles, ntiles;
    int fail_rank, fail_scale;
    struct pg_mpi_plan *pl;
    pg_mpi_stats stats;
};

/* The communicator of m (MPI_COMM_WORLD without a handle). */
MPI_Comm pg_mpi_comm_of(const pg_mpi *m);

/* Gather every rank's `words` items of `type` (word_bytes each) on rank 0: rank 0 gets
 * them rank after rank in a new array (others: NULL) and *total their count. *bad
 * (0 on entry) becomes nonzero on every rank when a count exceeds 2^31 - 1 items or
 * rank 0 runs out of memory. Counts what each rank sent as pits bytes. Collective. */
void *pg_mpi_gather_root(pg_mpi *m, const void *mine, size_t words, MPI_Datatype type,
                         size_t word_bytes, size_t *total, int *bad);

/* ---- a rank's cube tiles and the ring around them (pg_mpi_ring.c) ----
 * The cube (pg_pits cube ids: face * n^2 + y * n + x) cut into tiles x tiles tiles per
 * face, numbered face-major and owned as pg_mpi_tile_owner says. */
typedef struct pg_mpi_tiling {
    pg_mpi *m;
    const pg_pits_topo *t;
    int T;          /* tiles per face edge */
    uint32_t n, ts; /* texels per face edge, per tile edge */
    int ln, lts;    /* log2 of n and ts when both are powers of two, else -1 */
    int t0, t1;     /* this rank's tiles [t0, t1) */
} pg_mpi_tiling;

/* The cube topology of n texels per face edge into topo, and its tiling; BADINPUT when
 * the tiles do not divide n. */
pg_status pg_mpi_tiling_init(pg_mpi_tiling *g, pg_pits_topo *topo, pg_mpi *m, int tiles, uint32_t n,
                             pg_error *err);

/* The tile of a cell: called for every neighbour of every cell, so shifts when the
 * sizes allow (divisions took a third of the distributed fill's time). */
static inline int pg_mpi_tile_of(const pg_mpi_tiling *g, uint32_t id) {
    uint32_t T = (uint32_t)g->T;
    if (g->ln >= 0) {
        uint32_t f = id >> (2 * g->ln), y = (id >> g->ln) & (g->n - 1), x = id & (g->n - 1);
        return (int)(f * T * T + (y >> g->lts) * T + (x >> g->lts));
    }
    uint32_t per = g->n * g->n, f = id / per, y = id % per / g->n, x = id % g->n;
    return (int)(f * T * T + y / g->ts * T + x / g->ts);
}

/* The id of texel (x, y) of tile t. */
static inline uint32_t pg_mpi_tile_cell(const pg_mpi_tiling *g, int t, uint32_t x, uint32_t y) {
    uint32_t T = (uint32_t)g->T, f = (uint32_t)t / (T * T), tx = (uint32_t)t % T,
             ty = (uint32_t)t / T % T;
    return f * g->n * g->n + (ty * g->ts + y) * g->n + tx * g->ts + x;
}

/* Is the cell in one of this rank's tiles? */
static inline int pg_mpi_owned(const pg_mpi_tiling *g, uint32_t id) {
    int t = pg_mpi_tile_of(g, id);
    return t >= g->t0 && t < g->t1;
}

/* Every cell id of the tiles [t0, t1): tile by tile, row by row. */
#define PG_MPI_FOR_TILE_CELLS(g, t0, t1, id)                                                       \
    for (int t_ = (t0); t_ < (t1); t_++)                                                           \
        for (uint32_t y_ = 0; y_ < (g)->ts; y_++)                                                  \
            for (uint32_t x_ = 0, id = pg_mpi_tile_cell((g), t_, 0, y_); x_ < (g)->ts;             \
                 x_++, id = pg_mpi_tile_cell((g), t_, x_, y_))

/* Every cell id of this rank's tiles. */
#define PG_MPI_FOR_OWNED(g, id) PG_MPI_FOR_TILE_CELLS(g, (g)->t0, (g)->t1, id)

/* Every rank's ring cells (the cells of other ranks next to its tiles) get their
 * owners' values of arr (one element of elem bytes per cell id). Collective. */
pg_status pg_mpi_ring_exchange(const pg_mpi_tiling *g, void *arr, size_t elem, pg_error *err);

#endif

#endif
