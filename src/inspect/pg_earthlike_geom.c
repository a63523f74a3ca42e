/* pg_earthlike_geom.c - texel areas on the planet's ellipsoid and texel latitudes,
 * computed once per face kind for the Earth-likeness statistics (pg_earthlike.h).
 *
 * SOLID ANGLES. Gnomonic and equi-angular texels are rectangles [X0, X1] x [Y0, Y1]
 * of the gnomonic plane tangent to the face at distance 1 (X = A(u), Y = A(v),
 * pg_cube.h), i.e. quadrilaterals bounded by great circles. The solid angle of the
 * plane rectangle [0, X] x [0, Y] seen from the centre is
 *     F(X, Y) = atan(X Y / sqrt(1 + X^2 + Y^2))
 * (the classical rectangular-pyramid formula; F is odd in X and in Y), so by
 * inclusion-exclusion a texel has F(X1,Y1) - F(X0,Y1) - F(X1,Y0) + F(X0,Y0): exact,
 * one atan per texel corner. The equal-area grid is not a gnomonic rectangle grid; it
 * takes pg_pits_cube_face_areas (each texel as two spherical triangles between its
 * corner rays; the few texels round a face centre, whose edges are not great
 * circles, are then a few % off individually - cubesphere/pg_cube_distortion.c -
 * while the tiling, hence every total, stays exact).
 *
 * AREAS. On the ellipsoid a texel is the radial projection of its solid angle.
 * Radial projection onto the surface r(d) d has area element dA = r^2 / cos(theta)
 * dOmega, theta the angle between the ray and the surface normal. For
 * x^2/a^2 + y^2/a^2 + z^2/b^2 = 1 and a unit ray d = (dx, dy, dz), rho^2 = dx^2 + dy^2:
 *     1/r^2 = rho^2/a^2 + dz^2/b^2,   cos(theta) = 1 / (r^2 sqrt(rho^2/a^4 + dz^2/b^4)),
 *     dA/dOmega = J(d) = r^4 sqrt(rho^2/a^4 + dz^2/b^4)      (J = a^2 on a sphere).
 * A texel's area is its solid angle times J at its centre. J is smooth and varies by
 * 2f = 0.7% over a quadrant on WGS84, so the midpoint rule is off by O(f h^2) per
 * texel: the total matches the ellipsoid's area (GeographicLib's) to 3e-10 on WGS84
 * at N = 32, 3e-13 at N = 1024 (tests/test_earthlike.c).
 *
 * FIXED POINT. Areas are stored as integers in units of 4 pi a^2 / 2^60 (a the
 * equatorial radius: the circumscribed sphere's area, so any sum over the planet
 * stays below 2^60 and 64-bit sums cannot overflow). A texel is at least ~1e-9 of
 * the planet for N <= 8192, i.e. > 1e9 units, so rounding costs < 1e-9 relative.
 * Integer sums do not depend on order, so OpenMP reductions over them are
 * thread-count independent.
 *
 * LATITUDE is geodetic: the ray's surface point has normal proportional to
 * (x/a^2, y/a^2, z/b^2), so tan(lat) = (a/b)^2 dz / rho = dz / ((1 - f)^2 rho), the
 * same as pg_geo_dir_to_latlon (pg_geo.h) in closed form.
 *
 * SYMMETRY. Every projection maps grid coordinates to the same face-local
 * components (along n, e_u, e_v) on every face (pg_cube_to_dir), and the frames are
 * integer unit vectors, so one set of local components serves all six faces exactly:
 * on the equatorial faces dz is the e_v component (their e_v is +Z), on +Z the n
 * component, on -Z minus the n component. Hence one table for the four equatorial
 * faces (quarter turns about the polar axis keep dz), one for +Z, and -Z mirrors +Z
 * (same areas, J being even in dz; opposite latitudes). */
#include "pg_earthlike_internal.h"

#include "planetgen/pg_pits.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double RAD2DEG = 57.29577951308232;

double pg_earthlike_geodetic_lat(const pg_ellipsoid *e, const double dir[3]) {
    double rho = hypot(dir[0], dir[1]), k = (1 - e->f) * (1 - e->f);
    return atan2(dir[2], k * rho) * RAD2DEG;
}

/* Ellipsoid area per steradian along a unit ray with polar component dz and
 * equatorial component rho (J above). */
static double area_per_sr(const pg_ellipsoid *e, double dz, double rho) {
    double rho2 = rho * rho, z2 = dz * dz;
    double a2 = e->a * e->a, b = e->a * (1 - e->f), b2 = b * b;
    double r2 = 1 / (rho2 / a2 + z2 / b2);
    return r2 * r2 * sqrt(rho2 / (a2 * a2) + z2 / (b2 * b2));
}

static int lat_bin(double lat) {
    int b = (int)floor(lat + 90);
    return b < 0 ? 0 : b >= PG_EL_BINS ? PG_EL_BINS - 1 : b;
}

/* Solid angle of the gnomonic-plane rectangle [0, X] x [0, Y]. */
static double rect_sr(double X, double Y) {
    return atan2(X * Y, sqrt(1 + X * X + Y * Y));
}

/* Solid angles of the n x n texels of a face, steradians. */
static pg_status solid_angles(pg_cube_projection proj, int64_t n, double *sr, pg_error *err) {
    if (proj == PG_CUBE_EQUALAREA) return pg_pits_cube_face_areas(proj, (uint32_t)n, 1.0, sr, err);
    double *A = malloc((size_t)(n + 1) * sizeof *A);
    if (!A) return pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory for texel areas");
    for (int64_t i = 0; i <= n; i++) {
        double u = 2.0 * (double)i / (double)n - 1;
        A[i] = proj == PG_CUBE_EQUIANGULAR ? tan(M_PI / 4 * u) : u;
    }
#pragma omp parallel for schedule(static)
    for (int64_t y = 0; y < n; y++) {
        double f0 = rect_sr(A[0], A[y]), f1 = rect_sr(A[0], A[y + 1]);
        for (int64_t x = 0; x < n; x++) {
            double g0 = rect_sr(A[x + 1], A[y]), g1 = rect_sr(A[x + 1], A[y + 1]);
            sr[y * n + x] = g1 - f1 - g0 + f0;
            f0 = g0, f1 = g1;
        }
    }
    free(A);
    return PG_OK;
}

/* Row y of the tables from the solid angles sr: local components (n, e_u, e_v) of
 * the texel centre from face +X, whose frame is (x, y, z). */
static void fill_row(pg_earthlike_geom *g, const pg_planet *p, const double *sr, int64_t y) {
    const pg_ellipsoid *e = &p->ellipsoid;
    int64_t n = g->n;
    double v = (2.0 * (double)y + 1) / (double)n - 1;
    for (int64_t x = 0; x < n; x++) {
        double l[3], u = (2.0 * (double)x + 1) / (double)n - 1;
        pg_cube_to_dir(p->projection, PG_CUBE_FACE_PX, u, v, l);
        size_t i = (size_t)(y * n + x);
        double eq[3] = {l[0], l[1], l[2]}, pz[3] = {l[1], l[2], l[0]}; /* z = e_v; z = n */
        double rho_eq = hypot(l[0], l[1]), rho_p = hypot(l[1], l[2]);
        g->weight[0][i] = (uint64_t)llround(sr[i] * area_per_sr(e, l[2], rho_eq) / g->unit_m2);
        g->weight[1][i] = (uint64_t)llround(sr[i] * area_per_sr(e, l[0], rho_p) / g->unit_m2);
        double lat_p = pg_earthlike_geodetic_lat(e, pz);
        g->bin[0][i] = (uint8_t)lat_bin(pg_earthlike_geodetic_lat(e, eq));
        g->bin[1][i] = (uint8_t)lat_bin(lat_p);
        g->bin[2][i] = (uint8_t)lat_bin(-lat_p);
    }
}

pg_status pg_earthlike_geom_init(pg_earthlike_geom *g, const pg_planet *p, pg_error *err) {
    memset(g, 0, sizeof *g);
    if (p->n < 1 || p->n > 26754) /* 6 n^2 < 2^32: the census's texel ids */
        return pg_error_set(err, PG_ERR_BADINPUT, "earthlike: face size %lld out of range",
                            (long long)p->n);
    g->n = p->n;
    g->unit_m2 = 4 * M_PI * p->ellipsoid.a * p->ellipsoid.a / 1152921504606846976.0; /* 2^60 */
    size_t nn = (size_t)(p->n * p->n);
    double *sr = malloc(nn * sizeof *sr);
    int ok = sr != NULL;
    for (int k = 0; k < 3; k++) {
        if (k < 2) g->weight[k] = malloc(nn * sizeof *g->weight[k]);
        g->bin[k] = malloc(nn);
        ok = ok && g->weight[k < 2 ? k : 1] && g->bin[k];
    }
    g->weight[2] = g->weight[1];
    if (!ok) {
        free(sr);
        pg_earthlike_geom_free(g);
        return pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory for texel areas");
    }
    pg_status st = solid_angles(p->projection, p->n, sr, err);
    if (st == PG_OK) {
#pragma omp parallel for schedule(static)
        for (int64_t y = 0; y < g->n; y++)
            fill_row(g, p, sr, y);
    }
    free(sr);
    if (st != PG_OK) pg_earthlike_geom_free(g);
    return st;
}

void pg_earthlike_geom_free(pg_earthlike_geom *g) {
    free(g->weight[0]);
    free(g->weight[1]);
    for (int k = 0; k < 3; k++) {
        free(g->bin[k]);
        g->weight[k] = NULL;
        g->bin[k] = NULL;
    }
}
