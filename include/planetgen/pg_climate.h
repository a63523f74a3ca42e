/* pg_climate.h - a macro climate for a planet: annual mean temperature and
 * precipitation on a cube field of elevation, plus the biome-ish helpers (ice,
 * desert) that synthesis needs. docs/world.md, "Climate", describes the model, its
 * sources, its calibration on Earth and its limits.
 *
 * The model in one paragraph. Temperature is a linear function of the annual-mean
 * daily insolation at the texel's latitude for the planet's axial tilt (Berger 1978;
 * the linear map is Budyko's 1969 energy balance without transport), minus a lapse
 * rate times the height of land above sea level, plus a continentality term that
 * grows with the distance the prevailing wind has travelled over land, plus a global
 * offset. Precipitation is a zonal profile of the general circulation (ITCZ, dry
 * subtropics, wet westerlies, dry poles) times the moisture that the prevailing wind
 * carries from the ocean: marching upwind along the trade winds, westerlies and polar
 * easterlies, moisture recharges over the sea, decays over land and is wrung out when
 * the air climbs (rain shadow), while windward slopes get extra rain.
 *
 * Input: elevation in metres relative to sea level on a cube (6*n*n floats, global
 * texel id face*n*n + y*n + x, see pg_cube.h); land is elevation > 0. Output: fields
 * of the same layout in a caller-owned pg_climate. The result does not depend on the
 * number of OpenMP threads: every texel is computed independently. */
#ifndef PLANETGEN_PG_CLIMATE_H
#define PLANETGEN_PG_CLIMATE_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_cube.h"
#include "planetgen/pg_image.h"

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pg_climate_params {
    /* The planet. */
    double axial_tilt_deg;       /* obliquity, 0..90; Earth 23.4 */
    double temperature_offset_K; /* added to every texel: ice age < 0 < hothouse */
    double solar_constant_wm2;   /* top-of-atmosphere flux; Earth 1361 */
    double planet_radius_km;     /* for along-wind distances; Earth 6371 */
    /* Temperature: T = temp_intercept_c + temp_per_wm2 * Q + temp_per_wm2_sq * (Q - 300)^2
     *              - lapse * max(h, 0)
     *              + (1 - maritime) * (cont_const_K + cont_cos2lat_K * cos(2 lat)). */
    double temp_intercept_c;
    double temp_per_wm2;
    double temp_per_wm2_sq;     /* curvature: the poleward heat transport flattens the tropics */
    double lapse_rate_K_per_km; /* about 6.5 */
    double cont_const_K, cont_cos2lat_K;
    double continentality_km; /* e-folding over-land distance of the maritime influence */
    /* Precipitation, the zonal profile (mm/yr): polar floor + ITCZ and westerly bumps. */
    double precip_polar_mm;
    double precip_itcz_mm, itcz_lat_deg, itcz_width_deg;
    double precip_westerly_mm, westerly_lat_deg, westerly_width_deg;
    /* Precipitation, the moisture march. */
    double land_decay_km;     /* e-folding over-land distance of moisture */
    double sea_recharge_km;   /* e-folding over-sea distance of recharge */
    double orographic_m;      /* moisture falls by 1/e per this much climb */
    double windward_per_m_km; /* extra rain per metre of rise per km upwind */
    double precip_floor;      /* fraction of the zonal rain without advected moisture */
    double clausius_per_K;    /* relative drop of rain per kelvin of lapse cooling */
    double max_fetch_km;      /* how far upwind the march looks */
} pg_climate_params;

/* Earth's defaults: the constants fitted on Earth's northern hemisphere
 * (tests/test_climate.c prints the fit; docs/world.md lists the figures). */
void pg_climate_params_default(pg_climate_params *p);

typedef struct pg_climate {
    int64_t n;               /* texels per face edge */
    pg_cube_projection proj; /* the projection of the input field */
    float *temperature_c;    /* annual mean near-surface air temperature, deg C */
    float *precipitation_mm; /* annual precipitation, mm/yr */
    float *insolation_wm2;   /* annual-mean daily insolation at the top, W/m^2 */
    float *continentality;   /* 0 maritime .. 1 deep interior along the wind */
    float *moisture;         /* advected moisture 0..1 (ocean 1) */
} pg_climate;

/* Zero the struct (safe to free afterwards). */
void pg_climate_init(pg_climate *c);
void pg_climate_free(pg_climate *c);

/* Compute the climate of an elevation cube field (6*n*n floats, metres). c must be
 * initialised; its previous fields are freed. BADINPUT for n < 1, a NULL field, a
 * non-finite elevation, or parameters out of range (named in the message). */
pg_status pg_climate_compute(const pg_climate_params *p, pg_cube_projection proj, int64_t n,
                             const float *elevation_m, pg_climate *c, pg_error *err);

/* Annual-mean daily insolation (W/m^2) at a latitude for an axial tilt, circular
 * orbit (Berger 1978, averaged over the year in true longitude). */
double pg_climate_annual_insolation(double lat_deg, double tilt_deg, double solar_constant_wm2);
/* The same at count latitudes lat0 + i step (degrees) into out, with the declination's
 * terms computed once: the same values as count calls. */
void pg_climate_annual_insolation_table(double lat0_deg, double step_deg, int count,
                                        double tilt_deg, double solar_constant_wm2, double *out);

/* Ice: annual mean temperature below PG_CLIMATE_ICE_C. Earth: Antarctica,
 * Greenland's interior and the perennial Arctic sea ice lie below -10 deg C; the
 * seasonal sea ice and the glacier-free tundra mostly above (docs/world.md). */
#define PG_CLIMATE_ICE_C (-10.0)
bool pg_climate_is_ice(float temperature_c);

/* Holdridge's potential-evapotranspiration ratio: PET / P with PET = 58.93 mm/yr per
 * degree of biotemperature (T clamped to 0..30 deg C). > 1 is drier than humid;
 * Holdridge's desert belts start near 4 (arid) and 8 (per-arid). */
double pg_climate_pet_ratio(float temperature_c, float precipitation_mm);

/* Warm desert: less than 250 mm/yr of rain and an annual mean above 0 deg C
 * (the classic precipitation bound of a desert; the cold case is tundra or ice). */
#define PG_CLIMATE_DESERT_MM 250.0
bool pg_climate_is_desert(float temperature_c, float precipitation_mm);

/* Marble's climate maps (Legates & Willmott 1989 / CRU CL 2.0 as 8-bit grey, see
 * docs/world.md): grey 0..255 -> monthly mean deg C, linear -69..+42; grey ->
 * monthly mm, piecewise linear through the legend anchors of precipcolors.leg. */
double pg_climate_marble_temp_c(double grey);
double pg_climate_marble_precip_mm(double grey);

/* Preview: an equirectangular RGB image (height = width / 2, then two maps side by
 * side: width 2*w x w/2): temperature on the left (blue -40 .. red +35 deg C, white
 * for ice), precipitation on the right (brown 0 .. green .. blue >= 3000 mm/yr on a
 * square-root scale), sea a little darker. out is allocated (pg_image_free). */
pg_status pg_climate_render_preview(const pg_climate *c, const float *elevation_m, int width,
                                    pg_image *out, pg_error *err);

/* The preview colour of one temperature or precipitation value (RGB 0..1). */
void pg_climate_temperature_rgb(float temperature_c, float rgb[3]);
void pg_climate_precipitation_rgb(float precipitation_mm, float rgb[3]);

#ifdef __cplusplus
}
#endif

#endif
