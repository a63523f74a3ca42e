/* pg_inspect_copy.h - what the coordinate map says about a planet: how much of it is
 * Earth copied in place, and whether the face seams are stitched as coherently as the
 * faces' insides. Both read the map synthesis leaves (pg_planet.h, pg_planet_source;
 * source.exr in a planet directory) and report NaN for a planet without one.
 *
 * EARTH COPY FRACTION (docs/inspect.md, "Copy detection"): near = the share of all
 * texels whose source (the centre of the exemplar-cube texel they were copied from)
 * lies within PG_INSPECT_COPY_RADIUS_M of the texel itself, great-circle distance on a
 * sphere of the planet's mean radius. Layout earth starts synthesis from the exemplar
 * at the same direction, so some of this is by design; a source from another place at
 * the same latitude (climate zones) is legitimate too. The baseline shuffled = the same
 * share when every source keeps its latitude and takes a longitude drawn uniformly in
 * [-180, 180) from a hash of (seed, texel id): what sources from the right latitude
 * but no particular longitude score. earth_copy_fraction = near - shuffled: about 1
 * for Earth copied texel for texel, about 0 for a planet that is not Earth in place.
 *
 * FACE SEAM COHERENCE (docs/inspect.md, "Face seams"): a pair of 4-adjacent planet
 * texels is coherent when their sources are two distinct 8-neighbours on the exemplar
 * cube (across the exemplar's own face seams too): the pair continues one copied patch.
 * seam_share = coherent share of the pairs straddling the planet's 12 face seams,
 * interior_share = that of the 4-adjacent pairs inside faces; face_seam_coherence =
 * seam_share / interior_share: about 1 when patches run across face seams as they run
 * inside faces, well below 1 when the seams cut them (the gate is
 * PG_INSPECT_FACE_COHERENCE_GATE of pg_inspect.h).
 *
 * Both are exact counts, computed in parallel by rows; the results do not depend on
 * the thread count. */
#ifndef PLANETGEN_PG_INSPECT_COPY_H
#define PLANETGEN_PG_INSPECT_COPY_H

#include "planetgen/pg_planet.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A source closer than this is "in place" (great circle, metres). */
#define PG_INSPECT_COPY_RADIUS_M 500e3

typedef struct pg_inspect_copy_stat {
    double near_share;          /* sources within the radius of their texel */
    double shuffled_share;      /* the same with hashed source longitudes (the baseline) */
    double earth_copy_fraction; /* near_share - shuffled_share */
    uint64_t texels;            /* 6 N^2; 0 without a map (the figures are then NaN) */
} pg_inspect_copy_stat;

/* The earth copy fraction of p (above); the longitudes of the baseline are hashed from
 * p->seed. Without a coordinate map every figure is NaN and the result PG_OK. */
pg_status pg_inspect_copy_fraction(const pg_planet *p, pg_inspect_copy_stat *out, pg_error *err);

typedef struct pg_inspect_coherence_stat {
    double seam_share;          /* coherent share of the pairs across the 12 face seams */
    double interior_share;      /* coherent share of the 4-adjacent pairs inside faces */
    double face_seam_coherence; /* seam_share / interior_share (NaN if interior_share is 0) */
    uint64_t seam_pairs, interior_pairs; /* 12 N and 12 N (N - 1); 0 without a map */
} pg_inspect_coherence_stat;

/* The face seam coherence of p (above). Without a coordinate map every figure is NaN
 * and the result PG_OK. */
pg_status pg_inspect_copy_coherence(const pg_planet *p, pg_inspect_coherence_stat *out,
                                    pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
