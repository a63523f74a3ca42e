/* pg_plates_render.c - preview images of a plate world: equirectangular maps (pixel
 * (i, j) at longitude -180 + (i + 0.5) 360 / W, latitude 90 - (j + 0.5) 180 / H, as in
 * pg_cube.h), each pixel showing its nearest texel.
 *
 * The relief map is a hypsometric tint: piecewise-linear colour ramps over depth and
 * height. The plate map gives each plate a hue spaced by the golden angle (so
 * neighbouring ids differ strongly), darkened over ocean and lightened with height,
 * and paints boundary texels by kind: red convergent, blue divergent, green transform. */
#include "pg_plates_internal.h"

typedef struct pg_plates_stop {
    float z, r, g, b;
} pg_plates_stop;

static const pg_plates_stop pg_plates_ramp[] = {
    {-7000, 0.02f, 0.05f, 0.25f}, {-4500, 0.07f, 0.18f, 0.48f}, {-2000, 0.20f, 0.40f, 0.70f},
    {-200, 0.45f, 0.68f, 0.88f},  {0, 0.60f, 0.80f, 0.92f},     {1, 0.20f, 0.50f, 0.22f},
    {400, 0.45f, 0.62f, 0.30f},   {1000, 0.72f, 0.68f, 0.40f},  {2000, 0.62f, 0.45f, 0.28f},
    {3500, 0.50f, 0.38f, 0.32f},  {5000, 0.95f, 0.95f, 0.95f}};

static void pg_plates_tint(double z, float rgb[3]) {
    int n = (int)(sizeof pg_plates_ramp / sizeof pg_plates_ramp[0]);
    const pg_plates_stop *a = &pg_plates_ramp[0], *b = &pg_plates_ramp[n - 1];
    if (z <= a->z) {
        b = a;
    } else {
        for (int i = 1; i < n; i++)
            if (z <= pg_plates_ramp[i].z) {
                a = &pg_plates_ramp[i - 1];
                b = &pg_plates_ramp[i];
                break;
            }
        if (z > b->z) a = b;
    }
    double f = b->z > a->z ? (z - a->z) / (b->z - a->z) : 0;
    rgb[0] = (float)(a->r + f * (b->r - a->r));
    rgb[1] = (float)(a->g + f * (b->g - a->g));
    rgb[2] = (float)(a->b + f * (b->b - a->b));
}

static void pg_plates_hue(int k, float rgb[3]) {
    double h = fmod(k * 0.618033988749895, 1.0) * 6;
    double x = 1 - fabs(fmod(h, 2) - 1);
    double r = 0, g = 0, b = 0;
    switch ((int)h) {
    case 0:
        r = 1, g = x;
        break;
    case 1:
        r = x, g = 1;
        break;
    case 2:
        g = 1, b = x;
        break;
    case 3:
        g = x, b = 1;
        break;
    case 4:
        r = x, b = 1;
        break;
    default:
        r = 1, b = x;
        break;
    }
    rgb[0] = (float)(0.25 + 0.6 * r);
    rgb[1] = (float)(0.25 + 0.6 * g);
    rgb[2] = (float)(0.25 + 0.6 * b);
}

static pg_status pg_plates_render(const pg_plates_world *w, int width, int plates, pg_image *out,
                                  pg_error *err) {
    if (!w || !w->elevation_m || !out)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: render needs a generated world");
    if (width < 8 || width > 16384 || width % 2)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: width = %d is not even in 8..16384",
                            width);
    int height = width / 2;
    pg_status st = pg_image_alloc(out, width, height, 3, err);
    if (st != PG_OK) return st;
    pg_plates_grid g = {.n = w->n, .proj = w->proj}; /* only for nearest-texel lookups */
    if ((st = pg_cube_texel_finder_init(&g.find, w->proj, w->n, err)) != PG_OK) {
        pg_image_free(out);
        return st;
    }
#pragma omp parallel for schedule(static)
    for (int j = 0; j < height; j++) {
        double lat = (90 - (j + 0.5) * 180.0 / height) * PG_PLATES_PI / 180;
        for (int i = 0; i < width; i++) {
            double lon = (-180 + (i + 0.5) * 360.0 / width) * PG_PLATES_PI / 180;
            double d[3] = {cos(lat) * cos(lon), cos(lat) * sin(lon), sin(lat)};
            int64_t t = pg_plates_grid_nearest(&g, d);
            float *px = out->data + 3 * ((size_t)j * (size_t)width + (size_t)i), c[3];
            double z = w->elevation_m[t];
            if (!plates) {
                pg_plates_tint(z, px);
                continue;
            }
            pg_plates_hue(w->plate[t], c);
            double shade = z > 0 ? 0.85 + 0.15 * fmin(1, z / 3000) : 0.45 + 0.25 * (1 + z / 7000);
            for (int k = 0; k < 3; k++)
                px[k] = (float)(c[k] * shade);
            static const float kind[4][3] = {
                {0, 0, 0}, {0.9f, 0.05f, 0.05f}, {0.1f, 0.2f, 1.0f}, {0.1f, 0.85f, 0.1f}};
            if (w->boundary[t] != PG_PLATES_INTERIOR)
                for (int k = 0; k < 3; k++)
                    px[k] = kind[w->boundary[t] & 3][k];
        }
    }
    pg_cube_texel_finder_free(&g.find);
    return PG_OK;
}

pg_status pg_plates_render_plates(const pg_plates_world *w, int width, pg_image *out,
                                  pg_error *err) {
    return pg_plates_render(w, width, 1, out, err);
}

pg_status pg_plates_render_relief(const pg_plates_world *w, int width, pg_image *out,
                                  pg_error *err) {
    return pg_plates_render(w, width, 0, out, err);
}
