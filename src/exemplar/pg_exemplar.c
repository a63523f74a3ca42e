/* pg_exemplar.c - loading the exemplar pair onto one equirectangular grid.
 *
 * Order matters for the "no partial work on bad input" rule: both inputs are read
 * and validated (geometry, 2:1, finite values) before anything is derived. The
 * common grid is the coarser input's unless asked otherwise, so no input is
 * invented at a resolution it does not have. */
#include "pg_marble.h"
#include "planetgen/pg_equirect.h"
#include "planetgen/pg_exemplar.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PG_MIN_GLOBAL_HEIGHT 8 /* a global map smaller than 16x8 is not a map */

void pg_exemplar_opts_default(pg_exemplar_opts *o) {
    memset(o, 0, sizeof *o);
    o->height_scale = NAN;
    o->height_offset = NAN;
    o->sea_level = NAN;
    o->repair_ocean = true;
}

pg_status pg_exemplar_assemble_relief(const char *dir, int rows, int cols, pg_image *out,
                                      pg_error *err) {
    memset(out, 0, sizeof *out);
    int tw = 0, th = 0;
    pg_status st = PG_OK;
    char first[1024];
    snprintf(first, sizeof first, "%s/000000/000000_000000.jpg", dir);
    int ch;
    st = pg_image_probe(first, &tw, &th, &ch, err);
    if (st != PG_OK) return st;
    st = pg_image_alloc(out, tw * cols, th * rows, 1, err);
    if (st != PG_OK) return st;
    out->src_type = PG_SAMPLE_UINT8;
    out->unit_scale = 1.0f / 255.0f;
    snprintf(out->format_name, sizeof out->format_name, "jpeg");
    pg_error first_err = {0};
#pragma omp parallel for schedule(dynamic)
    for (int t = 0; t < rows * cols; t++) {
        int r = t / cols, c = t % cols;
        char path[1024];
        snprintf(path, sizeof path, "%s/%06d/%06d_%06d.jpg", dir, r, r, c);
        pg_image tile;
        pg_error e = {0};
        pg_status s = pg_image_read(path, 0, &tile, &e);
        if (s == PG_OK && (tile.width != tw || tile.height != th))
            s = pg_error_set(&e, PG_ERR_BADINPUT, "%s: tile is %dx%d, expected %dx%d", path,
                             tile.width, tile.height, tw, th);
        if (s == PG_OK) {
            for (int y = 0; y < th; y++)
                for (int x = 0; x < tw; x++)
                    out->data[(size_t)(r * th + y) * out->width + (size_t)c * tw + x] =
                        tile.data[((size_t)y * tw + x) * tile.channels];
        } else {
#pragma omp critical(pg_relief_err)
            if (first_err.status == PG_OK) first_err = e;
        }
        pg_image_free(&tile);
    }
    if (first_err.status != PG_OK) {
        pg_image_free(out);
        pg_error_set(err, first_err.status, "%s", first_err.msg);
        return first_err.status;
    }
    return PG_OK;
}

static pg_status check_global(const char *path, const pg_image *img, pg_error *err) {
    if (img->height < PG_MIN_GLOBAL_HEIGHT || img->width < 2 * PG_MIN_GLOBAL_HEIGHT)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: %dx%d is too small for a global map (minimum 16x8)", path,
                            img->width, img->height);
    if (abs(img->width - 2 * img->height) > 2)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: %dx%d is not 2:1, so not a global equirectangular map", path,
                            img->width, img->height);
    return PG_OK;
}

static pg_status check_finite(const char *path, const pg_image *img, pg_error *err) {
    size_t n = (size_t)img->width * img->height * img->channels;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(img->data[i])) {
            size_t p = i / img->channels;
            return pg_error_set(err, PG_ERR_BADINPUT, "%s: %s value at pixel (%zu, %zu)", path,
                                isnan(img->data[i]) ? "NaN" : "infinite", p % img->width,
                                p / img->width);
        }
    }
    return PG_OK;
}

static void note(pg_exemplar *ex, const char *fmt, const char *path) {
    size_t len = strlen(ex->notes);
    snprintf(ex->notes + len, sizeof ex->notes - len, fmt, path);
}

/* Any channel count to RGB 0..1: grey is replicated, alpha dropped with a note. */
static pg_status to_rgb(pg_exemplar *ex, const char *path, pg_image *img, pg_error *err) {
    int nc = img->channels;
    if (nc == 2 || nc > 3) note(ex, "%s: alpha/extra channels ignored; ", path);
    pg_image rgb;
    pg_status st = pg_image_alloc(&rgb, img->width, img->height, 3, err);
    if (st != PG_OK) return st;
    size_t n = (size_t)img->width * img->height;
    float s = img->unit_scale;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            rgb.data[3 * i + c] = img->data[i * nc + (nc >= 3 ? c : 0)] * s;
    pg_image_free(img);
    *img = rgb;
    return PG_OK;
}

static pg_status load_inputs(const pg_exemplar_opts *o, pg_exemplar *ex, pg_image *alb,
                             pg_image *hgt, pg_error *err) {
    const char *apath = o->albedo_path ? o->albedo_path : PG_MARBLE_ALBEDO;
    snprintf(ex->albedo_src, sizeof ex->albedo_src, "%s", apath);
    pg_status st = pg_image_read(apath, o->max_pixels, alb, err);
    if (st == PG_OK) st = check_global(apath, alb, err);
    if (st == PG_OK) st = check_finite(apath, alb, err);
    if (st != PG_OK) return st;
    if (o->height_path) {
        snprintf(ex->height_src, sizeof ex->height_src, "%s", o->height_path);
        st = pg_image_read(o->height_path, o->max_pixels, hgt, err);
    } else {
        const char *dir = o->relief_dir ? o->relief_dir : PG_MARBLE_RELIEF_DIR;
        snprintf(ex->height_src, sizeof ex->height_src, "%s (%dx%d tiles)", dir,
                 PG_MARBLE_RELIEF_ROWS, PG_MARBLE_RELIEF_COLS);
        st = pg_exemplar_assemble_relief(dir, PG_MARBLE_RELIEF_ROWS, PG_MARBLE_RELIEF_COLS, hgt,
                                         err);
    }
    const char *hpath = o->height_path ? o->height_path : ex->height_src;
    if (st == PG_OK) st = check_global(hpath, hgt, err);
    if (st == PG_OK) st = check_finite(hpath, hgt, err);
    if (st == PG_OK && hgt->channels > 1) note(ex, "%s: only the first channel is used; ", hpath);
    return st;
}

/* Keep channel 0 only, in place. */
static void first_channel(pg_image *img) {
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++)
        img->data[i] = img->data[i * img->channels];
    img->channels = 1;
}

static pg_status to_grid(float **data, int w, int h, int ch, int gw, pg_error *err) {
    if (w == gw && h == gw / 2) return PG_OK;
    float *out;
    pg_status st = pg_equirect_resample(*data, w, h, ch, gw, gw / 2, &out, err);
    if (st != PG_OK) return st;
    free(*data);
    *data = out;
    return PG_OK;
}

/* A grey relief becomes metres before it is resampled, because the ramp is not
 * linear: averaging greys and then mapping would bias every mixed pixel. The sea
 * level grey is fitted on the common grid, where the albedo's water mask lives. */
static pg_status calibrate_grey(const pg_exemplar_opts *o, pg_exemplar *ex, pg_image *hgt,
                                const uint8_t *water, pg_error *err) {
    float *coarse = hgt->data;
    pg_status st = PG_OK;
    if (hgt->width != ex->width)
        st = pg_equirect_resample(hgt->data, hgt->width, hgt->height, 1, ex->width, ex->height,
                                  &coarse, err);
    if (st == PG_OK)
        st = pg_exemplar_calibrate(coarse, water, ex->width, ex->height, &ex->calib, err);
    if (coarse != hgt->data) free(coarse);
    if (st == PG_OK && !o->height_path) st = pg_calibration_marble_refs(hgt, &ex->calib, err);
    if (st != PG_OK) return st;
    size_t n = (size_t)hgt->width * hgt->height;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++)
        hgt->data[i] = pg_calibration_apply(&ex->calib, hgt->data[i]);
    return PG_OK;
}

static pg_status heights_to_metres(const pg_exemplar_opts *o, pg_exemplar *ex, pg_image *hgt,
                                   pg_error *err) {
    size_t n = (size_t)hgt->width * hgt->height;
    bool grey = hgt->src_type == PG_SAMPLE_UINT8 || hgt->src_type == PG_SAMPLE_UINT16;
    bool user_lin = !isnan(o->height_scale) || !isnan(o->height_offset);
    double scale = isnan(o->height_scale) ? 1.0 : o->height_scale;
    double offset = isnan(o->height_offset) ? 0.0 : o->height_offset;
    ex->sea_level = isnan(o->sea_level) ? 0.0f : (float)o->sea_level;
    if (!grey || user_lin) {
        for (size_t i = 0; i < n; i++)
            hgt->data[i] = (float)(hgt->data[i] * scale + offset);
        return PG_OK;
    }
    ex->height_is_grey = true;
    size_t ng = (size_t)ex->width * ex->height;
    uint8_t *water = malloc(ng);
    if (!water) return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate the water mask");
    pg_exemplar_water_mask(ex->albedo, ex->width, ex->height, water);
    pg_status st = calibrate_grey(o, ex, hgt, water, err);
    free(water);
    return st;
}

static void measure_agreement(pg_exemplar *ex) {
    if (!ex->height_is_grey) return;
    size_t n = (size_t)ex->width * ex->height;
    uint8_t *water = malloc(n);
    if (!water) return;
    pg_exemplar_water_mask(ex->albedo, ex->width, ex->height, water);
    ex->calib.mask_agreement = pg_exemplar_mask_agreement(ex->elevation, ex->sea_level, water, n);
    free(water);
}

pg_status pg_exemplar_load(const pg_exemplar_opts *o, pg_exemplar *ex, pg_error *err) {
    memset(ex, 0, sizeof *ex);
    pg_image alb = {0}, hgt = {0};
    pg_status st = load_inputs(o, ex, &alb, &hgt, err);
    if (st == PG_OK) st = to_rgb(ex, ex->albedo_src, &alb, err);
    if (st != PG_OK) goto fail;
    if (hgt.channels > 1) first_channel(&hgt);
    ex->albedo_w = alb.width;
    ex->albedo_h = alb.height;
    ex->height_w = hgt.width;
    ex->height_h = hgt.height;
    int gw = o->grid_width > 0 ? o->grid_width : (alb.width < hgt.width ? alb.width : hgt.width);
    gw &= ~1;
    st = to_grid(&alb.data, alb.width, alb.height, 3, gw, err);
    if (st != PG_OK) goto fail;
    ex->width = gw;
    ex->height = gw / 2;
    ex->albedo = alb.data;
    alb.data = NULL;
    st = heights_to_metres(o, ex, &hgt, err);
    if (st == PG_OK) st = to_grid(&hgt.data, hgt.width, hgt.height, 1, gw, err);
    if (st != PG_OK) goto fail;
    ex->elevation = hgt.data;
    hgt.data = NULL;
    uint64_t repaired = 0;
    if (o->repair_ocean) st = pg_exemplar_repair_ocean(ex, &repaired, err);
    if (st != PG_OK) goto fail;
    if (repaired) {
        char what[96];
        snprintf(what, sizeof what, "%llu ocean texels repainted from depth (%%s); ",
                 (unsigned long long)repaired);
        note(ex, what, "data/README.md, \"Ocean colour repair\"");
    }
    measure_agreement(ex);
    return PG_OK;
fail:
    pg_image_free(&alb);
    pg_image_free(&hgt);
    pg_exemplar_free(ex);
    return st;
}

void pg_exemplar_free(pg_exemplar *ex) {
    if (!ex) return;
    free(ex->albedo);
    free(ex->elevation);
    ex->albedo = ex->elevation = NULL;
}

void pg_exemplar_compute_stats(const pg_exemplar *ex, pg_exemplar_stats *st) {
    memset(st, 0, sizeof *st);
    for (int c = 0; c < 3; c++) {
        st->albedo_min[c] = INFINITY;
        st->albedo_max[c] = -INFINITY;
    }
    st->height_min = INFINITY;
    st->height_max = -INFINITY;
    double sum_a[3] = {0}, sum_h = 0, land_w = 0, total_w = 0;
    size_t n = (size_t)ex->width * ex->height;
    for (int y = 0; y < ex->height; y++) {
        double w = cos((90.0 - 180.0 * (y + 0.5) / ex->height) * M_PI / 180.0);
        for (int x = 0; x < ex->width; x++) {
            size_t i = (size_t)y * ex->width + x;
            for (int c = 0; c < 3; c++) {
                float a = ex->albedo[3 * i + c];
                st->albedo_min[c] = fminf(st->albedo_min[c], a);
                st->albedo_max[c] = fmaxf(st->albedo_max[c], a);
                sum_a[c] += a;
            }
            float h = ex->elevation[i];
            st->height_min = fminf(st->height_min, h);
            st->height_max = fmaxf(st->height_max, h);
            sum_h += h;
            total_w += w;
            if (h > ex->sea_level) land_w += w;
        }
    }
    for (int c = 0; c < 3; c++)
        st->albedo_mean[c] = (float)(sum_a[c] / n);
    st->height_mean = (float)(sum_h / n);
    st->land_fraction = land_w / total_w;
}
