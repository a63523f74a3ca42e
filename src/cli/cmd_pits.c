/* cmd_pits.c - `planetgen pits`: remove pits from a flat DEM, or count them.
 *
 *   planetgen pits --method fill|breach|hybrid [--epsilon] [--max-depth D]
 *                  [--max-length L] [--sea-level H] [--lakes MASK] [--nodata V]
 *                  [--closed-edges] [--co KEY=VALUE]... [--cog] IN -o OUT
 *   planetgen pits --stats FILE|PLANET_DIR [--json F]
 *
 * It lets GIS users run the pit-removal module (pg_pits.h) on its own. Inputs are
 * rasters taken as raw heights: a georeferenced one, or any format only GDAL reads
 * (.hgt, .asc, .vrt, ...), through GDAL (pg_raster.h) with its CRS, geotransform and
 * NoData; the images OpenImageIO serves (PNG, JPEG, EXR, plain TIFF) through pg_image
 * as before. Cell areas come from the georeferencing (pg_geo_raster_row_areas) unless
 * --cell-size overrides. Outputs are float EXR, float GeoTIFF through GDAL (strict
 * descent survives; the input's CRS, geotransform and NoData are kept; --co and --cog
 * pass creation options) or 16-bit PNG (for unsigned integer inputs: the result is
 * rounded to the input's steps, which keeps every path non-ascending because rounding
 * is monotone). Map borders are outlets unless --closed-edges. All input is validated
 * before any output is created (docs/pits.md, "CLI"). */
#include "pg_commands.h"

#include "pg_planet_meta.h"
#include "planetgen/pg_image.h"
#include "planetgen/pg_json.h"
#include "planetgen/pg_pits.h"
#include "planetgen/pg_geo.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_raster.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

typedef struct pits_args {
    const char *method, *out, *lakes, *stats;
    bool epsilon, closed_edges, global, no_stats, cog;
    double max_depth, max_length, sea_level, nodata, cell_size, max_memory_gb;
    pg_opt_list co; /* GDAL creation options for a .tif output */
} pits_args;

/* A DEM as read: its cells and where they lie on the Earth (a zeroed geo: nowhere). */
typedef struct dem {
    pg_image img;
    pg_georef geo;
} dem;

static void dem_free(dem *d) {
    pg_image_free(&d->img);
    pg_georef_free(&d->geo);
}

/* Peak memory, measured (peak RSS) on a 4096^2 float EXR: 46 B per cell with the
 * depression counts (the image, the count's fill copy and labels, the flood queue),
 * 25 B without them (--no-stats); on planets of 6 x 512^2 and 6 x 1024^2 texels
 * (--stats DIR) 40 B per texel over 130 MB. The estimates round these up; a lakes
 * mask adds its decoded image (up to 4 floats per cell) and the 1-byte mask. */
#define PITS_BASE_BYTES 64e6
#define PITS_CELL_BYTES 52.0
#define PITS_CELL_BYTES_NO_STATS 32.0
#define PITS_LAKES_CELL_BYTES 17.0
#define PITS_PLANET_BASE_BYTES 150e6
#define PITS_PLANET_TEXEL_BYTES 48.0

/* The memory check for a flat DEM, from its header. A file whose header cannot be read
 * passes here; reading it then reports the problem. */
static int check_dem_memory(pg_cli *cli, const pits_args *a, const char *path, bool stats_only) {
    int w = 0, h = 0, c = 0;
    pg_error err = {0};
    if (pg_image_probe(path, &w, &h, &c, &err) != PG_OK &&
        pg_raster_probe(path, &w, &h, &c, NULL, NULL, &err) != PG_OK)
        return 0;
    double cells = (double)w * h;
    double per = stats_only || !a->no_stats ? PITS_CELL_BYTES : PITS_CELL_BYTES_NO_STATS;
    if (a->lakes) per += PITS_LAKES_CELL_BYTES;
    return pg_cli_check_memory(cli, path, PITS_BASE_BYTES + cells * per, a->max_memory_gb);
}

/* The same for a planet directory, from planet.json's grid. */
static int check_planet_memory(pg_cli *cli, const pits_args *a, const char *dir) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, PG_PLANET_META_NAME);
    pg_planet_meta meta;
    pg_error err = {0};
    if (pg_planet_meta_read(path, &meta, &err) != PG_OK) return 0;
    double n = (double)meta.tiles * meta.tile_size;
    return pg_cli_check_memory(
        cli, dir, PITS_PLANET_BASE_BYTES + 6 * n * n * PITS_PLANET_TEXEL_BYTES, a->max_memory_gb);
}

/* Cell areas that vary by row (geographic rasters): ctx holds one area per row. */
typedef struct row_areas {
    int w;
    double *rows;
} row_areas;

static double row_area(void *ctx, uint32_t id) {
    const row_areas *r = ctx;
    return r->rows[id / (uint32_t)r->w];
}

/* Drivers whose files OpenImageIO reads as before when they carry no georeferencing. */
static bool image_driver(const char *drv) {
    const char *const names[] = {"PNG", "JPEG", "GTiff", "EXR", "BMP", "GIF", "WEBP"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++)
        if (!strcmp(drv, names[i])) return true;
    return false;
}

/* Does the name end in an extension of the images pg_image reads? Their refusals
 * (damaged PNG chunks, a JPEG's bad segment) say more than GDAL's. */
static bool image_extension(const char *path) {
    const char *dot = strrchr(path, '.');
    const char *const ext[] = {".png", ".jpg", ".jpeg", ".exr", ".tif", ".tiff", ".bmp", ".webp"};
    for (size_t i = 0; dot && i < sizeof ext / sizeof *ext; i++)
        if (!strcasecmp(dot, ext[i])) return true;
    return false;
}

/* Read a raster: through GDAL when it is georeferenced or only GDAL reads it, else
 * through pg_image (OpenImageIO, OpenEXR) as a plain grid. */
static pg_status read_raster(const char *path, const char *what, dem *d, pg_error *err) {
    memset(d, 0, sizeof *d);
    struct stat sb;
    if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s %s: a directory (planet directories are read by --stats only)",
                            what, path);
    int w, h, b;
    char drv[32];
    pg_georef g;
    pg_error probe_err = {0};
    bool gdal = pg_raster_probe(path, &w, &h, &b, drv, &g, &probe_err) == PG_OK &&
                (pg_georef_present(&g) || !image_driver(drv));
    if (probe_err.status == PG_OK) pg_georef_free(&g);
    if (probe_err.status != PG_OK && !image_extension(path))
        return pg_error_set(err, probe_err.status, "%s", probe_err.msg);
    pg_status s = gdal ? pg_raster_read(path, 0, &d->img, &d->geo, err)
                       : pg_image_read(path, 0, &d->img, err);
    return s;
}

static pg_status read_dem(const char *path, const char *what, dem *d, pg_error *err) {
    pg_status s = read_raster(path, what, d, err);
    if (s) return s;
    if (d->img.channels != 1) {
        int channels = d->img.channels; /* dem_free clears the struct */
        dem_free(d);
        return pg_error_set(err, PG_ERR_BADINPUT, "%s %s: %d channels, expected 1 (a height map)",
                            what, path, channels);
    }
    return PG_OK;
}

static pg_status read_lakes(const char *path, const pg_image *dem, uint8_t **mask, pg_error *err) {
    struct dem md;
    pg_status s = read_raster(path, "--lakes", &md, err);
    if (s) return s;
    pg_image m = md.img;
    pg_georef_free(&md.geo);
    if (m.width != dem->width || m.height != dem->height) {
        s = pg_error_set(err, PG_ERR_BADINPUT, "--lakes %s: %dx%d, but the DEM is %dx%d", path,
                         m.width, m.height, dem->width, dem->height);
    } else if (!(*mask = malloc((size_t)m.width * m.height))) {
        s = pg_error_set(err, PG_ERR_NOMEM, "--lakes %s: out of memory", path);
    } else {
        for (size_t i = 0; i < (size_t)m.width * m.height; i++)
            (*mask)[i] = m.data[i * m.channels] != 0;
    }
    pg_image_free(&m);
    return s;
}

/* NoData: --nodata, else the file's NoData tag, else none. */
static void effective_nodata(const pits_args *a, const pg_georef *geo, bool *has, double *v) {
    *has = !isnan(a->nodata) || geo->has_nodata;
    *v = !isnan(a->nodata) ? a->nodata : geo->has_nodata ? geo->nodata : NAN;
}

static void set_opts(const pits_args *a, const pg_georef *geo, const uint8_t *lakes,
                     pg_pits_opts *o) {
    pg_pits_opts_default(o);
    pg_pits_method_parse(a->method, &o->method);
    o->epsilon = a->epsilon;
    o->max_depth = a->max_depth;
    o->max_length = a->max_length;
    o->has_sea_level = !isnan(a->sea_level);
    o->sea_level = a->sea_level;
    o->lakes = lakes;
    o->open_edges = !a->closed_edges;
    double v;
    effective_nodata(a, geo, &o->has_nodata, &v);
    o->nodata = (float)v;
}

/* The cell areas: --cell-size; else from the georeferencing (geographic: true areas on
 * the CRS's ellipsoid; projected: metres); else 1 m^2. --global requires a whole-globe
 * geographic grid, or, without georeferencing, a 2:1 grid taken as one on the sphere. */
static pg_status area_of(pg_cli *cli, const pits_args *a, const char *in, const dem *d,
                         row_areas *ra, pg_pits_area *area, pg_error *err) {
    memset(area, 0, sizeof *area);
    ra->rows = NULL;
    const int w = d->img.width, h = d->img.height;
    const pg_georef *g = &d->geo;
    pg_georef sphere = {0};
    if (!isnan(a->cell_size)) {
        area->constant = a->cell_size * a->cell_size;
        pg_cli_verbose(cli, "cells: %g m a side (--cell-size)\n", a->cell_size);
        return PG_OK;
    }
    if (a->global && pg_georef_present(g) && !pg_geo_raster_is_global(g, w, h))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: --global needs a whole-globe geographic grid (longitude 360 "
                            "degrees, latitude 90 to -90); this raster's georeferencing is not one",
                            in);
    if (a->global && !pg_georef_present(g)) {
        if (w != 2 * h)
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "%s: --global needs a whole-globe grid, but this raster has no "
                                "geotransform and is %dx%d, not 2:1",
                                in, w, h);
        /* the convention of an unreferenced global map: equirectangular on the sphere */
        const double t[6] = {-180, 360.0 / w, 0, 90, 0, -180.0 / h};
        sphere.has_transform = true;
        memcpy(sphere.transform, t, sizeof t);
        sphere.kind = PG_CRS_GEOGRAPHIC;
        sphere.a = PG_ELLIPSOID_SPHERE_RADIUS_M;
        sphere.unit = 1;
        g = &sphere;
    } else if (!pg_geo_raster_has_cells(g)) {
        area->constant = 1;
        pg_cli_verbose(cli, "cells: 1 m a side (no georeferencing; --cell-size sets it)\n");
        return PG_OK;
    }
    if (!(ra->rows = malloc((size_t)h * sizeof *ra->rows)))
        return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", in);
    pg_status s = pg_geo_raster_row_areas(g, w, h, in, ra->rows, err);
    if (s) {
        free(ra->rows);
        ra->rows = NULL;
        return s;
    }
    ra->w = w;
    area->fn = row_area;
    area->ctx = ra;
    if (g->kind == PG_CRS_GEOGRAPHIC)
        pg_cli_verbose(cli, "cells: true areas on the ellipsoid a = %.3f m, f = %.10g (%s)\n", g->a,
                       g->f, g == &sphere ? "--global" : g->crs_name);
    else
        pg_cli_verbose(cli, "cells: %.6g m^2 (%s)\n", ra->rows[0], g->crs_name);
    return PG_OK;
}

/* Print st; add it to the JSON object `into` (NULL without --json). */
static void report_stats(pg_cli *cli, const char *key, const pg_pits_stats *st, pg_json *into) {
    if (key)
        pg_cli_info(cli,
                    "%-7s %llu depressions, %llu cells, area %.6g m^2, volume %.6g m^3, "
                    "deepest %.6g\n",
                    key, (unsigned long long)st->depressions,
                    (unsigned long long)st->depression_cells, st->depression_area_m2,
                    st->depression_volume_m3, st->max_depth_m);
    if (!into) return;
    pg_json *o = into;
    pg_json_set_number(o, "depressions", (double)st->depressions);
    pg_json_set_number(o, "depression_cells", (double)st->depression_cells);
    pg_json_set_number(o, "depression_area_m2", st->depression_area_m2);
    pg_json_set_number(o, "depression_volume_m3", st->depression_volume_m3);
    pg_json_set_number(o, "max_depth", st->max_depth_m);
}

/* The output format, from OUT's extension: 'e' EXR, 'p' PNG, 't' TIFF, 0 unknown. */
static char out_kind(const char *out) {
    size_t n = strlen(out);
    if (n > 4 && !strcmp(out + n - 4, ".exr")) return 'e';
    if (n > 4 && !strcmp(out + n - 4, ".png")) return 'p';
    if ((n > 4 && !strcmp(out + n - 4, ".tif")) || (n > 5 && !strcmp(out + n - 5, ".tiff")))
        return 't';
    return 0;
}

static pg_raster_write_opts write_opts(const pits_args *a) {
    pg_raster_write_opts o = {a->co.v, a->co.n, a->cog};
    return o;
}

/* The GeoTIFF carries the input's CRS and geotransform and the NoData in effect. */
static pg_status write_dem(pg_cli *cli, const pits_args *a, dem *d, pg_error *err) {
    const char *out = a->out, *slash = strrchr(out, '/');
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - out) : 1, slash ? out : ".");
    if (!dir[0]) snprintf(dir, sizeof dir, "/");
    const char *name = slash ? slash + 1 : out;
    const char *tmp = pg_cli_output_path(cli, dir, name);
    pg_image *img = &d->img;
    if (!tmp) return pg_error_set(err, PG_ERR_NOMEM, "-o %s: out of memory", out);
    if (out_kind(name) == 'e') return pg_image_write_exr(tmp, img, NULL, err);
    if (out_kind(name) == 't') {
        effective_nodata(a, &d->geo, &d->geo.has_nodata, &d->geo.nodata);
        pg_raster_write_opts wo = write_opts(a);
        return pg_raster_write_geotiff(tmp, img, PG_RASTER_FLOAT32, &d->geo, &wo, err);
    }
    /* PNG: back to the input's integer steps; pg_image_write_png rounds */
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++)
        img->data[i] *= img->unit_scale;
    return pg_image_write_png(tmp, img, 16, err);
}

/* Output options that need no input: the format, and --co/--cog against GDAL. */
static pg_status check_output_opts(const pits_args *a, pg_error *err) {
    if (!out_kind(a->out))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "-o %s: write .exr or .tif (float) or .png (16-bit)", a->out);
    if ((a->co.n || a->cog) && out_kind(a->out) != 't')
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: only for a GeoTIFF output (-o F.tif)",
                            a->cog ? "--cog" : "--co");
    pg_raster_write_opts wo = write_opts(a);
    return pg_raster_check_options(&wo, "--co", err);
}

static pg_status check_output(const pits_args *a, const pg_image *img, pg_error *err) {
    int png = out_kind(a->out) == 'p';
    if (png && (img->unit_scale == 1.0f || img->src_type == PG_SAMPLE_FLOAT))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "-o %s: a float DEM cannot be written as PNG without losing "
                            "heights; write .exr",
                            a->out);
    if (png && (img->src_type == PG_SAMPLE_INT8 || img->src_type == PG_SAMPLE_INT16 ||
                img->src_type == PG_SAMPLE_INT32))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "-o %s: a signed DEM cannot be written as 16-bit PNG without losing "
                            "heights below 0; write .tif or .exr",
                            a->out);
    if (png && img->unit_scale < 1.0f / 65535.5f)
        return pg_error_set(err, PG_ERR_BADINPUT, "-o %s: input has more than 16 bits; write .exr",
                            a->out);
    return PG_OK;
}

static bool is_dir(const char *path) {
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
}

/* The planet's heights as one cube array (global texel ids). */
static pg_status planet_heights(const pg_planet *p, float **out, pg_error *err) {
    size_t nn = (size_t)p->n * (size_t)p->n;
    float *h = malloc(6 * nn * sizeof *h);
    if (!h) return pg_error_set(err, PG_ERR_NOMEM, "--stats: out of memory for the planet");
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        memcpy(h + f * nn, p->height[f], nn * sizeof *h);
    *out = h;
    return PG_OK;
}

/* --stats PLANET_DIR: one global count over all faces, true texel areas. */
static int run_planet_stats(pg_cli *cli, const pits_args *a) {
    if (a->lakes) return pg_cli_usage_error(cli, "--lakes: not supported with a planet directory");
    int rc = check_planet_memory(cli, a, a->stats);
    if (rc) return rc;
    pg_error err = {0};
    pg_planet p;
    pg_cli_stage_begin(cli, "load planet");
    if (pg_planet_load(a->stats, &p, &err)) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    pits_args pa = *a;
    if (isnan(pa.sea_level)) pa.sea_level = p.sea_level;
    pa.closed_edges = true; /* a sphere has no edges */
    pg_pits_opts o;
    const pg_georef nowhere = {0};
    set_opts(&pa, &nowhere, NULL, &o);
    pg_cli_stage_begin(cli, "count depressions on the planet");
    pg_pits_topo t;
    pg_pits_stats st;
    float *h = NULL;
    double *face = malloc((size_t)p.n * (size_t)p.n * sizeof *face);
    pg_pits_cube_areas ca = {face, (uint32_t)p.n};
    pg_pits_area area = {NULL, pg_pits_cube_area_fn, &ca, 0};
    pg_status s = face ? PG_OK : pg_error_set(&err, PG_ERR_NOMEM, "--stats: out of memory");
    if (!s) s = pg_pits_topo_cube(&t, (uint32_t)p.n, &err);
    if (!s) /* the authalic radius of the ellipsoid, to first order in f */
        s = pg_pits_cube_face_areas(p.projection, (uint32_t)p.n,
                                    p.ellipsoid.a * (1 - p.ellipsoid.f / 3), face, &err);
    if (!s) s = planet_heights(&p, &h, &err);
    if (!s) s = pg_pits_stats_compute(&t, h, &o, &area, &st, &err);
    free(h);
    free(face);
    pg_planet_free(&p);
    if (s) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    pg_json *r = pg_cli_report(cli);
    report_stats(cli, "stats", &st, r ? pg_json_set_object(r, "results") : NULL);
    return pg_cli_finish(cli);
}

static int run_stats(pg_cli *cli, const pits_args *a) {
    if (is_dir(a->stats)) return run_planet_stats(cli, a);
    int rc = check_dem_memory(cli, a, a->stats, true);
    if (rc) return rc;
    pg_error err = {0};
    dem d;
    uint8_t *lakes = NULL;
    /* the inputs are checked inside the stage: a bad one ends it without a progress
     * line, so the error stays the only line */
    pg_cli_stage_begin(cli, "read DEM");
    if (read_dem(a->stats, "--stats", &d, &err)) return pg_cli_fail(cli, &err);
    pg_pits_opts o;
    pg_pits_topo t;
    pg_pits_stats st;
    row_areas ra = {0};
    pg_pits_area area;
    pg_status s = a->lakes ? read_lakes(a->lakes, &d.img, &lakes, &err) : PG_OK;
    if (!s) s = area_of(cli, a, a->stats, &d, &ra, &area, &err);
    if (!s) {
        pg_cli_stage_end(cli);
        set_opts(a, &d.geo, lakes, &o);
        pg_cli_stage_begin(cli, "count depressions");
        s = pg_pits_topo_grid(&t, (uint32_t)d.img.width, (uint32_t)d.img.height, &err);
    }
    if (!s) s = pg_pits_stats_compute(&t, d.img.data, &o, &area, &st, &err);
    dem_free(&d);
    free(lakes);
    free(ra.rows);
    if (s) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    pg_json *r = pg_cli_report(cli);
    report_stats(cli, "stats", &st, r ? pg_json_set_object(r, "results") : NULL);
    return pg_cli_finish(cli);
}

static int run_remove(pg_cli *cli, const pits_args *a, const char *in) {
    pg_error err = {0};
    if (check_output_opts(a, &err)) return pg_cli_fail(cli, &err);
    int rc = is_dir(in) ? 0 : check_dem_memory(cli, a, in, false);
    if (rc) return rc;
    dem d;
    uint8_t *lakes = NULL;
    /* the inputs are checked inside the stage: a bad one ends it without a progress
     * line, so the error stays the only line */
    pg_cli_stage_begin(cli, "read DEM");
    if (read_dem(in, "input", &d, &err)) return pg_cli_fail(cli, &err);
    pg_image *img = &d.img;
    row_areas ra = {0};
    pg_pits_area area;
    pg_status s = check_output(a, img, &err);
    if (!s && a->lakes) s = read_lakes(a->lakes, img, &lakes, &err);
    if (!s) s = area_of(cli, a, in, &d, &ra, &area, &err);
    if (!s) pg_cli_stage_end(cli);
    pg_pits_opts o;
    set_opts(a, &d.geo, lakes, &o);
    pg_pits_topo t;
    if (!s) s = pg_pits_topo_grid(&t, (uint32_t)img->width, (uint32_t)img->height, &err);
    pg_pits_stats before, after;
    pg_pits_result res;
    if (!s) {
        pg_cli_verbose(cli, "method: %s%s\n", pg_pits_method_citation(o.method),
                       o.epsilon ? " (epsilon: strictly descending, no flats)" : "");
        /* the counts reuse the removal's own floods (docs/pits.md, "Metrics") */
        pg_cli_stage_begin(cli, a->no_stats ? "remove pits" : "remove pits and count depressions");
        s = a->no_stats
                ? pg_pits_remove(&t, img->data, &o, &res, &err)
                : pg_pits_remove_counted(&t, img->data, &o, &area, &res, &before, &after, &err);
        pg_cli_stage_end(cli);
    }
    if (!s) {
        pg_cli_stage_begin(cli, "write DEM");
        s = write_dem(cli, a, &d, &err);
        pg_cli_stage_end(cli);
    }
    char crs[128];
    snprintf(crs, sizeof crs, "%s", d.geo.crs_wkt ? d.geo.crs_name : "");
    dem_free(&d);
    free(lakes);
    free(ra.rows);
    if (s) return pg_cli_fail(cli, &err);
    pg_cli_info(cli, "%s: raised %llu cells (max %.6g), lowered %llu (max %.6g), %llu sinks\n",
                pg_pits_method_name(o.method), (unsigned long long)res.raised, res.max_raise,
                (unsigned long long)res.lowered, res.max_lower, (unsigned long long)res.sinks);
    if (o.method == PG_PITS_HYBRID)
        pg_cli_info(cli, "hybrid: %llu breach channels carved, %llu pits filled\n",
                    (unsigned long long)res.breaches, (unsigned long long)res.fills);
    pg_json *r = pg_cli_report(cli), *rj = NULL;
    if (r) {
        pg_json *p = pg_json_set_object(r, "parameters");
        pg_json_set_string(p, "method", a->method);
        pg_json_set_bool(p, "epsilon", a->epsilon);
        pg_json_set_string(p, "citation", pg_pits_method_citation(o.method));
        pg_json_set_string(p, "crs", crs);
        if (o.has_nodata && !isnan(o.nodata)) pg_json_set_number(p, "nodata", o.nodata);
        rj = pg_json_set_object(r, "results");
        pg_json_set_number(rj, "raised_cells", (double)res.raised);
        pg_json_set_number(rj, "lowered_cells", (double)res.lowered);
        pg_json_set_number(rj, "sinks", (double)res.sinks);
    }
    if (!a->no_stats) {
        report_stats(cli, "before", &before, rj ? pg_json_set_object(rj, "before") : NULL);
        report_stats(cli, "after", &after, rj ? pg_json_set_object(rj, "after") : NULL);
        /* the headline keys describe the delivered DEM */
        if (rj) report_stats(cli, NULL, &after, rj);
    }
    return pg_cli_finish(cli);
}

int pg_cmd_pits(pg_cli *cli, int argc, char **argv) {
    pits_args a = {.method = "breach",
                   .max_depth = INFINITY,
                   .max_length = INFINITY,
                   .sea_level = NAN,
                   .nodata = NAN,
                   .cell_size = NAN}; /* NAN: not given */
    const pg_opt opts[] = {
        {"--method", NULL, PG_OPT_CHOICE, &a.method, 0, 0, "fill|breach|hybrid", "M",
         "fill (Barnes 2014), breach (Soille 2004; default) or hybrid (Lindsay 2016)"},
        {"--epsilon", NULL, PG_OPT_FLAG, &a.epsilon, 0, 0, NULL, NULL,
         "strictly descending paths (nextafter steps): no flats left"},
        {"--max-depth", NULL, PG_OPT_DOUBLE, &a.max_depth, 0, 1e12, NULL, "D",
         "hybrid: deepest breach channel, height units (default unlimited)"},
        {"--max-length", NULL, PG_OPT_DOUBLE, &a.max_length, 0, 1e12, NULL, "L",
         "hybrid: longest breach channel, cells (default unlimited)"},
        {"--sea-level", NULL, PG_OPT_DOUBLE, &a.sea_level, -1e12, 1e12, NULL, "H",
         "cells at or below H are ocean sinks"},
        {"--lakes", NULL, PG_OPT_STRING, &a.lakes, 0, 0, NULL, "MASK",
         "image of the DEM's size; nonzero cells are lake sinks"},
        {"--nodata", NULL, PG_OPT_DOUBLE, &a.nodata, -1e38, 1e38, NULL, "V",
         "cells equal to V (or NaN) are no-data: outlets, left unchanged (default: the "
         "file's NoData)"},
        {"--closed-edges", NULL, PG_OPT_FLAG, &a.closed_edges, 0, 0, NULL, NULL,
         "the map border is not an outlet (default: it is)"},
        {"--cell-size", NULL, PG_OPT_DOUBLE, &a.cell_size, 1e-9, 1e9, NULL, "M",
         "cell edge in metres, for areas and volumes (default: from the georeferencing, "
         "else 1)"},
        {"--global", NULL, PG_OPT_FLAG, &a.global, 0, 0, NULL, NULL,
         "the DEM is a whole-globe latitude/longitude grid (a 2:1 grid without "
         "georeferencing: on the sphere)"},
        {"--no-stats", NULL, PG_OPT_FLAG, &a.no_stats, 0, 0, NULL, NULL,
         "skip counting depressions before and after"},
        {"--stats", NULL, PG_OPT_STRING, &a.stats, 0, 0, NULL, "FILE",
         "only count the depressions of FILE, or of a planet directory (globally)"},
        {"--output", "-o", PG_OPT_STRING, &a.out, 0, 0, NULL, "OUT",
         "output DEM (.exr, .tif: float, GeoTIFF; .png: 16-bit)"},
        {"--co", NULL, PG_OPT_LIST, &a.co, 0, 0, NULL, "KEY=VALUE",
         "GDAL creation option of the GeoTIFF output, repeatable (e.g. TILED=YES)"},
        {"--cog", NULL, PG_OPT_FLAG, &a.cog, 0, 0, NULL, NULL,
         "write a Cloud-Optimized GeoTIFF (GDAL's COG driver)"},
        PG_CLI_MAX_MEMORY_OPT(a.max_memory_gb),
        PG_OPT_END};
    const char *pos[2];
    int npos = 0;
    bool done = false;
    int rc = pg_cli_parse(cli, opts, argc, argv, pos, 2, &npos, &done);
    if (rc) return rc;
    if (done) {
        pg_cli_print_help(cli,
                          "--method fill|breach|hybrid [OPTIONS] IN -o OUT\n"
                          "       planetgen pits --stats FILE|PLANET_DIR [--json F]",
                          "Remove pits (closed depressions) from a flat DEM so that every cell "
                          "drains to an outlet,\nor count them with --stats. See docs/pits.md.",
                          opts, stdout);
        return 0;
    }
    if (a.global && !isnan(a.cell_size))
        return pg_cli_usage_error(cli, "--cell-size and --global: give one");
    if (a.stats) {
        if (npos) return pg_cli_usage_error(cli, "--stats takes no other input");
        return run_stats(cli, &a);
    }
    if (npos != 1) return pg_cli_usage_error(cli, "expected one input DEM (see --help)");
    if (!a.out) return pg_cli_usage_error(cli, "-o OUT is required");
    return run_remove(cli, &a, pos[0]);
}
