/* pg_equirect.c - sampling and resampling of equirectangular maps.
 *
 * Pixel (x, y) covers longitudes [-180 + 360x/W, -180 + 360(x+1)/W] and latitudes
 * [90 - 180y/H, 90 - 180(y+1)/H]; samples sit at pixel centres. Longitude wraps,
 * latitude clamps: the pole rows are the nearest data to the poles. */
#include "planetgen/pg_equirect.h"
#include "planetgen/pg_exemplar.h"

#include "pg_huge.h"

#include <math.h>
#include <stdlib.h>

void pg_equirect_sample(const float *img, int width, int height, int channels, double lat_deg,
                        double lon_deg, float *out) {
    double fx = (lon_deg + 180.0) / 360.0 * width - 0.5;
    double fy = (90.0 - lat_deg) / 180.0 * height - 0.5;
    if (fy < 0) fy = 0;
    if (fy > height - 1) fy = height - 1;
    double x0f = floor(fx), y0f = floor(fy);
    double ax = fx - x0f, ay = fy - y0f;
    long x0 = (long)x0f % width;
    if (x0 < 0) x0 += width;
    long x1 = (x0 + 1) % width;
    long y0 = (long)y0f, y1 = y0 + 1 < height ? y0 + 1 : y0;
    const float *p00 = img + ((size_t)y0 * width + x0) * channels;
    const float *p01 = img + ((size_t)y0 * width + x1) * channels;
    const float *p10 = img + ((size_t)y1 * width + x0) * channels;
    const float *p11 = img + ((size_t)y1 * width + x1) * channels;
    for (int c = 0; c < channels; c++) {
        double top = p00[c] + ax * (p01[c] - p00[c]);
        double bot = p10[c] + ax * (p11[c] - p10[c]);
        out[c] = (float)(top + ay * (bot - top));
    }
}

static void box_shrink(const float *src, int sw, int channels, int f, float *dst, int dw, int dh) {
    double inv = 1.0 / ((double)f * f);
#pragma omp parallel for schedule(static)
    for (int y = 0; y < dh; y++) {
        double acc[16];
        for (int x = 0; x < dw; x++) {
            for (int c = 0; c < channels; c++)
                acc[c] = 0;
            for (int j = 0; j < f; j++) {
                const float *row = src + ((size_t)(y * f + j) * sw + (size_t)x * f) * channels;
                if (channels == 1) /* the relief: no channel index to compute */
                    for (int i = 0; i < f; i++)
                        acc[0] += row[i];
                else
                    for (int i = 0; i < f; i++)
                        for (int c = 0; c < channels; c++)
                            acc[c] += row[i * channels + c];
            }
            for (int c = 0; c < channels; c++)
                dst[((size_t)y * dw + x) * channels + c] = (float)(acc[c] * inv);
        }
    }
}

pg_status pg_equirect_resample(const float *src, int sw, int sh, int channels, int dw, int dh,
                               float **out, pg_error *err) {
    if (channels > 16) return pg_error_set(err, PG_ERR_BADINPUT, "too many channels to resample");
    float *dst = pg_huge_malloc((size_t)dw * dh * channels * sizeof(float));
    if (!dst) return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate a %dx%d map", dw, dh);
    if (sw % dw == 0 && sh % dh == 0 && sw / dw == sh / dh) {
        box_shrink(src, sw, channels, sw / dw, dst, dw, dh);
    } else {
#pragma omp parallel for schedule(static)
        for (int y = 0; y < dh; y++) {
            double lat = 90.0 - 180.0 * (y + 0.5) / dh;
            for (int x = 0; x < dw; x++) {
                double lon = -180.0 + 360.0 * (x + 0.5) / dw;
                pg_equirect_sample(src, sw, sh, channels, lat, lon,
                                   dst + ((size_t)y * dw + x) * channels);
            }
        }
    }
    *out = dst;
    return PG_OK;
}
