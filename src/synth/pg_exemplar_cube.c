/* pg_exemplar_cube.c - the exemplar cube: the global exemplar reprojected onto the six
 * faces of the cube sphere, so that exemplar neighbourhoods are free of the latitude
 * stretching of the equirectangular map.
 *
 * Idea: each face is E x E texels in the cube's grid coordinates (pg_cube.h, the
 * default equi-angular projection), extended by a gutter of g texels on every side.
 * The gutter is sampled with the same projection continued past the face edge, which
 * lands on the neighbouring faces' part of the sphere: it is the seam-aware halo of the
 * face, taken directly from the sphere (so it needs no rotation bookkeeping and has no
 * resampling of an already resampled face). Neighbourhood reads near a face edge are
 * then valid up to g texels outside the face. A toroidal single face (tests, the
 * jitter-0 sanity check) has no gutter: reads wrap.
 *
 * Channels per texel: CIE Lab of the albedo and the height times lab_height_scale,
 * which makes the height's standard deviation w_h times the albedo's Lab standard
 * deviation, so the channel weight is a ratio independent of the exemplar's units. */
#include "pg_huge.h"
#include "pg_synth_internal.h"

#include "planetgen/pg_cube.h"
#include "planetgen/pg_equirect.h"
#include "planetgen/pg_exemplar.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

static float lab_f(float t) {
    const float d = 6.0f / 29.0f;
    return t > d * d * d ? cbrtf(t) : t / (3 * d * d) + 4.0f / 29.0f;
}

void pg_synth_srgb_to_lab(const float rgb[3], float lab[3]) {
    float r = srgb_to_linear(rgb[0]), g = srgb_to_linear(rgb[1]), b = srgb_to_linear(rgb[2]);
    float x = (0.4124f * r + 0.3576f * g + 0.1805f * b) / 0.95047f;
    float y = 0.2126f * r + 0.7152f * g + 0.0722f * b;
    float z = (0.0193f * r + 0.1192f * g + 0.9505f * b) / 1.08883f;
    float fx = lab_f(x), fy = lab_f(y), fz = lab_f(z);
    lab[0] = 116.0f * fy - 16.0f;
    lab[1] = 500.0f * (fx - fy);
    lab[2] = 200.0f * (fy - fz);
}

static uint8_t to_u8(float v) {
    v = v < 0 ? 0 : (v > 1 ? 1 : v);
    return (uint8_t)lrintf(v * 255.0f);
}

void pg_synth_faces_free(pg_synth_faces *f) {
    free(f->px);
    memset(f, 0, sizeof *f);
}

static pg_status faces_alloc(pg_synth_faces *f, int nfaces, int size, int gutter, bool torus,
                             pg_error *err) {
    f->nfaces = nfaces;
    f->size = size;
    f->gutter = gutter;
    f->ext = size + 2 * gutter;
    f->torus = torus;
    f->px = pg_huge_malloc((size_t)nfaces * f->ext * f->ext * PG_SYNTH_CH * sizeof(float));
    if (!f->px)
        return pg_error_set(err, PG_ERR_NOMEM, "exemplar cube: out of memory for %d faces of %d",
                            nfaces, f->ext);
    return PG_OK;
}

/* Mean and standard deviation of the Lab channels (pooled) and of the height over the
 * face interiors, to set lab_height_scale. */
static void channel_stats(const pg_synth_faces *f, double *lab_std, double *h_std) {
    double s[4] = {0}, s2[4] = {0};
    size_t n = 0;
    for (int face = 0; face < f->nfaces; face++)
        for (int y = 0; y < f->size; y++)
            for (int x = 0; x < f->size; x++) {
                const float *p = pg_synth_faces_at(f, face, x, y);
                for (int c = 0; c < 4; c++) {
                    s[c] += p[c];
                    s2[c] += (double)p[c] * p[c];
                }
                n++;
            }
    double var[4];
    for (int c = 0; c < 4; c++) {
        double m = s[c] / n;
        var[c] = s2[c] / n - m * m;
        if (var[c] < 0) var[c] = 0;
    }
    *lab_std = sqrt(var[0] + var[1] + var[2]);
    *h_std = sqrt(var[3]);
}

/* Scale the raw height channel (metres) so its std is w_h times the Lab std. */
static void weight_height(pg_synth_faces *f, double height_weight, pg_synth_exemplar *ex) {
    double lab_std, h_std;
    channel_stats(f, &lab_std, &h_std);
    if (lab_std < 1e-3) lab_std = 20.0; /* flat albedo: use a typical Lab spread */
    double s = h_std > 1e-6 ? height_weight * lab_std / h_std : 1.0;
    ex->lab_height_scale = (float)s;
    size_t n = (size_t)f->nfaces * f->ext * f->ext;
    for (size_t i = 0; i < n; i++)
        f->px[i * 4 + 3] *= (float)s;
}

static void store_finest(pg_synth_exemplar *ex, int face, int x, int y, const float rgb[3],
                         float h) {
    size_t t = ((size_t)face * ex->face_size + y) * ex->face_size + x;
    for (int c = 0; c < 3; c++)
        ex->albedo[t * 3 + c] = to_u8(rgb[c]);
    ex->height[t] = h;
}

pg_status pg_exemplar_cube_build(const float *albedo, const float *height, int width, int height_px,
                                 int size, int gutter, pg_synth_faces *faces, pg_synth_exemplar *ex,
                                 pg_error *err) {
    pg_status st = faces_alloc(faces, 6, size, gutter, false, err);
    if (st) return st;
    const int ext = faces->ext;
#pragma omp parallel for schedule(dynamic, 8) collapse(2)
    for (int face = 0; face < 6; face++)
        for (int y = 0; y < ext; y++) {
            for (int x = 0; x < ext; x++) {
                /* grid coordinates continued past the face edge into the gutter */
                double u = (2.0 * (x - gutter) + 1.0) / size - 1.0;
                double v = (2.0 * (y - gutter) + 1.0) / size - 1.0;
                double d[3];
                pg_cube_to_dir(PG_CUBE_DEFAULT_PROJECTION, face, u, v, d);
                double r = pg_vec3_length(d);
                double lat = asin(d[2] / r) * (180.0 / M_PI);
                double lon = atan2(d[1], d[0]) * (180.0 / M_PI);
                float rgb[3], h;
                pg_equirect_sample(albedo, width, height_px, 3, lat, lon, rgb);
                pg_equirect_sample(height, width, height_px, 1, lat, lon, &h);
                float *p = faces->px + (((size_t)face * ext + y) * ext + x) * PG_SYNTH_CH;
                pg_synth_srgb_to_lab(rgb, p);
                p[3] = h;
                int ix = x - gutter, iy = y - gutter;
                if (ix >= 0 && iy >= 0 && ix < size && iy < size)
                    store_finest(ex, face, ix, iy, rgb, h);
            }
        }
    return PG_OK;
}

pg_status pg_exemplar_torus_build(const float *albedo, const float *height, int size,
                                  pg_synth_faces *faces, pg_synth_exemplar *ex, pg_error *err) {
    pg_status st = faces_alloc(faces, 1, size, 0, true, err);
    if (st) return st;
    for (size_t i = 0; i < (size_t)size * size; i++) {
        float *p = faces->px + i * PG_SYNTH_CH;
        pg_synth_srgb_to_lab(albedo + i * 3, p);
        p[3] = height[i];
        store_finest(ex, 0, (int)(i % size), (int)(i / size), albedo + i * 3, height[i]);
    }
    return PG_OK;
}

void pg_exemplar_cube_weight_height(pg_synth_faces *f, double height_weight,
                                    pg_synth_exemplar *ex) {
    weight_height(f, height_weight, ex);
}
