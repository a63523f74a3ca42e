/* pg_planet_tiles.c - the tiled layout of a planet directory (pg_planet_tiles.h):
 * per-tile albedo PNG and height EXR, and index.json. Each tile is cut from the
 * in-memory faces and flipped so that row 0 is its +v edge, like the face images of
 * pg_planet_save; a tile depends only on its own texels, so any process that holds a
 * tile writes the same bytes. */
#include "planetgen/pg_planet_tiles.h"

#include "planetgen/pg_image.h"
#include "planetgen/pg_json.h"

#include <stdio.h>
#include <string.h>

void pg_planet_tile_names(const pg_planet *p, int t, char albedo[64], char height[64]) {
    const int T = p->tiles, f = t / (T * T), tx = t % T, ty = t / T % T;
    snprintf(albedo, 64, "albedo_%s_%d_%d.png", pg_cube_face_name(f), tx, ty);
    snprintf(height, 64, "height_%s_%d_%d.exr", pg_cube_face_name(f), tx, ty);
}

/* Tile t of `face` (ch channels per texel) into img, row 0 = the tile's +v edge. */
static void cut_tile(const pg_planet *p, const float *face, int ch, int t, pg_image *img) {
    const int T = p->tiles, S = p->tile_size, tx = t % T, ty = t / T % T;
    for (int y = 0; y < S; y++) {
        const float *src = face + ((size_t)(ty * S + y) * (size_t)p->n + (size_t)tx * S) * ch;
        memcpy(img->data + (size_t)(S - 1 - y) * S * ch, src, (size_t)S * ch * sizeof(float));
    }
}

static pg_status save_tile(const pg_planet *p, int t, pg_image *rgb, pg_image *h,
                           pg_planet_path_fn path_for, void *user, pg_error *err) {
    const int f = t / (p->tiles * p->tiles);
    char an[64], hn[64];
    pg_planet_tile_names(p, t, an, hn);
    cut_tile(p, p->albedo[f], 3, t, rgb);
    cut_tile(p, p->height[f], 1, t, h);
    const char *path = path_for(an, user);
    if (!path) return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    pg_status st = pg_image_write_png(path, rgb, 8, err);
    if (st) return st;
    if (!(path = path_for(hn, user))) return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    return pg_image_write_exr(path, h, NULL, err);
}

pg_status pg_planet_save_tiles(const pg_planet *p, int first, int last, pg_planet_path_fn path_for,
                               void *user, pg_error *err) {
    pg_image rgb = {0}, h = {0};
    pg_status st = pg_image_alloc(&rgb, p->tile_size, p->tile_size, 3, err);
    if (!st) st = pg_image_alloc(&h, p->tile_size, p->tile_size, 1, err);
    for (int t = first; !st && t < last; t++)
        st = save_tile(p, t, &rgb, &h, path_for, user, err);
    pg_image_free(&rgb);
    pg_image_free(&h);
    return st;
}

pg_status pg_planet_save_index(const pg_planet *p, pg_planet_path_fn path_for, void *user,
                               pg_error *err) {
    pg_json *j = pg_planet_meta_json(p);
    pg_json *arr = j ? pg_json_set_array(j, "tile_files") : NULL;
    if (j) {
        pg_json_set_string(j, "layout", "tiled");
        pg_json_set_string(j, "rows", "row 0 of every tile image is its +v edge");
    }
    const int T = p->tiles;
    for (int t = 0; arr && t < 6 * T * T; t++) {
        char an[64], hn[64];
        pg_planet_tile_names(p, t, an, hn);
        pg_json *o = pg_json_push_object(arr);
        pg_json_set_string(o, "face", pg_cube_face_name(t / (T * T)));
        pg_json_set_number(o, "tx", t % T);
        pg_json_set_number(o, "ty", t / T % T);
        pg_json_set_number(o, "x0", (double)(t % T) * p->tile_size);
        pg_json_set_number(o, "y0", (double)(t / T % T) * p->tile_size);
        pg_json_set_string(o, "albedo", an);
        pg_json_set_string(o, "height", hn);
    }
    return pg_planet_write_json(j, PG_PLANET_INDEX_NAME, path_for, user, err);
}
