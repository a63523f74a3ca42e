/* pg_geo.h - geodesy on the planet's ellipsoid (pg_ellipsoid.h): the conversions between
 * cube-sphere directions, geodetic latitude/longitude, ECEF positions and areas.
 *
 * The idea: the cube sphere gives unit directions; a direction d stands for the
 * point where the ray from the planet's centre along d pierces the ellipsoid.
 * Latitude is geodetic (the angle of the ellipsoid's normal), which differs from
 * the geocentric angle of d on a flattened planet by up to 0.19 degrees on WGS84.
 * The implementation is a thin adapter (cubesphere/pg_geodesy.cpp) over
 * GeographicLib (Geocentric, Geodesic, PolygonArea); no C++ type crosses this
 * header. Angles are in degrees, lengths in metres. */
#ifndef PLANETGEN_PG_GEO_H
#define PLANETGEN_PG_GEO_H

#include "planetgen/pg_ellipsoid.h"
#include "planetgen/pg_raster.h"

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Direction (any nonzero vector) -> geodetic lat/lon of the ray's surface point. */
void pg_geo_dir_to_latlon(const pg_ellipsoid *e, const double dir[3], double *lat, double *lon);
/* Batch form: n directions (3 doubles each). */
void pg_geo_dirs_to_latlon(const pg_ellipsoid *e, size_t n, const double *dirs, double *lat,
                           double *lon);
/* Geodetic lat/lon -> unit direction of that surface point from the centre. */
void pg_geo_latlon_to_dir(const pg_ellipsoid *e, double lat, double lon, double dir[3]);
void pg_geo_latlons_to_dirs(const pg_ellipsoid *e, size_t n, const double *lat, const double *lon,
                            double *dirs);

/* ECEF position of geodetic (lat, lon, height above the ellipsoid). */
void pg_geo_ecef(const pg_ellipsoid *e, double lat, double lon, double h, double xyz[3]);
/* ECEF of the surface point along dir raised by h along the ellipsoid normal. */
void pg_geo_dir_to_ecef(const pg_ellipsoid *e, const double dir[3], double h, double xyz[3]);

/* Area (m^2, positive) of the geodesic polygon through n vertices, and optionally
 * its interior angles at each vertex (degrees; angles may be NULL). Vertices go
 * counter-clockwise seen from outside; the angle at vertex i is measured from the
 * geodesic towards vertex i+1 round to the one towards vertex i-1. */
double pg_geo_polygon_area(const pg_ellipsoid *e, int n, const double *lat, const double *lon,
                           double *angles);
/* Batch form for npoly polygons of nvert vertices each (lat/lon: npoly*nvert;
 * area: npoly; angles: npoly*nvert or NULL). Sets up the geodesic once. */
void pg_geo_polygons(const pg_ellipsoid *e, size_t npoly, int nvert, const double *lat,
                     const double *lon, double *area, double *angles);

/* Total surface area of the ellipsoid. */
double pg_geo_total_area(const pg_ellipsoid *e);

/* Areas (m^2) of the n cells of a latitude/longitude grid column: cell i lies between
 * the parallels lat[i] and lat[i+1] (degrees, n+1 of them, either order, clamped to
 * +-90) and spans dlon degrees of longitude. Exact on the ellipsoid: the cells of a
 * whole-globe grid sum to pg_geo_total_area. */
void pg_geo_latlon_band_areas(const pg_ellipsoid *e, size_t n, const double *lat, double dlon,
                              double *area);

/* ---- georeferenced rasters (pg_raster.h; cubesphere/pg_geo_raster.c) ---- */

/* Does the width x height raster g describe have usable cell sizes: a geotransform and
 * a geographic or projected CRS? */
bool pg_geo_raster_has_cells(const pg_georef *g);
/* The area (m^2) of a cell in each of the height rows of a width x height raster:
 * geographic CRS - the true areas on the CRS's ellipsoid (north-up grids; a rotated
 * geotransform is refused); projected CRS - |det| of the geotransform in metres^2.
 * BADINPUT naming `what` when the georeferencing gives no cell sizes. */
pg_status pg_geo_raster_row_areas(const pg_georef *g, int width, int height, const char *what,
                                  double *rows, pg_error *err);
/* Is the raster a whole-globe geographic grid: north-up, 360 degrees of longitude and
 * +90 to -90 of latitude, to a hundredth of a cell? */
bool pg_geo_raster_is_global(const pg_georef *g, int width, int height);
/* The georeferencing of a whole-globe latitude/longitude grid of width x height cells
 * on ellipsoid e (west edge -180, north edge +90; CRS by pg_raster_geographic_crs). */
pg_status pg_geo_raster_global(const pg_ellipsoid *e, int width, int height, pg_georef *g,
                               pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
