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
    int node_size, node_rank; /* ranks on this rank's machine (MPI_COMM_TYPE_SHARED) */
    int tiles, ntiles;
    int fail_rank, fail_scale;
    uint64_t id_base, id_stride; /* tests only: pg_mpi_testing.h */
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
 * The cube (cube ids: face * n^2 + y * n + x, 64-bit: 6 x 65536^2 cells and more) cut
 * into tiles x tiles tiles per face, numbered face-major and owned as
 * pg_mpi_tile_owner says. The distributed pits keep a rank's cells in tile-local
 * arrays (local ids, 32-bit): its tiles one after the other (tile t0 + i holds the
 * local ids i * ts^2 + y * ts + x), then its ring (the cells of other ranks next to
 * its tiles, sorted by cube id): nown + nring cells, never the planet's. */
typedef struct pg_mpi_tiling {
    pg_mpi *m;
    int T;                 /* tiles per face edge */
    uint32_t n, ts;        /* texels per face edge, per tile edge */
    int ln, lts;           /* log2 of n and ts when both are powers of two, else -1 */
    int t0, t1;            /* this rank's tiles [t0, t1) */
    uint64_t base, stride; /* global id of cube id c: base + stride * c (0 and 1; tests:
                              above 2^32, pg_mpi_testing.h) */
    pg_cube_grid cube;     /* the seam map of the whole cube (T = n, S = 1) */
    pg_pits_topo t;        /* the local topology: the tiles as blocks, the ring after */
    uint32_t nown, nring;
    size_t nloc;             /* nown + nring */
    uint64_t *ring;          /* cube ids of the ring cells, sorted */
    pg_mpi_idx *send, *recv; /* per rank: local ids sent and received, in cube-id order */
} pg_mpi_tiling;

/* The tiling of n texels per face edge into g, with this rank's ring and exchange
 * plan; BADINPUT when the tiles do not divide n or a rank's cells exceed local ids.
 * Free with pg_mpi_tiling_free. Collective only in the sense that every rank must call
 * it (no communication). */
pg_status pg_mpi_tiling_init(pg_mpi_tiling *g, pg_mpi *m, int tiles, uint32_t n, pg_error *err);
void pg_mpi_tiling_free(pg_mpi_tiling *g);

/* The tile of a cube id: called for the neighbours of every border cell, so shifts
 * when the sizes allow. */
static inline int pg_mpi_tile_of(const pg_mpi_tiling *g, uint64_t id) {
    uint64_t T = (uint64_t)g->T;
    if (g->ln >= 0) {
        uint64_t f = id >> (2 * g->ln), y = (id >> g->ln) & (g->n - 1), x = id & (g->n - 1);
        return (int)(f * T * T + (y >> g->lts) * T + (x >> g->lts));
    }
    uint64_t per = (uint64_t)g->n * g->n, f = id / per, y = id % per / g->n, x = id % g->n;
    return (int)(f * T * T + y / g->ts * T + x / g->ts);
}

/* The cube id of texel (x, y) of tile t. */
static inline uint64_t pg_mpi_tile_cell(const pg_mpi_tiling *g, int t, uint32_t x, uint32_t y) {
    uint64_t T = (uint64_t)g->T, f = (uint64_t)t / (T * T), tx = (uint64_t)t % T,
             ty = (uint64_t)t / T % T;
    return f * g->n * g->n + (ty * g->ts + y) * g->n + tx * g->ts + x;
}

/* The cube id of a local id (owned or ring). */
static inline uint64_t pg_mpi_cube_id(const pg_mpi_tiling *g, uint32_t l) {
    if (l >= g->nown) return g->ring[l - g->nown];
    uint32_t per = g->ts * g->ts, i = l / per, r = l % per;
    return pg_mpi_tile_cell(g, g->t0 + (int)i, r % g->ts, r / g->ts);
}

/* The global id of a local id: what labels, tie-breaks and cross-rank pairs use. */
static inline uint64_t pg_mpi_gid(const pg_mpi_tiling *g, uint32_t l) {
    return g->base + g->stride * pg_mpi_cube_id(g, l);
}

/* The local id of a cube id, UINT32_MAX when neither owned nor in the ring. */
uint32_t pg_mpi_local_of(const pg_mpi_tiling *g, uint64_t id);

/* Every local id of this rank's own cells. */
#define PG_MPI_FOR_OWNED(g, l) for (uint32_t l = 0; l < (g)->nown; l++)

/* Copy this rank's cells of the caller's planet-sized array (float per cube id) into
 * the local array, and back; nothing else of the planet array is touched. */
void pg_mpi_tiling_load(const pg_mpi_tiling *g, const float *planet, float *local);
void pg_mpi_tiling_store(const pg_mpi_tiling *g, const float *local, float *planet);

/* Every rank's ring cells (local ids nown..) get their owners' values of arr (nloc
 * elements of elem bytes). Collective. */
pg_status pg_mpi_ring_exchange(const pg_mpi_tiling *g, void *arr, size_t elem, pg_error *err);

/* The same with the sent values made by pack(ctx, local id, out) and the received
 * ones written to ring_out[k] (nring elements): for values wider than the local array
 * (64-bit ids of 32-bit local references). Collective. */
typedef void (*pg_mpi_pack_fn)(const void *ctx, uint32_t l, void *out);
pg_status pg_mpi_ring_exchange_packed(const pg_mpi_tiling *g, size_t elem, pg_mpi_pack_fn pack,
                                      const void *ctx, void *ring_out, pg_error *err);

#endif

#endif
