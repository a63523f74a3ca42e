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
    const pg_export_heights *h;
    const pg_cube_grid *g;
    const pg_export_mesh *mesh;
    int64_t n, q; /* texels per face edge, per mesh quad edge */
    double sea;
    /* The vertex heights of the window's face, vertices [i0, i0 + vw) x [j0, j0 + vh), so
     * the texels there do not look up their four vertices in the mesh each (NULL: none). */
    const double *vt;
    int vface, i0, j0, vw, vh;
} nm_ctx;

static double clamped(const nm_ctx *c, int face, int64_t x, int64_t y) {
    double h = pg_export_height_at(c->h, face, x, y);
    return isnan(h) || h > c->sea ? h : c->sea;
}

static double vertex_height(const nm_ctx *c, int face, int i, int j) {
    if (c->vt && face == c->vface && i >= c->i0 && j >= c->j0 && i < c->i0 + c->vw &&
        j < c->j0 + c->vh)
        return c->vt[(size_t)(j - c->j0) * c->vw + (i - c->i0)];
    int64_t r = pg_export_verts_find(&c->mesh->verts, face, i, j);
    return r < 0 ? NAN : c->mesh->verts.vh[r];
}

/* Tabulate the vertex heights of the quads that texels [x0 - 1, x0 + w]^2 of the face
 * fall in (out of memory: no table, and every texel looks them up). */
static void vertex_table(nm_ctx *c, int face, int64_t x0, int64_t y0, int64_t w) {
    const int m = c->mesh->m;
    int64_t lo[2] = {x0 - 1, y0 - 1}, hi[2] = {x0 + w, y0 + w};
    int a[2], b[2];
    for (int k = 0; k < 2; k++) {
        lo[k] = lo[k] < 0 ? 0 : lo[k], hi[k] = hi[k] >= c->n ? c->n - 1 : hi[k];
        a[k] = (int)(lo[k] / c->q), b[k] = (int)(hi[k] / c->q);
        b[k] = (b[k] >= m ? m - 1 : b[k]) + 1; /* the last quad's far vertices */
    }
    c->vw = b[0] - a[0] + 1, c->vh = b[1] - a[1] + 1, c->i0 = a[0], c->j0 = a[1];
    double *t = malloc((size_t)c->vw * c->vh * sizeof *t);
    if (!t) return;
    for (int j = 0; j < c->vh; j++)
        for (int i = 0; i < c->vw; i++)
            t[(size_t)j * c->vw + i] = vertex_height(c, face, c->i0 + i, c->j0 + j);
    c->vface = face, c->vt = t;
}

/* The mesh's interpolated height at texel centre (x, y) of a face. */
static double coarse(const nm_ctx *c, int face, int64_t x, int64_t y) {
    int m = c->mesh->m;
    double fx = (x + 0.5) / (double)c->q, fy = (y + 0.5) / (double)c->q;
    int i = (int)fx, j = (int)fy;
    if (i >= m) i = m - 1;
    if (j >= m) j = m - 1;
    double tx = fx - i, ty = fy - j;
    double h00 = vertex_height(c, face, i, j), h10 = vertex_height(c, face, i + 1, j);
    double h01 = vertex_height(c, face, i, j + 1), h11 = vertex_height(c, face, i + 1, j + 1);
    return (1 - ty) * ((1 - tx) * h00 + tx * h10) + ty * ((1 - tx) * h01 + tx * h11);
}

static double detail(const nm_ctx *c, int face, int64_t x, int64_t y) {
    return clamped(c, face, x, y) - coarse(c, face, x, y);
}

/* Detail height at (x, y), which may lie one texel outside the window [x0, x0 + w)^2:
 * inside the face from d (the window and its one-texel ring, stored as floats),
 * across a face edge from the neighbouring face. */
static double detail_wrapped(const nm_ctx *c, int face, int64_t x, int64_t y, const float *d,
                             int64_t x0, int64_t y0, int64_t w) {
    int64_t n = c->n;
    if (x >= 0 && y >= 0 && x < n && y < n) return d[(y - y0 + 1) * (w + 2) + (x - x0 + 1)];
    int rot;
    int64_t id = pg_cube_wrap(c->g, face, x, y, &rot);
    int64_t nn = n * n, t = id % nn;
    return detail(c, (int)(id / nn), t % n, t / n);
}

/* Metres per texel along u and v at the centres of a SPACING_GRID^2 grid over the face. */
static void spacing_table(const pg_planet *p, int face, int64_t x0, int64_t y0, int64_t w,
                          double *su, double *sv) {
    const double del = 1e-3, texel = 2.0 / (double)p->n;
    /* only the cells the window [x0, x0 + w)^2 uses: a tile needs few of them */
    const int64_t n = p->n;
    for (int b = (int)(y0 * SPACING_GRID / n); b <= (int)((y0 + w - 1) * SPACING_GRID / n); b++)
        for (int a = (int)(x0 * SPACING_GRID / n); a <= (int)((x0 + w - 1) * SPACING_GRID / n);
             a++) {
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

pg_status pg_export_normal_map(const pg_export_heights *h, const pg_cube_grid *g,
                               const pg_export_mesh *mesh, double exaggeration, int face,
                               int64_t x0, int64_t y0, int64_t w, float *rgb, pg_error *err) {
    const pg_planet *p = h->p;
    int64_t n = p->n, dw = w + 2;
    nm_ctx c = {h, g, mesh, n, n / mesh->m, p->sea_level, NULL, 0, 0, 0, 0, 0};
    vertex_table(&c, face, x0, y0, w);
    float *d = malloc((size_t)dw * dw * sizeof(float));
    if (!d) {
        free((void *)c.vt);
        return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate the normal map of face %s",
                            pg_cube_face_name(face));
    }
    double su[SPACING_GRID * SPACING_GRID], sv[SPACING_GRID * SPACING_GRID];
    spacing_table(p, face, x0, y0, w, su, sv);
    /* the window and its ring inside the face, but for the ring's corners (never read) */
#pragma omp parallel for schedule(static)
    for (int64_t y = y0 - 1; y <= y0 + w; y++)
        for (int64_t x = x0 - 1; x <= x0 + w; x++) {
            bool corner = (x < x0 || x >= x0 + w) && (y < y0 || y >= y0 + w);
            if (x < 0 || y < 0 || x >= n || y >= n || corner) continue;
            d[(y - y0 + 1) * dw + (x - x0 + 1)] = (float)detail(&c, face, x, y);
        }
    bool ok = true;
#pragma omp parallel for schedule(static) reduction(&& : ok)
    for (int64_t y = y0; y < y0 + w; y++)
        for (int64_t x = x0; x < x0 + w; x++) {
            int64_t cell = (y * SPACING_GRID / n) * SPACING_GRID + x * SPACING_GRID / n;
            double gx = (detail_wrapped(&c, face, x + 1, y, d, x0, y0, w) -
                         detail_wrapped(&c, face, x - 1, y, d, x0, y0, w)) /
                        (2 * su[cell]);
            double gy = (detail_wrapped(&c, face, x, y + 1, d, x0, y0, w) -
                         detail_wrapped(&c, face, x, y - 1, d, x0, y0, w)) /
                        (2 * sv[cell]);
            double nx = -exaggeration * gx, ny = -exaggeration * gy;
            double l = sqrt(nx * nx + ny * ny + 1);
            float *o = rgb + 3 * ((y - y0) * w + (x - x0));
            o[0] = (float)(0.5 + 0.5 * nx / l);
            o[1] = (float)(0.5 + 0.5 * ny / l);
            o[2] = (float)(0.5 + 0.5 / l);
            ok = ok && isfinite(l);
        }
    free(d);
    free((void *)c.vt);
    if (!ok)
        return pg_error_set(err, PG_ERR_RUNTIME,
                            "normal map of face %s: heights around the window are missing",
                            pg_cube_face_name(face));
    return PG_OK;
}
