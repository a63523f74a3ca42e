/* pg_plates.h - the macro planet from plate tectonics: rigid plates on the cube sphere,
 * moved about their Euler poles for a few tens of Myr, with procedural rules for what
 * happens where they meet and part (after Cortial, Peytavie, Galin and Guerin 2019,
 * "Procedural Tectonic Planets", Computer Graphics Forum 38(2), HAL hal-02136820).
 *
 * The result is a coarse world (6 x n x n texels, default n = 64, about 140 km a texel
 * on an Earth-sized sphere): elevation in metres relative to sea level, crust type and
 * age, the plate of every texel, plate boundaries with their kind, and the distance to
 * the nearest convergent boundary. It is the large-scale guide that later stages
 * amplify; see docs/world.md, "Plates".
 *
 * CUBE FIELDS follow the shared convention: 6 faces x n x n values, face-major and
 * row-major, index (face*n + y)*n + x, in the projection given (pg_cube.h).
 *
 * DETERMINISM. Every random choice (plate seeds, Euler poles, speeds, continental
 * cores, hotspots, noise) is a hash of (seed, stream, index). Parallel loops compute
 * each output from inputs only and serial passes run in a fixed order, so the world
 * is byte-identical for any thread count and on every MPI rank. */
#ifndef PLANETGEN_PG_PLATES_H
#define PLANETGEN_PG_PLATES_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_cube.h"
#include "planetgen/pg_image.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PG_PLATES_MIN 2
#define PG_PLATES_MAX 64

typedef struct pg_plates_params {
    uint64_t seed;
    int64_t n;                /* texels per face edge, 8..1024; default 64 */
    pg_cube_projection proj;  /* default PG_CUBE_DEFAULT_PROJECTION */
    int plates;               /* 2..64; default 14 */
    int steps;                /* simulated steps, 0..200; default 20 */
    double step_myr;          /* Myr per step, (0, 20]; default 4 */
    double land_fraction;     /* share of the sphere's area above sea level, (0, 1); 0.29 */
    double continental_share; /* share of the sphere seeded with continental crust; 0.38 */
    int continents;           /* continental cores, 1..32; default 7 */
    int hotspots;             /* fixed mantle hotspots, 0..32; default 6 */
    double radius_km;         /* sphere radius, > 0; default 6371 */
} pg_plates_params;

void pg_plates_params_default(pg_plates_params *p);

typedef enum pg_plates_crust { PG_PLATES_OCEANIC = 0, PG_PLATES_CONTINENTAL = 1 } pg_plates_crust;

typedef enum pg_plates_boundary {
    PG_PLATES_INTERIOR = 0, /* not on a boundary */
    PG_PLATES_CONVERGENT,
    PG_PLATES_DIVERGENT,
    PG_PLATES_TRANSFORM
} pg_plates_boundary;

/* One plate: its motion and its final footprint. */
typedef struct pg_plates_plate {
    double seed_dir[3]; /* unit vector the plate grew from */
    double omega[3];    /* angular velocity, rad/Myr: axis = Euler pole, norm = rate */
    double speed_cm_yr; /* surface speed 90 degrees from the pole */
    double area_km2;    /* final area */
    double continental_km2;
} pg_plates_plate;

/* The world. Caller-owned: pg_plates_world_init before use, pg_plates_world_free after.
 * Every field is 6*n*n long and indexed as above. */
typedef struct pg_plates_world {
    int64_t n;
    pg_cube_projection proj;
    double radius_km;
    int nplates;
    double sea_level_m;      /* the raw level the land-fraction quantile chose (then 0) */
    float *elevation_m;      /* relative to sea level */
    uint8_t *crust;          /* pg_plates_crust */
    float *age_myr;          /* crust age (oceanic: since formation at a ridge) */
    uint8_t *plate;          /* plate id 0..nplates-1 */
    uint8_t *boundary;       /* pg_plates_boundary */
    float *convergent_km;    /* great-circle-path distance to the nearest convergent texel */
    float *area_km2;         /* texel areas on the sphere */
    pg_plates_plate *plates; /* nplates */
    int nhotspots;
    double hotspot_dir[32][3];
} pg_plates_world;

void pg_plates_world_init(pg_plates_world *w);
void pg_plates_world_free(pg_plates_world *w);

/* Build the world. BADINPUT naming the parameter when one is out of range. */
pg_status pg_plates_generate(const pg_plates_params *p, pg_plates_world *out, pg_error *err);

/* Classify plate boundaries on any plate map: a texel is on a boundary when one of its
 * 4 edge neighbours belongs to another plate; the kind comes from the relative velocity
 * of the other plate(s) with respect to this one, split into the component along the
 * outward boundary normal and the tangential one (pg_plates_boundaries.c). `omega` holds
 * nplates angular velocities (any consistent unit). `kind` receives 6*n*n values. */
pg_status pg_plates_classify(int64_t n, pg_cube_projection proj, const uint8_t *plate, int nplates,
                             const double (*omega)[3], uint8_t *kind, pg_error *err);

/* A target hypsometry: n quantiles of land heights (> 0 m) and of ocean heights (<= 0 m),
 * each ascending, at area fractions i / (n - 1). rank_offset_m (6 n^2 per texel, or NULL)
 * is added to a texel's height for ranking only: an ice sheet, whose surface stands high
 * above the rock the plates made (pg_plates_hypsometry.c). Tables belong to the caller. */
typedef struct pg_plates_hypsometry {
    int n;
    const float *land_m, *ocean_m;
    const float *rank_offset_m;
} pg_plates_hypsometry;

/* Remap the world's heights onto the target hypsometry, land onto land and ocean onto
 * ocean, keeping every texel's rank (area-weighted) and so every coast
 * (pg_plates_hypsometry.c). BADINPUT when a table is too short or not ascending. */
pg_status pg_plates_match_hypsometry(pg_plates_world *w, const pg_plates_hypsometry *h,
                                     pg_error *err);

/* Summary figures of a world (area-weighted on the sphere). */
typedef struct pg_plates_stats {
    double land_fraction;       /* area above 0 m / sphere */
    double largest_plate_share; /* largest plate area / sphere */
    double largest_land_share;  /* largest landmass / land (8-connected) */
    int landmasses_1e6km2;      /* landmasses of at least 1e6 km^2 (scaled to radius) */
    double
        mountain_belt_share; /* land above 2000 m within 500 km of convergent / land above 2000 m */
    double high_land_fraction; /* land above 2000 m / land */
    double land_mean_m;        /* mean height of land */
    double ocean_mean_depth_m; /* mean depth of the ocean, positive */
    int boundary_kinds[4];     /* texel counts by pg_plates_boundary */
} pg_plates_stats;

pg_status pg_plates_stats_compute(const pg_plates_world *w, pg_plates_stats *s, pg_error *err);

/* The macro fields as the synthesis samples them (docs/generate.md, "Layout world"):
 * nch interleaved channels on a cube of n texels a face edge resampled onto a cube of m
 * (> n, same projection), each texel taking the bilinear value at its direction moved
 * by a smooth hashed warp of about one source texel, so that contours on the coarse
 * grid (an ice margin, an escarpment) wander as on Earth instead of following its
 * lines and face seams. The warp is a function of (seed, direction) alone. out holds
 * 6 m^2 nch floats (caller-owned). */
pg_status pg_plates_detail(uint64_t seed, pg_cube_projection proj, int64_t n, const float *in,
                           int nch, int64_t m, float *out, pg_error *err);

/* Preview images, equirectangular width x width/2, RGB floats 0..1 (pg_image_alloc'd;
 * free with pg_image_free). Plates: a distinct colour per plate over a relief shade,
 * boundaries red (convergent), blue (divergent), green (transform). Relief: a
 * hypsometric tint (ocean blues by depth, land greens to browns to white). */
pg_status pg_plates_render_plates(const pg_plates_world *w, int width, pg_image *out,
                                  pg_error *err);
pg_status pg_plates_render_relief(const pg_plates_world *w, int width, pg_image *out,
                                  pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
