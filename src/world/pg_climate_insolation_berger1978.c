/* pg_climate_insolation_berger1978.c - the annual-mean daily insolation at the top
 * of the atmosphere as a function of latitude and axial tilt.
 *
 * Source: the daily-mean insolation formula (Berger 1978, "Long-term variations of
 * daily insolation and Quaternary climatic changes", J. Atmos. Sci. 35; the same
 * formula is eq. 2.15 of Hartmann, "Global Physical Climatology"):
 *   Q_day = (S0 / pi) (a/r)^2 [h0 sin(lat) sin(dec) + cos(lat) cos(dec) sin(h0)],
 *   cos(h0) = -tan(lat) tan(dec)   (h0 = pi in polar day, 0 in polar night),
 *   sin(dec) = sin(tilt) sin(lambda)  (lambda: the true longitude of the sun).
 * We take a circular orbit (a/r = 1, eccentricity ignored: 3% on Earth), so time is
 * uniform in lambda and the annual mean is the mean of Q_day over lambda in
 * [0, 2 pi). The midpoint rule on PG_INSOL_STEPS points is exact to far better than
 * the model needs (the integrand is smooth except for kinks at polar day/night).
 *
 * Checks that make it correct: at tilt 0 the result is (S0/pi) cos(lat), the pole 0;
 * at the pole for any tilt it is (S0/pi) sin(tilt) (the half year of daylight at
 * elevation dec); the global area mean is S0/4 for every tilt. */
#include "planetgen/pg_climate.h"

#include <math.h>

#define PG_INSOL_STEPS 720

/* The declination's terms at the midpoints of the year: they do not depend on the
 * latitude, so a table of latitudes computes them once (sin, cos and tan of dec). */
typedef struct insol_dec {
    double s, c, t;
} insol_dec;

static void declinations(double tilt, insol_dec *d) {
    for (int k = 0; k < PG_INSOL_STEPS; k++) {
        double lambda = 2.0 * M_PI * (k + 0.5) / PG_INSOL_STEPS;
        double dec = asin(sin(tilt) * sin(lambda));
        d[k] = (insol_dec){sin(dec), cos(dec), tan(dec)};
    }
}

static double annual(double lat_deg, const insol_dec *d, double s0) {
    double lat = lat_deg * M_PI / 180.0;
    /* keep tan(lat) finite: the formula is continuous at the pole */
    if (lat > M_PI / 2 - 1e-9) lat = M_PI / 2 - 1e-9;
    if (lat < -M_PI / 2 + 1e-9) lat = -M_PI / 2 + 1e-9;
    const double sl = sin(lat), cl = cos(lat), tl = tan(lat);
    double sum = 0.0;
    for (int k = 0; k < PG_INSOL_STEPS; k++) { /* the daily mean at declination k */
        double t = -tl * d[k].t;
        double h0 = t >= 1.0 ? 0.0 : (t <= -1.0 ? M_PI : acos(t));
        sum += s0 / M_PI * (h0 * sl * d[k].s + cl * d[k].c * sin(h0));
    }
    return sum / PG_INSOL_STEPS;
}

double pg_climate_annual_insolation(double lat_deg, double tilt_deg, double solar_constant_wm2) {
    insol_dec d[PG_INSOL_STEPS];
    declinations(tilt_deg * M_PI / 180.0, d);
    return annual(lat_deg, d, solar_constant_wm2);
}

void pg_climate_annual_insolation_table(double lat0_deg, double step_deg, int count,
                                        double tilt_deg, double solar_constant_wm2, double *out) {
    insol_dec d[PG_INSOL_STEPS];
    declinations(tilt_deg * M_PI / 180.0, d);
#pragma omp parallel for schedule(static)
    for (int i = 0; i < count; i++)
        out[i] = annual(lat0_deg + step_deg * i, d, solar_constant_wm2);
}
