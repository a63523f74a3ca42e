/* pg_drainage.h - drainage-network measures of a planet: D8 flow on the cube sphere,
 * flow accumulation, rivers, Hack's law, drainage density and basin shares
 * (docs/inspect.md, "Drainage network").
 *
 * The idea: real terrain is carved by rivers, and river networks obey scaling laws
 * that synthesized terrain need not. Route every land texel to its steepest-descent
 * neighbour (D8, O'Callaghan & Mark 1984) across face seams, accumulate the area that
 * drains through each texel, and measure the network:
 *   - Hack's law (Hack 1957): main-stream length L ~ A^h over the river basins that
 *     reach the sea; real networks have h ~ 0.5-0.6, the Scheidegger random network
 *     (Scheidegger 1967) exactly 2/3, parallel gullies 1;
 *   - drainage density (Horton 1945): river length per land area, km^-1;
 *   - the land share of the largest basin, and the share that ends in closed basins
 *     (pits) instead of the sea.
 *
 * Two layers: a core that works on any receiver graph (pg_drainage_compute; tests
 * build Scheidegger networks with it), and the cube-sphere layer (D8 with true texel
 * distances and areas on the planet's ellipsoid, the whole-cube wrapper, the
 * closed-land share used by synthesis, and the rivers preview). The cube-sphere layer
 * reads a pg_drainage_terrain, the few fields of a planet it needs
 * (pg_planet_drainage_terrain of pg_planet.h fills one), so drainage does not depend on
 * the planet module. Results do not depend on the thread count. */
#ifndef PLANETGEN_PG_DRAINAGE_H
#define PLANETGEN_PG_DRAINAGE_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_cube.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the core: any receiver graph ------------------------------------------------ */

/* Cell flags. A cell without PG_DRAINAGE_LAND is sea: an outlet that must have no
 * receiver. A land cell without a receiver is a pit (closed basin) unless it carries
 * PG_DRAINAGE_OUTLET (it drains out of the domain, e.g. the edge of a flat grid). */
#define PG_DRAINAGE_LAND 1u
#define PG_DRAINAGE_OUTLET 2u

typedef struct pg_drainage_graph {
    uint64_t ncell;          /* < 2^31 */
    const int32_t *receiver; /* ncell: the cell it drains into, or -1 (outlet or pit) */
    const float *area_km2;   /* ncell: cell area, >= 0 */
    const float *length_km;  /* ncell: flow length to the receiver (to the domain's edge
                                for an outlet), >= 0 */
    const uint8_t *flags;    /* ncell: PG_DRAINAGE_* */
} pg_drainage_graph;

typedef struct pg_drainage_opts {
    double river_threshold_km2; /* a land cell is a river when accumulation >= this */
    double hack_min_area_km2;   /* basins fitted by Hack's law have at least this area */
} pg_drainage_opts;

/* Defaults: both 1e4 km^2 (a river of about 100 km; 2 orders of magnitude above the
 * default planet's 81 km^2 texels, so basins have enough texels to have a shape). */
void pg_drainage_opts_default(pg_drainage_opts *o);

typedef struct pg_drainage_stats {
    uint64_t land_cells;
    double land_area_km2;
    uint64_t mouths; /* land cells that drain into the sea or out of the domain */
    uint64_t pits;   /* land cells without receiver that are not outlets */
    uint64_t river_cells;
    double river_length_km;         /* sum of length_km over river cells */
    double drainage_density_per_km; /* river_length_km / land_area_km2 */
    /* Hack's law L = c A^h, least squares of ln L on ln A over the mouths with
     * A >= hack_min_area_km2; NaN (and basins < 3) when it cannot be fitted. */
    double hack_exponent, hack_coefficient, hack_r2;
    uint64_t hack_basins;
    double largest_basin_km2;        /* land area of the largest mouth or pit basin */
    double largest_basin_land_share; /* ... / land_area_km2 */
    double closed_land_share;        /* land area that ends in a pit / land_area_km2 */
} pg_drainage_stats;

/* Flow accumulation and the measures above. Accumulation of a cell = its own area +
 * the accumulation of its donors (cells whose receiver it is), computed in topological
 * order (Kahn 1962) in O(ncell). A basin is the set of land cells that drain through
 * the same mouth or into the same pit. The main stream of a mouth: walk upstream from
 * it, always to the donor of largest accumulation (ties: lowest id), to a cell without
 * donors; L = the sum of length_km over its cells, the mouth included. acc_km2
 * (ncell floats, may be NULL) receives the accumulation of every cell. Errors
 * (PG_ERR_BADINPUT): a receiver out of range or a cycle, a sea cell with a receiver,
 * negative or non-finite areas or lengths, bad options; PG_ERR_NOMEM. */
pg_status pg_drainage_compute(const pg_drainage_graph *g, const pg_drainage_opts *o, float *acc_km2,
                              pg_drainage_stats *st, pg_error *err);

/* ---- the cube sphere ------------------------------------------------------------- */

/* Area (km^2) of every texel of the 6 x n x n cube (global texel ids, pg_cube.h) on the
 * ellipsoid (NULL: a sphere of PG_ELLIPSOID_SPHERE_RADIUS_M): the spherical excess of the texel's
 * corners on the unit sphere times the ellipsoid's area element at the texel centre. */
pg_status pg_drainage_cube_areas(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                 float *area_km2, pg_error *err);

/* D8 flow directions (O'Callaghan & Mark 1984) on the cube, 8-connected across face
 * seams (7 neighbours at the cube-corner texels; pg_pits.h). heights[f] is face f's
 * n x n field in metres. A cell at or below sea_level is sea (flags 0, receiver -1).
 * A land cell drains to the neighbour of steepest descent, (h - h_j) / distance
 * between the texel centres on the ellipsoid, ties to the lowest id; without a lower
 * neighbour it is a pit (receiver -1; flats count as not lower). Outputs (6*n*n each):
 * receiver, length_km (distance to the receiver, 0 without one; may be NULL) and flags.
 * NaN heights are PG_ERR_BADINPUT. */
pg_status pg_drainage_cube_d8(const float *const heights[PG_CUBE_NFACES], int64_t n,
                              pg_cube_projection p, const pg_ellipsoid *ell, float sea_level,
                              int32_t *receiver, float *length_km, uint8_t *flags, pg_error *err);

/* A planet's terrain as the cube-sphere layer reads it (the heights are borrowed, not
 * copied or freed). */
typedef struct pg_drainage_terrain {
    int64_t n;                           /* texels per face edge */
    const float *height[PG_CUBE_NFACES]; /* face f's n x n heights, metres */
    pg_cube_projection projection;
    pg_ellipsoid ellipsoid;
    float sea_level; /* metres */
} pg_drainage_terrain;

/* Everything on a planet's terrain: D8 on its heights with its sea level, projection
 * and ellipsoid, then pg_drainage_compute (o NULL: defaults). When acc_out is not NULL
 * it receives a malloc'd 6*n*n field (global texel ids; caller frees): the accumulation
 * in km^2 on land, 0 on sea. */
pg_status pg_drainage_planet(const pg_drainage_terrain *t, const pg_drainage_opts *o,
                             pg_drainage_stats *st, float **acc_out, pg_error *err);

/* The closed-land share alone, on a contiguous height field (6*n*n floats, global
 * texel ids) of the given projection and ellipsoid (NULL: sphere); the same figure as
 * pg_drainage_planet's, in under 20 bytes per texel instead of about 40 (synthesis calls it
 * while the whole planet is in memory). NaN without land. */
pg_status pg_drainage_closed_land_share(const float *heights, int64_t n, pg_cube_projection p,
                                        const pg_ellipsoid *ell, float sea_level, double *share,
                                        pg_error *err);

/* The rivers preview: draw the cells with accumulation >= threshold_km2 in blue over an
 * equirectangular RGB image (w x h, row 0 north, latitudes geodetic on t's ellipsoid;
 * e.g. pg_relief_shade's output), in place. acc is a 6*n*n field of t's geometry (as
 * from pg_drainage_planet). Each pixel takes the largest accumulation among the 2 x 2
 * texels around its centre, so one-texel rivers survive downsampling; opacity and
 * width (1 to 4 px) grow with log(acc / threshold) up to 1000 x threshold. */
pg_status pg_drainage_draw_rivers(const pg_drainage_terrain *t, const float *acc,
                                  double threshold_km2, float *rgb, int w, int h, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
