/* cmd_export.c - `planetgen export DIR`: re-export an existing planet directory as a
 * glTF globe (planet.glb), float heights (height.exr) and previews, with other mesh
 * or texture options than `generate` used, and/or (--format geotiff) as GIS rasters:
 * equirectangular GeoTIFFs, one pair per tile plus VRT mosaics for a tiled planet.
 *
 * Everything the user can get wrong is checked before the planet is loaded: the
 * options against the planet's grid from planet.json (a mesh resolution must fit
 * its tiles and texels), then the exaggeration against the loaded heights. All
 * files are staged under temporary names and renamed at the end, so an export into
 * a directory that already holds one replaces each file atomically, and a failed
 * export leaves the old files untouched. */
#include "pg_commands.h"

#include "pg_planet_meta.h"
#include "planetgen/pg_export.h"
#include "planetgen/pg_json.h"
#include "planetgen/pg_planet_tiles.h"

#include <stdio.h>
#include <string.h>

typedef struct export_args {
    const char *outdir, *texture_format, *format;
    long mesh_res, jpeg_quality, globe_size;
    double exaggeration, max_memory_gb;
    bool external, no_previews;
} export_args;

typedef struct stage_ctx {
    pg_cli *cli;
    const char *dir;
} stage_ctx;

static const char *staged_path(const char *name, void *user) {
    stage_ctx *c = user;
    return pg_cli_output_path(c->cli, c->dir, name);
}

static void report_json(pg_cli *cli, const char *dir, const export_args *a,
                        const pg_export_result *r) {
    pg_json *j = pg_cli_report(cli);
    if (!j) return;
    pg_json_set_string(pg_json_set_object(j, "inputs"), "planet", dir);
    pg_json *p = pg_json_set_object(j, "parameters");
    pg_json_set_string(p, "outdir", a->outdir);
    pg_json_set_string(p, "format", a->format);
    pg_json_set_number(p, "mesh_res", r->mesh_res);
    pg_json_set_number(p, "exaggeration", r->exaggeration);
    pg_json_set_string(p, "texture_format", a->texture_format);
    pg_json_set_bool(p, "external_textures", a->external);
    pg_json *res = pg_json_set_object(j, "results");
    pg_json_set_number(res, "vertices", (double)r->vertices);
    pg_json_set_number(res, "triangles", (double)r->triangles);
    pg_json_set_number(res, "glb_bytes", r->glb_bytes);
    pg_json_set_number(res, "height_min_m", r->height_min);
    pg_json_set_number(res, "height_max_m", r->height_max);
    pg_json_set_number(res, "files", r->nfiles);
}

/* --format: a comma-separated list of glb (planet.glb, height.exr and the previews)
 * and geotiff (the GIS rasters). */
static pg_status parse_format(const char *list, pg_export_opts *o, pg_error *err) {
    o->glb = o->exr = o->previews = o->geotiff = false;
    char buf[256];
    snprintf(buf, sizeof buf, "%s", list);
    for (char *save = NULL, *w = strtok_r(buf, ",", &save); w; w = strtok_r(NULL, ",", &save)) {
        if (!strcmp(w, "glb"))
            o->glb = o->exr = o->previews = true;
        else if (!strcmp(w, "geotiff"))
            o->geotiff = true;
        else
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "--format '%s': unknown format '%s' (glb, geotiff, or both "
                                "as glb,geotiff)",
                                list, w);
    }
    if (!o->glb && !o->geotiff)
        return pg_error_set(err, PG_ERR_BADINPUT, "--format '%s': no format", list);
    return PG_OK;
}

/* Options against planet.json's (or a tiled planet's index.json's) grid, before the
 * planet is loaded. */
static pg_status check_against_meta(const char *dir, const pg_export_opts *o, pg_planet_meta *meta,
                                    pg_error *err) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir,
             pg_planet_dir_is_tiled(dir) ? PG_PLANET_INDEX_NAME : PG_PLANET_META_NAME);
    FILE *f = fopen(path, "r");
    if (!f)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: not a planet output (no %s)", dir,
                            PG_PLANET_META_NAME);
    fclose(f);
    pg_status st = pg_planet_meta_read(path, meta, err);
    return st == PG_OK ? pg_export_check_opts(o, meta->tiles, meta->tile_size, err) : st;
}

/* Peak memory of an export. Measured (peak RSS) on planets of 6 x 512^2 and 6 x 1024^2
 * texels with 64..1024 quads per face edge: about 250 MB of libraries and previews,
 * 32 B per planet texel (the loaded planet, its textures and images) and 125 B per mesh
 * vertex (positions, normals, UVs, indices and the .glb buffer that copies them). The
 * estimate takes 300 MB, 48 B and 160 B, so that it stays an upper bound (1.63 GB
 * estimated for 1.22 GB measured at 6 x 1024^2, M = 1024), plus 4 floats per pixel of
 * each of the 4 globe renders. */
static double export_bytes(const pg_planet_meta *m, const pg_export_opts *o) {
    double n = (double)m->tiles * m->tile_size;
    int res = o->mesh_res ? o->mesh_res : pg_export_default_mesh_res(m->tiles, m->tile_size);
    double verts = 6.0 * (res + 1.0) * (res + 1.0), globe = (double)o->globe_size * o->globe_size;
    double glb = o->glb ? verts * 160 + globe * 16 * 4 : 0;
    /* GeoTIFF: the 4N x 2N albedo as floats and bytes (15 B a pixel; 8 N^2 pixels),
     * one tile of S^2 pixels at a time when tiled */
    double s = m->tile_size, tif = !o->geotiff ? 0 : o->geotiff_tiled ? 16 * s * s : 8 * n * n * 15;
    return 300e6 + 6 * n * n * 48 + glb + tif;
}

static int run_export(pg_cli *cli, const char *dir, const export_args *a, pg_export_opts *o) {
    pg_error err = {0};
    pg_status st = pg_export_texture_format_parse(a->texture_format, "--texture-format",
                                                  &o->texture_format, &err);
    if (st == PG_OK) st = parse_format(a->format, o, &err);
    o->previews = o->previews && !a->no_previews;
    o->geotiff_tiled = pg_planet_dir_is_tiled(dir);
    pg_planet_meta meta;
    if (st == PG_OK) st = check_against_meta(dir, o, &meta, &err);
    if (st != PG_OK) return pg_cli_fail(cli, &err);
    int rc = pg_cli_check_memory(cli, dir, export_bytes(&meta, o), a->max_memory_gb);
    if (rc) return rc;
    pg_planet p;
    pg_cli_stage_begin(cli, "load planet");
    if (pg_planet_load(dir, &p, &err) != PG_OK) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    st = pg_export_check_planet(o, &p, &err);
    if (st == PG_OK) st = pg_cli_prepare_outdir(cli, a->outdir, &err);
    pg_export_result r;
    stage_ctx ctx = {cli, a->outdir};
    pg_cli_stage_begin(cli, "export");
    if (st == PG_OK) st = pg_export_write(&p, o, staged_path, &ctx, &r, &err);
    pg_planet_free(&p);
    if (st != PG_OK) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    if (o->glb) {
        pg_cli_info(cli, "globe    %s/%s: %d quads per face edge, %lld triangles, %.1f MB\n",
                    a->outdir, PG_EXPORT_GLB_NAME, r.mesh_res, (long long)r.triangles,
                    r.glb_bytes / 1e6);
        pg_cli_info(cli, "relief   %.0f .. %.0f m, exaggerated %gx on the mesh\n", r.height_min,
                    r.height_max, r.exaggeration);
    }
    if (o->geotiff)
        pg_cli_info(cli, "geotiff  %s/%s: %lld x %lld pixels, latitude/longitude%s\n", a->outdir,
                    o->geotiff_tiled ? "height.vrt, albedo.vrt" : "height.tif, albedo.tif",
                    (long long)(4 * (int64_t)meta.tiles * meta.tile_size),
                    (long long)(2 * (int64_t)meta.tiles * meta.tile_size),
                    o->geotiff_tiled ? ", one GeoTIFF per tile" : "");
    report_json(cli, dir, a, &r);
    return pg_cli_finish(cli);
}

int pg_cmd_export(pg_cli *cli, int argc, char **argv) {
    export_args a = {NULL, "png", "glb", 0, 90, 512, PG_EXPORT_DEFAULT_EXAGGERATION,
                     0,    false, false};
    const pg_opt opts[] = {
        {"--output", "-o", PG_OPT_STRING, &a.outdir, 0, 0, NULL, "OUT",
         "output directory (default: the planet directory itself)"},
        {"--format", NULL, PG_OPT_STRING, &a.format, 0, 0, NULL, "LIST",
         "glb (planet.glb, height.exr, previews; the default), geotiff (height.tif and "
         "albedo.tif; per tile plus .vrt for a tiled planet), or glb,geotiff"},
        {"--mesh-res", NULL, PG_OPT_INT, &a.mesh_res, 1, 65536, NULL, "M",
         "quads per face edge: a multiple of the tiles per face edge dividing the face's "
         "texels (default: about 200k triangles)"},
        {"--exaggeration", NULL, PG_OPT_DOUBLE, &a.exaggeration, 0, PG_EXPORT_MAX_EXAGGERATION,
         NULL, "X", "relief exaggeration of the mesh and normal maps (default 10)"},
        {"--texture-format", NULL, PG_OPT_STRING, &a.texture_format, 0, 0, NULL, "png|jpeg",
         "albedo texture format (default png)"},
        {"--jpeg-quality", NULL, PG_OPT_INT, &a.jpeg_quality, 1, 100, NULL, "Q",
         "JPEG quality (default 90)"},
        {"--external-textures", NULL, PG_OPT_FLAG, &a.external, 0, 0, NULL, NULL,
         "write textures as separate files next to the .glb instead of embedding them"},
        {"--globe-size", NULL, PG_OPT_INT, &a.globe_size, 16, 16384, NULL, "PX",
         "size of the orthographic globe renders (default 512)"},
        {"--no-previews", NULL, PG_OPT_FLAG, &a.no_previews, 0, 0, NULL, NULL,
         "skip albedo.png, relief.png and the globe renders"},
        PG_CLI_MAX_MEMORY_OPT(a.max_memory_gb),
        PG_OPT_END};
    const char *pos[1];
    int npos;
    int rc =
        pg_cli_parse_or_help(cli, opts, argc, argv, pos, 1, &npos,
                             "DIR [-o OUT] [--mesh-res M] [--exaggeration X] [OPTIONS]",
                             "Export the planet in DIR (written by generate) as a glTF 2.0 globe\n"
                             "(planet.glb), float heights (height.exr) and previews (albedo.png,\n"
                             "relief.png, globe_*.png), or as georeferenced GeoTIFFs (--format\n"
                             "geotiff), into OUT. Existing files are replaced atomically.");
    if (rc >= 0) return rc;
    if (npos != 1) return pg_cli_usage_error(cli, "expected one planet directory (see --help)");
    if (!a.outdir) a.outdir = pos[0];
    pg_export_opts o;
    pg_export_opts_default(&o);
    o.mesh_res = (int)a.mesh_res;
    o.exaggeration = a.exaggeration;
    o.jpeg_quality = (int)a.jpeg_quality;
    o.external_textures = a.external;
    o.globe_size = (int)a.globe_size;
    return run_export(cli, pos[0], &a, &o);
}
