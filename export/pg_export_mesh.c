/* pg_export_mesh.c - the subdivided-cube globe mesh, whole or one tile at a time:
 * vertices on the planet's ellipsoid raised by the exaggerated height, normals of the
 * displaced surface, tangents along the face texture's u.
 *
 * Watertightness by construction: a vertex on a seam is the same cube point seen
 * from two (or, at a cube corner, three) faces. Its integer lattice point
 * L = m n + (2i - m) e_u + (2j - m) e_v is identical from every face, so it names a
 * canonical face (the lowest id whose normal component of L is m) and the vertex's
 * (i, j) there. Height, direction and position are computed only from that
 * canonical (face, i, j), and every face copies the result: coincident seam vertices
 * are bit-identical and the gap is exactly 0. A vertex's normal is the area-weighted
 * sum of the triangles around it in every face that holds it, gathered in one fixed
 * order (face, quad row, quad, triangle), so it agrees across seams too.
 *
 * The same functions build the globe (every slot, in a dense table) and a tile (the
 * slots of its vertices and of the ring of quads around them, in a small hash table,
 * heights from the tile and the texels around it): a tile's vertices, normals and
 * tangents are the globe's, bit for bit, and the tiles of a planet join without
 * cracks whichever process wrote each. */
#include "pg_export_internal.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void pg_export_heights_whole(const pg_planet *p, pg_export_heights *h) {
    memset(h, 0, sizeof *h);
    h->p = p;
    h->first = 0;
    h->last = 6 * (int64_t)p->tiles * p->tiles;
}

double pg_export_height_at(const pg_export_heights *h, int face, int64_t x, int64_t y) {
    const pg_planet *p = h->p;
    const int64_t S = p->tile_size, T = p->tiles;
    const int64_t t = ((int64_t)face * T + y / S) * T + x / S;
    if (t >= h->first && t < h->last) return p->height[face][y * p->n + x];
    for (int k = 0; k < h->nstrips; k++) {
        const pg_export_strip *s = &h->strips[k];
        if (s->tile == t && x >= s->x0 && y >= s->y0 && x < s->x0 + s->w && y < s->y0 + s->h)
            return s->data[(y - s->y0) * s->w + (x - s->x0)];
    }
    return NAN;
}

/* max(h, sea level), keeping a NaN (a texel not held) a NaN. */
static double above_sea(double h, double sea) {
    return isnan(h) || h > sea ? h : sea;
}

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

/* ---- the vertex store ---- */

static int64_t slot_key(const pg_export_verts *v, int f, int i, int j) {
    return (int64_t)f * v->nv + (int64_t)j * (v->m + 1) + i;
}

static size_t hash_of(int64_t key, size_t cap) {
    uint64_t x = (uint64_t)key * UINT64_C(0x9E3779B97F4A7C15);
    return (size_t)(x >> 17) & (cap - 1);
}

int64_t pg_export_verts_find(const pg_export_verts *v, int f, int i, int j) {
    if (v->canon) return v->canon[slot_key(v, f, i, j)];
    int cf, ci, cj;
    pg_export_mesh_canonical(v->m, f, i, j, &cf, &ci, &cj);
    int64_t key = slot_key(v, cf, ci, cj);
    for (size_t k = hash_of(key, v->cap);; k = (k + 1) & (v->cap - 1)) {
        if (v->keys[k] == key) return v->index[k];
        if (v->keys[k] < 0) return -1;
    }
}

/* Add the canonical slot of (f, i, j) to a hashed store (no-op if present); its row, or
 * -1 when the store is full. */
static int64_t verts_insert(pg_export_verts *v, int f, int i, int j, int64_t *rowkey) {
    int cf, ci, cj;
    pg_export_mesh_canonical(v->m, f, i, j, &cf, &ci, &cj);
    int64_t key = slot_key(v, cf, ci, cj);
    size_t k = hash_of(key, v->cap);
    for (; v->keys[k] >= 0; k = (k + 1) & (v->cap - 1))
        if (v->keys[k] == key) return v->index[k];
    if (2 * (v->n + 1) > v->cap) return -1;
    v->keys[k] = key;
    v->index[k] = (uint32_t)v->n;
    rowkey[v->n] = key;
    return (int64_t)v->n++;
}

static void verts_free(pg_export_verts *v) {
    free(v->keys);
    free(v->index);
    free(v->pos);
    free(v->nrm);
    free(v->vh);
}

/* ---- the functions of a canonical slot ---- */

/* Height at texel corner (cx, cy) of a face: the mean of the distinct texels around
 * it (4, or 3 at a cube corner), each raised to sea level. */
static double corner_height(const pg_export_heights *hs, const pg_cube_grid *g, int face,
                            int64_t cx, int64_t cy) {
    const pg_planet *p = hs->p;
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
        int64_t r = ids[k] % nn;
        s += above_sea(pg_export_height_at(hs, (int)(ids[k] / nn), r % p->n, r / p->n),
                       p->sea_level);
    }
    return s / nid;
}

/* Position and height of the vertex whose canonical slot is key. */
static void place_slot(const pg_export_heights *hs, const pg_cube_grid *g, const pg_export_verts *v,
                       double exaggeration, int64_t key, size_t row) {
    const pg_planet *p = hs->p;
    int m = v->m, w = m + 1;
    int f = (int)(key / v->nv), j = (int)(key % v->nv) / w, i = (int)(key % v->nv) % w;
    int64_t q = p->n / m;
    double h = corner_height(hs, g, f, (int64_t)i * q, (int64_t)j * q), dir[3];
    v->vh[row] = h;
    pg_cube_to_dir(p->projection, f, (double)(2 * i - m) / m, (double)(2 * j - m) / m, dir);
    pg_geo_dir_to_ecef(&p->ellipsoid, dir, h * exaggeration, v->pos + 3 * row);
}

/* Unit normal at vertex (f, i, j): the area-weighted normals of the triangles around
 * it in every face that holds it, summed in face, quad row, quad, triangle order.
 * false when a position is missing from the store. */
static bool vertex_normal(const pg_export_verts *v, int f, int i, int j, double out[3]) {
    int m = v->m, n[3], eu[3], ev[3], L[3];
    pg_cube_face_frame(f, n, eu, ev);
    for (int c = 0; c < 3; c++)
        L[c] = m * n[c] + (2 * i - m) * eu[c] + (2 * j - m) * ev[c];
    out[0] = out[1] = out[2] = 0;
    for (int g = 0; g < PG_CUBE_NFACES; g++) {
        pg_cube_face_frame(g, n, eu, ev);
        if (L[0] * n[0] + L[1] * n[1] + L[2] * n[2] != m) continue;
        int gi = (L[0] * eu[0] + L[1] * eu[1] + L[2] * eu[2] + m) / 2;
        int gj = (L[0] * ev[0] + L[1] * ev[1] + L[2] * ev[2] + m) / 2;
        for (int qj = gj - 1; qj <= gj; qj++)
            for (int qi = gi - 1; qi <= gi; qi++) {
                if (qi < 0 || qj < 0 || qi >= m || qj >= m) continue;
                /* the quad's corners a b c d and its triangles a b c, a c d */
                const int ci[4] = {qi, qi + 1, qi + 1, qi}, cj[4] = {qj, qj, qj + 1, qj + 1};
                const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
                for (int t = 0; t < 2; t++) {
                    bool has = false;
                    for (int k = 0; k < 3; k++)
                        has = has || (ci[tri[t][k]] == gi && cj[tri[t][k]] == gj);
                    if (!has) continue;
                    const double *pk[3];
                    for (int k = 0; k < 3; k++) {
                        int64_t r = pg_export_verts_find(v, g, ci[tri[t][k]], cj[tri[t][k]]);
                        if (r < 0) return false;
                        pk[k] = v->pos + 3 * r;
                    }
                    double e1[3], e2[3], nt[3];
                    pg_vec3_sub(pk[1], pk[0], e1);
                    pg_vec3_sub(pk[2], pk[0], e2);
                    pg_vec3_cross(e1, e2, nt);
                    for (int c = 0; c < 3; c++)
                        out[c] += nt[c];
                }
            }
    }
    pg_vec3_normalize(out);
    return true;
}

/* Tangent at vertex (f, i, j): the face's +u direction along the surface, orthogonal to
 * the normal; w = +1 when normal x tangent points along +v (the texture's up). */
static bool tangent_at(const pg_export_verts *v, int f, int i, int j, const double nrm[3],
                       float out[4]) {
    int m = v->m;
    int i0 = i > 0 ? i - 1 : i, i1 = i < m ? i + 1 : i;
    int j0 = j > 0 ? j - 1 : j, j1 = j < m ? j + 1 : j;
    int64_t ra = pg_export_verts_find(v, f, i0, j), rb = pg_export_verts_find(v, f, i1, j);
    int64_t rc = pg_export_verts_find(v, f, i, j0), rd = pg_export_verts_find(v, f, i, j1);
    if (ra < 0 || rb < 0 || rc < 0 || rd < 0) return false;
    const double *a = v->pos + 3 * ra, *b = v->pos + 3 * rb;
    const double *c = v->pos + 3 * rc, *d = v->pos + 3 * rd;
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
    return true;
}

/* ---- the mesh ---- */

static pg_status alloc_mesh(pg_export_mesh *mesh, int m, int nprims, int mt, pg_error *err) {
    memset(mesh, 0, sizeof *mesh);
    mesh->m = m;
    mesh->nprims = nprims;
    mesh->mt = mt;
    mesh->nv = (uint32_t)(mt + 1) * (uint32_t)(mt + 1);
    mesh->ni = 6u * (uint32_t)mt * (uint32_t)mt;
    mesh->verts.m = m;
    mesh->verts.nv = (uint32_t)(m + 1) * (uint32_t)(m + 1);
    size_t nv = mesh->nv;
    mesh->uv = malloc(nv * 2 * sizeof(float));
    mesh->idx = malloc(mesh->ni * sizeof(uint32_t));
    bool ok = mesh->uv && mesh->idx;
    for (int f = 0; f < nprims; f++) {
        mesh->pos[f] = malloc(nv * 3 * sizeof(float));
        mesh->nrm[f] = malloc(nv * 3 * sizeof(float));
        mesh->tan[f] = malloc(nv * 4 * sizeof(float));
        ok = ok && mesh->pos[f] && mesh->nrm[f] && mesh->tan[f];
    }
    if (ok) return PG_OK;
    pg_export_mesh_free(mesh);
    return pg_error_set(err, PG_ERR_NOMEM, "--mesh-res %d: cannot allocate the mesh", m);
}

static pg_status alloc_rows(pg_export_verts *v, size_t rows, int m, pg_error *err) {
    v->pos = malloc(rows * 3 * sizeof(double));
    v->nrm = malloc(rows * 3 * sizeof(double));
    v->vh = malloc(rows * sizeof(double));
    if (v->pos && v->nrm && v->vh) return PG_OK;
    return pg_error_set(err, PG_ERR_NOMEM, "--mesh-res %d: cannot allocate the mesh", m);
}

void pg_export_mesh_free(pg_export_mesh *mesh) {
    free(mesh->canon);
    verts_free(&mesh->verts);
    free(mesh->uv);
    free(mesh->idx);
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        free(mesh->pos[f]);
        free(mesh->nrm[f]);
        free(mesh->tan[f]);
    }
    memset(mesh, 0, sizeof *mesh);
}

/* Texture coordinates and triangles of an mt x mt grid, shared by the primitives. */
static void fill_topology(pg_export_mesh *mesh) {
    int mt = mesh->mt, w = mt + 1;
    for (int j = 0; j <= mt; j++)
        for (int i = 0; i <= mt; i++) {
            mesh->uv[2 * (j * w + i)] = (float)i / (float)mt;
            mesh->uv[2 * (j * w + i) + 1] = 1.0f - (float)j / (float)mt; /* glTF: V down */
        }
    uint32_t *t = mesh->idx;
    for (int j = 0; j < mt; j++)
        for (int i = 0; i < mt; i++) {
            uint32_t a = (uint32_t)(j * w + i), b = a + 1, c = a + 1 + (uint32_t)w,
                     d = a + (uint32_t)w;
            /* (u, v) is right-handed seen from outside: a b c is counter-clockwise */
            *t++ = a, *t++ = b, *t++ = c;
            *t++ = a, *t++ = c, *t++ = d;
        }
}

/* The primitives' vertex arrays from the store: position, normal, tangent. */
static bool emit(pg_export_mesh *mesh) {
    const pg_export_verts *v = &mesh->verts;
    int mt = mesh->mt, w = mt + 1;
    bool ok = true;
#pragma omp parallel for schedule(static) reduction(&& : ok)
    for (int k = 0; k < mesh->nprims; k++) {
        int f = mesh->nprims == 1 ? mesh->face : k;
        for (int j = 0; j <= mt; j++)
            for (int i = 0; i <= mt; i++) {
                size_t o = (size_t)j * w + i;
                int fi = mesh->i0 + i, fj = mesh->j0 + j;
                int64_t r = pg_export_verts_find(v, f, fi, fj);
                if (r < 0) {
                    ok = false;
                    continue;
                }
                for (int c = 0; c < 3; c++) {
                    mesh->pos[k][3 * o + c] = (float)v->pos[3 * r + c];
                    mesh->nrm[k][3 * o + c] = (float)v->nrm[3 * r + c];
                }
                ok = tangent_at(v, f, fi, fj, v->nrm + 3 * r, mesh->tan[k] + 4 * o) && ok;
            }
    }
    return ok;
}

pg_status pg_export_mesh_build(const pg_planet *p, const pg_cube_grid *g, int m,
                               double exaggeration, pg_export_mesh *mesh, pg_error *err) {
    pg_status st = alloc_mesh(mesh, m, PG_CUBE_NFACES, m, err);
    if (st != PG_OK) return st;
    pg_export_verts *v = &mesh->verts;
    size_t slots = 6 * (size_t)v->nv;
    mesh->canon = malloc(slots * sizeof *mesh->canon);
    st = mesh->canon ? alloc_rows(v, slots, m, err)
                     : pg_error_set(err, PG_ERR_NOMEM, "--mesh-res %d: cannot allocate", m);
    if (st != PG_OK) {
        pg_export_mesh_free(mesh);
        return st;
    }
    v->canon = mesh->canon;
    v->n = slots;
    fill_topology(mesh);
    int w = m + 1;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int j = 0; j <= m; j++)
            for (int i = 0; i <= m; i++) {
                int cf, ci, cj;
                pg_export_mesh_canonical(m, f, i, j, &cf, &ci, &cj);
                mesh->canon[(size_t)f * v->nv + (size_t)j * w + i] =
                    (uint32_t)((size_t)cf * v->nv + (size_t)cj * w + ci);
            }
    pg_export_heights hs;
    pg_export_heights_whole(p, &hs);
    int64_t total = (int64_t)slots;
#pragma omp parallel for schedule(static)
    for (int64_t s = 0; s < total; s++)
        if (mesh->canon[s] == (uint32_t)s) place_slot(&hs, g, v, exaggeration, s, (size_t)s);
#pragma omp parallel for schedule(static)
    for (int64_t s = 0; s < total; s++)
        if (mesh->canon[s] == (uint32_t)s) {
            int f = (int)(s / v->nv), j = (int)(s % v->nv) / w, i = (int)(s % v->nv) % w;
            vertex_normal(v, f, i, j, v->nrm + 3 * s);
        }
    emit(mesh);
    return PG_OK;
}

pg_status pg_export_mesh_build_tile(const pg_export_heights *h, const pg_cube_grid *g, int m,
                                    double exaggeration, int64_t t, pg_export_mesh *mesh,
                                    pg_error *err) {
    const int T = h->p->tiles, mt = m / T;
    pg_status st = alloc_mesh(mesh, m, 1, mt, err);
    if (st != PG_OK) return st;
    mesh->face = (int)(t / ((int64_t)T * T));
    mesh->i0 = (int)(t % T) * mt;
    mesh->j0 = (int)(t / T % T) * mt;
    pg_export_verts *v = &mesh->verts;
    /* the tile's vertices, the ring of quads around them, and the first row of quads
     * across a face edge: at most (mt + 3)^2 + 4 (mt + 3) slots */
    size_t need = (size_t)(mt + 3) * (mt + 3) + 4 * (size_t)(mt + 3) + 16;
    for (v->cap = 16; v->cap < 2 * need; v->cap *= 2) {
    }
    v->keys = malloc(v->cap * sizeof *v->keys);
    v->index = malloc(v->cap * sizeof *v->index);
    int64_t *rowkey = malloc(need * sizeof *rowkey);
    st = v->keys && v->index && rowkey ? alloc_rows(v, need, m, err)
                                       : pg_error_set(err, PG_ERR_NOMEM, "cannot allocate a tile");
    if (st == PG_OK) memset(v->keys, 0xff, v->cap * sizeof *v->keys); /* all -1: empty */
    bool ok = true;
    for (int j = mesh->j0; st == PG_OK && j <= mesh->j0 + mt; j++)
        for (int i = mesh->i0; i <= mesh->i0 + mt; i++) {
            /* the corners of the quads around (i, j) in every face that holds it */
            int n[3], eu[3], ev[3], L[3];
            pg_cube_face_frame(mesh->face, n, eu, ev);
            for (int c = 0; c < 3; c++)
                L[c] = m * n[c] + (2 * i - m) * eu[c] + (2 * j - m) * ev[c];
            for (int gf = 0; gf < PG_CUBE_NFACES; gf++) {
                pg_cube_face_frame(gf, n, eu, ev);
                if (L[0] * n[0] + L[1] * n[1] + L[2] * n[2] != m) continue;
                int gi = (L[0] * eu[0] + L[1] * eu[1] + L[2] * eu[2] + m) / 2;
                int gj = (L[0] * ev[0] + L[1] * ev[1] + L[2] * ev[2] + m) / 2;
                for (int b = gj - 1; b <= gj + 1; b++)
                    for (int a = gi - 1; a <= gi + 1; a++)
                        if (a >= 0 && b >= 0 && a <= m && b <= m)
                            ok = verts_insert(v, gf, a, b, rowkey) >= 0 && ok;
            }
        }
    if (st == PG_OK && !ok)
        st = pg_error_set(err, PG_ERR_RUNTIME, "tile %lld: slot table full", (long long)t);
    if (st == PG_OK) {
        int64_t rows = (int64_t)v->n;
#pragma omp parallel for schedule(static)
        for (int64_t r = 0; r < rows; r++)
            place_slot(h, g, v, exaggeration, rowkey[r], (size_t)r);
        for (int64_t r = 0; r < rows; r++)
            ok = ok && isfinite(v->pos[3 * r]) && isfinite(v->vh[r]);
        if (!ok)
            st = pg_error_set(err, PG_ERR_RUNTIME, "tile %lld: heights around the tile are missing",
                              (long long)t);
    }
    for (int j = mesh->j0; st == PG_OK && j <= mesh->j0 + mt; j++)
        for (int i = mesh->i0; i <= mesh->i0 + mt; i++) {
            int64_t r = pg_export_verts_find(v, mesh->face, i, j);
            ok = r >= 0 && vertex_normal(v, mesh->face, i, j, v->nrm + 3 * r) && ok;
        }
    if (st == PG_OK) {
        fill_topology(mesh);
        ok = ok && emit(mesh);
        if (!ok)
            st = pg_error_set(err, PG_ERR_RUNTIME, "tile %lld: mesh ring incomplete", (long long)t);
    }
    free(rowkey);
    if (st != PG_OK) pg_export_mesh_free(mesh);
    return st;
}
