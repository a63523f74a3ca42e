/* pg_relief_shade.c - shaded-relief previews of equirectangular height maps.
 *
 * Colour = hypsometric tint (blues by depth below sea level; greens, browns and
 * white by height above) times a Lambertian hill shade lit from the north-west at
 * 45 deg elevation. Slopes are taken in metres on a sphere of Earth's mean radius,
 * with a vertical exaggeration of PG_SHADE_EXAGGERATION: at a few km per pixel,
 * true slopes are too gentle to see. */
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_relief.h"

#include <math.h>

#define PG_SHADE_EXAGGERATION 20.0
#define PG_SHADE_RADIUS_M 6371008.8

typedef struct tint_stop {
    float h, r, g, b;
} tint_stop;

static const tint_stop tint_sea[] = {{-11000, .02f, .05f, .20f},
                                     {-6000, .05f, .12f, .35f},
                                     {-3000, .10f, .25f, .55f},
                                     {-200, .25f, .50f, .75f},
                                     {0, .45f, .70f, .85f}};
static const tint_stop tint_land[] = {{0, .25f, .50f, .25f},    {300, .45f, .62f, .32f},
                                      {1000, .72f, .70f, .42f}, {2500, .60f, .45f, .30f},
                                      {4500, .80f, .78f, .76f}, {9000, 1.f, 1.f, 1.f}};

static void tint(const tint_stop *s, int n, float h, float *rgb) {
    if (h <= s[0].h) {
        rgb[0] = s[0].r, rgb[1] = s[0].g, rgb[2] = s[0].b;
        return;
    }
    for (int i = 1; i < n; i++) {
        if (h <= s[i].h) {
            float t = (h - s[i - 1].h) / (s[i].h - s[i - 1].h);
            rgb[0] = s[i - 1].r + t * (s[i].r - s[i - 1].r);
            rgb[1] = s[i - 1].g + t * (s[i].g - s[i - 1].g);
            rgb[2] = s[i - 1].b + t * (s[i].b - s[i - 1].b);
            return;
        }
    }
    rgb[0] = s[n - 1].r, rgb[1] = s[n - 1].g, rgb[2] = s[n - 1].b;
}

void pg_relief_shade(const float *height, int width, int height_px, float sea_level,
                     float *rgb_out) {
    const double lx = -0.5, ly = 0.5, lz = 0.70710678; /* from the NW, 45 deg up */
    double dy_m = M_PI * PG_SHADE_RADIUS_M / height_px;
#pragma omp parallel for schedule(static)
    for (int y = 0; y < height_px; y++) {
        double lat = (90.0 - 180.0 * (y + 0.5) / height_px) * M_PI / 180.0;
        double dx_m = 2 * M_PI * PG_SHADE_RADIUS_M * fmax(cos(lat), 1e-3) / width;
        int yn = y > 0 ? y - 1 : y, ys = y + 1 < height_px ? y + 1 : y;
        for (int x = 0; x < width; x++) {
            int xw = (x + width - 1) % width, xe = (x + 1) % width;
            const float *row = height + (size_t)y * width;
            double gx = (row[xe] - row[xw]) / (2 * dx_m) * PG_SHADE_EXAGGERATION;
            double gy = (height[(size_t)yn * width + x] - height[(size_t)ys * width + x]) /
                        ((ys - yn) * dy_m) * PG_SHADE_EXAGGERATION;
            /* normal of z = h(x east, y north): (-gx, -gy, 1) */
            double len = sqrt(gx * gx + gy * gy + 1);
            double shade = (-gx * lx - gy * ly + lz) / len;
            shade = 0.35 + 0.65 * fmax(shade, 0) / lz;
            float h = row[x] - sea_level, rgb[3];
            if (h <= 0)
                tint(tint_sea, 5, h, rgb);
            else
                tint(tint_land, 6, h, rgb);
            float *o = rgb_out + ((size_t)y * width + x) * 3;
            for (int c = 0; c < 3; c++)
                o[c] = (float)fmin(1.0, rgb[c] * shade);
        }
    }
}
