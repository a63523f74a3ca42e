/* pg_planet_world.c - the macro world of layout world (pg_plates.h, pg_climate.h) as the
 * synthesis' controls: its elevation as the guide of Scott & Dodgson 2021 (soft
 * constraint, pg_guide.c) and its climate as the type constraints of Gain, Merry & Marais
 * 2015 (hard constraint, pg_types.c), so that ice stays where the climate is cold and
 * desert where it is dry (docs/generate.md, "Layout world"). The synthesis samples them
 * on the cube at each level (pg_planet_world_level); pg_planet_world_guide and
 * pg_planet_world_types make the same controls as equirectangular maps.
 *
 * THE CLIMATE RULE per pixel (T annual mean, P annual rain, from pg_climate.h):
 *   T >= PG_CLIMATE_ICE_C + 8  no ice (a warm climate never shows an ice sheet)
 *   T <  PG_CLIMATE_ICE_C      on land ice or mountain only, at sea ice or ocean (an ice
 *                              climate shows no forest, grass or desert, and its land
 *                              is an ice sheet, as Antarctica's and Greenland's)
 *   T <  PG_CLIMATE_ICE_C + 6  on land ice, grass (tundra) or mountain (and the sea at the
 *                              coast): no forest or desert next to an ice sheet
 *   elevation < -150 m         ocean (or sea ice) only; > 150 m: no ocean (land stays
 *                              where the plates put it, the coasts are the exemplar's)
 *   warm and P >= 1000 mm/yr   no desert (a wet climate never shows a sand sea)
 *   elevation < 1000 m         no mountain (high ground only where the plates raised it:
 *                              the belts along convergent boundaries and the plateaus)
 * Everything else allows every type; a pixel the rules leave empty allows every type. */
#include "pg_huge.h"
#include "planetgen/pg_planet_synth.h"

#include "planetgen/pg_climate.h"
#include "planetgen/pg_cube.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WORLD_WARM_MARGIN_K 8.0
#define WORLD_WET_MM 1000.0
#define WORLD_HIGH_M 1000.0
#define WORLD_TUNDRA_K 6.0
#define WORLD_COAST_M 150.0

static pg_status check_world(const pg_planet_world *w, int width, pg_error *err) {
    if (!w || w->n < 1 || !w->elevation_m || !w->temperature_c || !w->precipitation_mm)
        return pg_error_set(err, PG_ERR_BADINPUT, "layout world: no macro world");
    if (width < 4 || width % 2)
        return pg_error_set(err, PG_ERR_BADINPUT, "layout world: bad width %d", width);
    return PG_OK;
}

pg_status pg_planet_world_guide(const pg_planet_world *w, int width, pg_guide *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    pg_status st = check_world(w, width, err);
    if (st) return st;
    out->metres = malloc((size_t)width * (width / 2) * sizeof(float));
    if (!out->metres) return pg_error_set(err, PG_ERR_NOMEM, "layout world: out of memory");
    st = pg_cube_to_equirect(PG_CUBE_DEFAULT_PROJECTION, w->n, NULL, w->elevation_m, 1, out->metres,
                             width, width / 2, err);
    if (st) return pg_guide_free(out), st;
    out->width = width;
    out->height = width / 2;
    return PG_OK;
}

static uint8_t climate_mask(float h, float t, float p) {
    const uint8_t bit_ice = 1u << PG_TYPE_ICE, bit_desert = 1u << PG_TYPE_DESERT,
                  bit_mountain = 1u << PG_TYPE_MOUNTAIN, bit_ocean = 1u << PG_TYPE_OCEAN;
    const uint8_t high = h >= WORLD_HIGH_M ? bit_mountain : 0;
    uint8_t m;
    if (t < PG_CLIMATE_ICE_C)
        m = (uint8_t)(bit_ice | (h > 0 ? high : bit_ocean));
    else if (h > 0 && t < PG_CLIMATE_ICE_C + WORLD_TUNDRA_K)
        m = (uint8_t)(bit_ice | (1u << PG_TYPE_GRASS) | high | bit_ocean);
    else
        m = (uint8_t)((PG_TYPES_ALL & ~bit_mountain) | high);
    if (t >= PG_CLIMATE_ICE_C + WORLD_WARM_MARGIN_K) m &= (uint8_t)~bit_ice;
    if (t >= 0 && p >= WORLD_WET_MM) m &= (uint8_t)~bit_desert;
    if (h < -WORLD_COAST_M) m &= (uint8_t)(bit_ocean | bit_ice);
    if (h > WORLD_COAST_M) m &= (uint8_t)~bit_ocean;
    return m ? m : PG_TYPES_ALL;
}

/* Row (face f, y) of level r: the fields at each texel, bilinear on the world's own cube
 * grid (the same projection, so a level texel's centre is a linear map of the world's
 * texel coordinates), averaged over k x k points of the texel when the level is coarser
 * than the world. hpt is the world interleaved (elevation, temperature, rain). */
static int8_t temp_c(double t) {
    return (int8_t)lrint(fmin(127, fmax(-128, t)));
}

static void level_row(const pg_cube_grid *g, const float *hpt, int64_t r, int f, int64_t y,
                      float *guide, uint8_t *mask, int8_t *temp) {
    const int64_t n = g->n;
    const int k = r >= n ? 1 : (int)((n + r - 1) / r);
    const double scale = (double)n / (double)r;
    if (k == 1) { /* one point a texel: the bilinear inline away from the face's edges */
        const double fy = ((double)y + 0.5) * scale - 0.5, y0 = floor(fy), ty = fy - y0;
        const int64_t iy = (int64_t)y0;
        const float *face = hpt + (size_t)f * (size_t)(n * n) * 3;
        for (int64_t x = 0; x < r; x++) {
            const double fx = ((double)x + 0.5) * scale - 0.5, x0 = floor(fx), tx = fx - x0;
            const int64_t ix = (int64_t)x0;
            float v[3];
            if (ix >= 0 && iy >= 0 && ix + 1 < n && iy + 1 < n) { /* as face_sample_g */
                const float *t0 = face + (size_t)(iy * n + ix) * 3, *t2 = t0 + (size_t)n * 3;
                for (int c = 0; c < 3; c++) {
                    double a = t0[c] + tx * ((double)t0[c + 3] - t0[c]),
                           b = t2[c] + tx * ((double)t2[c + 3] - t2[c]);
                    v[c] = (float)(a + ty * (b - a));
                }
            } else {
                pg_cube_sample_face(g, hpt, 3, f, fx, fy, v);
            }
            if (guide) guide[x] = v[0];
            if (mask) mask[x] = climate_mask(v[0], v[1], v[2]);
            if (temp) temp[x] = temp_c(v[1]);
        }
        return;
    }
    for (int64_t x = 0; x < r; x++) {
        double acc[3] = {0, 0, 0};
        for (int sy = 0; sy < k; sy++)
            for (int sx = 0; sx < k; sx++) {
                float v[3];
                double fx = ((double)x + (sx + 0.5) / k) * scale - 0.5,
                       fy = ((double)y + (sy + 0.5) / k) * scale - 0.5;
                pg_cube_sample_face(g, hpt, 3, f, fx, fy, v);
                acc[0] += v[0], acc[1] += v[1], acc[2] += v[2];
            }
        const double kk = (double)k * k;
        const float h = (float)(acc[0] / kk);
        if (guide) guide[x] = h;
        if (mask) mask[x] = climate_mask(h, (float)(acc[1] / kk), (float)(acc[2] / kk));
        if (temp) temp[x] = temp_c(acc[1] / kk);
    }
}

pg_status pg_planet_world_level(const pg_planet_world *w, int64_t r, int64_t row0, int64_t row1,
                                float *guide, uint8_t *mask, pg_error *err) {
    return pg_planet_world_level_climate(w, r, row0, row1, guide, mask, NULL, err);
}

pg_status pg_planet_world_level_climate(const pg_planet_world *w, int64_t r, int64_t row0,
                                        int64_t row1, float *guide, uint8_t *mask, int8_t *temp,
                                        pg_error *err) {
    pg_status st = check_world(w, 4, err);
    if (st) return st;
    if (r < 1 || row0 < 0 || row1 > 6 * r || row0 > row1)
        return pg_error_set(err, PG_ERR_BADINPUT, "layout world: bad level rows");
    const int64_t n = w->n;
    const size_t nw = (size_t)6 * n * n;
    float *hpt = malloc(nw * 3 * sizeof *hpt);
    if (!hpt) return pg_error_set(err, PG_ERR_NOMEM, "layout world: out of memory");
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < nw; i++) {
        hpt[3 * i] = w->elevation_m[i];
        hpt[3 * i + 1] = w->temperature_c[i];
        hpt[3 * i + 2] = w->precipitation_mm[i];
    }
    pg_cube_grid g;
    pg_cube_sample_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, n);
#pragma omp parallel for schedule(static)
    for (int64_t row = row0; row < row1; row++) {
        size_t o = (size_t)(row - row0) * (size_t)r;
        level_row(&g, hpt, r, (int)(row / r), row % r, guide ? guide + o : NULL,
                  mask ? mask + o : NULL, temp ? temp + o : NULL);
    }
    free(hpt);
    return PG_OK;
}

uint8_t pg_planet_world_mask_at(const pg_planet_world *w, size_t i) {
    return climate_mask(w->elevation_m[i], w->temperature_c[i], w->precipitation_mm[i]);
}

pg_status pg_planet_world_types(const pg_planet_world *w, int width, pg_types_map *out,
                                pg_error *err) {
    memset(out, 0, sizeof *out);
    pg_status st = check_world(w, width, err);
    if (st) return st;
    const int height = width / 2;
    const size_t np = (size_t)width * height;
    float *t = pg_huge_malloc(np * sizeof *t), *p = pg_huge_malloc(np * sizeof *p),
          *h = pg_huge_malloc(np * sizeof *h);
    out->mask = pg_huge_malloc(np);
    if (!t || !p || !h || !out->mask) {
        free(t), free(p), free(h), pg_types_map_free(out);
        return pg_error_set(err, PG_ERR_NOMEM, "layout world: out of memory");
    }
    st = pg_cube_to_equirect(PG_CUBE_DEFAULT_PROJECTION, w->n, NULL, w->temperature_c, 1, t, width,
                             height, err);
    if (!st)
        st = pg_cube_to_equirect(PG_CUBE_DEFAULT_PROJECTION, w->n, NULL, w->precipitation_mm, 1, p,
                                 width, height, err);
    if (!st)
        st = pg_cube_to_equirect(PG_CUBE_DEFAULT_PROJECTION, w->n, NULL, w->elevation_m, 1, h,
                                 width, height, err);
    for (size_t i = 0; !st && i < np; i++)
        out->mask[i] = climate_mask(h[i], t[i], p[i]);
    free(t), free(p), free(h);
    if (st) return pg_types_map_free(out), st;
    out->width = width;
    out->height = height;
    return PG_OK;
}
