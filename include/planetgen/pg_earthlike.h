/* pg_earthlike.h - Earth-likeness statistics of a planet for the realism report
 * (`planetgen inspect`, docs/inspect.md): land fraction, landmass census, hypsometry,
 * zonal climate and novelty against Earth's own land/ocean layout.
 *
 * The idea: every figure is computed by ONE function on ANY pg_planet, so the same
 * numbers come out for a synthesized planet and for Earth itself (the exemplar
 * reprojected onto a cube of the planet's size with pg_planet_from_exemplar); the
 * report then compares the two. Every figure is area-weighted on the planet's
 * ellipsoid: texel areas are the solid angles of the texels (exact, closed form for
 * the gnomonic and equi-angular grids; pg_pits_cube_face_areas for equal-area) times
 * the ellipsoid's area per steradian at the texel centre (the radial-projection
 * Jacobian); they sum to the ellipsoid's area to 3e-10 on WGS84 at N = 32 (falling
 * as 1/N^2; tests/test_earthlike.c). See src/pg_earthlike_geom.c.
 * Latitudes are GEODETIC on the planet's ellipsoid (the ray's surface point, as in
 * pg_geo.h; closed form for an ellipsoid of revolution).
 *
 * Land is height > p->sea_level; everything else is ocean. Terrain types are those of
 * pg_types_classify (pg_types.h) on the albedo rounded to 8-bit sRGB.
 *
 * Results do not depend on the OpenMP thread count: areas are summed as 64-bit
 * integers (fixed point, 2^-60 of the circumscribed sphere's area per unit), whose
 * sums do not depend on order, and the height moments per texel row, added in row
 * order. */
#ifndef PLANETGEN_PG_EARTHLIKE_H
#define PLANETGEN_PG_EARTHLIKE_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_types.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PG_EARTHLIKE_QUANTILES 1024 /* quantile function samples, at (k + 1/2) / K */
#define PG_EARTHLIKE_BANDS 18       /* 10-degree geodetic latitude bands, south first */

typedef struct pg_earthlike {
    int64_t n;            /* face size of the planet measured */
    double total_area_m2; /* sum of all texel areas */
    double land_area_m2;
    double land_fraction; /* land area / total area */

    /* Landmass census: regions of land texels 8-connected across face seams and cube
     * corners (pg_pits_neighbours on the cube topology). */
    uint64_t landmasses;           /* all of them, any size */
    uint64_t landmasses_1e4;       /* with area >= 1e4 km^2 */
    uint64_t landmasses_1e6;       /* with area >= 1e6 km^2 */
    double largest_landmass_km2;   /* 0 without land */
    double largest_landmass_share; /* largest / all land area; NaN without land */
    double rank_size_slope;        /* least-squares slope of ln(area) on ln(rank) over
                                      the landmasses >= 1e4 km^2; NaN with fewer than 3 */

    /* Hypsometry, heights in metres ABOVE SEA LEVEL (h - p->sea_level): area-weighted
     * quantile functions, element k = F^-1((k + 1/2) / K), from a 65536-bin histogram
     * over each distribution's own range with linear interpolation inside a bin
     * (resolution: range / 65536, 0.14 m for Earth's land). NaN when there is no
     * land (no ocean). Means and standard deviations are exact area-weighted moments. */
    double land_quantiles[PG_EARTHLIKE_QUANTILES];
    double ocean_quantiles[PG_EARTHLIKE_QUANTILES];
    double land_mean_m, land_std_m;
    double ocean_mean_m, ocean_std_m;

    /* Zonal climate: band b covers geodetic latitudes [-90 + 10b, -80 + 10b) (the
     * last band includes 90). zonal[b][t] = area share of type t (pg_types_id) in
     * band b; the six shares of a band sum to 1. */
    double band_area_m2[PG_EARTHLIKE_BANDS];
    double zonal[PG_EARTHLIKE_BANDS][PG_TYPE_COUNT];
    /* Ice share of ALL area within |lat| < 20 deg. */
    double ice_equator_fraction;
    /* Share of LAND (height > sea level) poleward of 66 deg (both hemispheres) that is
     * ice: sea ice is classified ice but is not land, so it does not count. NaN when
     * the polar land is under 1% of the polar area. */
    double ice_polar_fraction;
    /* (desert share of land within 15..35 deg, both hemispheres) / (desert share of
     * land within |lat| < 10 deg). NaN when either zone has no land or when neither
     * has desert; +INFINITY when the subtropics have desert and the equator none. */
    double desert_band_ratio;
    /* Continental shelf along the coasts (pg_earthlike_shelf.c): a coast texel is land
     * with a sea neighbour (8-connected); its shelf width is the distance through the
     * sea to the nearest texel more than PG_EARTHLIKE_SHELF_BREAK_M below sea level, in
     * km (hops of the 8-neighbour graph times the coast texel's width, so one texel
     * width at least). Quantiles over the coast texels that reach such depth; NaN when
     * none does. Coast texels of seas that never reach it are counted apart. */
    uint64_t shelf_coast_texels;  /* all coast texels */
    uint64_t shelf_closed_texels; /* of those, on seas without deep water */
    double shelf_width_p10_km, shelf_width_p50_km, shelf_width_p90_km;
} pg_earthlike;

#define PG_EARTHLIKE_SHELF_BREAK_M 200.0 /* the shelf break: depth below sea level */

/* All figures above for planet p. BADINPUT for an empty planet, a face size above
 * 26754 (texel ids must fit 32 bits) or a non-finite height or sea level; NOMEM.
 * Takes about 0.41-0.47 s for N = 1024 on 2 cores (bench_earthlike, with the serial
 * shelf search; 0.25 s before it) and about 110 MB of working memory (texel tables, the
 * census's mask and queue, the shelf search's hop counts and queue). */
pg_status pg_earthlike_compute(const pg_planet *p, pg_earthlike *out, pg_error *err);

/* Wasserstein-1 distances (metres) between the land height distributions and
 * between the ocean height distributions of a and b: the integral over q of
 * |Fa^-1(q) - Fb^-1(q)|, by the midpoint rule on the K stored quantiles. NaN when
 * either side has no land (no ocean). Either output may be NULL. */
void pg_earthlike_w1(const pg_earthlike *a, const pg_earthlike *b, double *land_m, double *ocean_m);

/* Similarity of the two zonal profiles: for each terrain type, the Pearson
 * correlation over the 18 bands of its area share (each band counts once, so the
 * small polar bands, where the ice is, weigh as much as the tropics); the result is
 * the mean over the types. A type whose profile is constant on both planets (e.g.
 * absent from both) is left out; one constant on one planet only (e.g. no ice at
 * all) counts 0. NaN when every type is left out. per_type (may be NULL) receives
 * each type's correlation, NaN for the left-out ones.
 * Why per type and not the flattened 18 x 6 table: there the large ocean shares
 * against the small land-type shares dominate. A planet with Earth's global type
 * shares in every band (no zonal structure at all) correlates 0.79 with Earth in
 * the flattened table, and 0 here (every type constant on one side). */
double pg_earthlike_zonal_correlation(const pg_earthlike *a, const pg_earthlike *b,
                                      double per_type[PG_TYPE_COUNT]);

/* Novelty: how much of the planet's land/ocean layout is Earth's, in place. */
typedef struct pg_earthlike_novelty {
    double agreement;            /* area share where planet and Earth are both land or
                                    both ocean */
    double chance;               /* f_p f_e + (1 - f_p)(1 - f_e): agreement of two
                                    unrelated layouts with these land fractions */
    double planet_land_fraction; /* f_p */
    double earth_land_fraction;  /* f_e: Earth's land share over the same texels */
    double kappa;                /* (agreement - chance) / (1 - chance): Cohen's kappa,
                                    1 for Earth itself, ~0 for an unrelated layout */
    double novelty;              /* 1 - kappa; NaN when chance is 1 (both all land or
                                    both all ocean) */
    /* Chance agreement of two layouts independent GIVEN latitude: the chance above
     * per 1-degree latitude bin, area-weighted. A planet with Earth's zonal land
     * profile but its own longitudes (e.g. Earth turned 180 degrees about the axis:
     * Antarctica and the Southern Ocean stay put) agrees by more than `chance`
     * (0.67 against 0.59) but by about `chance_zonal`. */
    double chance_zonal;
    double kappa_zonal; /* (agreement - chance_zonal) / (1 - chance_zonal) */
} pg_earthlike_novelty;

/* Compare planet p with the equirectangular exemplar ex (its elevation and
 * sea_level): each texel's Earth land/ocean comes from the exemplar elevation,
 * bilinear (pg_equirect_sample) at the texel centre's geodetic latitude and
 * longitude on p's ellipsoid. No Earth cube is built. BADINPUT for an empty planet
 * or exemplar; NOMEM. */
pg_status pg_earthlike_novelty_compute(const pg_planet *p, const pg_exemplar *ex,
                                       pg_earthlike_novelty *out, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
