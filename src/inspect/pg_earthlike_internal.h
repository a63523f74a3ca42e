/* pg_earthlike_internal.h - what the Earth-likeness files (src/pg_earthlike*.c) share:
 * the per-texel area weights and latitude bins of one planet's cube grid.
 *
 * Texel areas are fixed-point integers (see pg_earthlike_geom.c) so that any sum of
 * them is exact and independent of summation order, hence of the thread count. */
#ifndef PLANETGEN_PG_EARTHLIKE_INTERNAL_H
#define PLANETGEN_PG_EARTHLIKE_INTERNAL_H

#include "planetgen/pg_earthlike.h"

#define PG_EL_BINS 180 /* 1-degree geodetic latitude bins, bin 0 = [-90, -89) */

/* Tables for one face size, shared by faces of the same kind: kind 0 = the four
 * equatorial faces (congruent by quarter turns about the polar axis, which keep
 * latitudes), kind 1 = +Z, kind 2 = -Z (mirror images of each other: same areas,
 * opposite latitudes). Element y*n + x is texel (x, y). */
typedef struct pg_earthlike_geom {
    int64_t n;
    double unit_m2;      /* m^2 per weight unit */
    uint64_t *weight[3]; /* texel area in units; weight[2] == weight[1] */
    uint8_t *bin[3];     /* 1-degree latitude bin of the texel centre, 0..179 */
} pg_earthlike_geom;

static inline int pg_earthlike_face_kind(int face) {
    return face < PG_CUBE_FACE_PZ ? 0 : face - PG_CUBE_FACE_PZ + 1;
}

pg_status pg_earthlike_geom_init(pg_earthlike_geom *g, const pg_planet *p, pg_error *err);
void pg_earthlike_geom_free(pg_earthlike_geom *g);

/* Geodetic latitude (degrees) of the surface point that the ray along dir (any
 * nonzero vector) pierces on ellipsoid e. */
double pg_earthlike_geodetic_lat(const pg_ellipsoid *e, const double dir[3]);

/* The landmass census fields of out (pg_earthlike_census.c). */
pg_status pg_earthlike_census(const pg_planet *p, const pg_earthlike_geom *g, pg_earthlike *out,
                              pg_error *err);

/* The shelf width fields of out (pg_earthlike_shelf.c). */
pg_status pg_earthlike_shelf(const pg_planet *p, const pg_earthlike_geom *g, pg_earthlike *out,
                             pg_error *err);

#endif
