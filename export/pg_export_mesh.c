/* pg_export_mesh.c - the subdivided-cube globe mesh: vertices on the planet's
 * ellipsoid raised by the exaggerated height, normals of the displaced surface,
 * tangents along the face texture's u.
 *
 * Watertightness by construction: a vertex on a seam is the same cube point seen
 * from two (or, at a cube corner, three) faces. Its integer lattice point
 * L = m n + (2i - m) e_u + (2j - m) e_v is identical from every face, so it names a
 * canonical face (the lowest id whose normal component of L is m) and the vertex's
 * (i, j) there. Height, direction and position are computed only from that
 * canonical (face, i, j), once, and every face copies the result: coincident seam
 * vertices are bit-identical and the gap is exactly 0. Normals are accumulated per
 * canonical slot from the triangles of all faces around it (area-weighted), so they
 * agree across seams too and the shading shows no crease. */
#include "pg_export_internal.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pg_export_mesh_canonical(int m, int face, int i, int j, int *cface, int *ci, int *cj) {
    int n[3], eu[3], ev[3], L[3];
    pg_cube_face_frame(face, n, eu, ev);
    for (int c = 0; c < 3; c++)
        L[c] = m * n[c] + (2 * i - m) * eu[c] + (2 * j - m) * ev[c];
    for (int g = 0; g < PG_CUBE_NFACES; g++) {
        pg_cube_face_frame(g, n, eu, ev);
        if (L[0] * n[0] + L[1] * n[1] + L[2] * n[2] != m) continue;
        /* components of L along e_u, e_v all have m's parity, so these are exact */
        *cface = g;
        *ci = (L[0] * eu[0] + L[1] * eu[1] + L[2] * eu[2] + m) / 2;
        *cj = (L[0] * ev[0] + L[1] * ev[1] + L[2] * ev[2] + m) / 2;
        return;
    }
    *cface = face, *ci = i, *cj = j; /* unreachable: face itself always qualifies */
}

/* Height at texel corner (cx, cy) of a face: the mean of the distinct texels around
 * it (4, or 3 at a cube corner), each raised to sea level. */
static double corner_height(const pg_planet *p, const pg_cube_grid *g, int face, int64_t cx,
                            int64_t cy) {
    int64_t ids[4];
    int nid = 0;
    for (int dy = -1; dy <= 0; dy++)
        for (int dx = -1; dx <= 0; dx++) {
            int rot;
            int64_t id = pg_cube_wrap(g, face, cx + dx, cy + dy, &rot);
            bool dup = false;
            for (int k = 0; k < nid; k++)
                dup = dup || ids[k] == id;
            if (!dup) ids[nid++] = id;
        }
    int64_t nn = p->n * p->n;
    double s = 0;
    for (int k = 0; k < nid; k++) {
        double h = p->height[ids[k] / nn][ids[k] % nn];
        s += h > p->sea_level ? h : p->sea_level;
    }
    return s / nid;
}

static pg_status alloc_mesh(pg_export_mesh *mesh, int m, pg_error *err) {
    memset(mesh, 0, sizeof *mesh);
    mesh->m = m;
    mesh->nv = (uint32_t)(m + 1) * (uint32_t)(m + 1);
    mesh->ni = 6u * (uint32_t)m * (uint32_t)m;
    size_t nv = mesh->nv;
    mesh->canon = malloc(6 * nv * sizeof *mesh->canon);
    mesh->vheight = malloc(6 * nv * sizeof *mesh->vheight);
    mesh->uv = malloc(nv * 2 * sizeof(float));
    mesh->idx = malloc(mesh->ni * sizeof(uint32_t));
    bool ok = mesh->canon && mesh->vheight && mesh->uv && mesh->idx;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        mesh->pos[f] = malloc(nv * 3 * sizeof(float));
        mesh->nrm[f] = malloc(nv * 3 * sizeof(float));
        mesh->tan[f] = malloc(nv * 4 * sizeof(float));
        ok = ok && mesh->pos[f] && mesh->nrm[f] && mesh->tan[f];
    }
    if (ok) return PG_OK;
    pg_export_mesh_free(mesh);
    return pg_error_set(err, PG_ERR_NOMEM, "--mesh-res %d: cannot allocate the mesh", m);
}

void pg_export_mesh_free(pg_export_mesh *mesh) {
    free(mesh->canon);
    free(mesh->vheight);
    free(mesh->uv);
    free(mesh->idx);
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        free(mesh->pos[f]);
        free(mesh->nrm[f]);
        free(mesh->tan[f]);
    }
    memset(mesh, 0, sizeof *mesh);
}

static void fill_topology(pg_export_mesh *mesh) {
    int m = mesh->m, w = m + 1;
    for (int j = 0; j <= m; j++)
        for (int i = 0; i <= m; i++) {
            mesh->uv[2 * (j * w + i)] = (float)i / (float)m;
            mesh->uv[2 * (j * w + i) + 1] = 1.0f - (float)j / (float)m; /* glTF: V down */
        }
    uint32_t *t = mesh->idx;
    for (int j = 0; j < m; j++)
        for (int i = 0; i < m; i++) {
            uint32_t a = (uint32_t)(j * w + i), b = a + 1, c = a + 1 + (uint32_t)w,
                     d = a + (uint32_t)w;
            /* (u, v) is right-handed seen from outside: a b c is counter-clockwise */
            *t++ = a, *t++ = b, *t++ = c;
            *t++ = a, *t++ = c, *t++ = d;
        }
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int j = 0; j <= m; j++)
            for (int i = 0; i <= m; i++) {
                int cf, ci, cj;
                pg_export_mesh_canonical(m, f, i, j, &cf, &ci, &cj);
                mesh->canon[(size_t)f * mesh->nv + (size_t)j * w + i] =
                    (uint32_t)((size_t)cf * mesh->nv + (size_t)cj * w + ci);
            }
}

/* Positions of the canonical slots (other slots untouched). */
static void place_vertices(const pg_planet *p, const pg_cube_grid *g, const pg_export_mesh *mesh,
                           double exaggeration, double *cpos) {
    int m = mesh->m, w = m + 1;
    int64_t q = p->n / m;
    int64_t total = 6 * (int64_t)mesh->nv;
#pragma omp parallel for schedule(static)
    for (int64_t s = 0; s < total; s++) {
        if (mesh->canon[s] != (uint32_t)s) continue;
        int f = (int)(s / mesh->nv), j = (int)(s % mesh->nv) / w, i = (int)(s % mesh->nv) % w;
        double h = corner_height(p, g, f, (int64_t)i * q, (int64_t)j * q), dir[3];
        mesh->vheight[s] = h;
        pg_cube_to_dir(p->projection, f, (double)(2 * i - m) / m, (double)(2 * j - m) / m, dir);
        pg_geo_dir_to_ecef(&p->ellipsoid, dir, h * exaggeration, cpos + 3 * s);
    }
}

/* Area-weighted triangle normals summed into canonical slots, in a fixed order. */
static void accumulate_normals(const pg_export_mesh *mesh, const double *cpos, double *cnrm) {
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        const uint32_t *canon = mesh->canon + (size_t)f * mesh->nv;
        for (uint32_t t = 0; t < mesh->ni; t += 3) {
            uint32_t k[3] = {canon[mesh->idx[t]], canon[mesh->idx[t + 1]], canon[mesh->idx[t + 2]]};
            double e1[3], e2[3], nt[3];
            pg_vec3_sub(cpos + 3 * k[1], cpos + 3 * k[0], e1);
            pg_vec3_sub(cpos + 3 * k[2], cpos + 3 * k[0], e2);
            pg_vec3_cross(e1, e2, nt);
            for (int v = 0; v < 3; v++)
                for (int c = 0; c < 3; c++)
                    cnrm[3 * k[v] + c] += nt[c];
        }
    }
}

/* Tangent: the face's +u direction along the surface, orthogonal to the normal;
 * w = +1 when normal x tangent points along +v (the texture's up). */
static void tangent_at(const pg_export_mesh *mesh, const double *cpos, int f, int i, int j,
                       const double nrm[3], float out[4]) {
    int m = mesh->m, w = m + 1;
    const uint32_t *canon = mesh->canon + (size_t)f * mesh->nv;
    int i0 = i > 0 ? i - 1 : i, i1 = i < m ? i + 1 : i;
    int j0 = j > 0 ? j - 1 : j, j1 = j < m ? j + 1 : j;
    const double *a = cpos + 3 * canon[j * w + i0], *b = cpos + 3 * canon[j * w + i1];
    const double *c = cpos + 3 * canon[j0 * w + i], *d = cpos + 3 * canon[j1 * w + i];
    double t[3], bt[3];
    pg_vec3_sub(b, a, t);
    pg_vec3_sub(d, c, bt);
    double dn = pg_vec3_dot(t, nrm);
    for (int k = 0; k < 3; k++)
        t[k] -= dn * nrm[k];
    pg_vec3_normalize(t);
    double nxt[3];
    pg_vec3_cross(nrm, t, nxt);
    double s = pg_vec3_dot(nxt, bt);
    for (int k = 0; k < 3; k++)
        out[k] = (float)t[k];
    out[3] = s >= 0 ? 1.0f : -1.0f;
}

static void emit_faces(pg_export_mesh *mesh, const double *cpos, double *cnrm) {
    int m = mesh->m, w = m + 1;
    int64_t total = 6 * (int64_t)mesh->nv;
#pragma omp parallel for schedule(static)
    for (int64_t s = 0; s < total; s++)
        if (mesh->canon[s] == (uint32_t)s) pg_vec3_normalize(cnrm + 3 * s);
#pragma omp parallel for schedule(static)
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int j = 0; j <= m; j++)
            for (int i = 0; i <= m; i++) {
                size_t v = (size_t)j * w + i;
                uint32_t k = mesh->canon[(size_t)f * mesh->nv + v];
                for (int c = 0; c < 3; c++) {
                    mesh->pos[f][3 * v + c] = (float)cpos[3 * k + c];
                    mesh->nrm[f][3 * v + c] = (float)cnrm[3 * k + c];
                }
                tangent_at(mesh, cpos, f, i, j, cnrm + 3 * k, mesh->tan[f] + 4 * v);
            }
}

pg_status pg_export_mesh_build(const pg_planet *p, const pg_cube_grid *g, int m,
                               double exaggeration, pg_export_mesh *mesh, pg_error *err) {
    pg_status st = alloc_mesh(mesh, m, err);
    if (st != PG_OK) return st;
    size_t slots = 6 * (size_t)mesh->nv;
    double *cpos = calloc(slots * 3, sizeof(double));
    double *cnrm = calloc(slots * 3, sizeof(double));
    if (!cpos || !cnrm) {
        free(cpos);
        free(cnrm);
        pg_export_mesh_free(mesh);
        return pg_error_set(err, PG_ERR_NOMEM, "--mesh-res %d: cannot allocate the mesh", m);
    }
    fill_topology(mesh);
    place_vertices(p, g, mesh, exaggeration, cpos);
    accumulate_normals(mesh, cpos, cnrm);
    emit_faces(mesh, cpos, cnrm);
    free(cpos);
    free(cnrm);
    return PG_OK;
}
