/* pg_export_tiles.c - a tiled planet's glTF files (pg_export.h, docs/export.md,
 * "Tiled planets"): one .glb per tile, written by the process that holds the tile.
 *
 * A tile's mesh and normal map read the texels around it: the quads of the
 * ring around the tile (their corner heights average the texels around each corner) and
 * one texel for the normal map's central differences. R = N/M + 2 texels covers both.
 * The texels a process does not hold are read from the other tiles' committed height
 * EXRs: for each such tile, the box of its texels that the ring touches is cut into a
 * strip and the tile image freed, so a tile needs its own texels, the strips and one
 * neighbour image at a time, never the planet. The heights in the EXRs are the float
 * heights the owner holds, so every process computes the same bits. */
#include "pg_export_internal.h"

#include "planetgen/pg_image.h"
#include "planetgen/pg_planet_tiles.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct box {
    int64_t tile, x0, y0, x1, y1; /* face texels [x0, x1) x [y0, y1) of the tile's face */
} box;

static void free_strips(pg_export_heights *h) {
    for (int k = 0; k < h->nstrips; k++)
        free(h->strips[k].data);
    free(h->strips);
    h->strips = NULL;
    h->nstrips = 0;
}

/* The boxes of texels outside [first, last) that tile t's ring touches. */
static pg_status ring_boxes(const pg_export_heights *h, const pg_cube_grid *g, int64_t t, int64_t R,
                            box **out, int *nout, pg_error *err) {
    const pg_planet *p = h->p;
    const int64_t T = p->tiles, S = p->tile_size, n = p->n, nn = n * n;
    const int f = (int)(t / (T * T));
    const int64_t x0 = t % T * S, y0 = t / T % T * S;
    box *b = NULL;
    int nb = 0, cap = 0;
    for (int64_t y = y0 - R; y < y0 + S + R; y++)
        for (int64_t x = x0 - R; x < x0 + S + R; x++) {
            if (x == x0 && y >= y0 && y < y0 + S) x = x0 + S; /* skip the tile itself */
            if (x >= x0 + S + R) break;
            bool outx = x < 0 || x >= n, outy = y < 0 || y >= n;
            if (outx && outy) continue; /* past a cube vertex: no texel there */
            int rot;
            int64_t id = pg_cube_wrap(g, f, x, y, &rot);
            int64_t gf = id / nn, gx = id % nn % n, gy = id % nn / n;
            int64_t gt = (gf * T + gy / S) * T + gx / S;
            if (gt >= h->first && gt < h->last) continue;
            int k = 0;
            while (k < nb && b[k].tile != gt)
                k++;
            if (k == nb) {
                if (nb == cap) {
                    cap = cap ? 2 * cap : 16;
                    box *nbx = realloc(b, (size_t)cap * sizeof *b);
                    if (!nbx) {
                        free(b);
                        return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
                    }
                    b = nbx;
                }
                b[nb++] = (box){gt, gx, gy, gx + 1, gy + 1};
            }
            b[k].x0 = gx < b[k].x0 ? gx : b[k].x0;
            b[k].y0 = gy < b[k].y0 ? gy : b[k].y0;
            b[k].x1 = gx + 1 > b[k].x1 ? gx + 1 : b[k].x1;
            b[k].y1 = gy + 1 > b[k].y1 ? gy + 1 : b[k].y1;
        }
    *out = b;
    *nout = nb;
    return PG_OK;
}

/* Cut each box from its tile's height EXR in dir. */
static pg_status read_strips(pg_export_heights *h, const char *dir, const box *b, int nb,
                             pg_error *err) {
    const pg_planet *p = h->p;
    const int64_t T = p->tiles, S = p->tile_size;
    h->strips = calloc((size_t)(nb ? nb : 1), sizeof *h->strips);
    if (!h->strips) return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    for (int k = 0; k < nb; k++) {
        char an[64], hn[64], path[4096];
        pg_planet_tile_names(p, (int)b[k].tile, an, hn);
        if (!dir)
            return pg_error_set(err, PG_ERR_RUNTIME, "%s: not held and no directory to read", hn);
        snprintf(path, sizeof path, "%s/%s", dir, hn);
        pg_image img;
        pg_status st = pg_image_read_exr(path, NULL, &img, err);
        if (st != PG_OK) return st;
        if (img.width != S || img.height != S || img.channels != 1) {
            pg_image_free(&img);
            return pg_error_set(err, PG_ERR_BADINPUT, "%s: expected one %lldx%lld channel", path,
                                (long long)S, (long long)S);
        }
        pg_export_strip *s = &h->strips[h->nstrips];
        s->tile = b[k].tile;
        s->x0 = b[k].x0, s->y0 = b[k].y0;
        s->w = b[k].x1 - b[k].x0, s->h = b[k].y1 - b[k].y0;
        s->data = malloc((size_t)(s->w * s->h) * sizeof(float));
        if (!s->data) {
            pg_image_free(&img);
            return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
        }
        h->nstrips++;
        const int64_t tx0 = b[k].tile % T * S, ty0 = b[k].tile / T % T * S;
        for (int64_t y = 0; y < s->h; y++) { /* image row 0 is the tile's +v edge */
            int64_t row = S - 1 - (s->y0 + y - ty0);
            memcpy(s->data + y * s->w, img.data + row * S + (s->x0 - tx0),
                   (size_t)s->w * sizeof(float));
        }
        pg_image_free(&img);
    }
    return PG_OK;
}

pg_status pg_export_tiles_glb(const pg_planet *p, int first, int last, const char *dir,
                              const pg_export_opts *o, pg_planet_path_fn path_for, void *user,
                              pg_export_result *res, pg_error *err) {
    pg_status st = pg_export_check_opts(o, p->tiles, p->tile_size, err);
    if (st != PG_OK) return st;
    pg_cube_grid g;
    st = pg_cube_grid_init(&g, p->projection, p->tiles, p->tile_size, err);
    if (st != PG_OK) return st;
    const int m = o->mesh_res ? o->mesh_res : pg_export_default_mesh_res(p->tiles, p->tile_size);
    int64_t R = p->n / m + 2;
    if (R > p->n) R = p->n;
    for (int t = first; st == PG_OK && t < last; t++) {
        pg_export_heights h = {.p = p, .first = first, .last = last};
        box *b = NULL;
        int nb = 0;
        st = ring_boxes(&h, &g, t, R, &b, &nb, err);
        if (st == PG_OK) st = read_strips(&h, dir, b, nb, err);
        free(b);
        if (st == PG_OK) st = pg_export_tile_glb_write(&h, &g, o, t, path_for, user, res, err);
        free_strips(&h);
    }
    return st;
}
