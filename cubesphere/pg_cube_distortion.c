/* pg_cube_distortion.c - texel areas and corner angles of the cube grid on the
 * planet's ellipsoid, for `planetgen grid` and the distortion table.
 *
 * Each texel is the geodesic quadrilateral through its four corner points; its area
 * comes from GeographicLib's PolygonArea and its corner angles from geodesic
 * azimuths (pg_geo.h). Doing that for all 6*N^2 texels would take minutes at
 * N = 2048, so we use the cube's symmetry, which is exact because every projection
 * commutes with the face's symmetries:
 *  - a sphere: all 6 faces are congruent, and each face has the 8 symmetries of the
 *    square (x -> N-1-x, y -> N-1-y, x <-> y), so one eighth of one face suffices;
 *  - an ellipsoid of revolution: +X, -X, +Y, -Y are congruent (90-degree turns
 *    about the polar axis) and each is symmetric under x -> N-1-x and y -> N-1-y
 *    (the meridian plane and the equator), so one quarter of +X suffices; +Z and -Z
 *    are congruent (the equator mirror) and +Z has all 8 square symmetries (the
 *    polar axis is its centre), so one eighth of +Z suffices.
 * Every representative texel is weighted by the size of its orbit so totals stay
 * exact.
 *
 * Texel edges are the images of grid lines. For gnomonic and equi-angular grids
 * those are great circles, so the geodesic quadrilateral is the texel. The
 * equal-area map has a conical point at the face centre, where grid lines become
 * arcs around the centre: a 4-vertex geodesic polygon there is off by ~6% whatever
 * N is. So for equal-area we densify each edge with m points along the grid line,
 * m = 1 + floor(24 / r) for an edge whose midpoint is r texel widths from the face
 * centre (the chord
 * error falls like 1/(m r)^2), which brings every texel within ~0.1% of its true,
 * exactly equal area at the cost of a few extra polygons near the centre. Corner
 * angles are taken between the first sub-segments, i.e. the edge tangents. Partial sums are kept
 * per row and added in row order, so the result does not depend on the number of OpenMP threads. */
#include "pg_cube_internal.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>

typedef struct row_stats {
    double amin, amax, asum, dev;
} row_stats;

/* Orbit size of texel (x, y) under the 4 mirror symmetries, or the 8 with x <-> y. */
static int orbit_size(int64_t n, int64_t x, int64_t y, int eight) {
    int64_t img[8][2];
    int k = 0;
    for (int s = 0; s < (eight ? 8 : 4); s++) {
        int64_t a = (s & 1) ? n - 1 - x : x, b = (s & 2) ? n - 1 - y : y;
        if (s & 4) {
            int64_t t = a;
            a = b, b = t;
        }
        int dup = 0;
        for (int i = 0; i < k; i++)
            dup |= img[i][0] == a && img[i][1] == b;
        if (!dup) img[k][0] = a, img[k][1] = b, k++;
    }
    return k;
}

/* Points per edge when densifying: by the edge midpoint's distance r (in texels)
 * from the face centre, so the two texels sharing an edge densify it identically
 * and the polygons still tile the face exactly. r >= 0.5 for every edge. */
static int edge_points(const pg_cube_grid *g, double mx, double my) {
    double c = (double)g->n / 2, r = hypot(mx - c, my - c);
    int m = 1 + (int)floor(24 / r);
    return m > 48 ? 48 : m;
}

/* One equal-area texel as a densified polygon: area and worst corner deviation. */
static double dense_texel(const pg_cube_grid *g, const pg_ellipsoid *ell, int face, int64_t x,
                          int64_t y, double *dev) {
    double d[3 * 192], lat[192], lon[192], ang[192];                   /* 4 edges x <= 48 points */
    static const int CX[5] = {0, 1, 1, 0, 0}, CY[5] = {0, 0, 1, 1, 0}; /* counter-clockwise */
    int nv = 0, corner[4];
    for (int k = 0; k < 4; k++) {
        double x0 = (double)x + CX[k], y0 = (double)y + CY[k];
        double ex = CX[k + 1] - CX[k], ey = CY[k + 1] - CY[k];
        int m = edge_points(g, x0 + ex / 2, y0 + ey / 2);
        corner[k] = nv;
        for (int i = 0; i < m; i++, nv++) {
            double t = (double)i / m;
            double u = 2 * (x0 + t * ex) / (double)g->n - 1,
                   v = 2 * (y0 + t * ey) / (double)g->n - 1;
            pg_cube_to_dir(g->proj, face, u, v, d + 3 * nv);
        }
    }
    pg_geo_dirs_to_latlon(ell, (size_t)nv, d, lat, lon);
    double a = pg_geo_polygon_area(ell, nv, lat, lon, ang);
    for (int k = 0; k < 4; k++)
        *dev = fmax(*dev, fabs(ang[corner[k]] - 90));
    return a;
}

/* Texels x in [0, xend) of row y (or x in [y, xend) when `eight`). */
static int do_row(const pg_cube_grid *g, const pg_ellipsoid *ell, int face, int64_t y, int eight,
                  row_stats *rs) {
    int64_t n = g->n, h = (n + 1) / 2, xs = eight ? y : 0, cnt = h - xs;
    rs->amin = INFINITY, rs->amax = 0, rs->asum = 0, rs->dev = 0;
    if (cnt <= 0) return 0;
    size_t nc = (size_t)cnt + 1;
    double *d = malloc(nc * 2 * 3 * sizeof *d), *cl = malloc(nc * 4 * sizeof *cl);
    double *q = malloc((size_t)cnt * 18 * sizeof *q);
    if (!d || !cl || !q) {
        free(d), free(cl), free(q);
        return -1;
    }
    for (size_t i = 0; i < nc; i++) {
        pg_cube_corner_dir(g, face, xs + (int64_t)i, y, d + 3 * i);
        pg_cube_corner_dir(g, face, xs + (int64_t)i, y + 1, d + 3 * (nc + i));
    }
    double *clat = cl, *clon = cl + 2 * nc;
    pg_geo_dirs_to_latlon(ell, 2 * nc, d, clat, clon);
    double *qlat = q, *qlon = q + 4 * cnt, *area = q + 8 * cnt, *ang = q + 9 * cnt;
    static const int CORNER[4] = {0, 1, 1, 0}, ROW[4] = {0, 0, 1, 1}; /* counter-clockwise */
    for (int64_t i = 0; i < cnt; i++) {
        for (int k = 0; k < 4; k++) {
            size_t c = (size_t)ROW[k] * nc + (size_t)i + CORNER[k];
            qlat[4 * i + k] = clat[c], qlon[4 * i + k] = clon[c];
        }
    }
    if (g->proj != PG_CUBE_EQUALAREA) pg_geo_polygons(ell, (size_t)cnt, 4, qlat, qlon, area, ang);
    for (int64_t i = 0; i < cnt; i++) {
        double a = area[i];
        if (g->proj == PG_CUBE_EQUALAREA)
            a = dense_texel(g, ell, face, xs + i, y, &rs->dev);
        else
            for (int k = 0; k < 4; k++)
                rs->dev = fmax(rs->dev, fabs(ang[4 * i + k] - 90));
        rs->amin = fmin(rs->amin, a), rs->amax = fmax(rs->amax, a);
        rs->asum += a * orbit_size(n, xs + i, y, eight);
    }
    free(d), free(cl), free(q);
    return 0;
}

/* One face's representative region, rows in parallel, combined in row order. */
static pg_status do_face(const pg_cube_grid *g, const pg_ellipsoid *ell, int face, int eight,
                         row_stats *out, pg_error *err) {
    int64_t h = (g->n + 1) / 2;
    row_stats *rows = malloc((size_t)h * sizeof *rows);
    if (!rows) return pg_error_set(err, PG_ERR_NOMEM, "distortion: out of memory");
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(| : failed)
    for (int64_t y = 0; y < h; y++)
        failed |= do_row(g, ell, face, y, eight, &rows[y]);
    *out = (row_stats){INFINITY, 0, 0, 0};
    for (int64_t y = 0; y < h; y++) {
        out->amin = fmin(out->amin, rows[y].amin), out->amax = fmax(out->amax, rows[y].amax);
        out->asum += rows[y].asum, out->dev = fmax(out->dev, rows[y].dev);
    }
    free(rows);
    if (failed) return pg_error_set(err, PG_ERR_NOMEM, "distortion: out of memory");
    return PG_OK;
}

pg_status pg_cube_distortion_compute(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                     pg_cube_distortion *out, pg_error *err) {
    if (n < 1) return pg_error_set(err, PG_ERR_BADINPUT, "distortion: bad face size");
    pg_cube_grid g;
    pg_cube_grid_init_faces(&g, p, n);
    row_stats polar, side;
    pg_status st = do_face(&g, ell, PG_CUBE_FACE_PZ, 1, &polar, err);
    if (st != PG_OK) return st;
    if (ell->f == 0) {
        side = polar; /* all faces congruent on a sphere */
    } else {
        st = do_face(&g, ell, PG_CUBE_FACE_PX, 0, &side, err);
        if (st != PG_OK) return st;
    }
    out->area_min_m2 = fmin(polar.amin, side.amin);
    out->area_max_m2 = fmax(polar.amax, side.amax);
    out->area_ratio = out->area_max_m2 / out->area_min_m2;
    out->max_angle_dev_deg = fmax(polar.dev, side.dev);
    out->total_area_m2 = 2 * polar.asum + 4 * side.asum;
    out->mean_texel_km = sqrt(out->total_area_m2 / (6.0 * (double)n * (double)n)) / 1000;
    return PG_OK;
}

double pg_cube_spherical_triangle(const double a[3], const double b[3], const double c[3]) {
    double bxc[3];
    pg_vec3_cross(b, c, bxc);
    double num = fabs(pg_vec3_dot(a, bxc));
    double den = 1 + pg_vec3_dot(a, b) + pg_vec3_dot(b, c) + pg_vec3_dot(c, a);
    return 2 * atan2(num, den);
}
