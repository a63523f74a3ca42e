/* pg_pits_topology.c - the cell neighbourhoods pit removal runs on: a flat 8-connected
 * grid and the cube sphere (6 faces of N x N texels, 8-connected across face seams).
 *
 * The cube uses the cube-sphere module's face frames and seam map (pg_cube.h): a
 * step off a face is wrapped by pg_cube_wrap, an exact integer transform onto the
 * face across the seam, so pits and synthesis agree on which texels touch. The grid
 * is built with tiles of one texel (T = N, S = 1), which allows any face size N. A
 * step that leaves the face across two edges at once exists only at the 8 cube
 * corners, where three faces meet: that diagonal neighbour does not exist, so the
 * corner texels have 7 neighbours (pg_cube_wrap would unfold it onto a duplicate).
 * Interior cells never get here: pg_pits_neighbours in the header handles them. */
#include "pg_pits_internal.h"

static pg_status topo_init(pg_pits_topo *t, pg_pits_topo_kind kind, uint32_t w, uint32_t h,
                           uint32_t nfaces, pg_error *err) {
    uint64_t n = (uint64_t)w * h * nfaces;
    if (w == 0 || h == 0) return pg_error_set(err, PG_ERR_BADINPUT, "pits: empty grid %ux%u", w, h);
    if (n >= 0xFFFFFFFFull)
        return pg_error_set(err, PG_ERR_BADINPUT, "pits: %llu cells exceed the 2^32-1 cell limit",
                            (unsigned long long)n);
    t->kind = kind;
    t->w = w;
    t->h = h;
    t->nfaces = nfaces;
    t->ncells = n;
    t->inv_w = 1.0 / w;
    t->inv_face = 1.0 / ((double)w * h);
    return PG_OK;
}

pg_status pg_pits_topo_grid(pg_pits_topo *t, uint32_t w, uint32_t h, pg_error *err) {
    return topo_init(t, PG_PITS_GRID, w, h, 1, err);
}

pg_status pg_pits_topo_blocks(pg_pits_topo *t, uint32_t w, uint32_t nblocks, uint32_t extra,
                              pg_pits_border_fn border, const void *ctx, pg_error *err) {
    uint64_t n = (uint64_t)w * w * nblocks + extra;
    if (w == 0 || !border)
        return pg_error_set(err, PG_ERR_BADINPUT, "pits: empty blocks or no border function");
    if (n >= 0xFFFFFFFFull)
        return pg_error_set(err, PG_ERR_BADINPUT, "pits: %llu cells exceed the 2^32-1 cell limit",
                            (unsigned long long)n);
    *t = (pg_pits_topo){.kind = PG_PITS_BLOCKS,
                        .w = w,
                        .h = w,
                        .nfaces = nblocks ? nblocks : 1,
                        .ncells = n,
                        .inv_w = 1.0 / w,
                        .inv_face = 1.0 / ((double)w * w),
                        .border = border,
                        .border_ctx = ctx,
                        .extra = extra};
    return PG_OK;
}

pg_status pg_pits_topo_cube(pg_pits_topo *t, uint32_t n, pg_error *err) {
    if (n < 2) return pg_error_set(err, PG_ERR_BADINPUT, "pits: cube face size %u < 2", n);
    pg_status s = topo_init(t, PG_PITS_CUBE, n, n, 6, err);
    if (s) return s;
    return pg_cube_grid_init(&t->cube, PG_CUBE_EQUIANGULAR, (int)n, 1, err);
}

int pg_pits_neighbours_slow(const pg_pits_topo *t, uint32_t id, uint32_t out[8]) {
    if (t->kind == PG_PITS_BLOCKS) return t->border(t->border_ctx, id, out);
    int W = (int)t->w, H = (int)t->h, k = 0;
    uint32_t fsz = t->w * t->h, f = id / fsz, r = id % fsz;
    int x = (int)(r % t->w), y = (int)(r / t->w);
    for (int dy = -1; dy <= 1; dy++) {
        for (int dx = -1; dx <= 1; dx++) {
            if (!dx && !dy) continue;
            int nx = x + dx, ny = y + dy;
            int outx = nx < 0 || nx >= W, outy = ny < 0 || ny >= H;
            if (!outx && !outy) {
                out[k++] = f * fsz + (uint32_t)ny * t->w + (uint32_t)nx;
            } else if (t->kind == PG_PITS_CUBE && !(outx && outy)) {
                out[k++] = (uint32_t)pg_cube_wrap(&t->cube, (int)f, nx, ny, NULL);
            }
        }
    }
    return k;
}
