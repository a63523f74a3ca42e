/* pg_export_normalmap.c - tangent-space normal maps of the cube faces, made from the
 * height field so the globe shows relief finer than its mesh.
 *
 * The idea: the mesh already carries the relief at its own resolution (heights at
 * its vertices, interpolated in between), and its normals tilt with it. A normal
 * map that encoded the full slope would count that coarse slope twice. So each
 * texel's normal is taken from the detail height: the (sea-level-clamped) height
 * minus the mesh's bilinear interpolation at that texel. Its gradient, in metres per
 * metre along the face's u and v (times the exaggeration), gives the tangent-space
 * normal (-dx, -dy, 1), x along +u (the mesh tangent) and y along +v (the
 * bitangent, the texture's up). Texel spacing in metres comes from the projection on
 * the ellipsoid, tabulated on a coarse grid because it varies slowly. Differences at
 * face borders take the neighbour texel across the seam (pg_cube_wrap), with that
 * face's own coarse surface, so the maps agree along seams. */
#include "pg_export_internal.h"

#include <math.h>
#include <stdlib.h>

#define SPACING_GRID 64

typedef struct nm_ctx {
    const pg_planet *p;
    const pg_cube_grid *g;
    const pg_export_mesh *mesh;
    int64_t q; /* texels per mesh quad edge */
} nm_ctx;

static double clamped(const nm_ctx *c, int face, int64_t x, int64_t y) {
    double h = c->p->height[face][y * c->p->n + x];
    return h > c->p->sea_level ? h : c->p->sea_level;
}

/* The mesh's interpolated height at texel centre (x, y) of a face. */
static double coarse(const nm_ctx *c, int face, int64_t x, int64_t y) {
    const pg_export_mesh *mh = c->mesh;
    int w = mh->m + 1;
    double fx = (x + 0.5) / (double)c->q, fy = (y + 0.5) / (double)c->q;
    int i = (int)fx, j = (int)fy;
    if (i >= mh->m) i = mh->m - 1;
    if (j >= mh->m) j = mh->m - 1;
    double tx = fx - i, ty = fy - j;
    const uint32_t *cn = mh->canon + (size_t)face * mh->nv;
    const double *vh = mh->vheight;
    double h00 = vh[cn[j * w + i]], h10 = vh[cn[j * w + i + 1]];
    double h01 = vh[cn[(j + 1) * w + i]], h11 = vh[cn[(j + 1) * w + i + 1]];
    return (1 - ty) * ((1 - tx) * h00 + tx * h10) + ty * ((1 - tx) * h01 + tx * h11);
}

static double detail(const nm_ctx *c, int face, int64_t x, int64_t y) {
    return clamped(c, face, x, y) - coarse(c, face, x, y);
}

/* Detail height at (x, y), which may lie one texel outside the face. */
static double detail_wrapped(const nm_ctx *c, int face, int64_t x, int64_t y, const float *d) {
    int64_t n = c->p->n;
    if (x >= 0 && y >= 0 && x < n && y < n) return d[y * n + x];
    int rot;
    int64_t id = pg_cube_wrap(c->g, face, x, y, &rot);
    int64_t nn = n * n, t = id % nn;
    return detail(c, (int)(id / nn), t % n, t / n);
}

/* Metres per texel along u and v at the centres of a SPACING_GRID^2 grid. */
static void spacing_table(const pg_planet *p, int face, double *su, double *sv) {
    const double del = 1e-3, texel = 2.0 / (double)p->n;
    for (int b = 0; b < SPACING_GRID; b++)
        for (int a = 0; a < SPACING_GRID; a++) {
            double u = (2.0 * a + 1) / SPACING_GRID - 1, v = (2.0 * b + 1) / SPACING_GRID - 1;
            double pts[4][3], dir[3];
            const double off[4][2] = {{del, 0}, {-del, 0}, {0, del}, {0, -del}};
            for (int k = 0; k < 4; k++) {
                pg_cube_to_dir(p->projection, face, u + off[k][0], v + off[k][1], dir);
                pg_geo_dir_to_ecef(&p->ellipsoid, dir, 0, pts[k]);
            }
            double du = 0, dv = 0;
            for (int k = 0; k < 3; k++) {
                du += (pts[0][k] - pts[1][k]) * (pts[0][k] - pts[1][k]);
                dv += (pts[2][k] - pts[3][k]) * (pts[2][k] - pts[3][k]);
            }
            su[b * SPACING_GRID + a] = sqrt(du) / (2 * del) * texel;
            sv[b * SPACING_GRID + a] = sqrt(dv) / (2 * del) * texel;
        }
}

pg_status pg_export_normal_map(const pg_planet *p, const pg_cube_grid *g,
                               const pg_export_mesh *mesh, double exaggeration, int face,
                               float *rgb, pg_error *err) {
    int64_t n = p->n;
    nm_ctx c = {p, g, mesh, n / mesh->m};
    float *d = malloc((size_t)n * n * sizeof(float));
    if (!d)
        return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate the normal map of face %s",
                            pg_cube_face_name(face));
    double su[SPACING_GRID * SPACING_GRID], sv[SPACING_GRID * SPACING_GRID];
    spacing_table(p, face, su, sv);
#pragma omp parallel for schedule(static)
    for (int64_t y = 0; y < n; y++)
        for (int64_t x = 0; x < n; x++)
            d[y * n + x] = (float)detail(&c, face, x, y);
#pragma omp parallel for schedule(static)
    for (int64_t y = 0; y < n; y++)
        for (int64_t x = 0; x < n; x++) {
            int64_t cell = (y * SPACING_GRID / n) * SPACING_GRID + x * SPACING_GRID / n;
            double gx =
                (detail_wrapped(&c, face, x + 1, y, d) - detail_wrapped(&c, face, x - 1, y, d)) /
                (2 * su[cell]);
            double gy =
                (detail_wrapped(&c, face, x, y + 1, d) - detail_wrapped(&c, face, x, y - 1, d)) /
                (2 * sv[cell]);
            double nx = -exaggeration * gx, ny = -exaggeration * gy;
            double l = sqrt(nx * nx + ny * ny + 1);
            float *o = rgb + 3 * (y * n + x);
            o[0] = (float)(0.5 + 0.5 * nx / l);
            o[1] = (float)(0.5 + 0.5 * ny / l);
            o[2] = (float)(0.5 + 0.5 / l);
        }
    free(d);
    return PG_OK;
}
