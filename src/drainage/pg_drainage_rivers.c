/* pg_drainage_rivers.c - the rivers preview (pg_drainage.h): river texels drawn in blue
 * over an equirectangular relief image.
 *
 * Two passes over the output pixels. (1) Strength: each pixel's centre (geodetic
 * latitude on the planet's ellipsoid, as pg_cube.h's equirectangular convention) is
 * turned into the ray direction of that surface point, looked up on the cube with
 * pg_cube_from_dir, and takes the largest accumulation of the 2 x 2 texels around it
 * (a texel-wide river survives when a pixel spans two texels); its strength is
 * t = log(acc / threshold) / log(1000) clamped to [0, 1], or none below the threshold.
 * (2) Drawing: a pixel is covered by every river pixel within that river's width
 * radius 0.5 + 1.5 t (longitude wraps); it blends towards blue with opacity 0.45 + 0.55 t
 * of the strongest river covering it. Every pixel depends only on the inputs, so rows
 * run in parallel. */
#include "planetgen/pg_drainage.h"

#include <math.h>
#include <stdlib.h>

#define RIVER_DECADES 3.0 /* strength 1 at 1000 x the threshold */
#define RIVER_REACH 2     /* the widest radius, 2 px, rounded up */

static const float river_rgb[3] = {0.05f, 0.25f, 0.95f};

/* Ray direction of the surface point at geodetic (lat, lon) on an ellipsoid of
 * flattening f: the point is (N cos lat cos lon, N cos lat sin lon, N (1-f)^2 sin lat). */
static void geodetic_dir(double lat, double lon, double f, double d[3]) {
    double cl = cos(lat), e = (1.0 - f) * (1.0 - f);
    d[0] = cl * cos(lon), d[1] = cl * sin(lon), d[2] = e * sin(lat);
}

static int64_t clamp64(int64_t v, int64_t lo, int64_t hi) {
    return v < lo ? lo : v > hi ? hi : v;
}

/* Largest accumulation among the 2 x 2 texels around the direction. */
static float acc_at(const pg_drainage_terrain *p, const float *acc, const double d[3]) {
    int face;
    double u, v;
    pg_cube_from_dir(p->projection, d, &face, &u, &v);
    const int64_t n = p->n;
    int64_t x0 = clamp64((int64_t)floor((u + 1) * 0.5 * n - 0.5), 0, n - 2);
    int64_t y0 = clamp64((int64_t)floor((v + 1) * 0.5 * n - 0.5), 0, n - 2);
    const float *a = acc + (size_t)face * n * n;
    float m = 0;
    for (int64_t y = y0; y <= y0 + 1; y++)
        for (int64_t x = x0; x <= x0 + 1; x++)
            if (a[y * n + x] > m) m = a[y * n + x];
    return m;
}

static float strength(float a, double thr) {
    if (!(a >= thr)) return -1.0f;
    double t = log(a / thr) / (RIVER_DECADES * log(10.0));
    return (float)(t > 1 ? 1 : t);
}

static void strength_row(const pg_drainage_terrain *p, const float *acc, double thr, int w, int h,
                         int j, float *out) {
    const double deg = 3.14159265358979323846 / 180.0;
    double lat = (90.0 - (j + 0.5) * 180.0 / h) * deg;
    for (int i = 0; i < w; i++) {
        double d[3];
        geodetic_dir(lat, (-180.0 + (i + 0.5) * 360.0 / w) * deg, p->ellipsoid.f, d);
        out[i] = strength(acc_at(p, acc, d), thr);
    }
}

/* Strength of the strongest river covering pixel (i, j), or -1. */
static float cover(const float *s, int w, int h, int i, int j) {
    float best = -1.0f;
    for (int dy = -RIVER_REACH; dy <= RIVER_REACH; dy++) {
        int y = j + dy;
        if (y < 0 || y >= h) continue;
        for (int dx = -RIVER_REACH; dx <= RIVER_REACH; dx++) {
            float t = s[(size_t)y * w + (size_t)((i + dx + w) % w)];
            float r = 0.5f + 1.5f * t;
            if (t > best && (float)(dx * dx + dy * dy) <= r * r) best = t;
        }
    }
    return best;
}

pg_status pg_drainage_draw_rivers(const pg_drainage_terrain *p, const float *acc,
                                  double threshold_km2, float *rgb, int w, int h, pg_error *err) {
    if (w < 1 || h < 1 || p->n < 2 || !(threshold_km2 > 0))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "drainage: rivers image %d x %d, threshold %g: bad size or threshold",
                            w, h, threshold_km2);
    float *s = malloc((size_t)w * (size_t)h * sizeof *s);
    if (!s) return pg_error_set(err, PG_ERR_NOMEM, "drainage: out of memory for the rivers");
#pragma omp parallel for schedule(dynamic, 8)
    for (int j = 0; j < h; j++)
        strength_row(p, acc, threshold_km2, w, h, j, s + (size_t)j * w);
#pragma omp parallel for schedule(dynamic, 8)
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            float t = cover(s, w, h, i, j);
            if (t < 0) continue;
            float alpha = 0.45f + 0.55f * t, *px = rgb + 3 * ((size_t)j * w + i);
            for (int k = 0; k < 3; k++)
                px[k] = px[k] * (1 - alpha) + river_rgb[k] * alpha;
        }
    free(s);
    return PG_OK;
}
