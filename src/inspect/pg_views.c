/* pg_views.c - gnomonic views of a planet from any source; see pg_views.h.
 *
 * The idea: a view is defined purely by directions, so a planet's cube faces, the
 * exemplar reprojected onto a cube and the original equirectangular exemplar can all
 * be rendered into pixel-identical frames and compared with the LPIPS-style metric.
 * Pixels run in parallel with OpenMP; each depends only on its own samples, so the
 * result does not depend on the thread count. */
#include "planetgen/pg_equirect.h"
#include "planetgen/pg_views.h"

#include "planetgen/pg_exemplar.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double VIEWS_PI = 3.14159265358979323846;

static const pg_views_centre views_centres[PG_VIEWS_COUNT] = {
    {"north", 90, 0, true},        {"south", -90, 0, true},        {"equator_0", 0, 0, false},
    {"equator_90e", 0, 90, false}, {"equator_180", 0, 180, false}, {"equator_90w", 0, -90, false}};

const pg_views_centre *pg_views_centre_get(int view) {
    return (view >= 0 && view < PG_VIEWS_COUNT) ? &views_centres[view] : NULL;
}

void pg_views_frame(int view, double c[3], double r[3], double u[3]) {
    const pg_views_centre *vc = pg_views_centre_get(view);
    double lon = vc->lon_deg * VIEWS_PI / 180;
    if (view == PG_VIEW_NORTH) {
        c[0] = 0, c[1] = 0, c[2] = 1;
        u[0] = -1, u[1] = 0, u[2] = 0; /* towards longitude 180 */
    } else if (view == PG_VIEW_SOUTH) {
        c[0] = 0, c[1] = 0, c[2] = -1;
        u[0] = 1, u[1] = 0, u[2] = 0; /* towards longitude 0 */
    } else {
        c[0] = cos(lon), c[1] = sin(lon), c[2] = 0;
        u[0] = 0, u[1] = 0, u[2] = 1; /* north */
    }
    pg_vec3_cross(u, c, r); /* so that r x u = c */
}

double pg_views_prefilter_deg(int size, double fov_deg, double planet_texel_deg,
                              double exemplar_pixel_deg) {
    double spacing = fmax(fov_deg / size, fmax(planet_texel_deg, exemplar_pixel_deg));
    return PG_VIEWS_PREFILTER_SPACINGS * spacing;
}

void pg_view_free(pg_view *v) {
    free(v->rgb);
    free(v->height);
    v->rgb = v->height = NULL;
}

/* Point samples (R, G, B, height) on an m x m grid covering the view. */
static void point_samples(int view, int m, double fov_deg, pg_views_sampler s, void *user,
                          float *pts) {
    double c[3], r[3], u[3], t = tan(fov_deg * VIEWS_PI / 360);
    pg_views_frame(view, c, r, u);
#pragma omp parallel for schedule(dynamic, 8)
    for (int j = 0; j < m; j++) {
        for (int i = 0; i < m; i++) {
            double x = t * (2 * (i + 0.5) / m - 1), y = t * (1 - 2 * (j + 0.5) / m);
            double d[3] = {c[0] + x * r[0] + y * u[0], c[1] + x * r[1] + y * u[1],
                           c[2] + x * r[2] + y * u[2]};
            pg_vec3_normalize(d);
            s(user, d, pts + ((size_t)j * m + i) * 4);
        }
    }
}

/* Gaussian reduction by f along one axis of an image of 4-float samples: axis 0 turns
 * rows x (f*n) into rows x n; axis 1 turns (f*n) x rows into n x rows. Output sample o
 * sits at input coordinate f*o + (f-1)/2; weights are renormalised at the border. */
static void reduce(const float *src, int n, int rows, int f, const double *k, int r, int axis,
                   float *dst) {
    int m = n * f;
#pragma omp parallel for schedule(static)
    for (int row = 0; row < rows; row++) {
        for (int o = 0; o < n; o++) {
            double acc[4] = {0, 0, 0, 0}, ws = 0;
            for (int t = -r; t <= r; t++) {
                int a = f * o + (f - 1) / 2 + t;
                if (a < 0 || a >= m) continue;
                const float *p =
                    axis ? src + ((size_t)a * rows + row) * 4 : src + ((size_t)row * m + a) * 4;
                for (int c = 0; c < 4; c++)
                    acc[c] += k[t + r] * p[c];
                ws += k[t + r];
            }
            float *q = axis ? dst + ((size_t)o * rows + row) * 4 : dst + ((size_t)row * n + o) * 4;
            for (int c = 0; c < 4; c++)
                q[c] = (float)(acc[c] / ws);
        }
    }
}

pg_status pg_views_render(int view, int size, double fov_deg, double sigma_deg, pg_views_sampler s,
                          void *user, pg_view *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    if (!pg_views_centre_get(view))
        return pg_error_set(err, PG_ERR_BADINPUT, "views: no view %d", view);
    if (size < 1 || size > 8192)
        return pg_error_set(err, PG_ERR_BADINPUT, "views: view size %d out of range", size);
    if (!(fov_deg > 0 && fov_deg < 120) || !(sigma_deg >= 0) || !isfinite(sigma_deg))
        return pg_error_set(err, PG_ERR_BADINPUT, "views: field %g deg or filter %g deg bad",
                            fov_deg, sigma_deg);
    const int f = PG_VIEWS_SUPERSAMPLE;
    size_t m = (size_t)size * f, np = (size_t)size * size;
    double sig = fmax(sigma_deg / (fov_deg / (double)m), 0.5 * f); /* in supersamples */
    int r = (int)ceil(3 * sig);
    double *k = malloc((2 * (size_t)r + 1) * sizeof *k);
    float *pts = malloc(m * m * 4 * sizeof *pts), *mid = malloc(m * size * 4 * sizeof *mid);
    out->rgb = malloc(np * 3 * sizeof(float));
    out->height = malloc(np * sizeof(float));
    if (!k || !pts || !mid || !out->rgb || !out->height) {
        free(k), free(pts), free(mid);
        pg_view_free(out);
        return pg_error_set(err, PG_ERR_NOMEM, "views: out of memory for a %d px view", size);
    }
    for (int t = -r; t <= r; t++)
        k[t + r] = exp(-0.5 * t * t / (sig * sig));
    out->size = size;
    point_samples(view, (int)m, fov_deg, s, user, pts);
    reduce(pts, size, (int)m, f, k, r, 0, mid); /* m rows of size samples */
    reduce(mid, size, size, f, k, r, 1, pts);   /* size x size, reusing pts */
    for (size_t p = 0; p < np; p++) {
        memcpy(out->rgb + 3 * p, pts + 4 * p, 3 * sizeof(float));
        out->height[p] = pts[4 * p + 3];
    }
    free(k), free(pts), free(mid);
    return PG_OK;
}

void pg_views_sample_cube(void *user, const double dir[3], float rgbh[4]) {
    const pg_views_cube_src *src = user;
    int face;
    double u, v;
    pg_cube_from_dir(src->proj, dir, &face, &u, &v);
    double fx = (u + 1) / 2 * (double)src->n - 0.5, fy = (v + 1) / 2 * (double)src->n - 0.5;
    double x0 = floor(fx), y0 = floor(fy), tx = fx - x0, ty = fy - y0;
    if (x0 < 0 || y0 < 0 || x0 + 1 >= (double)src->n || y0 + 1 >= (double)src->n) {
        /* a tap beyond the face: pg_cube_sample wraps it across the seam */
        pg_cube_sample(src->proj, src->n, src->rgbh, 4, dir, rgbh);
        return;
    }
    const float *p = src->rgbh + (((size_t)face * src->n + (size_t)y0) * src->n + (size_t)x0) * 4;
    size_t dy = (size_t)src->n * 4;
    for (int c = 0; c < 4; c++) {
        double a = p[c] + tx * (p[4 + c] - p[c]), b = p[dy + c] + tx * (p[dy + 4 + c] - p[dy + c]);
        rgbh[c] = (float)(a + ty * (b - a));
    }
}

void pg_views_sample_equirect(void *user, const double dir[3], float rgbh[4]) {
    const pg_views_equirect_src *src = user;
    double lat, lon;
    if (src->ell.f != 0) {
        pg_geo_dir_to_latlon(&src->ell, dir, &lat, &lon);
    } else { /* on a sphere geocentric = geodetic: skip the adapter */
        lat = atan2(dir[2], hypot(dir[0], dir[1])) * 180 / VIEWS_PI;
        lon = atan2(dir[1], dir[0]) * 180 / VIEWS_PI;
    }
    pg_equirect_sample(src->rgb, src->width, src->height_px, 3, lat, lon, rgbh);
    rgbh[3] = 0;
    if (src->height)
        pg_equirect_sample(src->height, src->width, src->height_px, 1, lat, lon, rgbh + 3);
}

pg_image pg_view_rgb_image(const pg_view *v) {
    pg_image img;
    memset(&img, 0, sizeof img);
    img.width = img.height = v->size;
    img.channels = 3;
    img.data = v->rgb;
    img.unit_scale = 1;
    return img;
}

pg_status pg_views_montage(const pg_view *const *views, int count, int gap, pg_image *out,
                           pg_error *err) {
    int s = views[0]->size, w = count * s + (count - 1) * gap;
    pg_status st = pg_image_alloc(out, w, s, 3, err);
    if (st != PG_OK) return st;
    for (size_t i = 0; i < (size_t)w * s * 3; i++)
        out->data[i] = 1;
    for (int k = 0; k < count; k++)
        for (int j = 0; j < s; j++)
            memcpy(out->data + ((size_t)j * w + (size_t)k * (s + gap)) * 3,
                   views[k]->rgb + (size_t)j * s * 3, (size_t)s * 3 * sizeof(float));
    return PG_OK;
}
