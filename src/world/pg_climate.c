/* pg_climate.c - the climate model's driver: parameters, the output fields, and the
 * per-texel evaluation of temperature and precipitation (the formulas are in
 * pg_climate.h; the moisture march in pg_climate_march_upwind.c; the insolation in
 * pg_climate_insolation_berger1978.c).
 *
 * The temperature law is Budyko's (1969) linear outgoing-radiation balance read
 * backwards: with outgoing longwave A + B T balancing absorbed sunlight, T is linear
 * in the local insolation Q; transport and albedo are folded into the two fitted
 * constants. The lapse rate is the standard atmosphere's 6.5 K/km. The zonal rain
 * profile is the shape of the observed zonal mean (GPCP; Hartmann ch. 6): a peak at
 * the ITCZ a few degrees north of the equator, minima in the subtropics, a second
 * peak in the westerlies near 45-50 degrees, little rain at the poles. Colder air
 * holds less water (Clausius-Clapeyron, about 7% per kelvin), so land lifted above
 * sea level gets less rain by exp(-clausius_per_K * lapse cooling).
 *
 * The default constants were fitted on Earth's northern hemisphere against Marble's
 * climate maps (tests/test_climate.c, docs/world.md "Climate"). */
#include "pg_climate_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PG_INSOL_TABLE 1801 /* latitude -90..90 in 0.1 degree steps */

void pg_climate_params_default(pg_climate_params *p) {
    p->axial_tilt_deg = 23.4;
    p->temperature_offset_K = 0.0;
    p->solar_constant_wm2 = 1361.0;
    p->planet_radius_km = 6371.0;
    p->temp_intercept_c = -34.80;
    p->temp_per_wm2 = 0.1558;
    p->temp_per_wm2_sq = -2.072e-4;
    p->lapse_rate_K_per_km = 6.5;
    p->cont_const_K = -0.19;
    p->cont_cos2lat_K = 4.98;
    p->continentality_km = 1500.0;
    p->precip_polar_mm = 150.0;
    p->precip_itcz_mm = 1800.0;
    p->itcz_lat_deg = 5.0;
    p->itcz_width_deg = 10.0;
    p->precip_westerly_mm = 900.0;
    p->westerly_lat_deg = 48.0;
    p->westerly_width_deg = 13.0;
    p->land_decay_km = 400.0;
    p->sea_recharge_km = 300.0;
    p->orographic_m = 1600.0;
    p->windward_per_m_km = 0.05;
    p->precip_floor = 0.6;
    p->clausius_per_K = 0.05;
    p->max_fetch_km = 6000.0;
}

void pg_climate_init(pg_climate *c) {
    memset(c, 0, sizeof *c);
}

void pg_climate_free(pg_climate *c) {
    free(c->temperature_c);
    free(c->precipitation_mm);
    free(c->insolation_wm2);
    free(c->continentality);
    free(c->moisture);
    pg_climate_init(c);
}

static pg_status check_range(double v, double lo, double hi, const char *name, pg_error *err) {
    if (!(v >= lo && v <= hi))
        return pg_error_set(err, PG_ERR_BADINPUT, "climate: %s = %g is outside [%g, %g]", name, v,
                            lo, hi);
    return PG_OK;
}

static pg_status check_params(const pg_climate_params *p, pg_error *err) {
    pg_status st = PG_OK;
    if (!st) st = check_range(p->axial_tilt_deg, 0.0, 90.0, "axial_tilt_deg", err);
    if (!st) st = check_range(p->temperature_offset_K, -100.0, 100.0, "temperature_offset_K", err);
    if (!st) st = check_range(p->solar_constant_wm2, 0.0, 1e5, "solar_constant_wm2", err);
    if (!st) st = check_range(p->planet_radius_km, 1.0, 1e6, "planet_radius_km", err);
    if (!st) st = check_range(p->lapse_rate_K_per_km, 0.0, 20.0, "lapse_rate_K_per_km", err);
    if (!st) st = check_range(p->continentality_km, 1.0, 1e6, "continentality_km", err);
    if (!st) st = check_range(p->land_decay_km, 1.0, 1e6, "land_decay_km", err);
    if (!st) st = check_range(p->sea_recharge_km, 1.0, 1e6, "sea_recharge_km", err);
    if (!st) st = check_range(p->orographic_m, 1.0, 1e6, "orographic_m", err);
    if (!st) st = check_range(p->max_fetch_km, 0.0, 1e5, "max_fetch_km", err);
    if (!st) st = check_range(p->precip_floor, 0.0, 1.0, "precip_floor", err);
    if (!st) st = check_range(p->itcz_width_deg, 0.1, 180.0, "itcz_width_deg", err);
    if (!st) st = check_range(p->westerly_width_deg, 0.1, 180.0, "westerly_width_deg", err);
    double finite[] = {p->temp_intercept_c, p->temp_per_wm2,      p->temp_per_wm2_sq,
                       p->cont_const_K,     p->cont_cos2lat_K,    p->precip_polar_mm,
                       p->precip_itcz_mm,   p->itcz_lat_deg,      p->precip_westerly_mm,
                       p->westerly_lat_deg, p->windward_per_m_km, p->clausius_per_K};
    for (size_t i = 0; !st && i < sizeof finite / sizeof finite[0]; i++)
        if (!isfinite(finite[i]))
            st = pg_error_set(err, PG_ERR_BADINPUT, "climate: a constant is not finite");
    return st;
}

/* The zonal rain profile, mm/yr, before moisture and height. */
static double zonal_precip(const pg_climate_params *p, double lat_deg) {
    double di = (lat_deg - p->itcz_lat_deg) / p->itcz_width_deg;
    double dw = (fabs(lat_deg) - p->westerly_lat_deg) / p->westerly_width_deg;
    return p->precip_polar_mm + p->precip_itcz_mm * exp(-di * di) +
           p->precip_westerly_mm * exp(-dw * dw);
}

static double table_lookup(const double *t, double lat_deg) {
    double x = (lat_deg + 90.0) * 10.0;
    if (x <= 0.0) return t[0];
    if (x >= PG_INSOL_TABLE - 1) return t[PG_INSOL_TABLE - 1];
    int i = (int)x;
    double f = x - i;
    return t[i] * (1.0 - f) + t[i + 1] * f;
}

static void texel_dir(pg_cube_projection proj, int64_t n, int64_t id, double dir[3]) {
    int64_t face = id / (n * n), r = id % (n * n);
    double u = (2.0 * (double)(r % n) + 1.0) / (double)n - 1.0;
    double v = (2.0 * (double)(r / n) + 1.0) / (double)n - 1.0;
    pg_cube_to_dir(proj, (int)face, u, v, dir);
}

static void eval_texel(const pg_climate_params *p, const pg_cube_grid *g, const float *elev,
                       const float *mask, const double *insol, int64_t id, pg_climate *c) {
    double dir[3];
    texel_dir(g->proj, g->n, id, dir);
    double lat = asin(fmax(-1.0, fmin(1.0, dir[2]))) * 180.0 / M_PI;
    float h = elev[id];
    pg_climate_march_result mr = {1.0f, 1.0f, 0.0f};
    if (h > 0.0f) pg_climate_march(p, g, elev, mask, dir, h, &mr);
    double q = table_lookup(insol, lat);
    double cooling = p->lapse_rate_K_per_km * fmax((double)h, 0.0) / 1000.0;
    double cont = 1.0 - mr.maritime;
    double coslat2 = cos(2.0 * lat * M_PI / 180.0);
    double t = p->temp_intercept_c + p->temp_per_wm2 * q +
               p->temp_per_wm2_sq * (q - 300.0) * (q - 300.0) - cooling +
               cont * (p->cont_const_K + p->cont_cos2lat_K * coslat2) + p->temperature_offset_K;
    double rain = zonal_precip(p, lat) * (p->precip_floor + (1.0 - p->precip_floor) * mr.moisture) *
                  (1.0 + p->windward_per_m_km * mr.windward_rise) *
                  exp(-p->clausius_per_K * cooling);
    c->temperature_c[id] = (float)t;
    c->precipitation_mm[id] = (float)rain;
    c->insolation_wm2[id] = (float)q;
    c->continentality[id] = (float)cont;
    c->moisture[id] = mr.moisture;
}

pg_status pg_climate_compute(const pg_climate_params *p, pg_cube_projection proj, int64_t n,
                             const float *elevation_m, pg_climate *c, pg_error *err) {
    if (!p || !c) return pg_error_set(err, PG_ERR_BADINPUT, "climate: NULL parameters or output");
    if (n < 1 || n > 65536)
        return pg_error_set(err, PG_ERR_BADINPUT, "climate: n = %lld is outside [1, 65536]",
                            (long long)n);
    if (!elevation_m) return pg_error_set(err, PG_ERR_BADINPUT, "climate: elevation is NULL");
    pg_status st = check_params(p, err);
    if (st) return st;
    pg_cube_grid g; /* the seam maps of the march's samples, built once */
    pg_cube_sample_grid_init(&g, proj, n);
    int64_t total = 6 * n * n;
    for (int64_t i = 0; i < total; i++)
        if (!isfinite(elevation_m[i]))
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "climate: elevation of texel %lld is not finite", (long long)i);
    pg_climate_free(c);
    c->n = n;
    c->proj = proj;
    size_t bytes = (size_t)total * sizeof(float);
    c->temperature_c = malloc(bytes);
    c->precipitation_mm = malloc(bytes);
    c->insolation_wm2 = malloc(bytes);
    c->continentality = malloc(bytes);
    c->moisture = malloc(bytes);
    double *insol = malloc(PG_INSOL_TABLE * sizeof(double));
    float *mask = malloc(bytes);
    if (!c->temperature_c || !c->precipitation_mm || !c->insolation_wm2 || !c->continentality ||
        !c->moisture || !insol || !mask) {
        free(insol);
        free(mask);
        pg_climate_free(c);
        return pg_error_set(err, PG_ERR_NOMEM, "climate: out of memory for n = %lld", (long long)n);
    }
    pg_climate_annual_insolation_table(-90.0, 0.1, PG_INSOL_TABLE, p->axial_tilt_deg,
                                       p->solar_constant_wm2, insol);
    for (int64_t id = 0; id < total; id++)
        mask[id] = elevation_m[id] > 0.0f ? 1.0f : 0.0f;
#pragma omp parallel for schedule(dynamic, 256)
    for (int64_t id = 0; id < total; id++)
        eval_texel(p, &g, elevation_m, mask, insol, id, c);
    free(insol);
    free(mask);
    return PG_OK;
}
