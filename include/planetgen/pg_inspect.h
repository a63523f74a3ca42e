/* pg_inspect.h - realism figures of a planet: the seam statistic, the LPIPS-style
 * pole check, depressions and neighbourhood fidelity. `planetgen inspect` prints
 * them; the planet synthesis tests reuse the seam statistic.
 *
 * SEAM STATISTIC (docs/inspect.md, "Seams"): over every pair of 4-adjacent texels, the mean |delta|
 * of a field across the pairs that straddle a tile edge or one of the 12 face seams, divided by the
 * mean |delta| across the pairs inside a tile. A seamless planet scores ~1; a planet whose tiles
 * were made independently scores well above. For albedo, |delta| is the mean over R, G, B of the
 * absolute difference (sRGB 0..1).
 *
 * TEXTURE COMPARISON (docs/inspect.md, "Texture comparison"; formerly the pole check): the six
 * views of pg_views.h are rendered from the planet, from the exemplar reprojected onto a cube of
 * the planet's geometry ("exemplar cube") and from the original equirectangular exemplar ("exemplar
 * equirect"). For each view, d = LPIPS-style distance (pg_lpips.h) between the planet's view and
 * the exemplar equirect's view: how far the planet there is from what the exemplar shows there.
 * ratio(pole) = (d(pole) + JND) / (mean over the four equator views of d + JND); the
 * planet's pole/equator ratio is the larger of the two poles'. A planet whose poles are
 * distorted (pinched, smeared) scores well above 1; the gate is <= 1.15.
 *
 * JND (PG_INSPECT_JND) keeps the ratio meaningful when both distances are
 * imperceptible: an exact copy of the exemplar sits at the resampling floor (~0.0003)
 * everywhere, and the raw ratio of two floors only reflects how much fine detail each
 * place has (1.3 for the Earth's north pole). JND is 0.005, below the distance that a
 * Gaussian blur of one view pixel causes on Blue Marble texture (0.0066, test_lpips);
 * with distances of 0.05 and up, as synthesized texture has, it changes the ratio by a
 * few percent. The raw ratios are reported as well. */
#ifndef PLANETGEN_PG_INSPECT_H
#define PLANETGEN_PG_INSPECT_H

#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_lpips.h"
#include "planetgen/pg_pits.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_views.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The old pole check (docs/inspect.md, "Texture comparison"): distance(pole) <= this x
 * mean distance(equator). Reported, no longer a gate: it compares with Earth at the same
 * place. */
#define PG_INSPECT_POLE_GATE 1.15
/* Just-noticeable LPIPS-style distance added to both sides of the pole ratio (above). */
#define PG_INSPECT_JND 0.005
/* Seam gate (docs/inspect.md, "Seams"): seam |delta| <= this x interior |delta|. */
#define PG_INSPECT_SEAM_GATE 1.1
/* Face seams alone (docs/inspect.md, "Face seams"): face_seam_ratio <= this, and
 * face_seam_coherence >= PG_INSPECT_FACE_COHERENCE_GATE. */
#define PG_INSPECT_FACE_SEAM_GATE 1.10
#define PG_INSPECT_FACE_COHERENCE_GATE 0.8

/* ---- seam statistic ---- */

typedef struct pg_inspect_seam_stat {
    double seam_mean;        /* mean |delta| over pairs straddling tile edges and face seams */
    double interior_mean;    /* mean |delta| over adjacent pairs inside a tile */
    double ratio;            /* seam_mean / interior_mean (NaN if there are no pairs) */
    double tile_edge_mean;   /* the tile edges inside faces alone (NaN with 1 tile per face) */
    double face_seam_mean;   /* the 12 face seams alone */
    double within_face_mean; /* every adjacent pair inside a face, tile edges included */
    /* face_seam_mean / within_face_mean: tiles are views into one face array, so their
     * edges are ordinary pairs here, and only the 12 face seams are judged */
    double face_seam_ratio;
    /* the pairs next to the seams, across the seam's direction, 1..9 texels in on either
     * side: each seam's own ground */
    double near_face_seam_mean;
    /* face_seam_mean / near_face_seam_mean: each seam against the ground beside it, so
     * that how busy the ground under the seams happens to be cancels out
     * (docs/inspect.md, "Face seams"); reported beside the gated figure */
    double face_seam_ratio_local;
    double tile_edge_ratio; /* tile_edge_mean / interior_mean (NaN with 1 tile per face) */
    uint64_t seam_pairs, interior_pairs, face_seam_pairs;
    /* The seam with the largest face_seam_ratio of its own (its pairs' mean |delta| /
     * within_face_mean), its two faces (ascending), and that seam against its own ground
     * as face_seam_ratio_local is for all 12: where to look first when the pooled figure
     * fails (ranked against the faces' mean, it may also be the seam on the busiest
     * ground). No seam (a bad input, no pairs): faces -1, ratios NaN. */
    double worst_seam_ratio, worst_seam_ratio_local;
    int worst_seam_faces[2];
} pg_inspect_seam_stat;

typedef struct pg_inspect_seams {
    pg_inspect_seam_stat height, albedo;
    double ratio;                 /* the larger of the height and albedo ratios */
    double face_seam_ratio;       /* the larger of the two face_seam_ratio (gate
                                     PG_INSPECT_FACE_SEAM_GATE) */
    double face_seam_ratio_local; /* the larger of the two face_seam_ratio_local */
    double tile_edge_ratio;       /* the larger of the two tile_edge_ratio */
    /* the worse of the two fields' worst seams: its figures, faces, and field ("height"
     * or "albedo", "" with no seam; held in the struct, not pointed to: the report caches
     * Earth's figures as the struct's bytes). It may be another field than the one whose
     * pooled figure is face_seam_ratio. */
    double worst_seam_ratio, worst_seam_ratio_local;
    int worst_seam_faces[2];
    char worst_seam_field[8];
} pg_inspect_seams;

/* The statistic of one field: faces[f] holds n*n texels of ch floats in the layout of
 * pg_cube.h (row y = 0 first); tiles are tile_size texels wide (n % tile_size == 0,
 * tile_size a power of two). BADINPUT otherwise. */
pg_status pg_inspect_seam_field(int64_t n, int tile_size, const float *const faces[PG_CUBE_NFACES],
                                int ch, pg_inspect_seam_stat *out, pg_error *err);

/* Both fields of a planet. */
pg_status pg_inspect_seams_compute(const pg_planet *p, pg_inspect_seams *out, pg_error *err);

/* ---- views and the pole check ---- */

enum { PG_INSPECT_SRC_PLANET, PG_INSPECT_SRC_EXCUBE, PG_INSPECT_SRC_EXRECT, PG_INSPECT_NSRC };

/* "planet", "exemplar_cube", "exemplar_equirect". */
const char *pg_inspect_source_name(int src);

typedef struct pg_inspect_views {
    int size;
    double fov_deg, sigma_deg; /* field; the common prefilter (pg_views_prefilter_deg) */
    pg_view v[PG_INSPECT_NSRC][PG_VIEWS_COUNT];
} pg_inspect_views;

/* Render the six views of the three sources at size x size (fov PG_VIEWS_DEFAULT_FOV_DEG),
 * all with the same prefilter. The exemplar cube has the planet's projection, face size
 * and ellipsoid. */
pg_status pg_inspect_render_views(const pg_planet *p, const pg_exemplar *ex, int size,
                                  pg_inspect_views *out, pg_error *err);
/* The same without the exemplar cube (the resampling floor), whose distances are then
 * NaN: what `inspect` reports, a third cheaper. */
pg_status pg_inspect_render_views_nofloor(const pg_planet *p, const pg_exemplar *ex, int size,
                                          pg_inspect_views *out, pg_error *err);
void pg_inspect_views_free(pg_inspect_views *v);

typedef struct pg_inspect_poles {
    /* d[src][view]: distance of source src's view to the exemplar equirect's view
     * (d[PG_INSPECT_SRC_EXRECT] is 0); d[EXCUBE] is the floor that resampling alone
     * leaves. */
    pg_lpips_result d[PG_INSPECT_NSRC][PG_VIEWS_COUNT];
    /* d(planet view, exemplar cube view) */
    pg_lpips_result d_vs_cube[PG_VIEWS_COUNT];
    double equator_mean;             /* mean planet d over the four equator views */
    double ratio_north, ratio_south; /* (d(pole) + JND) / (equator_mean + JND) */
    double pole_equator_ratio;       /* max of the two */
    double raw_north, raw_south;     /* d(pole) / equator_mean, without JND */
    double floor_ratio;              /* pole_equator_ratio of the exemplar cube (resampling only) */
} pg_inspect_poles;

pg_status pg_inspect_pole_scores(const pg_inspect_views *v, const pg_lpips_params *lp,
                                 pg_inspect_poles *out, pg_error *err);

/* The exemplar reprojected onto a cube with the planet's projection and ellipsoid and n
 * texels per face edge (2x2 bilinear taps per texel, like pg_planet_from_exemplar):
 * 6*n*n*4 floats (R, G, B sRGB 0..1, height in metres), face-major; caller frees. */
pg_status pg_inspect_exemplar_cube(const pg_planet *p, int64_t n, const pg_exemplar *ex,
                                   float **out, pg_error *err);

/* ---- neighbourhood fidelity (pg_inspect_fidelity.c) ----
 *
 * How far the planet's local neighbourhoods are from the nearest neighbourhood the
 * exemplar has (Kwatra et al. 2005's texture energy; Lefebvre & Hoppe 2005/2006's
 * neighbourhood matching): a neighbourhood is 5x5 texels of Lab albedo and height
 * (scaled so its std equals the Lab std over the exemplar); the distance of two is
 * the RMS difference per texel and channel (Lab units). The planet is read at the
 * exemplar's scale: faces box-averaged down to at most PG_INSPECT_FID_FACE texels,
 * against the exemplar reprojected onto a cube of that size. fidelity = mean over
 * hashed planet texels (all six faces) of the distance to the nearest exemplar
 * neighbourhood; two baselines on the same exemplar database say what good and bad
 * are: leave-one-out (exemplar neighbourhoods against the rest of the exemplar, every
 * entries within PG_INSPECT_FID_EXCLUDE texels of the query excluded) and random (neighbourhoods of
 * 25 hashed exemplar texels: the exemplar's colours and heights without structure).
 * Completeness is the other direction (Simakov et al. 2008's bidirectional
 * similarity): the leave-one-out query texels of the exemplar against the nearest
 * planet neighbourhood; it sees what fidelity cannot, exemplar structure the planet
 * lacks (e.g. a blurred planet, whose smooth neighbourhoods do match the exemplar's
 * smooth ocean and plains, scores a *better* fidelity). The search is exact (see
 * pg_inspect_fidelity.c). */
#define PG_INSPECT_FID_FACE 512    /* analysis face size: the synthesis exemplar's default */
#define PG_INSPECT_FID_RADIUS 2    /* 5x5 neighbourhoods */
#define PG_INSPECT_FID_STRIDE 4    /* exemplar database: every 4th texel in x and y */
#define PG_INSPECT_FID_QUERIES 256 /* hashed query texels per face: planet, leave-one-out */
/* random baseline, per face: its figure (~12x leave-one-out) varies little, and each of
 * its queries costs ~10x more (far from everything, the lower bound prunes little) */
#define PG_INSPECT_FID_RANDOM_QUERIES 32
#define PG_INSPECT_FID_PREFIX 16 /* DCT coefficients in the pruning lower bound */
/* Matches within this many analysis texels of a query's own exemplar position (its
 * source, for a planet texel) do not count, in every direction of the search: a copy
 * is not fidelity. 8 texels is well beyond a neighbourhood's radius (2), so no
 * overlapping neighbourhood is found, and well below a face (512). */
#define PG_INSPECT_FID_EXCLUDE 8
/* Gates (docs/inspect.md, "Neighbourhood fidelity"): fidelity_ratio and
 * completeness_ratio each <= this. */
#define PG_INSPECT_FIDELITY_GATE 1.5

typedef struct pg_inspect_fidelity {
    double fidelity;     /* planet: mean nearest-exemplar distance (Lab units) */
    double loo;          /* exemplar leave-one-out: the same, exemplar against itself */
    double random;       /* neighbourhoods of shuffled exemplar texels */
    double ratio;        /* fidelity / loo: ~1 = as close as the exemplar is to itself */
    double random_ratio; /* random / loo: where structureless texture lands */
    double completeness; /* the other direction: exemplar neighbourhoods (the leave-one-out
                          * queries) against the nearest planet neighbourhood */
    double structure_completeness_ratio; /* completeness / loo */
    /* The same search on the local detail amplitude (pg_inspect_fidelity.c): phase-free,
     * so it sees missing detail (blur) that the L2 match above prefers */
    double detail_loo, detail_completeness, detail_completeness_ratio;
    double completeness_ratio; /* max(structure_completeness_ratio, detail_completeness_ratio) */
    int analysis_size;         /* texels per face edge the figures were computed at */
    int magnification;         /* planet texels per analysis texel (box-averaged) */
    int queries;               /* planet and leave-one-out (6 x PG_INSPECT_FID_QUERIES) */
    int random_queries;        /* random baseline (6 x PG_INSPECT_FID_RANDOM_QUERIES) */
    int database;              /* exemplar neighbourhoods searched */
    double height_scale;       /* Lab units per metre of height */
} pg_inspect_fidelity;

/* Neighbourhood fidelity of a planet against an exemplar. Deterministic: the same
 * figures for any thread count. */
pg_status pg_inspect_fidelity_compute(const pg_planet *p, const pg_exemplar *ex,
                                      pg_inspect_fidelity *out, pg_error *err);

/* The exemplar's side of the fidelity measures: its analysis field, detail amplitude and
 * baselines (leave-one-out, random) for planets of one geometry. It depends on the
 * exemplar and the geometry only, so `inspect` caches it on disk (save/load; load
 * returns NULL for a missing, foreign or stale file). Owned by the caller. */
typedef struct pg_inspect_fid_exemplar pg_inspect_fid_exemplar;
pg_status pg_inspect_fid_exemplar_build(const pg_planet *geometry, const pg_exemplar *ex,
                                        pg_inspect_fid_exemplar **out, pg_error *err);
void pg_inspect_fid_exemplar_free(pg_inspect_fid_exemplar *fx);
pg_status pg_inspect_fid_exemplar_save(const pg_inspect_fid_exemplar *fx, const char *path,
                                       uint64_t key, pg_error *err);
pg_inspect_fid_exemplar *pg_inspect_fid_exemplar_load(const char *path, uint64_t key);
/* pg_inspect_fidelity_compute with the exemplar's side given (the same figures). */
pg_status pg_inspect_fidelity_with(const pg_planet *p, const pg_inspect_fid_exemplar *fx,
                                   pg_inspect_fidelity *out, pg_error *err);

/* ---- mountain belts ---- */

/* mountain_belt_fraction: the area share of non-ice land above 2000 m that lies within
 * 500 km of a convergent plate boundary, read from the convergent_km channel of the
 * macro world file world_exr (`generate --layout world`); NaN when the file is absent
 * or there is no such land (pg_inspect_belts.c). */
pg_status pg_inspect_mountain_belts(const pg_planet *p, const char *world_exr, double *fraction,
                                    pg_error *err);

/* ---- depressions ---- */

/* pg_pits_stats_compute on the planet's heights over the whole cube sphere, sinks at
 * and below the planet's sea level, areas from the mean texel area. */
pg_status pg_inspect_depressions(const pg_planet *p, pg_pits_stats *out, pg_error *err);

/* The planet's heights as one 6*n*n global field (caller frees). */
float *pg_inspect_height_field(const pg_planet *p);

#ifdef __cplusplus
}
#endif

#endif
