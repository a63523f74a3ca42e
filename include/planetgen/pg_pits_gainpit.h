/* pg_pits_gainpit.h - pit removal inside the synthesis ("Gain-pit", Scott & Dodgson
 * 2021 §5; Scott's thesis §4.2.1 and §5.3.2), as a pass hook for pg_synth.
 *
 * After every correction pass of every level except the finest skip_levels, the
 * hook reconstructs the level's heights R = E_s(S) + V, removes the pits of R with
 * one global pass (pg_pits_correct_offsets) and adds R' - R to the offsets V, so the
 * next correction works on pit-free terrain. The delivered heights still need a
 * final pass (pg_pits_remove) because the finest levels are skipped and E + V only
 * reproduces R' to float rounding.
 *
 * For the flat driver (pg_synth_flat) the region's border is an outlet, like a map
 * edge; the sea level is the exemplar's. A planet driver calls
 * pg_pits_correct_offsets on the whole cube level instead (never per tile). */
#ifndef PLANETGEN_PG_PITS_GAINPIT_H
#define PLANETGEN_PG_PITS_GAINPIT_H

#include "planetgen/pg_pits.h"
#include "planetgen/pg_synth.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pg_pits_gainpit {
    pg_pits_opts opts; /* method, epsilon, limits; sea level: the exemplar's */
    int skip_levels;   /* no pit removal at scales < skip_levels (default 1) */
    uint64_t runs;     /* passes that ran pit removal */
    uint64_t changed;  /* cells whose offset changed, summed over runs */
    double seconds;    /* wall time spent in the hook */
    pg_error err;      /* the first failure (a hook cannot return one) */
} pg_pits_gainpit;

/* Defaults: breach with epsilon (Scott & Dodgson's choice), skip the finest level. */
void pg_pits_gainpit_init(pg_pits_gainpit *g);

/* A pg_synth_pass_hook; user is a pg_pits_gainpit *. */
void pg_pits_gainpit_hook(void *user, const pg_synth_exemplar *ex, int scale, int pass, uint32_t *S,
                          float *V, int res, ptrdiff_t stride);

#ifdef __cplusplus
}
#endif

#endif
