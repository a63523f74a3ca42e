/* pg_climate_internal.h - the pieces of the climate model shared between its files:
 * the prevailing wind and the upwind moisture march. */
#ifndef PG_CLIMATE_INTERNAL_H
#define PG_CLIMATE_INTERNAL_H

#include "planetgen/pg_climate.h"

/* What the march along the prevailing wind finds for one texel. */
typedef struct pg_climate_march_result {
    float moisture;      /* 0..1: moisture the wind brings (1 over the sea) */
    float maritime;      /* 0..1: the sea's influence on temperature (1 over the sea) */
    float windward_rise; /* metres of climb per km just upwind of the texel (>= 0) */
} pg_climate_march_result;

/* The prevailing surface wind at a latitude as a unit vector (east, north): trade
 * winds below 30 degrees, westerlies to 60, polar easterlies beyond. */
void pg_climate_wind(double lat_deg, double *east, double *north);

/* March upwind from the texel at unit direction dir (elevation h0) through the
 * elevation cube field (land_mask: 1 on land, 0 on sea, the same layout; the sea is
 * where its bilinear sample is below 1/2, so the coastline does not move when the
 * land is raised) and integrate the moisture and maritime influence back
 * downwind. g is the field's grid (pg_cube_sample_grid_init), its seam maps
 * built once by the caller. Pure function of its arguments. */
void pg_climate_march(const pg_climate_params *p, const pg_cube_grid *g, const float *elevation_m,
                      const float *land_mask, const double dir[3], float h0,
                      pg_climate_march_result *out);

#endif
