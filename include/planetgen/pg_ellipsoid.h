/* pg_ellipsoid.h - the planet's reference ellipsoid (equatorial radius and flattening):
 * the mean-radius sphere, WGS84, or any valid (a, f). Lengths in metres. */
#ifndef PLANETGEN_PG_ELLIPSOID_H
#define PLANETGEN_PG_ELLIPSOID_H

#include "planetgen/pg_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pg_ellipsoid {
    double a; /* equatorial radius, metres, > 0 */
    double f; /* flattening, in [0, 1) */
} pg_ellipsoid;

#define PG_ELLIPSOID_SPHERE_RADIUS_M 6371008.8 /* IUGG mean Earth radius */

/* The sphere of radius PG_ELLIPSOID_SPHERE_RADIUS_M, and WGS84. */
pg_ellipsoid pg_ellipsoid_sphere(void);
pg_ellipsoid pg_ellipsoid_wgs84(void);
/* Validate a, f (BADINPUT naming `option` if a <= 0, f outside [0, 1), not finite). */
pg_status pg_ellipsoid_make(double a, double f, const char *option, pg_ellipsoid *out,
                            pg_error *err);
/* "sphere", "wgs84" or "A,F" (metres, flattening). */
pg_status pg_ellipsoid_parse(const char *spec, const char *option, pg_ellipsoid *out,
                             pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
