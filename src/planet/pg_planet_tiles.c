/* pg_planet_tiles.c - the tiled layout of a planet directory (pg_planet_tiles.h):
 * per-tile albedo PNG and height EXR, and index.json. Each tile is cut from the
 * in-memory faces and flipped so that row 0 is its +v edge, like the face images of
 * pg_planet_save; a tile depends only on its own texels, so any process that holds a
 * tile writes the same bytes. Loading pastes the tiles back, flipped the other way,
 * after checking every file's presence and size from its header. */
#include "planetgen/pg_planet_tiles.h"

#include "planetgen/pg_image.h"
#include "planetgen/pg_json.h"
#include "pg_planet_meta.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

void pg_planet_tile_names(const pg_planet *p, int t, char albedo[64], char height[64]) {
    const int T = p->tiles, f = t / (T * T), tx = t % T, ty = t / T % T;
    snprintf(albedo, 64, "albedo_%s_%d_%d.png", pg_cube_face_name(f), tx, ty);
    snprintf(height, 64, "height_%s_%d_%d.exr", pg_cube_face_name(f), tx, ty);
}

void pg_planet_tile_glb_name(const pg_planet *p, int t, char glb[64]) {
    const int T = p->tiles, f = t / (T * T), tx = t % T, ty = t / T % T;
    snprintf(glb, 64, "planet_%s_%d_%d.glb", pg_cube_face_name(f), tx, ty);
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
    return pg_planet_save_index_glb(p, false, path_for, user, err);
}

pg_status pg_planet_save_index_glb(const pg_planet *p, bool glb, pg_planet_path_fn path_for,
                                   void *user, pg_error *err) {
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
        if (glb) {
            char gn[64];
            pg_planet_tile_glb_name(p, t, gn);
            pg_json_set_string(o, "glb", gn);
        }
    }
    return pg_planet_write_json(j, PG_PLANET_INDEX_NAME, path_for, user, err);
}

bool pg_planet_dir_is_tiled(const char *dir) {
    char path[4096];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, PG_PLANET_META_NAME);
    if (stat(path, &st) == 0) return false;
    snprintf(path, sizeof path, "%s/%s", dir, PG_PLANET_INDEX_NAME);
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Every tile file exists and has the tile's size, from the headers alone: a damaged
 * index.json must not make us allocate a planet its tiles do not hold. */
static pg_status check_tiles(const char *dir, const pg_planet_meta *m, pg_error *err) {
    pg_planet geo = {.tiles = m->tiles, .tile_size = m->tile_size};
    char path[4096], names[2][64];
    for (int t = 0; t < 6 * m->tiles * m->tiles; t++) {
        pg_planet_tile_names(&geo, t, names[0], names[1]);
        for (int k = 0; k < 2; k++) {
            struct stat st;
            snprintf(path, sizeof path, "%s/%s", dir, names[k]);
            if (stat(path, &st) != 0)
                return pg_error_set(err, PG_ERR_BADINPUT, "%s: missing %s", dir, names[k]);
            int w, h, c;
            pg_status s = pg_image_probe(path, &w, &h, &c, err);
            if (s != PG_OK) return s;
            if (w != m->tile_size || h != m->tile_size)
                return pg_error_set(err, PG_ERR_BADINPUT, "%s: %dx%d, but %s says %dx%d", path, w,
                                    h, PG_PLANET_INDEX_NAME, m->tile_size, m->tile_size);
        }
    }
    return PG_OK;
}

/* Tile image img (row 0 = the tile's +v edge) into the face, scaled by `scale`. */
static void paste_tile(const pg_planet *p, float *face, int ch, int t, const pg_image *img,
                       float scale) {
    const int T = p->tiles, S = p->tile_size, tx = t % T, ty = t / T % T;
    for (int y = 0; y < S; y++) {
        float *dst = face + ((size_t)(ty * S + y) * (size_t)p->n + (size_t)tx * S) * ch;
        const float *src = img->data + (size_t)(S - 1 - y) * S * img->channels;
        for (int x = 0; x < S; x++)
            for (int c = 0; c < ch; c++)
                dst[(size_t)x * ch + c] = src[(size_t)x * img->channels + c] * scale;
    }
}

static pg_status load_tile(const char *dir, pg_planet *p, int t, pg_error *err) {
    const int f = t / (p->tiles * p->tiles);
    char names[2][64], path[4096];
    pg_planet_tile_names(p, t, names[0], names[1]);
    pg_image img;
    snprintf(path, sizeof path, "%s/%s", dir, names[0]);
    pg_status s = pg_image_read(path, 0, &img, err);
    if (s != PG_OK) return s;
    if (img.channels < 3) s = pg_error_set(err, PG_ERR_BADINPUT, "%s: expected RGB", path);
    if (s == PG_OK) paste_tile(p, p->albedo[f], 3, t, &img, img.unit_scale);
    pg_image_free(&img);
    if (s != PG_OK) return s;
    snprintf(path, sizeof path, "%s/%s", dir, names[1]);
    if ((s = pg_image_read_exr(path, NULL, &img, err)) != PG_OK) return s;
    if (img.width != p->tile_size || img.height != p->tile_size || img.channels != 1)
        s = pg_error_set(err, PG_ERR_BADINPUT, "%s: expected one %dx%d channel", path, p->tile_size,
                         p->tile_size);
    else
        paste_tile(p, p->height[f], 1, t, &img, 1.0f);
    pg_image_free(&img);
    return s;
}

pg_status pg_planet_tiles_check(const char *dir, int *tiles, int *tile_size, pg_error *err) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, PG_PLANET_INDEX_NAME);
    pg_planet_meta meta;
    pg_status s = pg_planet_meta_read(path, &meta, err);
    if (s == PG_OK) s = check_tiles(dir, &meta, err);
    *tiles = s ? 0 : meta.tiles;
    *tile_size = s ? 0 : meta.tile_size;
    return s;
}

pg_status pg_planet_load_tiles(const char *dir, pg_planet *p, pg_error *err) {
    memset(p, 0, sizeof *p);
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, PG_PLANET_INDEX_NAME);
    pg_planet_meta meta;
    pg_status s = pg_planet_meta_read(path, &meta, err);
    if (s == PG_OK) s = check_tiles(dir, &meta, err);
    if (s == PG_OK) s = pg_planet_alloc_meta(&meta, PG_PLANET_INDEX_NAME, p, err);
    if (s != PG_OK) return s;
    s = pg_planet_load_tile_files(dir, p, err);
    if (s != PG_OK) pg_planet_free(p);
    return s;
}

pg_status pg_planet_load_tile_files(const char *dir, pg_planet *p, pg_error *err) {
    pg_status s = PG_OK;
    for (int t = 0; s == PG_OK && t < 6 * p->tiles * p->tiles; t++)
        s = load_tile(dir, p, t, err);
    return s;
}
