/* pg_mpi_pits.h - what the distributed pit algorithms share (not public API): the
 * heights of a rank's tiles with their sea level, and the epsilon rounds that the fill,
 * the breach and the statistics all run. Each algorithm is one file:
 *   pg_mpi_pits_barnes2016_fill.c      the plain fill (pg_mpi_pits_fill)
 *   pg_mpi_pits_planchon2002_eps.c     the minimal epsilon-surface in rounds
 *   pg_mpi_pits_descent_breach.c       breach and hybrid (pg_mpi_pits_remove)
 *   pg_mpi_pits_stats_unionfind.c      depression statistics (pg_mpi_pits_stats)
 * Their place among the layers of src/mpi: pg_mpi_comm.h. */
#ifndef PG_MPI_PITS_H
#define PG_MPI_PITS_H

#include "pg_mpi_comm.h"

#include <stdbool.h>

#ifdef PG_HAVE_MPI

/* A rank's heights in tile-local arrays (pg_mpi_comm.h): h holds nloc floats, its
 * tiles then its ring; sinks are the cells at or below the sea level. */
typedef struct pg_mpi_pits_grid {
    const pg_mpi_tiling *g;
    float *h;
    double sea;
} pg_mpi_pits_grid;

static inline bool pg_mpi_pits_sink(const pg_mpi_pits_grid *d, uint32_t l) {
    return d->h[l] <= d->sea;
}

/* The plain fill (with o->epsilon, the minimal epsilon-surface) of the local heights
 * d->h, whose ring need not be current; afterwards the ring holds the owners' values.
 * Collective. */
pg_status pg_mpi_pits_fill_local(pg_mpi_pits_grid *d, const pg_pits_opts *o, pg_mpi_pits_info *info,
                                 pg_error *err);

/* BADINPUT unless o asks for the fill with a sea level, no lakes and no no-data. */
pg_status pg_mpi_pits_check_fill(const pg_pits_opts *o, pg_error *err);

/* Lift d->h (the plain fill on this rank's tiles) to the minimal epsilon-surface, in
 * rounds of ring exchanges (pg_mpi_pits_planchon2002_eps.c); counts the rounds and
 * their time into info. Collective. */
pg_status pg_mpi_pits_eps_rounds(pg_mpi_pits_grid *d, pg_mpi_pits_info *info, pg_error *err);

#endif

#endif
