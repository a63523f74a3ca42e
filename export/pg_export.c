/* pg_export.c - export a planet: options, their checks, and the writing of the
 * glTF globe, the EXR heights and the previews; see pg_export.h.
 *
 * The .glb is assembled face by face so that only one face's full-resolution
 * images exist as floats at a time: the albedo, the normal map and the 16-bit
 * height are encoded (PNG/JPEG bytes in memory) and the floats freed before the
 * next face. The encoded bytes then go to the tinygltf adapter (pg_gltf.cpp), or to
 * separate files with --external-textures. */
#include "pg_huge.h"
#include "pg_export_encode.h"
#include "pg_export_internal.h"
#include "pg_gltf.h"

#include "planetgen/pg_exr.h"
#include "planetgen/pg_planet_tiles.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void pg_export_opts_default(pg_export_opts *o) {
    memset(o, 0, sizeof *o);
    o->exaggeration = PG_EXPORT_DEFAULT_EXAGGERATION;
    o->texture_format = PG_EXPORT_TEXTURE_PNG;
    o->jpeg_quality = 90;
    o->glb = o->exr = o->previews = true;
    o->globe_size = 512;
}

int pg_export_default_mesh_res(int tiles, int tile_size) {
    int best = tiles;
    for (int m = 1; m <= tile_size; m *= 2) {
        double tri = 12.0 * (double)tiles * m * (double)tiles * m;
        if (tile_size % m == 0 && tri <= 1.5 * PG_EXPORT_TARGET_TRIANGLES) best = tiles * m;
    }
    return best;
}

pg_status pg_export_texture_format_parse(const char *name, const char *option,
                                         pg_export_texture_format *out, pg_error *err) {
    if (!strcmp(name, "png")) {
        *out = PG_EXPORT_TEXTURE_PNG;
    } else if (!strcmp(name, "jpeg") || !strcmp(name, "jpg")) {
        *out = PG_EXPORT_TEXTURE_JPEG;
    } else {
        return pg_error_set(err, PG_ERR_BADINPUT, "%s '%s': unknown texture format (png, jpeg)",
                            option, name);
    }
    return PG_OK;
}

pg_status pg_export_check_opts(const pg_export_opts *o, int tiles, int tile_size, pg_error *err) {
    int64_t n = (int64_t)tiles * tile_size;
    int m = o->mesh_res ? o->mesh_res : pg_export_default_mesh_res(tiles, tile_size);
    if (m < 1 || m % tiles != 0 || n % m != 0)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--mesh-res %d: must be a multiple of the planet's %d tiles per face "
                            "edge that divides its %lld texels per face edge (e.g. %d)",
                            m, tiles, (long long)n, pg_export_default_mesh_res(tiles, tile_size));
    if (12 * (int64_t)m * m > PG_EXPORT_MAX_TRIANGLES)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--mesh-res %d: %lld triangles exceed the limit of %lld", m,
                            (long long)(12 * (int64_t)m * m), (long long)PG_EXPORT_MAX_TRIANGLES);
    if (!(o->exaggeration >= 0 && o->exaggeration <= PG_EXPORT_MAX_EXAGGERATION))
        return pg_error_set(err, PG_ERR_BADINPUT, "--exaggeration %g: must be in [0, %g]",
                            o->exaggeration, PG_EXPORT_MAX_EXAGGERATION);
    if (o->texture_format == PG_EXPORT_TEXTURE_JPEG &&
        (o->jpeg_quality < 1 || o->jpeg_quality > 100))
        return pg_error_set(err, PG_ERR_BADINPUT, "JPEG quality %d: must be in 1..100",
                            o->jpeg_quality);
    if (o->preview_width < 0 || o->preview_width > 65536 || o->preview_width % 2)
        return pg_error_set(err, PG_ERR_BADINPUT, "preview width %d: must be even, <= 65536",
                            o->preview_width);
    if (o->globe_size < 0 || o->globe_size > 16384)
        return pg_error_set(err, PG_ERR_BADINPUT, "globe size %d: must be <= 16384", o->globe_size);
    return PG_OK;
}

static void height_range(const pg_planet *p, double *lo, double *hi) {
    double mn = INFINITY, mx = -INFINITY;
    const int64_t n = p->n;
#pragma omp parallel for collapse(2) schedule(static) reduction(min : mn) reduction(max : mx)
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                double h = p->height[f][y * n + x];
                mn = h < mn ? h : mn;
                mx = h > mx ? h : mx;
            }
    *lo = mn, *hi = mx;
}

/* Heights lo..hi (of the planet, or of a tile: `what`) finite, and their exaggerated
 * relief below a quarter of the radius, or the globe would fold through itself. */
static pg_status check_relief(const pg_export_opts *o, const pg_planet *p, double lo, double hi,
                              const char *what, pg_error *err) {
    if (!isfinite(lo) || !isfinite(hi))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s heights are not finite", what);
    double top = fmax(fabs(hi > p->sea_level ? hi : p->sea_level), fabs(lo));
    if (top * o->exaggeration >= 0.25 * p->ellipsoid.a)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--exaggeration %g: relief of %.0f m would reach %.0f km, over a "
                            "quarter of the %.0f km radius",
                            o->exaggeration, top, top * o->exaggeration / 1000,
                            p->ellipsoid.a / 1000);
    return PG_OK;
}

pg_status pg_export_check_planet(const pg_export_opts *o, const pg_planet *p, pg_error *err) {
    pg_status st = pg_export_check_opts(o, p->tiles, p->tile_size, err);
    if (st != PG_OK) return st;
    double lo, hi;
    height_range(p, &lo, &hi);
    return check_relief(o, p, lo, hi, "planet", err);
}

/* ---- the glTF globe, and the glTF file of one tile ---- */

typedef struct glb_images {
    pg_gltf_image img[3 * PG_CUBE_NFACES]; /* per primitive: albedo, normal, height */
    uint8_t *bytes[3 * PG_CUBE_NFACES];
    char names[3 * PG_CUBE_NFACES][64];
    char uris[3 * PG_CUBE_NFACES][64];
} glb_images;

static const char *const face_tag[PG_CUBE_NFACES] = {"px", "nx", "py", "ny", "pz", "nz"};

/* What a .glb shows: the globe (six faces) or one tile of face `face` covering the
 * texels [x0, x0 + w)^2, and where its heights come from. */
typedef struct glb_part {
    const pg_planet *p;
    const pg_export_heights *h;
    const pg_cube_grid *g;
    const pg_export_mesh *mesh;
    int64_t x0, y0, w; /* texel window of each primitive (the globe: 0, 0, n) */
    char tag[32];      /* "" for the globe, "_+X_TX_TY" for a tile */
} glb_part;

static int part_face(const glb_part *gp, int k) {
    return gp->mesh->nprims == 1 ? gp->mesh->face : k;
}

/* Name slot k, the image of primitive k/3. */
static void name_slot(const glb_part *gp, glb_images *gi, int k, const char *kind,
                      pg_export_codec codec) {
    int face = part_face(gp, k / 3);
    const char *ext = codec == PG_EXPORT_CODEC_JPEG ? "jpg" : "png";
    if (gp->tag[0])
        snprintf(gi->names[k], sizeof gi->names[k], "%s%s", kind, gp->tag);
    else
        snprintf(gi->names[k], sizeof gi->names[k], "%s_%s", kind, pg_cube_face_name(face));
    snprintf(gi->uris[k], sizeof gi->uris[k], "planet_%s_%s.%s", kind, face_tag[face], ext);
    gi->img[k].name = gi->names[k];
    gi->img[k].mime = codec == PG_EXPORT_CODEC_JPEG ? "image/jpeg" : "image/png";
}

/* Encode one image of primitive k/3 into slot k and name it. */
static pg_status encode_slot(const glb_part *gp, glb_images *gi, int k, const char *kind,
                             const float *data, int ch, int bits, pg_export_codec codec,
                             int quality, pg_error *err) {
    name_slot(gp, gi, k, kind, codec);
    return pg_export_encode(data, (int)gp->w, (int)gp->w, ch, bits, true, codec, quality,
                            gi->uris[k], &gi->bytes[k], &gi->img[k].size, err);
}

/* Slot k from albedo PNG bytes the caller encoded already (a copy: slots own theirs). */
static pg_status reuse_slot(const glb_part *gp, glb_images *gi, int k, const uint8_t *png,
                            size_t size, pg_error *err) {
    name_slot(gp, gi, k, "albedo", PG_EXPORT_CODEC_PNG);
    gi->bytes[k] = malloc(size);
    if (!gi->bytes[k]) return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate textures");
    memcpy(gi->bytes[k], png, size);
    gi->img[k].size = size;
    return PG_OK;
}

/* The window's texels of a face array (ch floats a texel), rows bottom-up. */
static float *cut_window(const glb_part *gp, const float *face, int ch) {
    size_t w = (size_t)gp->w;
    float *out = pg_huge_malloc(w * w * (size_t)ch * sizeof(float));
    for (size_t y = 0; out && y < w; y++)
        memcpy(out + y * w * ch,
               face + (((size_t)gp->y0 + y) * (size_t)gp->p->n + (size_t)gp->x0) * ch,
               w * ch * sizeof(float));
    return out;
}

/* One of the three images of a primitive (k: 0 albedo, 1 normal map, 2 normalised
 * heights), its input computed inside the job: encodings are single-threaded (zlib), so
 * the images are encoded in parallel, and only the jobs in flight hold a face's float
 * buffer. The normal map's own loops run on the job's thread alone then; each texel is
 * computed the same way on any thread, so the bytes are those of a serial run. */
static pg_status encode_job(const glb_part *gp, const pg_export_opts *o, double lo, double scale,
                            int prim, int k, glb_images *gi, pg_error *err) {
    static const char *const kind[3] = {"albedo", "normal", "height"};
    static const int ch[3] = {3, 3, 1}, bits[3] = {8, 8, 16};
    const pg_planet *p = gp->p;
    const int f = part_face(gp, prim);
    const bool whole = gp->w == p->n;
    size_t nn = (size_t)gp->w * (size_t)gp->w;
    pg_export_codec codec = PG_EXPORT_CODEC_PNG;
    if (k == 0 && o->texture_format == PG_EXPORT_TEXTURE_JPEG) codec = PG_EXPORT_CODEC_JPEG;
    if (k == 0 && whole && codec == PG_EXPORT_CODEC_PNG && o->albedo_png &&
        o->albedo_png->albedo_png[f])
        return reuse_slot(gp, gi, 3 * prim, o->albedo_png->albedo_png[f],
                          o->albedo_png->albedo_png_size[f], err);
    float *data = NULL;
    if (k == 0)
        data = whole ? p->albedo[f] : cut_window(gp, p->albedo[f], 3);
    else if (k == 2 && !whole)
        data = cut_window(gp, p->height[f], 1);
    else
        data = pg_huge_malloc(nn * (size_t)ch[k] * sizeof(float));
    pg_status st = data ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "cannot allocate textures");
    if (st == PG_OK && k == 1)
        st = pg_export_normal_map(gp->h, gp->g, gp->mesh, o->exaggeration, f, gp->x0, gp->y0, gp->w,
                                  data, err);
    if (st == PG_OK && k == 2)
        for (size_t i = 0; i < nn; i++)
            data[i] = (float)(((whole ? p->height[f][i] : data[i]) - lo) / scale);
    if (st == PG_OK)
        st = encode_slot(gp, gi, 3 * prim + k, kind[k], data, ch[k], bits[k], codec,
                         o->jpeg_quality, err);
    if (data != p->albedo[f]) free(data);
    return st;
}

/* All images; the first failure in primitive order is reported. */
static pg_status encode_prims(const glb_part *gp, const pg_export_opts *o, double lo, double scale,
                              glb_images *gi, pg_error *err) {
    const int njobs = 3 * gp->mesh->nprims;
    pg_status sk[3 * PG_CUBE_NFACES];
    pg_error e[3 * PG_CUBE_NFACES];
    memset(e, 0, sizeof e);
#pragma omp parallel for schedule(dynamic, 1)
    for (int j = 0; j < njobs; j++)
        sk[j] = encode_job(gp, o, lo, scale, j / 3, j % 3, gi, &e[j]);
    for (int j = 0; j < njobs; j++)
        if (sk[j] != PG_OK) return pg_error_set(err, sk[j], "%s", e[j].msg);
    return PG_OK;
}

static void set_extra_num(pg_gltf_extra *e, const char *key, double v, int is_int) {
    e->key = key, e->string = NULL, e->number = v, e->is_int = is_int;
}

static void set_extra_str(pg_gltf_extra *e, const char *key, const char *s) {
    e->key = key, e->string = s, e->number = 0, e->is_int = 0;
}

static void describe_primitives(const glb_part *gp, double lo, double scale,
                                pg_gltf_primitive prims[PG_CUBE_NFACES],
                                char names[PG_CUBE_NFACES][32]) {
    const pg_export_mesh *mesh = gp->mesh;
    const int S = gp->p->tile_size;
    for (int k = 0; k < mesh->nprims; k++) {
        int f = part_face(gp, k);
        pg_gltf_primitive *q = &prims[k];
        memset(q, 0, sizeof *q);
        if (gp->tag[0])
            snprintf(names[k], 32, "tile %s %d %d", pg_cube_face_name(f), (int)(gp->x0 / S),
                     (int)(gp->y0 / S));
        else
            snprintf(names[k], 32, "face %s", pg_cube_face_name(f));
        q->material_name = names[k];
        q->nverts = mesh->nv;
        q->positions = mesh->pos[k];
        q->normals = mesh->nrm[k];
        q->tangents = mesh->tan[k];
        q->texcoords = mesh->uv;
        q->nindices = mesh->ni;
        q->indices = mesh->idx;
        q->base_color_image = 3 * k;
        q->normal_image = 3 * k + 1;
        q->nextras = 4;
        set_extra_num(&q->extras[0], "heightTexture", 3 * k + 2, 1);
        set_extra_num(&q->extras[1], "heightScale", scale, 0);
        set_extra_num(&q->extras[2], "heightOffset", lo, 0);
        set_extra_str(&q->extras[3], "face", pg_cube_face_name(f));
        if (gp->tag[0]) {
            q->nextras = 6;
            set_extra_num(&q->extras[4], "tile_x", (double)(gp->x0 / S), 1);
            set_extra_num(&q->extras[5], "tile_y", (double)(gp->y0 / S), 1);
        }
    }
}

/* Scene extras: the planet parameters, for tools that read the .glb alone. */
static int scene_extras(const pg_planet *p, const pg_export_opts *o, int m, char *seed,
                        pg_gltf_extra *e) {
    snprintf(seed, 32, "%llu", (unsigned long long)p->seed);
    set_extra_num(&e[0], "radius_m", p->ellipsoid.a, 0);
    set_extra_num(&e[1], "flattening", p->ellipsoid.f, 0);
    set_extra_str(&e[2], "projection", pg_cube_projection_name(p->projection));
    set_extra_num(&e[3], "tiles", p->tiles, 1);
    set_extra_num(&e[4], "tile_size", p->tile_size, 1);
    set_extra_str(&e[5], "seed", seed);
    set_extra_str(&e[6], "exemplar", p->exemplar);
    set_extra_num(&e[7], "sea_level_m", p->sea_level, 0);
    set_extra_num(&e[8], "exaggeration", o->exaggeration, 0);
    set_extra_num(&e[9], "mesh_res", m, 1);
    return 10;
}

static pg_status write_glb(const glb_part *gp, const pg_export_opts *o, double lo, double hi,
                           const char *name, pg_planet_path_fn path_for, void *user,
                           pg_export_result *res, pg_error *err) {
    const pg_planet *p = gp->p;
    const pg_export_mesh *mesh = gp->mesh;
    const int nimg = 3 * mesh->nprims;
    double scale = hi > lo ? hi - lo : 1.0;
    glb_images *gi = calloc(1, sizeof *gi);
    if (!gi) return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    pg_status st = PG_OK;
    st = encode_prims(gp, o, lo, scale, gi, err);
    double embedded = 0; /* bytes of the binary chunk: images plus the mesh */
    for (int k = 0; k < nimg; k++)
        embedded += (double)gi->img[k].size;
    embedded += mesh->nprims * (double)mesh->nv * 12 * sizeof(float) + mesh->ni * sizeof(uint32_t);
    if (st == PG_OK && !o->external_textures && embedded > 4.0e9) /* the .glb limit: 2^32 */
        st = pg_error_set(err, PG_ERR_BADINPUT,
                          "%s: %.1f GB of textures do not fit a .glb (4 GiB at most); use "
                          "--external-textures",
                          name, embedded / 1e9);
    for (int k = 0; st == PG_OK && k < nimg; k++) {
        gi->img[k].bytes = gi->bytes[k];
        if (!o->external_textures || gp->tag[0]) continue; /* a tile's images: embedded */
        gi->img[k].uri = gi->uris[k];
        const char *path = path_for(gi->uris[k], user);
        st = path ? pg_write_file(path, gi->bytes[k], gi->img[k].size, err)
                  : pg_error_set(err, PG_ERR_NOMEM, "out of memory");
        res->nfiles++;
    }
    pg_gltf_primitive prims[PG_CUBE_NFACES];
    char names[PG_CUBE_NFACES][32], seed[32], mesh_name[48];
    pg_gltf_extra extras[13];
    describe_primitives(gp, lo, scale, prims, names);
    int nextras = scene_extras(p, o, mesh->m, seed, extras);
    snprintf(mesh_name, sizeof mesh_name, "planet%s", gp->tag);
    if (gp->tag[0]) { /* which tile of the globe this file holds */
        set_extra_str(&extras[nextras++], "tile_face", pg_cube_face_name(mesh->face));
        set_extra_num(&extras[nextras++], "tile_x", (double)(gp->x0 / p->tile_size), 1);
        set_extra_num(&extras[nextras++], "tile_y", (double)(gp->y0 / p->tile_size), 1);
    }
    /* ECEF has +Z north; glTF has +Y up: rotate -90 degrees about X */
    const double rot[4] = {-sqrt(0.5), 0, 0, sqrt(0.5)};
    char generator[64];
    snprintf(generator, sizeof generator, "planetgen %s", pg_version());
    pg_gltf_desc d = {generator, mesh_name, rot,     mesh->nprims, prims,
                      nimg,      gi->img,   nextras, extras};
    const char *path = st == PG_OK ? path_for(name, user) : NULL;
    if (st == PG_OK && !path) st = pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    if (st == PG_OK) st = pg_gltf_write_glb(path, &d, err);
    if (st == PG_OK) {
        struct stat sb;
        res->glb_bytes += stat(path, &sb) == 0 ? (double)sb.st_size : 0;
        res->nfiles++;
    }
    for (int k = 0; k < nimg; k++)
        free(gi->bytes[k]);
    free(gi);
    return st;
}

static pg_status export_glb(const pg_planet *p, const pg_export_opts *o, int m, double lo,
                            double hi, pg_planet_path_fn path_for, void *user,
                            pg_export_result *res, pg_error *err) {
    pg_cube_grid g;
    pg_status st = pg_cube_grid_init(&g, p->projection, p->tiles, p->tile_size, err);
    pg_export_mesh mesh;
    if (st == PG_OK) st = pg_export_mesh_build(p, &g, m, o->exaggeration, &mesh, err);
    if (st != PG_OK) return st;
    res->vertices = 6 * (int64_t)mesh.nv;
    res->triangles = 2 * (int64_t)mesh.ni;
    pg_export_heights hs;
    pg_export_heights_whole(p, &hs);
    glb_part gp = {p, &hs, &g, &mesh, 0, 0, p->n, ""};
    st = write_glb(&gp, o, lo, hi, PG_EXPORT_GLB_NAME, path_for, user, res, err);
    pg_export_mesh_free(&mesh);
    return st;
}

pg_status pg_export_tile_glb_write(const pg_export_heights *h, const pg_cube_grid *g,
                                   const pg_export_opts *o, int64_t t, pg_planet_path_fn path_for,
                                   void *user, pg_export_result *res, pg_error *err) {
    const pg_planet *p = h->p;
    const int T = p->tiles, S = p->tile_size;
    const int m = o->mesh_res ? o->mesh_res : pg_export_default_mesh_res(T, S);
    const int f = (int)(t / ((int64_t)T * T)), tx = (int)(t % T), ty = (int)(t / T % T);
    glb_part gp = {p, h, g, NULL, (int64_t)tx * S, (int64_t)ty * S, S, ""};
    snprintf(gp.tag, sizeof gp.tag, "_%s_%d_%d", pg_cube_face_name(f), tx, ty);
    /* the tile's own height range: its file stands alone, whatever the other tiles hold */
    double lo = INFINITY, hi = -INFINITY;
    for (int64_t y = gp.y0; y < gp.y0 + S; y++)
        for (int64_t x = gp.x0; x < gp.x0 + S; x++) {
            double v = p->height[f][y * p->n + x];
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
    char what[48];
    snprintf(what, sizeof what, "tile %s %d %d", pg_cube_face_name(f), tx, ty);
    pg_status st = check_relief(o, p, lo, hi, what, err);
    if (st != PG_OK) return st;
    pg_export_mesh mesh;
    st = pg_export_mesh_build_tile(h, g, m, o->exaggeration, t, &mesh, err);
    if (st != PG_OK) return st;
    gp.mesh = &mesh;
    char name[64];
    pg_planet_tile_glb_name(p, (int)t, name);
    if (res) {
        res->mesh_res = m;
        res->exaggeration = o->exaggeration;
        res->vertices += mesh.nv;
        res->triangles += mesh.ni / 3;
    }
    pg_export_result local = {0};
    st = write_glb(&gp, o, lo, hi, name, path_for, user, res ? res : &local, err);
    pg_export_mesh_free(&mesh);
    return st;
}

static pg_status export_exr(const pg_planet *p, pg_planet_path_fn path_for, void *user,
                            pg_export_result *res, pg_error *err) {
    pg_image parts[PG_CUBE_NFACES];
    const char *names[PG_CUBE_NFACES];
    memset(parts, 0, sizeof parts);
    pg_status st = PG_OK;
    size_t row = (size_t)p->n;
    for (int f = 0; st == PG_OK && f < PG_CUBE_NFACES; f++) {
        names[f] = pg_cube_face_name(f);
        st = pg_image_alloc(&parts[f], (int)p->n, (int)p->n, 1, err);
        for (int64_t y = 0; st == PG_OK && y < p->n; y++) /* image rows top-down */
            memcpy(parts[f].data + (size_t)(p->n - 1 - y) * row, p->height[f] + (size_t)y * row,
                   row * sizeof(float));
    }
    const char *path = st == PG_OK ? path_for(PG_PLANET_HEIGHT_NAME, user) : NULL;
    if (st == PG_OK && !path) st = pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    if (st == PG_OK) st = pg_exr_write_parts(path, PG_CUBE_NFACES, names, parts, NULL, err);
    if (st == PG_OK) res->nfiles++;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        pg_image_free(&parts[f]);
    return st;
}

pg_status pg_export_write(const pg_planet *p, const pg_export_opts *o, pg_planet_path_fn path_for,
                          void *user, pg_export_result *res, pg_error *err) {
    pg_export_result local;
    if (!res) res = &local;
    memset(res, 0, sizeof *res);
    pg_status st = pg_export_check_opts(o, p->tiles, p->tile_size, err);
    if (st != PG_OK) return st;
    height_range(p, &res->height_min, &res->height_max);
    st = check_relief(o, p, res->height_min, res->height_max, "planet", err);
    if (st != PG_OK) return st;
    int m = o->mesh_res ? o->mesh_res : pg_export_default_mesh_res(p->tiles, p->tile_size);
    res->mesh_res = m;
    res->exaggeration = o->exaggeration;
    if (o->glb)
        st = export_glb(p, o, m, res->height_min, res->height_max, path_for, user, res, err);
    if (st == PG_OK && o->exr) st = export_exr(p, path_for, user, res, err);
    if (st == PG_OK && o->previews)
        st = pg_export_previews(p, o, path_for, user, &res->nfiles, err);
    if (st == PG_OK && o->geotiff) st = pg_export_geotiff(p, o, path_for, user, &res->nfiles, err);
    return st;
}
