/* pg_realism.h - the realism report of a planet (docs/inspect.md): every figure of
 * `planetgen inspect`, computed the same way on the planet and on Earth, so that the
 * planet is compared with itself and with Earth's statistics, never with Earth at the
 * same place.
 *
 * One pg_realism holds the figures of one side. The planet's side reads its coordinate
 * map (pg_planet_source) where a figure needs it; Earth's side is the exemplar
 * reprojected onto a cube of the planet's geometry, whose map is the identity, and
 * whose drainage is measured after a pit fill (Earth's relief has closed basins; the
 * planet's final pass removed its own). Earth's side depends only on the exemplar and
 * the planet's geometry, so pg_realism_earth_cached keeps it on disk beside the
 * synthesis exemplar cache.
 *
 * Ownership: plain data, no pointers; the caller owns both structs. */
#ifndef PLANETGEN_PG_REALISM_H
#define PLANETGEN_PG_REALISM_H

#include "planetgen/pg_drainage.h"
#include "planetgen/pg_earthlike.h"
#include "planetgen/pg_inspect.h"
#include "planetgen/pg_inspect_copy.h"
#include "planetgen/pg_inspect_distortion.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The stages, in order, as reported to the progress callback. */
enum {
    PG_REALISM_DISTORTION,
    PG_REALISM_SEAMS,
    PG_REALISM_COPY,
    PG_REALISM_FIDELITY,
    PG_REALISM_EARTHLIKE,
    PG_REALISM_DRAINAGE,
    PG_REALISM_DEPRESSIONS,
    PG_REALISM_NSTAGES
};
const char *pg_realism_stage_name(int stage);

typedef struct pg_realism {
    /* distortion of what was copied (pg_inspect_distortion.h) */
    double pole_distortion_ratio, distortion_share_ratio, distortion_reference;
    double distortion_worst_figure;
    char distortion_worst_view[32];
    /* seams */
    pg_inspect_seams seams;
    pg_inspect_coherence_stat coherence;
    /* copying */
    pg_inspect_copy_stat copy;
    pg_inspect_fidelity fidelity;
    /* Earth-likeness statistics; w1 and zonal correlation against the other side */
    pg_earthlike earthlike;
    pg_earthlike_novelty novelty;
    double hypsometry_w1_land_m, hypsometry_w1_ocean_m, hypsometry_w1_m;
    double zonal_correlation, zonal_correlation_per_type[PG_TYPE_COUNT];
    /* drainage on the pit-free heights */
    pg_drainage_stats drainage;
    double closed_land_share_before_final; /* NaN when unknown */
    pg_pits_stats depressions;             /* of the heights as given */
    double seconds[PG_REALISM_NSTAGES];
} pg_realism;

/* Stage progress: begin = true before a stage, false after it. */
typedef void (*pg_realism_progress_fn)(void *user, int stage, bool begin);

/* The planet's figures. fx (may be NULL: built here) is the exemplar's side of the
 * fidelity measures for p's geometry; earth (may be NULL) the other side for the
 * hypsometry and zonal comparisons. acc_out (may be NULL) receives the drainage
 * accumulation field (pg_drainage_planet; caller frees), dist_out (may be NULL) the
 * distortion views. */
pg_status pg_realism_planet(const pg_planet *p, const pg_exemplar *ex,
                            const pg_inspect_fid_exemplar *fx, const pg_realism *earth,
                            pg_realism_progress_fn progress, void *user, pg_realism *out,
                            float **acc_out, pg_inspect_distortion *dist_out, pg_error *err);

/* Earth's figures on a cube of p's geometry (projection, tiles, tile size, ellipsoid):
 * the exemplar reprojected (2 x 2 taps) with the identity coordinate map. The hypsometry
 * distances are 0 and the zonal correlation 1 by construction (Earth against itself). */
pg_status pg_realism_earth(const pg_planet *geometry, const pg_exemplar *ex,
                           pg_realism_progress_fn progress, void *user, pg_realism *out,
                           pg_inspect_fid_exemplar **fx_out, pg_error *err);

/* pg_realism_earth through two cache files in cache_dir (NULL: the synthesis
 * exemplar's default cache directory; "": no cache), keyed by a hash of the exemplar's
 * data, the geometry and the report's version: Earth's figures, and the exemplar's side
 * of the fidelity measures (fx_out, caller frees with pg_inspect_fid_exemplar_free).
 * *from_cache tells which way it went. */
pg_status pg_realism_earth_cached(const pg_planet *geometry, const pg_exemplar *ex,
                                  const char *cache_dir, pg_realism_progress_fn progress,
                                  void *user, pg_realism *out, pg_inspect_fid_exemplar **fx_out,
                                  bool *from_cache, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
