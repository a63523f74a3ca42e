/* pg_climate_preview.c - a picture of a climate: the temperature and precipitation
 * cube fields resampled to an equirectangular grid (pg_cube_to_equirect) and
 * coloured, side by side in one RGB image for a quick look.
 *
 * Colours: temperature on a blue (-40) - white-cyan (0) - yellow (+15) - red (+35)
 * ramp, with ice (pg_climate_is_ice) drawn white; precipitation on a square-root
 * scale from desert brown (0) through green (about 1000 mm) to deep blue (3000 mm and
 * more). Sea texels are drawn at 70% brightness so that coasts stay visible. */
#include "planetgen/pg_climate.h"

#include <math.h>
#include <stdlib.h>

typedef struct ramp_knot {
    float x, r, g, b;
} ramp_knot;

static void ramp(const ramp_knot *k, int nk, float x, float rgb[3]) {
    if (x <= k[0].x) {
        rgb[0] = k[0].r, rgb[1] = k[0].g, rgb[2] = k[0].b;
        return;
    }
    for (int i = 1; i < nk; i++) {
        if (x <= k[i].x) {
            float f = (x - k[i - 1].x) / (k[i].x - k[i - 1].x);
            rgb[0] = k[i - 1].r + f * (k[i].r - k[i - 1].r);
            rgb[1] = k[i - 1].g + f * (k[i].g - k[i - 1].g);
            rgb[2] = k[i - 1].b + f * (k[i].b - k[i - 1].b);
            return;
        }
    }
    rgb[0] = k[nk - 1].r, rgb[1] = k[nk - 1].g, rgb[2] = k[nk - 1].b;
}

void pg_climate_temperature_rgb(float temperature_c, float rgb[3]) {
    static const ramp_knot k[] = {{-40.f, 0.10f, 0.05f, 0.45f}, {-10.f, 0.25f, 0.45f, 0.90f},
                                  {0.f, 0.65f, 0.90f, 0.95f},   {15.f, 0.95f, 0.90f, 0.30f},
                                  {25.f, 0.95f, 0.50f, 0.10f},  {35.f, 0.65f, 0.05f, 0.05f}};
    ramp(k, 6, temperature_c, rgb);
}

void pg_climate_precipitation_rgb(float precipitation_mm, float rgb[3]) {
    static const ramp_knot k[] = {{0.f, 0.80f, 0.65f, 0.40f},  {10.f, 0.90f, 0.85f, 0.55f},
                                  {20.f, 0.55f, 0.75f, 0.35f}, {32.f, 0.15f, 0.55f, 0.20f},
                                  {45.f, 0.15f, 0.45f, 0.70f}, {55.f, 0.05f, 0.15f, 0.50f}};
    ramp(k, 6, sqrtf(fmaxf(precipitation_mm, 0.0f)), rgb);
}

pg_status pg_climate_render_preview(const pg_climate *c, const float *elevation_m, int width,
                                    pg_image *out, pg_error *err) {
    if (!c || !c->temperature_c || !elevation_m || !out)
        return pg_error_set(err, PG_ERR_BADINPUT, "climate preview: NULL climate or elevation");
    if (width < 4 || width > 16384 || width % 2)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "climate preview: width = %d must be even and in [4, 16384]", width);
    int h = width / 2;
    size_t np = (size_t)width * h;
    float *t = malloc(np * sizeof(float)), *p = malloc(np * sizeof(float));
    float *e = malloc(np * sizeof(float));
    pg_status st =
        (t && p && e) ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "climate preview: no memory");
    if (!st) st = pg_cube_to_equirect(c->proj, c->n, NULL, c->temperature_c, 1, t, width, h, err);
    if (!st)
        st = pg_cube_to_equirect(c->proj, c->n, NULL, c->precipitation_mm, 1, p, width, h, err);
    if (!st) st = pg_cube_to_equirect(c->proj, c->n, NULL, elevation_m, 1, e, width, h, err);
    if (!st) st = pg_image_alloc(out, 2 * width, h, 3, err);
    if (!st) {
        for (int y = 0; y < h; y++)
            for (int x = 0; x < width; x++) {
                size_t i = (size_t)y * width + x;
                float shade = e[i] > 0.0f ? 1.0f : 0.7f, a[3], b[3];
                pg_climate_temperature_rgb(t[i], a);
                if (pg_climate_is_ice(t[i])) a[0] = a[1] = a[2] = 1.0f;
                pg_climate_precipitation_rgb(p[i], b);
                float *l = out->data + ((size_t)y * 2 * width + x) * 3;
                float *r = l + (size_t)width * 3;
                for (int k = 0; k < 3; k++) {
                    l[k] = a[k] * shade;
                    r[k] = b[k] * shade;
                }
            }
    }
    free(t);
    free(p);
    free(e);
    return st;
}
