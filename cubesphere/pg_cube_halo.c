/* pg_cube_halo.c - fill a tile's apron from its neighbours across seams.
 *
 * The idea: each of the 8 apron strips (4 edges, 4 corners) lies inside one
 * neighbour tile, and the neighbour's integer transform is a rotation plus an
 * offset, so within a strip the source address is affine in (x, y): one base
 * offset and two constant strides. The gather is thus a handful of strided copies
 * per tile, with no per-texel index map to build or store, and cheap enough to run
 * every synthesis sub-pass on all 6*T^2 tiles. Only the corner block at a cube
 * vertex (no diagonal neighbour exists) goes texel by texel through pg_cube_wrap,
 * which unfolds the deeper edge first; pg_cube.h documents what that block holds.
 * Vector payloads are rotated by the same quarter turns as the coordinates. */
#include "planetgen/pg_cube.h"

#include <string.h>

void pg_cube_rotate_vec(double *x, double *y, int quarter_turns) {
    for (int i = 0; i < (quarter_turns & 3); i++) {
        double t = *x;
        *x = -*y;
        *y = t;
    }
}

static void rotate_elem(const pg_cube_payload *pl, unsigned char *e, int rot) {
    if (!rot) return;
    if (pl->rotate) {
        pl->rotate(e, rot, pl->user);
        return;
    }
    unsigned char *p = e + pl->vec_offset;
    if (pl->vec == PG_CUBE_VEC_F32) {
        float v[2];
        memcpy(v, p, sizeof v);
        double x = v[0], y = v[1];
        pg_cube_rotate_vec(&x, &y, rot);
        v[0] = (float)x, v[1] = (float)y;
        memcpy(p, v, sizeof v);
    } else if (pl->vec == PG_CUBE_VEC_F64) {
        double v[2];
        memcpy(v, p, sizeof v);
        pg_cube_rotate_vec(&v[0], &v[1], rot);
        memcpy(p, v, sizeof v);
    } else if (pl->vec == PG_CUBE_VEC_I32) {
        int32_t v[2];
        memcpy(v, p, sizeof v);
        for (int i = 0; i < rot; i++) {
            int32_t t = v[0];
            v[0] = -v[1];
            v[1] = t;
        }
        memcpy(p, v, sizeof v);
    }
}

/* Copy one element; fixed sizes let the compiler inline the copy. */
static inline void copy_elem(unsigned char *d, const unsigned char *s, size_t sz) {
    switch (sz) {
    case 1:
        *d = *s;
        break;
    case 4:
        memcpy(d, s, 4);
        break;
    case 8:
        memcpy(d, s, 8);
        break;
    case 12:
        memcpy(d, s, 12);
        break;
    case 16:
        memcpy(d, s, 16);
        break;
    default:
        memcpy(d, s, sz);
        break;
    }
}

typedef struct halo_job {
    const pg_cube_grid *g;
    const unsigned char *field;
    const pg_cube_payload *pl;
    unsigned char *padded;
    int64_t P, w; /* padded width, apron width */
    int face;
    int64_t tx0, ty0; /* tile origin in face texels */
} halo_job;

/* Strip [x0,x1) x [y0,y1) (tile-local) from an existing neighbour tile. */
static void copy_strip(const halo_job *j, const pg_cube_neighbor *nb, int64_t x0, int64_t x1,
                       int64_t y0, int64_t y1) {
    const pg_cube_grid *g = j->g;
    int64_t n = g->n, T = g->tiles, S = g->tile_size;
    size_t sz = j->pl->elem_size;
    int64_t nf = nb->tile / (T * T), ntx = nb->tile % T, nty = nb->tile / T % T;
    pg_cube_xform inv = pg_cube_xform_inverse(nb->xf);
    int64_t bx, by, ex, ey, fx, fy;
    pg_cube_xform_apply(inv, x0, y0, &bx, &by);
    pg_cube_xform_apply(inv, x0 + 1, y0, &ex, &ey);
    pg_cube_xform_apply(inv, x0, y0 + 1, &fx, &fy);
    /* source index of (x, y) = base + (x - x0) * sx + (y - y0) * sy */
    int64_t base = (nf * n + nty * S + by) * n + ntx * S + bx;
    int64_t sx = (ey - by) * n + (ex - bx), sy = (fy - by) * n + (fx - bx);
    int rot = nb->xf.rot;
    int plain = !rot || (!j->pl->rotate && j->pl->vec == PG_CUBE_VEC_NONE);
    for (int64_t y = y0; y < y1; y++) {
        unsigned char *d = j->padded + ((y + j->w) * j->P + x0 + j->w) * sz;
        int64_t s = base + (y - y0) * sy;
        if (sx == 1) { /* the strip runs along source rows: one copy per row */
            memcpy(d, j->field + s * sz, (size_t)(x1 - x0) * sz);
        } else {
            for (int64_t x = x0; x < x1; x++, s += sx, d += sz)
                copy_elem(d, j->field + s * sz, sz);
            d -= (size_t)(x1 - x0) * sz;
        }
        if (!plain)
            for (int64_t x = x0; x < x1; x++, d += sz)
                rotate_elem(j->pl, d, rot);
    }
}

/* Corner block at a cube vertex: texel by texel through pg_cube_wrap. */
static void copy_vertex_block(const halo_job *j, int64_t x0, int64_t x1, int64_t y0, int64_t y1) {
    size_t sz = j->pl->elem_size;
    for (int64_t y = y0; y < y1; y++) {
        for (int64_t x = x0; x < x1; x++) {
            int rot;
            int64_t id = pg_cube_wrap(j->g, j->face, j->tx0 + x, j->ty0 + y, &rot);
            unsigned char *d = j->padded + ((y + j->w) * j->P + x + j->w) * sz;
            copy_elem(d, j->field + id * sz, sz);
            rotate_elem(j->pl, d, rot);
        }
    }
}

static void copy_interior(const halo_job *j) {
    int64_t n = j->g->n, S = j->g->tile_size;
    size_t sz = j->pl->elem_size;
    for (int64_t y = 0; y < S; y++) {
        const unsigned char *s = j->field + (((j->face * n) + j->ty0 + y) * n + j->tx0) * sz;
        memcpy(j->padded + ((y + j->w) * j->P + j->w) * sz, s, (size_t)S * sz);
    }
}

pg_status pg_cube_halo_gather(const pg_cube_grid *g, int64_t tile, int w, const void *field,
                              const pg_cube_payload *pl, bool halo_only, void *padded,
                              pg_error *err) {
    int64_t S = g->tile_size, T = g->tiles;
    if (tile < 0 || tile >= g->ntiles)
        return pg_error_set(err, PG_ERR_BADINPUT, "halo: tile %lld out of range", (long long)tile);
    if (w < 1 || w > S)
        return pg_error_set(err, PG_ERR_BADINPUT, "halo: width %d outside 1..%lld", w,
                            (long long)S);
    if (!pl || pl->elem_size == 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "halo: payload element size is 0");
    halo_job j = {g, field, pl, padded, S + 2 * w, w, (int)(tile / (T * T)), 0, 0};
    j.tx0 = tile % T * S;
    j.ty0 = tile / T % T * S;
    if (!halo_only) copy_interior(&j);
    pg_cube_neighbor nb[8];
    pg_cube_tile_neighbors(g, tile, nb);
    for (int d = 0; d < 8; d++) {
        int dx, dy;
        pg_cube_dir_offset((pg_cube_dir)d, &dx, &dy);
        int64_t x0 = dx < 0 ? -w : dx > 0 ? S : 0, x1 = dx < 0 ? 0 : dx > 0 ? S + w : S;
        int64_t y0 = dy < 0 ? -w : dy > 0 ? S : 0, y1 = dy < 0 ? 0 : dy > 0 ? S + w : S;
        if (nb[d].tile >= 0)
            copy_strip(&j, &nb[d], x0, x1, y0, y1);
        else
            copy_vertex_block(&j, x0, x1, y0, y1);
    }
    return PG_OK;
}
