/* pg_drainage_cube.c - cube geometry for the drainage measures: texel centres
 * (pg_drainage_internal.h) and true texel areas on the ellipsoid (pg_drainage.h).
 *
 * Texel area on an ellipsoid of revolution (semi-axes a, a, b): the surface r(d) d,
 * r^-2 = s(d) = (dx^2 + dy^2)/a^2 + dz^2/b^2, has the area element
 *     dA = r^2 / cos(alpha) dOmega = |g| / s^2 dOmega,  g = (dx/a^2, dy/a^2, dz/b^2)
 * (alpha = angle between the ray and the surface normal, which is parallel to g; with
 * unit d, cos(alpha) = s / |g|). On a sphere it is a^2 dOmega. A texel's solid angle is
 * the spherical excess of its four corners (two triangles, Van Oosterom & Strackee
 * 1983), the same on every face by the cube's symmetry. The element varies slowly, so
 * taking it at the texel centre errs by O(texel^2 f): below 1e-5 relative at 16 texels
 * per face edge on WGS84, 1e-9 at the default planet's 1024.
 *
 * The element depends on dz only, which is the same for texel (x, y) on the four
 * equatorial faces and, up to sign, on both polar faces: two n x n tables serve all,
 * and each is symmetric about the face's two mid-lines. */
#include "pg_huge.h"
#include "pg_drainage_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* An m x m grid of face-local points at u = (2x + off)/n - 1, v likewise (x, y < m).
 * Point (m-1-x, y) sits at -u, so it is point (x, y) with l_u negated (and likewise in
 * v): compute one quadrant, mirror the rest - a quarter of the projection calls, and a
 * grid that is exactly symmetric. Rows y and m-1-y belong to one iteration. */
static void local_grid(pg_cube_projection p, int64_t n, int64_t m, int off, double *l) {
    const int64_t h = (m + 1) / 2;
#pragma omp parallel for schedule(static)
    for (int64_t y = 0; y < h; y++)
        for (int64_t x = 0; x < h; x++) {
            double q[3];
            pg_cube_to_dir(p, PG_CUBE_FACE_PZ, (2.0 * (double)x + off) / (double)n - 1,
                           (2.0 * (double)y + off) / (double)n - 1, q); /* +Z: l itself */
            for (int k = 0; k < 4; k++) {
                int64_t xx = k & 1 ? m - 1 - x : x, yy = k & 2 ? m - 1 - y : y;
                double *o = l + 3 * (yy * m + xx);
                o[0] = k & 1 ? -q[0] : q[0], o[1] = k & 2 ? -q[1] : q[1], o[2] = q[2];
            }
        }
}

void pg_drainage_local_centres(pg_cube_projection p, int64_t n, double *l) {
    local_grid(p, n, n, 1, l);
}

void pg_drainage_local_to_dir(const double l[3], int polar, double d[3]) {
    if (polar)
        d[0] = l[0], d[1] = l[1], d[2] = l[2];
    else
        d[0] = l[2], d[1] = l[0], d[2] = l[1];
}

void pg_drainage_surface_point(const double d[3], double a, double b, double p[3]) {
    double s = (d[0] * d[0] + d[1] * d[1]) / (a * a) + d[2] * d[2] / (b * b);
    double r = 1.0 / sqrt(s);
    p[0] = r * d[0], p[1] = r * d[1], p[2] = r * d[2];
}

/* |g| / s^2 for a unit direction with z component dz, in a's unit squared per sr. */
static double area_element(double dz, double a, double b) {
    double q = 1.0 - dz * dz;
    double s = q / (a * a) + dz * dz / (b * b);
    double g = sqrt(q / (a * a * a * a) + dz * dz / (b * b * b * b));
    return g / (s * s);
}

/* The area tables: t[0..nn) for the equatorial faces, t[nn..2nn) for the polar ones.
 * Excess and element are symmetric under x -> n-1-x and y -> n-1-y (the element
 * depends on dz^2), so one quadrant is computed and mirrored. */
static void area_tables(int64_t n, const double *corner, const double *centre, double a, double b,
                        float *t) {
    const int64_t nn = n * n, m = n + 1, h = (n + 1) / 2;
#pragma omp parallel for schedule(static)
    for (int64_t y = 0; y < h; y++)
        for (int64_t x = 0; x < h; x++) {
            const double *c00 = corner + 3 * (y * m + x), *c10 = c00 + 3;
            const double *c01 = c00 + 3 * m, *c11 = c01 + 3;
            double e = pg_cube_spherical_triangle(c00, c10, c11) +
                       pg_cube_spherical_triangle(c00, c11, c01);
            const double *l = centre + 3 * (y * n + x);
            float eq = (float)(e * area_element(l[1], a, b)); /* +X: dz = l_v */
            float po = (float)(e * area_element(l[2], a, b)); /* +Z: dz = l_n */
            for (int k = 0; k < 4; k++) {
                int64_t i = (k & 2 ? n - 1 - y : y) * n + (k & 1 ? n - 1 - x : x);
                t[i] = eq, t[nn + i] = po;
            }
        }
}

pg_status pg_drainage_cube_areas(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                 float *area_km2, pg_error *err) {
    if (n < 1 || n > 18918)
        return pg_error_set(err, PG_ERR_BADINPUT, "drainage: face size %lld outside 1..18918",
                            (long long)n);
    pg_ellipsoid e = ell ? *ell : pg_ellipsoid_sphere();
    double a = e.a / 1000.0, b = a * (1.0 - e.f);
    size_t nn = (size_t)n * (size_t)n, m = (size_t)(n + 1) * (size_t)(n + 1);
    double *corner = pg_huge_malloc(3 * m * sizeof *corner),
           *centre = pg_huge_malloc(3 * nn * sizeof *centre);
    float *t = pg_huge_malloc(2 * nn * sizeof *t);
    pg_status s = PG_OK;
    if (!corner || !centre || !t)
        s = pg_error_set(err, PG_ERR_NOMEM, "drainage: out of memory for texel areas");
    if (!s) {
        local_grid(p, n, n + 1, 0, corner);
        pg_drainage_local_centres(p, n, centre);
        area_tables(n, corner, centre, a, b, t);
        for (int f = 0; f < PG_CUBE_NFACES; f++)
            memcpy(area_km2 + f * nn, t + (f >= PG_CUBE_FACE_PZ) * nn, nn * sizeof *t);
    }
    free(corner), free(centre), free(t);
    return s;
}
