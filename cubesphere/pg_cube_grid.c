/* pg_cube_grid.c - the tile grid and the adjacency map across seams.
 *
 * The idea: all seam maps are derived from the face frames. Unfolding the cube
 * about the edge it shares with face f lays the neighbour face g flat beside f;
 * a point of g at grid coordinates (a, b) lands in f's extended plane at
 *   out-axis:   sign * (2 - q.n_f)      (distance past the edge = 1 - q.n_f)
 *   along-axis: q.s                       (s: the edge's direction, e_v or e_u of f)
 * with q = n_g + a e_u^g + b e_v^g. That is an affine map with a 2x2 matrix of
 * 0/+-1 entries, which we turn into texel-index form x_f = M x_g + c. Because both
 * frames are right-handed and unfolding preserves orientation, M is a rotation
 * (checked by the tests). Because every projection treats the four edges of a face
 * alike, texel row k past f's edge is exactly texel row k of g, so the map is exact
 * on texel indices and geometrically the mirror image across the seam.
 *
 * Tiles inherit the face maps: a neighbour tile's transform is face map composed
 * with the two tiles' origins. At the 8 cube vertices three faces meet, so the
 * corner neighbour of a tile touching a vertex does not exist (tile -1). */
#include "pg_cube_internal.h"

#include <stdlib.h>

static int dot3(const int a[3], const int b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static const int DIR_OFF[8][2] = {{1, 0}, {0, 1},  {-1, 0},  {0, -1},
                                  {1, 1}, {-1, 1}, {-1, -1}, {1, -1}};

void pg_cube_dir_offset(pg_cube_dir d, int *dx, int *dy) {
    *dx = DIR_OFF[d][0];
    *dy = DIR_OFF[d][1];
}

void pg_cube_xform_apply(pg_cube_xform t, int64_t x, int64_t y, int64_t *xo, int64_t *yo) {
    int64_t rx, ry;
    switch (t.rot & 3) {
    case 0:
        rx = x, ry = y;
        break;
    case 1:
        rx = -y, ry = x;
        break;
    case 2:
        rx = -x, ry = -y;
        break;
    default:
        rx = y, ry = -x;
        break;
    }
    *xo = rx + t.ox;
    *yo = ry + t.oy;
}

pg_cube_xform pg_cube_xform_inverse(pg_cube_xform t) {
    /* p = R^-r (p' - o) */
    pg_cube_xform inv = {(4 - (t.rot & 3)) & 3, 0, 0};
    pg_cube_xform_apply(inv, -t.ox, -t.oy, &inv.ox, &inv.oy);
    return inv;
}

pg_cube_xform pg_cube_xform_compose(pg_cube_xform a, pg_cube_xform b) {
    pg_cube_xform c = {(a.rot + b.rot) & 3, 0, 0};
    pg_cube_xform_apply(a, b.ox, b.oy, &c.ox, &c.oy);
    return c;
}

/* Rotation index of an integer rotation matrix given by its first column. */
static int rot_of(int m00, int m10) {
    if (m00 == 1) return 0;
    if (m10 == 1) return 1;
    if (m00 == -1) return 2;
    return 3;
}

/* The map from the face across edge e of face f into f's extended texel frame. */
static void edge_map(int f, int e, int64_t n, int *gout, pg_cube_xform *xf) {
    int nf[3], uf[3], vf[3], ng[3], ug[3], vg[3], t[3];
    int dx = DIR_OFF[e][0], dy = DIR_OFF[e][1];
    pg_cube_face_frame(f, nf, uf, vf);
    for (int i = 0; i < 3; i++)
        t[i] = dx * uf[i] + dy * vf[i];
    int g = 0;
    for (; g < PG_CUBE_NFACES; g++) {
        pg_cube_face_frame(g, ng, ug, vg);
        if (dot3(ng, t) == 1) break;
    }
    int out = dx != 0 ? 0 : 1, sign = dx + dy;
    const int *s = dx != 0 ? vf : uf;
    int M[2][2], o[2];
    M[out][0] = -sign * dot3(ug, nf);
    M[out][1] = -sign * dot3(vg, nf);
    o[out] = 2 * sign;
    M[1 - out][0] = dot3(ug, s);
    M[1 - out][1] = dot3(vg, s);
    o[1 - out] = 0;
    /* grid coords a = 2(x + 1/2)/N - 1  =>  x_f = M x_g + (N/2)(o + 1 - M1) + (M1 - 1)/2 */
    int64_t off[2];
    for (int r = 0; r < 2; r++) {
        int m1 = M[r][0] + M[r][1];
        off[r] = n * (o[r] + 1 - m1) / 2 + (m1 - 1) / 2;
    }
    *gout = g;
    xf->rot = rot_of(M[0][0], M[1][0]);
    xf->ox = off[0];
    xf->oy = off[1];
}

void pg_cube_grid_init_faces(pg_cube_grid *g, pg_cube_projection p, int64_t n) {
    g->proj = p;
    g->tiles = 1;
    g->tile_size = (int)n;
    g->n = n;
    g->ntiles = PG_CUBE_NFACES;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int e = 0; e < 4; e++)
            edge_map(f, e, n, &g->nbr_face[f][e], &g->edge[f][e]);
}

pg_status pg_cube_grid_init(pg_cube_grid *g, pg_cube_projection p, int tiles, int tile_size,
                            pg_error *err) {
    if ((unsigned)p > PG_CUBE_EQUALAREA)
        return pg_error_set(err, PG_ERR_BADINPUT, "projection: unknown projection id %d", (int)p);
    if (tiles < 1) return pg_error_set(err, PG_ERR_BADINPUT, "tiles: must be >= 1, got %d", tiles);
    if (tile_size < 1 || tile_size > 8192 || (tile_size & (tile_size - 1)))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "tile-size: must be a power of two <= 8192, got %d", tile_size);
    if ((int64_t)tiles * tile_size > ((int64_t)1 << 30))
        return pg_error_set(err, PG_ERR_BADINPUT, "tiles: %d x %d texels per face is too many",
                            tiles, tile_size);
    pg_cube_grid_init_faces(g, p, (int64_t)tiles * tile_size);
    g->tiles = tiles;
    g->tile_size = tile_size;
    g->ntiles = (int64_t)PG_CUBE_NFACES * tiles * tiles;
    return PG_OK;
}

/* The tile across one face edge, and its transform into the tile (f, tx, ty). */
static pg_cube_neighbor across_edge(const pg_cube_grid *g, int f, int64_t tx, int64_t ty, int d,
                                    int e) {
    int64_t S = g->tile_size, T = g->tiles;
    pg_cube_xform F = g->edge[f][e], Finv = pg_cube_xform_inverse(F);
    int64_t cx = (tx + DIR_OFF[d][0]) * S + S / 2, cy = (ty + DIR_OFF[d][1]) * S + S / 2, gx, gy;
    pg_cube_xform_apply(Finv, cx, cy, &gx, &gy);
    int64_t gtx = gx / S, gty = gy / S;
    pg_cube_xform to_face = {0, gtx * S, gty * S}, to_tile = {0, -tx * S, -ty * S};
    pg_cube_neighbor nb;
    nb.tile = ((int64_t)g->nbr_face[f][e] * T + gty) * T + gtx;
    nb.xf = pg_cube_xform_compose(to_tile, pg_cube_xform_compose(F, to_face));
    return nb;
}

void pg_cube_tile_neighbors(const pg_cube_grid *g, int64_t tile, pg_cube_neighbor out[8]) {
    int64_t T = g->tiles, S = g->tile_size;
    int f = (int)(tile / (T * T));
    int64_t tx = tile % T, ty = tile / T % T;
    for (int d = 0; d < 8; d++) {
        int64_t nx = tx + DIR_OFF[d][0], ny = ty + DIR_OFF[d][1];
        int outx = nx < 0 || nx >= T, outy = ny < 0 || ny >= T;
        if (!outx && !outy) {
            out[d].tile = ((int64_t)f * T + ny) * T + nx;
            out[d].xf = (pg_cube_xform){0, DIR_OFF[d][0] * S, DIR_OFF[d][1] * S};
        } else if (outx && outy) {
            out[d].tile = -1;
            out[d].xf = (pg_cube_xform){0, 0, 0};
        } else {
            int e = outx ? (nx < 0 ? PG_CUBE_XM : PG_CUBE_XP) : (ny < 0 ? PG_CUBE_YM : PG_CUBE_YP);
            out[d] = across_edge(g, f, tx, ty, d, e);
        }
    }
}

int64_t pg_cube_wrap(const pg_cube_grid *g, int face, int64_t x, int64_t y, int *rot) {
    int64_t n = g->n;
    int r = 0;
    for (int step = 0; step < 4; step++) {
        int64_t depx = x < 0 ? -x : x >= n ? x - n + 1 : 0;
        int64_t depy = y < 0 ? -y : y >= n ? y - n + 1 : 0;
        if (!depx && !depy) break;
        int e =
            depx >= depy ? (x < 0 ? PG_CUBE_XM : PG_CUBE_XP) : (y < 0 ? PG_CUBE_YM : PG_CUBE_YP);
        pg_cube_xform F = g->edge[face][e];
        pg_cube_xform_apply(pg_cube_xform_inverse(F), x, y, &x, &y);
        r += F.rot;
        face = g->nbr_face[face][e];
    }
    if (rot) *rot = r & 3;
    return ((int64_t)face * n + y) * n + x;
}

void pg_cube_corner_dir(const pg_cube_grid *g, int face, int64_t cx, int64_t cy, double dir[3]) {
    double u = 2.0 * (double)cx / (double)g->n - 1, v = 2.0 * (double)cy / (double)g->n - 1;
    pg_cube_to_dir(g->proj, face, u, v, dir);
}

void pg_cube_texel_dir(const pg_cube_grid *g, int64_t id, double dir[3]) {
    int64_t n = g->n;
    int face = (int)(id / (n * n));
    int64_t y = id / n % n, x = id % n;
    double u = (2.0 * (double)x + 1) / (double)n - 1, v = (2.0 * (double)y + 1) / (double)n - 1;
    pg_cube_to_dir(g->proj, face, u, v, dir);
}
