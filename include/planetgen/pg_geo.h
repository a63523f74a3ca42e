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

#ifdef __cplusplus
}
#endif

#endif
