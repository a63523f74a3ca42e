/* pg_mpi.h - MPI-distributed planet synthesis (docs/mpi.md): which process owns which
 * tiles, the tile-edge exchange the synthesis needs at every level and sub-pass, and
 * the few collectives the CLI needs to start, agree and stop together.
 *
 * THE IDEA. The synthesis (pg_planet_synth.h) corrects every tile from its own texels
 * and a one-texel halo of its neighbours' current edges. So a process that owns a set
 * of tiles needs, before each correction step, only the ring of texels around its
 * tiles; the owners of the neighbouring tiles send them point-to-point. Plans (which
 * texel goes to which rank) are computed by every rank from the same ownership
 * function, so they need no negotiation, and they are cached per level.
 *
 * OWNERSHIP. Tiles are numbered face-major, t = f T^2 + ty T + tx, and rank q owns the
 * contiguous block [q n / P, (q + 1) n / P) of the n = 6 T^2 tiles: balanced by count
 * (blocks differ by at most one tile) and each face's tiles together where the block
 * boundaries allow.
 *
 * What is NOT distributed (docs/mpi.md says why and what it costs): the Gain-pit pass
 * inside the synthesis, the land/ocean agreement figure, the final pit removal and the
 * depression counts run on the whole level on every rank, after an allgather of the
 * level (width -1 exchanges). With --pits off none of these run and each rank touches
 * only its tiles and their rings.
 *
 * Without MPI (cmake -DPG_MPI=OFF) the same functions exist: pg_mpi_built() is false,
 * pg_mpi_init refuses, and the CLI refuses to run under a launcher with more than one
 * rank (pg_mpi_launcher_size). */
#ifndef PLANETGEN_PG_MPI_H
#define PLANETGEN_PG_MPI_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_planet_synth.h"

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Whether this build has MPI (PG_MPI). */
bool pg_mpi_built(void);

/* The ranks a launcher (mpirun / srun) started, from OMPI_COMM_WORLD_SIZE, PMI_SIZE or
 * PMIX_SIZE; 1 when there is none. Works without MPI: it is how a build without MPI
 * notices that it was launched by mpirun. *rank gets the launcher's rank (or 0). */
int pg_mpi_launcher_size(int *rank);

typedef struct pg_mpi pg_mpi;

/* MPI_Init (MPI_THREAD_FUNNELED: only the main thread calls MPI; OpenMP threads
 * never do). PG_ERR_RUNTIME without MPI. */
pg_status pg_mpi_init(pg_mpi **out, pg_error *err);
void pg_mpi_finalize(pg_mpi *m);
/* Kill the whole job (MPI_Abort) with this exit code. */
void pg_mpi_abort(pg_mpi *m, int code);

int pg_mpi_rank(const pg_mpi *m);
int pg_mpi_size(const pg_mpi *m);
/* The ranks on this rank's machine (MPI_Comm_split_type MPI_COMM_TYPE_SHARED): they share
 * its memory, and map one copy of the exemplar's cache file between them. */
int pg_mpi_node_size(const pg_mpi *m);
/* This rank's number among them (0 .. pg_mpi_node_size - 1). */
int pg_mpi_node_rank(const pg_mpi *m);
void pg_mpi_barrier(pg_mpi *m);
/* Allreduce: the largest v over the ranks. */
int pg_mpi_max_int(pg_mpi *m, int v);
/* Gather one double per rank to rank 0 (out: size doubles, on rank 0 only). */
void pg_mpi_gather_double(pg_mpi *m, double v, double *out);
/* Allreduce: the sum of v over the ranks. */
double pg_mpi_sum_double(pg_mpi *m, double v);

/* Ownership (no MPI needed): the first tile of `rank`'s block; rank = nranks gives
 * ntiles. */
int pg_mpi_tile_first(int ntiles, int nranks, int rank);
/* The rank that owns tile t. */
int pg_mpi_tile_owner(int ntiles, int nranks, int t);

/* What a rank sent, per synthesis scale (index = scale, 0 finest). */
#define PG_MPI_MAX_SCALES 16
typedef struct pg_mpi_stats {
    double halo_bytes[PG_MPI_MAX_SCALES];   /* tile edges sent point-to-point */
    double gather_bytes[PG_MPI_MAX_SCALES]; /* own tiles sent in allgathers (width -1) */
    int halo_messages[PG_MPI_MAX_SCALES];
    int exchanges[PG_MPI_MAX_SCALES];
    double seconds;      /* inside exchanges, waiting included */
    double pits_seconds; /* inside the distributed pit removal and statistics */
    double pits_bytes;   /* sent by them: rings, spill graphs, label tables */
} pg_mpi_stats;

/* Count bytes the distributed pit removal sent (pg_mpi_pits_barnes2016.c). */
void pg_mpi_note_pits_bytes(pg_mpi *m, double bytes);

/* Fill the synthesis hooks for a planet of `tiles` x `tiles` tiles per face. The hooks
 * hold m; statistics accumulate in pg_mpi_stats_get. */
void pg_mpi_synth_dist(pg_mpi *m, int tiles, pg_planet_synth_dist *d);
const pg_mpi_stats *pg_mpi_stats_get(const pg_mpi *m);

/* Distributed plain depression filling on the cube sphere (Barnes 2016, "Flexibly
 * distributed Priority-Flood depression filling for teracell DEMs";
 * src/mpi/pg_mpi_pits_barnes2016_fill.c): each rank floods its tiles, builds the spill
 * graph over their perimeters, rank 0 solves it, every rank applies it. h is the
 * planet's 6 n^2 heights (cube ids, 64-bit: any n up to 65536 and beyond) in this rank's
 * address space, of which only the rank's tiles (n / tiles texels square, owned as
 * pg_mpi_tile_owner says) are read and written: no other cell of h is touched, so h may
 * be a lazily committed planet-sized range. They come out bit-identical to
 * pg_pits_remove's fill. Every buffer is tile-local (docs/mpi.md, "Pit removal across
 * ranks": bytes per owned cell). With o->epsilon the plain fill is then
 * lifted to the minimal epsilon-surface (pg_pits_planchon2002_minimal_eps.c) in rounds:
 * every rank floods its tiles from the current ring, until no rank's cells change; the
 * surface is the unique solution of its equation, so it is the serial one bit for bit.
 * Preconditions (BADINPUT otherwise): o->method fill, a sea level, no lakes, no
 * no-data, at least one cell at or below the sea level. Collective. */
typedef struct pg_mpi_pits_info {
    double flood_seconds, solve_seconds; /* steps 1-2 on this rank; 3-4 (rank 0 solving) */
    double edges;                        /* spill-graph edges this rank sent */
    double labels;                       /* labels of the whole graph */
    uint64_t max_label;    /* its largest label: 2 + a global cell id (64-bit; docs/mpi.md) */
    uint64_t raised;       /* cells of this rank raised (by the plain fill) */
    int eps_rounds;        /* epsilon: ring exchanges until nothing changed */
    double eps_seconds;    /* epsilon: time of those rounds on this rank */
    int breach_rounds;     /* breach/hybrid: token rounds until nothing changed */
    double breach_seconds; /* breach/hybrid: the whole removal on this rank */
} pg_mpi_pits_info;
pg_status pg_mpi_pits_fill(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                           pg_mpi_pits_info *info, pg_error *err);

/* Any method: the fill as above; breach and hybrid along the descent tree
 * (o->descent, src/pg_pits_descent_breach.c), with epsilon: W by the distributed
 * fill, then the tokens in rounds of ring exchanges until none changes. Owned cells
 * come out bit-identical to pg_pits_remove with the same options. Preconditions as
 * for the fill, plus o->descent and o->epsilon for breach and hybrid. Collective. */
pg_status pg_mpi_pits_remove(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                             pg_mpi_pits_info *info, pg_error *err);

/* pg_pits_stats_compute over the ranks' tiles (h: owned tiles valid): the counts and
 * the deepest cell are exactly the serial ones; the area and volume sums may differ in
 * their last bits (another summation order). Preconditions as for the fill. Every
 * rank gets the totals. Collective. */
pg_status pg_mpi_pits_stats(pg_mpi *m, int tiles, uint32_t n, const float *h, const pg_pits_opts *o,
                            const pg_pits_area *area, pg_pits_stats *out, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
