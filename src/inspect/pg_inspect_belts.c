/* pg_inspect_belts.c - mountain_belt_fraction of the realism report (docs/inspect.md):
 * the share of the planet's high land (non-ice land more than 2000 m above sea level)
 * that lies within 500 km of a convergent plate boundary, as Earth's high ground lies in
 * the belts where plates collide (the Himalaya, the Andes, the Alps). The boundaries come
 * from the macro world that `generate --layout world` writes (world.exr, channel
 * convergent_km, pg_plates.h); a planet without it has no figure (NaN, null in JSON).
 *
 * Ice is pg_types_classify's (the same rule as the report's ice figures); areas are the
 * texels' solid angles (two spherical triangles a texel). The convergent distance is
 * sampled bilinearly from the macro cube at each texel's direction. */
#include "planetgen/pg_inspect.h"

#include "planetgen/pg_exr.h"
#include "planetgen/pg_planet_synth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define BELT_HIGH_M 2000.0
#define BELT_NEAR_KM 500.0

/* The convergent_km channel of world.exr as a cube field (6*n*n, caller frees); EXR
 * readers list channels in the file's alphabetical order, where convergent_km comes
 * first of the four. */
static pg_status read_convergent(const char *path, float **out, int64_t *n_out, pg_error *err) {
    *out = NULL;
    float *conv = NULL;
    int64_t n = 0;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        pg_image img;
        pg_status st = pg_image_read_exr(path, pg_cube_face_name(f), &img, err);
        if (st) return free(conv), st;
        if (img.channels != 4 || img.width != img.height || (f && img.width != n)) {
            pg_image_free(&img), free(conv);
            return pg_error_set(err, PG_ERR_BADINPUT, "%s: not a world field", path);
        }
        n = img.width;
        if (!conv && !(conv = malloc((size_t)6 * n * n * sizeof *conv))) {
            pg_image_free(&img);
            return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", path);
        }
        for (int64_t y = 0; y < n; y++) /* image row 0 is the face's +v edge */
            for (int64_t x = 0; x < n; x++)
                conv[((size_t)f * n + y) * n + x] = img.data[((size_t)(n - 1 - y) * n + x) * 4];
        pg_image_free(&img);
    }
    *out = conv, *n_out = n;
    return PG_OK;
}

static uint8_t to8(float v) {
    return (uint8_t)(!(v > 0) ? 0 : v >= 1 ? 255 : v * 255.0f + 0.5f);
}

static double texel_area(const pg_cube_grid *g, int f, int64_t x, int64_t y) {
    double a[3], b[3], c[3], d[3];
    pg_cube_corner_dir(g, f, x, y, a), pg_cube_corner_dir(g, f, x + 1, y, b);
    pg_cube_corner_dir(g, f, x + 1, y + 1, c), pg_cube_corner_dir(g, f, x, y + 1, d);
    return pg_cube_spherical_triangle(a, b, c) + pg_cube_spherical_triangle(a, c, d);
}

pg_status pg_inspect_mountain_belts(const pg_planet *p, const char *world_exr, double *fraction,
                                    pg_error *err) {
    *fraction = NAN;
    struct stat sb;
    if (!world_exr || stat(world_exr, &sb) != 0) return PG_OK;
    float *conv;
    int64_t nw;
    pg_status st = read_convergent(world_exr, &conv, &nw, err);
    pg_cube_grid g;
    if (!st) st = pg_cube_grid_init(&g, p->projection, p->tiles, p->tile_size, err);
    if (st) return free(conv), st;
    const int64_t n = p->n;
    double high = 0, near = 0;
#pragma omp parallel for schedule(static) reduction(+ : high, near)
    for (int64_t row = 0; row < 6 * n; row++) {
        int f = (int)(row / n);
        int64_t y = row % n;
        for (int64_t x = 0; x < n; x++) {
            size_t i = (size_t)(y * n + x);
            float h = p->height[f][i];
            const float *rgb = p->albedo[f] + 3 * i;
            uint8_t c[3] = {to8(rgb[0]), to8(rgb[1]), to8(rgb[2])};
            if (h - p->sea_level <= BELT_HIGH_M ||
                pg_types_classify(c, h, p->sea_level) == PG_TYPE_ICE)
                continue;
            double d[3], a = texel_area(&g, f, x, y);
            float km;
            pg_cube_texel_dir(&g, ((int64_t)f * n + y) * n + x, d);
            pg_cube_sample(PG_CUBE_DEFAULT_PROJECTION, nw, conv, 1, d, &km);
            high += a;
            if (km <= BELT_NEAR_KM) near += a;
        }
    }
    free(conv);
    if (high > 0) *fraction = near / high;
    return PG_OK;
}
