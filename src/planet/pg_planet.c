/* pg_planet.c - the planet in memory and its directory format; see pg_planet.h.
 *
 * Faces are stored bottom-up (row 0 = -v edge) to match the cube frames, while image
 * files are top-down; every read and write flips rows, so a face PNG shows north up
 * on the equatorial faces, as a user opening it expects.
 *
 * The coordinate map (source.exr, optional) is streamed a chunk of rows at a time
 * through pg_exr's integer parts, unpacked into channels face, u, v, so that the file
 * holds no packing convention of ours and any EXR tool shows it. planet.json names
 * the file and the exemplar cube the coordinates refer to; a map that planet.json
 * names must load completely and in range, or the planet is refused: the measures
 * that read it (pg_inspect_copy.h) index the exemplar cube with it. */
#include "pg_huge.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_planet_tiles.h"

#include "planetgen/pg_exr.h"
#include "planetgen/pg_json.h"
#include "planetgen/pg_planet_tiles.h"
#include "planetgen/pg_synth.h"
#include "pg_planet_meta.h"
#include "pg_span.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* The fields of a planet without faces. */
static void planet_fields(pg_planet *p, pg_cube_projection proj, int tiles, int tile_size,
                          pg_ellipsoid ell) {
    memset(p, 0, sizeof *p);
    p->tiles = tiles;
    p->tile_size = tile_size;
    p->n = (int64_t)tiles * tile_size;
    p->projection = proj;
    p->ellipsoid = ell;
    p->closed_land_share_before_final = NAN;
}

pg_status pg_planet_alloc(pg_planet *p, pg_cube_projection proj, int tiles, int tile_size,
                          pg_ellipsoid ell, pg_error *err) {
    planet_fields(p, proj, tiles, tile_size, ell);
    size_t nn = (size_t)p->n * (size_t)p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        p->albedo[f] = pg_huge_calloc(nn * 3, sizeof(float));
        p->height[f] = pg_huge_calloc(nn, sizeof(float));
        if (!p->albedo[f] || !p->height[f]) {
            pg_planet_free(p);
            return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate a planet of 6 x %lld^2",
                                (long long)(nn ? (long long)p->n : 0));
        }
    }
    return PG_OK;
}

pg_status pg_planet_alloc_rows(pg_planet *p, pg_cube_projection proj, int tiles, int tile_size,
                               pg_ellipsoid ell, const int64_t y0[PG_CUBE_NFACES],
                               const int64_t y1[PG_CUBE_NFACES], pg_error *err) {
    planet_fields(p, proj, tiles, tile_size, ell);
    pg_status st = PG_OK;
    const size_t n = (size_t)p->n, nn = n * n;
    for (int f = 0; f < PG_CUBE_NFACES && !st; f++) {
        for (int k = 0; k < 2 && !st; k++) {
            const size_t per = k ? 1 : 3, row = n * per * sizeof(float);
            pg_span s;
            st = pg_span_reserve(&s, nn * per * sizeof(float), err);
            if (st) break;
            if (k)
                p->height[f] = s.base;
            else
                p->albedo[f] = s.base;
            p->reserved_bytes[f][k] = s.bytes;
            if (y1[f] > y0[f])
                st = pg_span_open(&s, (size_t)y0[f] * row, (size_t)(y1[f] - y0[f]) * row, err);
        }
    }
    if (st) pg_planet_free(p);
    return st;
}

pg_status pg_planet_open_all_rows(pg_planet *p, pg_error *err) {
    pg_status st = PG_OK;
    for (int f = 0; f < PG_CUBE_NFACES && !st; f++) {
        pg_span a = {p->albedo[f], p->reserved_bytes[f][0]};
        pg_span h = {p->height[f], p->reserved_bytes[f][1]};
        st = pg_span_open(&a, 0, a.bytes, err);
        if (!st) st = pg_span_open(&h, 0, h.bytes, err);
    }
    return st;
}

void pg_planet_free(pg_planet *p) {
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        if (p->reserved_bytes[f][0] || p->reserved_bytes[f][1]) {
            pg_span a = {p->albedo[f], p->reserved_bytes[f][0]};
            pg_span h = {p->height[f], p->reserved_bytes[f][1]};
            pg_span_free(&a), pg_span_free(&h);
            p->reserved_bytes[f][0] = p->reserved_bytes[f][1] = 0;
        } else {
            free(p->albedo[f]);
            free(p->height[f]);
        }
        p->albedo[f] = p->height[f] = NULL;
    }
    pg_planet_source_free(p);
}

double pg_planet_bytes(int tiles, int tile_size) {
    double n = (double)tiles * tile_size;
    return 6.0 * n * n * 4.0 * sizeof(float);
}

pg_status pg_planet_from_exemplar(pg_planet *p, const pg_exemplar *ex, int samples, pg_error *err) {
    size_t nn = (size_t)p->n * (size_t)p->n;
    float *cube = malloc(6 * nn * 4 * sizeof(float));
    float *rgbh = malloc((size_t)ex->width * ex->height * 4 * sizeof(float));
    if (!cube || !rgbh) {
        free(cube);
        free(rgbh);
        return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate the reprojection buffers");
    }
    size_t np = (size_t)ex->width * ex->height;
    for (size_t i = 0; i < np; i++) {
        memcpy(rgbh + 4 * i, ex->albedo + 3 * i, 3 * sizeof(float));
        rgbh[4 * i + 3] = ex->elevation[i];
    }
    pg_status st = pg_cube_from_equirect(p->projection, p->n, &p->ellipsoid, rgbh, ex->width,
                                         ex->height, 4, samples, cube, err);
    free(rgbh);
    if (st == PG_OK) {
        for (int f = 0; f < PG_CUBE_NFACES; f++) {
            const float *src = cube + (size_t)f * nn * 4;
            for (size_t i = 0; i < nn; i++) {
                memcpy(p->albedo[f] + 3 * i, src + 4 * i, 3 * sizeof(float));
                p->height[f][i] = src[4 * i + 3];
            }
        }
        p->sea_level = ex->sea_level;
        int k = snprintf(p->exemplar, sizeof p->exemplar, "%.250s + ", ex->albedo_src);
        snprintf(p->exemplar + k, sizeof p->exemplar - (size_t)k, "%.250s", ex->height_src);
    }
    free(cube);
    return st;
}

void pg_planet_albedo_name(int face, char *buf, size_t size) {
    snprintf(buf, size, "albedo_%s.png", pg_cube_face_name(face));
}

/* Copy a face into an image with rows flipped (face rows bottom-up, images top-down). */
static void flip_rows(const float *src, float *dst, int64_t n, int ch) {
    size_t row = (size_t)n * ch;
    for (int64_t y = 0; y < n; y++)
        memcpy(dst + (size_t)(n - 1 - y) * row, src + (size_t)y * row, row * sizeof(float));
}

/* Encode face f's albedo PNG, write it to path, and keep its bytes when asked. */
static pg_status save_albedo_face(const pg_planet *p, int f, const char *path, uint8_t **keep,
                                  size_t *keep_size, pg_error *err) {
    pg_image img;
    pg_status st = pg_image_alloc(&img, (int)p->n, (int)p->n, 3, err);
    if (st != PG_OK) return st;
    flip_rows(p->albedo[f], img.data, p->n, 3);
    uint8_t *b = NULL;
    size_t n = 0;
    st = pg_image_encode_png(&img, 8, &b, &n, err);
    pg_image_free(&img);
    if (st == PG_OK) st = pg_write_file(path, b, n, err);
    if (st == PG_OK && keep) {
        *keep = b, *keep_size = n;
        return PG_OK;
    }
    free(b);
    return st;
}

void pg_planet_encoded_free(pg_planet_encoded *e) {
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        free(e->albedo_png[f]);
    memset(e, 0, sizeof *e);
}

static pg_status save_height(const pg_planet *p, const char *path, pg_error *err) {
    pg_image parts[PG_CUBE_NFACES];
    const char *names[PG_CUBE_NFACES];
    memset(parts, 0, sizeof parts);
    pg_status st = PG_OK;
    for (int f = 0; st == PG_OK && f < PG_CUBE_NFACES; f++) {
        names[f] = pg_cube_face_name(f);
        st = pg_image_alloc(&parts[f], (int)p->n, (int)p->n, 1, err);
        if (st == PG_OK) flip_rows(p->height[f], parts[f].data, p->n, 1);
    }
    if (st == PG_OK) st = pg_exr_write_parts(path, PG_CUBE_NFACES, names, parts, NULL, err);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        pg_image_free(&parts[f]);
    return st;
}

pg_json *pg_planet_meta_json(const pg_planet *p) {
    pg_json *j = pg_json_object();
    if (!j) return NULL;
    pg_json_set_number(j, "format_version", PG_PLANET_FORMAT_VERSION);
    pg_json_set_string(j, "generator", "planetgen");
    pg_json_set_number(j, "radius_m", p->ellipsoid.a);
    pg_json_set_number(j, "flattening", p->ellipsoid.f);
    pg_json_set_string(j, "projection", pg_cube_projection_name(p->projection));
    pg_json_set_number(j, "tiles", p->tiles);
    pg_json_set_number(j, "tile_size", p->tile_size);
    char seed[32];
    snprintf(seed, sizeof seed, "%llu", (unsigned long long)p->seed);
    pg_json_set_string(j, "seed", seed); /* a string: JSON numbers lose 64-bit seeds */
    pg_json_set_number(j, "sea_level_m", p->sea_level);
    pg_json_set_string(j, "exemplar", p->exemplar);
    if (isfinite(p->closed_land_share_before_final))
        pg_json_set_number(j, "closed_land_share_before_final", p->closed_land_share_before_final);
    const pg_planet_generation *g = &p->generation;
    if (g->layout[0]) {
        pg_json *o = pg_json_set_object(j, "generation");
        pg_json_set_string(o, "layout", g->layout);
        if (g->plates > 0) {
            pg_json_set_number(o, "plates", g->plates);
            pg_json_set_number(o, "land_fraction", g->land_fraction);
            pg_json_set_number(o, "axial_tilt_deg", g->axial_tilt_deg);
            pg_json_set_number(o, "temperature_offset_K", g->temperature_offset_K);
            pg_json_set_bool(o, "sea_ice", g->sea_ice);
        }
        pg_json_set_number(o, "jitter", g->jitter);
        pg_json_set_number(o, "passes", g->passes);
        pg_json_set_number(o, "grid_shape", g->grid_shape);
    }
    return j;
}

pg_status pg_planet_write_json(pg_json *j, const char *name, pg_planet_path_fn path_for, void *user,
                               pg_error *err) {
    const char *path = j ? path_for(name, user) : NULL;
    FILE *fp = path ? fopen(path, "w") : NULL;
    pg_status st = PG_OK;
    if (!fp) {
        st = j ? pg_error_set(err, PG_ERR_IO, "%s: cannot write", name)
               : pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", name);
    } else {
        int wr = pg_json_write(j, fp);
        if (fclose(fp) != 0 || wr != 0)
            st = pg_error_set(err, PG_ERR_IO, "%s: write failed (disk full?)", path);
    }
    pg_json_free(j);
    return st;
}

/* ---- the coordinate map: source.exr ---- */

#define SOURCE_NAME "source.exr"
static const char *const source_channels[3] = {"face", "u", "v"};

/* File rows y0.. of face `part` (top-down) as interleaved face, u, v. */
static void fill_source_rows(int part, int y0, int rows, uint32_t *buf, void *user) {
    const pg_planet *p = user;
    const int64_t n = p->n;
    for (int r = 0; r < rows; r++) {
        const uint32_t *src = p->source.coords[part] + (size_t)(n - 1 - (y0 + r)) * (size_t)n;
        uint32_t *dst = buf + (size_t)r * (size_t)n * 3;
        for (int64_t x = 0; x < n; x++) {
            dst[3 * x] = (uint32_t)pg_synth_face(src[x]);
            dst[3 * x + 1] = (uint32_t)pg_synth_u(src[x]);
            dst[3 * x + 2] = (uint32_t)pg_synth_v(src[x]);
        }
    }
}

static pg_status save_source(const pg_planet *p, const char *path, pg_error *err) {
    const char *names[PG_CUBE_NFACES];
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        names[f] = pg_cube_face_name(f);
    return pg_exr_write_uint_parts(path, PG_CUBE_NFACES, names, (int)p->n, (int)p->n, 3,
                                   source_channels, fill_source_rows, (void *)p, err);
}

static pg_status save_meta(const pg_planet *p, pg_planet_path_fn path_for, void *user,
                           pg_error *err) {
    pg_json *j = pg_planet_meta_json(p);
    if (j) {
        pg_json *faces = pg_json_set_array(j, "faces");
        for (int f = 0; f < PG_CUBE_NFACES; f++)
            pg_json_push_string(faces, pg_cube_face_name(f));
        if (pg_planet_has_source(p)) {
            pg_json *src = pg_json_set_object(j, "source");
            pg_json_set_string(src, "file", SOURCE_NAME);
            pg_json_set_number(src, "exemplar_face_size", p->source.face_size);
            pg_json_set_string(src, "exemplar_projection",
                               pg_cube_projection_name(p->source.projection));
        }
    }
    return pg_planet_write_json(j, PG_PLANET_META_NAME, path_for, user, err);
}

/* The files of a planet, written at once (docs/generate.md, "Performance"): every
 * encoder (zlib inside PNG and the coordinate map's ZIP) is single-threaded, and each
 * file is written by one thread from data no other thread writes, so the bytes are those
 * of a serial run. The paths are taken first, in a fixed order, because path_for need
 * not be thread-safe; the first failure in that order is reported. */
enum { SAVE_SOURCE = PG_CUBE_NFACES, SAVE_HEIGHT, SAVE_JOBS };

pg_status pg_planet_save(const pg_planet *p, pg_planet_path_fn path_for, void *user,
                         pg_error *err) {
    return pg_planet_save_encoded(p, path_for, user, NULL, err);
}

pg_status pg_planet_save_encoded(const pg_planet *p, pg_planet_path_fn path_for, void *user,
                                 pg_planet_encoded *keep, pg_error *err) {
    if (keep) memset(keep, 0, sizeof *keep);
    char paths[SAVE_JOBS][4096];
    bool has_source = pg_planet_has_source(p);
    for (int j = 0; j < SAVE_JOBS; j++) {
        char name[64];
        if (j < PG_CUBE_NFACES)
            pg_planet_albedo_name(j, name, sizeof name);
        else
            snprintf(name, sizeof name, "%s",
                     j == SAVE_HEIGHT ? PG_PLANET_HEIGHT_NAME : SOURCE_NAME);
        const char *path = j == SAVE_SOURCE && !has_source ? "" : path_for(name, user);
        if (!path) return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
        snprintf(paths[j], sizeof paths[j], "%s", path);
    }
    pg_status sk[SAVE_JOBS];
    pg_error e[SAVE_JOBS];
    memset(e, 0, sizeof e);
    /* the coordinate map first: its ZIP encoding is the longest job */
#pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < SAVE_JOBS; k++) {
        int j = (k + SAVE_SOURCE) % SAVE_JOBS; /* source, height, then the faces */
        if (j < PG_CUBE_NFACES)
            sk[j] = save_albedo_face(p, j, paths[j], keep ? &keep->albedo_png[j] : NULL,
                                     keep ? &keep->albedo_png_size[j] : NULL, &e[j]);
        else if (j == SAVE_HEIGHT)
            sk[j] = save_height(p, paths[j], &e[j]);
        else
            sk[j] = has_source ? save_source(p, paths[j], &e[j]) : PG_OK;
    }
    pg_status st = PG_OK;
    for (int j = 0; st == PG_OK && j < SAVE_JOBS; j++)
        if (sk[j] != PG_OK) st = pg_error_set(err, sk[j], "%s", e[j].msg);
    if (st == PG_OK) st = save_meta(p, path_for, user, err);
    if (st != PG_OK && keep) pg_planet_encoded_free(keep);
    return st;
}

const char *pg_planet_dir_path(const char *name, void *user) {
    pg_planet_dir_paths *d = user;
    snprintf(d->buf, sizeof d->buf, "%s/%s", d->dir, name);
    return d->buf;
}

pg_status pg_planet_save_dir(const pg_planet *p, const char *dir, pg_error *err) {
    pg_planet_dir_paths d = {.dir = dir};
    return pg_planet_save(p, pg_planet_dir_path, &d, err);
}

static pg_status load_faces(const char *dir, pg_planet *p, pg_error *err) {
    char path[4096];
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        char name[64];
        pg_planet_albedo_name(f, name, sizeof name);
        snprintf(path, sizeof path, "%s/%s", dir, name);
        pg_image img;
        pg_status st = pg_image_read(path, 0, &img, err);
        if (st != PG_OK) return st;
        if (img.width != p->n || img.height != p->n || img.channels < 3) {
            pg_image_free(&img);
            return pg_error_set(err, PG_ERR_BADINPUT, "%s: expected %lldx%lld RGB", path,
                                (long long)p->n, (long long)p->n);
        }
        float *rgb = malloc((size_t)p->n * p->n * 3 * sizeof(float));
        for (size_t i = 0; rgb && i < (size_t)p->n * p->n; i++)
            for (int c = 0; c < 3; c++)
                rgb[3 * i + c] = img.data[i * img.channels + c] * img.unit_scale;
        if (rgb) flip_rows(rgb, p->albedo[f], p->n, 3);
        free(rgb);
        pg_image_free(&img);
        snprintf(path, sizeof path, "%s/%s", dir, PG_PLANET_HEIGHT_NAME);
        st = pg_image_read_exr(path, pg_cube_face_name(f), &img, err);
        if (st != PG_OK) return st;
        if (img.width != p->n || img.height != p->n || img.channels != 1) {
            pg_image_free(&img);
            return pg_error_set(err, PG_ERR_BADINPUT, "%s: part %s is not %lldx%lld", path,
                                pg_cube_face_name(f), (long long)p->n, (long long)p->n);
        }
        flip_rows(img.data, p->height[f], p->n, 1);
        pg_image_free(&img);
    }
    return PG_OK;
}

/* Reading one face of source.exr: rows arrive top-down and are checked against the
 * exemplar cube planet.json names before they are packed. */
typedef struct source_reader {
    pg_planet *p;
    int face;
    const char *path;
} source_reader;

static pg_status take_source_rows(int y0, int rows, const uint32_t *buf, void *user,
                                  pg_error *err) {
    const source_reader *r = user;
    const int64_t n = r->p->n;
    const uint32_t e = (uint32_t)r->p->source.face_size;
    for (int k = 0; k < rows; k++) {
        const uint32_t *row = buf + (size_t)k * (size_t)n * 3;
        uint32_t *dst = r->p->source.coords[r->face] + (size_t)(n - 1 - (y0 + k)) * (size_t)n;
        for (int64_t x = 0; x < n; x++) {
            const uint32_t *c = row + 3 * x;
            if (c[0] >= PG_CUBE_NFACES || c[1] >= e || c[2] >= e)
                return pg_error_set(err, PG_ERR_BADINPUT,
                                    "%s: part %s, pixel (%lld, %d): (face %u, u %u, v %u) outside "
                                    "faces 0..5 and texels 0..%u of the exemplar cube",
                                    r->path, pg_cube_face_name(r->face), (long long)x, y0 + k, c[0],
                                    c[1], c[2], e - 1);
            dst[x] = pg_synth_pack((int)c[0], (int)c[1], (int)c[2]);
        }
    }
    return PG_OK;
}

static pg_status load_source(const char *dir, const pg_planet_meta *meta, pg_planet *p,
                             pg_error *err) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, meta->source_file);
    pg_cube_projection proj;
    pg_status st = pg_cube_projection_parse(
        meta->source_projection, PG_PLANET_META_NAME " source.exemplar_projection", &proj, err);
    if (st == PG_OK) st = pg_planet_source_alloc(p, meta->source_face_size, proj, err);
    for (int f = 0; st == PG_OK && f < PG_CUBE_NFACES; f++) {
        source_reader r = {p, f, path};
        st = pg_exr_read_uint_part(path, pg_cube_face_name(f), (int)p->n, (int)p->n, 3,
                                   source_channels, take_source_rows, &r, err);
    }
    if (st != PG_OK) pg_planet_source_free(p);
    return st;
}

/* Every file the planet directory must hold: the faces, height.exr and the map that
 * planet.json names. The error names the first one missing. */
static pg_status check_files(const char *dir, const pg_planet_meta *meta, pg_error *err) {
    char path[4096];
    struct stat st;
    for (int f = 0; f <= PG_CUBE_NFACES + 1; f++) {
        char name[300];
        if (f < PG_CUBE_NFACES)
            pg_planet_albedo_name(f, name, sizeof name);
        else if (f == PG_CUBE_NFACES)
            snprintf(name, sizeof name, "%s", PG_PLANET_HEIGHT_NAME);
        else if (meta->has_source)
            snprintf(name, sizeof name, "%s", meta->source_file);
        else
            break;
        snprintf(path, sizeof path, "%s/%s", dir, name);
        if (stat(path, &st) != 0)
            return pg_error_set(err, PG_ERR_BADINPUT, "%s: missing %s", dir, name);
    }
    return PG_OK;
}

pg_drainage_terrain pg_planet_drainage_terrain(const pg_planet *p) {
    pg_drainage_terrain t = {.n = p->n,
                             .projection = p->projection,
                             .ellipsoid = p->ellipsoid,
                             .sea_level = p->sea_level};
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        t.height[f] = p->height[f];
    return t;
}

pg_status pg_planet_alloc_meta(const pg_planet_meta *meta, const char *file, pg_planet *p,
                               pg_error *err) {
    pg_cube_projection proj;
    pg_status s = pg_cube_projection_parse(meta->projection, file, &proj, err);
    if (s == PG_OK)
        s = pg_planet_alloc(p, proj, meta->tiles, meta->tile_size, meta->ellipsoid, err);
    if (s != PG_OK) return s;
    p->seed = meta->seed;
    p->sea_level = (float)meta->sea_level;
    snprintf(p->exemplar, sizeof p->exemplar, "%s", meta->exemplar);
    p->closed_land_share_before_final = meta->closed_land_share_before_final;
    return PG_OK;
}

pg_status pg_planet_load(const char *dir, pg_planet *p, pg_error *err) {
    memset(p, 0, sizeof *p);
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: not a directory", dir);
    if (pg_planet_dir_is_tiled(dir)) return pg_planet_load_tiles(dir, p, err);
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, PG_PLANET_META_NAME);
    if (stat(path, &st) != 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: not a planet output (no %s)", dir,
                            PG_PLANET_META_NAME);
    pg_planet_meta meta;
    pg_status s = pg_planet_meta_read(path, &meta, err);
    if (s != PG_OK) return s;
    /* check every expected file first, so the error names the missing one */
    s = check_files(dir, &meta, err);
    if (s != PG_OK) return s;
    /* The face images must have the size planet.json claims, checked from their
     * headers before the planet is allocated: a damaged or hostile planet.json must
     * not make us allocate terabytes. */
    int64_t n = (int64_t)meta.tiles * meta.tile_size;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        char name[64];
        int w, h, c;
        pg_planet_albedo_name(f, name, sizeof name);
        snprintf(path, sizeof path, "%s/%s", dir, name);
        s = pg_image_probe(path, &w, &h, &c, err);
        if (s != PG_OK) return s;
        if (w != n || h != n)
            return pg_error_set(err, PG_ERR_BADINPUT, "%s: %dx%d, but %s says %lldx%lld", path, w,
                                h, PG_PLANET_META_NAME, (long long)n, (long long)n);
    }
    s = pg_planet_alloc_meta(&meta, PG_PLANET_META_NAME, p, err);
    if (s != PG_OK) return s;
    s = load_faces(dir, p, err);
    if (s == PG_OK && meta.has_source) s = load_source(dir, &meta, p, err);
    if (s != PG_OK) pg_planet_free(p);
    return s;
}
