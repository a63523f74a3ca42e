/* pg_planet_world.c - the macro world of layout world (pg_plates.h, pg_climate.h) as the
 * synthesis' existing controls: its elevation as the equirectangular guide of Scott &
 * Dodgson 2021 (soft constraint, pg_guide.c) and its climate as a type map of Gain,
 * Merry & Marais 2015 (hard constraint, pg_types.c), so that ice stays where the climate
 * is cold and desert where it is dry (docs/generate.md, "Layout world").
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
#include "planetgen/pg_planet_synth.h"

#include "planetgen/pg_climate.h"
#include "planetgen/pg_cube.h"

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

pg_status pg_planet_world_types(const pg_planet_world *w, int width, pg_types_map *out,
                                pg_error *err) {
    memset(out, 0, sizeof *out);
    pg_status st = check_world(w, width, err);
    if (st) return st;
    const int height = width / 2;
    const size_t np = (size_t)width * height;
    float *t = malloc(np * sizeof *t), *p = malloc(np * sizeof *p), *h = malloc(np * sizeof *h);
    out->mask = malloc(np);
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
