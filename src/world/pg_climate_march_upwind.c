/* pg_climate_march_upwind.c - moisture and maritime influence carried by the
 * prevailing wind: a semi-Lagrangian march upwind from each texel, then a forward
 * integration of the air column's moisture back to the texel.
 *
 * Sources: the general-circulation wind belts (Hadley, Ferrel and polar cells:
 * Hartmann, "Global Physical Climatology", ch. 6; trades from the north-east /
 * south-east, westerlies from the south-west / north-west, polar easterlies); the
 * "distance from the ocean along the wind" and orographic rain shadow follow the
 * spirit of WorldEngine's precipitation and of the linear upslope model of Smith &
 * Barstad 2004 (rain proportional to the uplift rate, moisture removed as air
 * climbs), reduced here to exponential laws with fitted lengths.
 *
 * The march. From the texel's direction, step backwards against the local wind by a
 * fixed angle (half a texel), re-evaluating the wind at every point, sampling the
 * elevation and the land mask bilinearly at one located point (pg_cube_locate, then
 * pg_cube_sample_face: seamless across faces). It stops after a long
 * stretch of open sea (where the air is saturated: recharge has converged to within
 * e^-3) or at max_fetch_km. Then the column is integrated downwind, starting
 * saturated: over the sea moisture relaxes towards 1 over sea_recharge_km; over land
 * it decays over land_decay_km and by exp(-climb / orographic_m) for every metre the
 * air climbs. The maritime influence on temperature is integrated the same way with
 * continentality_km and no orographic term.
 *
 * Why it is correct for our needs: the result is a pure function of the texel and
 * the field (no order dependence, so any thread count gives the same bits); a sea
 * texel upwind of the texel sets moisture near 1, long overland fetch and ranges
 * upwind dry it out (the lee side of a ridge receives the air after its climb, the
 * windward side before it). Where the wind belts diverge (near 30 degrees) the upwind
 * march stalls and oscillates about the belt edge: it then samples the same small
 * region, which is the descending, dry air of the subtropical high. */
#include "pg_climate_internal.h"

#include <math.h>

#define PG_MARCH_MAX_STEPS 2048
#define PG_WIND_VEER_DEG 25.0 /* angle of the wind to the parallels */

void pg_climate_wind(double lat_deg, double *east, double *north) {
    double a = PG_WIND_VEER_DEG * M_PI / 180.0;
    double s = lat_deg > 0 ? 1.0 : (lat_deg < 0 ? -1.0 : 0.0);
    double al = fabs(lat_deg);
    if (al < 30.0 || al >= 60.0) { /* trades and polar easterlies: westward, equatorward */
        *east = -cos(a);
        *north = -sin(a) * s;
    } else { /* westerlies: eastward, poleward */
        *east = cos(a);
        *north = sin(a) * s;
    }
}

/* The wind at the unit vector p: pg_climate_wind at its latitude, which depends on the
 * latitude only through its sign and its belt (|latitude| below 30, 30 to 60, from 60
 * degrees). Away from those parallels the belt follows from p[2] against their sines
 * and a latitude inside it stands in, without asin; within 1e-9 of them (asin's
 * rounding is below 1e-15 there) the latitude itself is computed. So the wind is
 * exactly pg_climate_wind's. */
static void wind_at(const double p[3], double *we, double *wn) {
    const double z = fmax(-1.0, fmin(1.0, p[2])), az = fabs(z);
    const double s30 = 0.5, s60 = 0.86602540378443864676;
    double lat;
    if (fabs(az - s30) < 1e-9 || fabs(az - s60) < 1e-9)
        lat = asin(z) * 180.0 / M_PI;
    else
        lat = z == 0 ? 0.0 : copysign(az < s30 ? 15.0 : (az < s60 ? 45.0 : 75.0), z);
    pg_climate_wind(lat, we, wn);
}

/* Move the unit vector p by `step` radians against the wind. */
static void step_upwind(double p[3], double step) {
    double we, wn;
    wind_at(p, &we, &wn);
    double r = sqrt(p[0] * p[0] + p[1] * p[1]);
    double e[3] = {0.0, 1.0, 0.0};
    if (r > 1e-12) {
        e[0] = -p[1] / r;
        e[1] = p[0] / r;
        e[2] = 0.0;
    }
    double nv[3] = {p[1] * e[2] - p[2] * e[1], p[2] * e[0] - p[0] * e[2],
                    p[0] * e[1] - p[1] * e[0]};
    double q[3], len = 0.0;
    for (int k = 0; k < 3; k++) {
        q[k] = p[k] - step * (we * e[k] + wn * nv[k]);
        len += q[k] * q[k];
    }
    len = sqrt(len);
    for (int k = 0; k < 3; k++)
        p[k] = q[k] / len;
}

void pg_climate_march(const pg_climate_params *p, const pg_cube_grid *g, const float *elevation_m,
                      const float *land_mask, const double dir[3], float h0,
                      pg_climate_march_result *out) {
    float h[PG_MARCH_MAX_STEPS + 1];
    unsigned char land[PG_MARCH_MAX_STEPS + 1];
    double step = 0.25 * M_PI / (double)g->n; /* half a texel at the face centre */
    double step_km = step * p->planet_radius_km;
    int max_steps = (int)ceil(p->max_fetch_km / step_km);
    if (max_steps > PG_MARCH_MAX_STEPS) { /* a very fine grid: lengthen the step */
        max_steps = PG_MARCH_MAX_STEPS;
        step_km = p->max_fetch_km / max_steps;
        step = step_km / p->planet_radius_km;
    }
    double sea_run_stop = 3.0 * p->sea_recharge_km, sea_run = 0.0;
    double q[3] = {dir[0], dir[1], dir[2]};
    h[0] = h0;
    land[0] = 1;
    int k = 0;
    while (k < max_steps && sea_run < sea_run_stop) {
        step_upwind(q, step);
        k++;
        float lm;
        int face;
        double fx, fy; /* one projection for both fields */
        pg_cube_locate(g, q, &face, &fx, &fy);
        pg_cube_sample_face(g, elevation_m, 1, face, fx, fy, &h[k]);
        pg_cube_sample_face(g, land_mask, 1, face, fx, fy, &lm);
        land[k] = lm >= 0.5f;
        sea_run = land[k] ? 0.0 : sea_run + step_km;
    }
    double m = 1.0, c = 1.0; /* far upwind the air is taken as saturated and maritime */
    double sea_keep = exp(-step_km / p->sea_recharge_km);
    double land_keep = exp(-step_km / p->land_decay_km);
    double cont_keep = exp(-step_km / p->continentality_km);
    for (int j = k; j >= 1; j--) {
        float to = h[j - 1];
        if (!land[j - 1]) {
            m = 1.0 - (1.0 - m) * sea_keep;
            c = 1.0 - (1.0 - c) * sea_keep;
        } else {
            double climb = (double)to - fmax((double)h[j], 0.0);
            m *= land_keep * (climb > 0.0 ? exp(-climb / p->orographic_m) : 1.0);
            c *= cont_keep;
        }
    }
    double rise = 0.0;
    if (k >= 2 && h0 > 0.0f) rise = ((double)h0 - fmax((double)h[2], 0.0)) / (2.0 * step_km);
    out->moisture = (float)m;
    out->maritime = (float)c;
    out->windward_rise = (float)(rise > 0.0 ? rise : 0.0);
}
