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

static double daily_insolation(double lat, double dec, double s0) {
    double t = -tan(lat) * tan(dec);
    double h0 = t >= 1.0 ? 0.0 : (t <= -1.0 ? M_PI : acos(t));
    return s0 / M_PI * (h0 * sin(lat) * sin(dec) + cos(lat) * cos(dec) * sin(h0));
}

double pg_climate_annual_insolation(double lat_deg, double tilt_deg, double solar_constant_wm2) {
    double lat = lat_deg * M_PI / 180.0, tilt = tilt_deg * M_PI / 180.0;
    /* keep tan(lat) finite: the formula is continuous at the pole */
    if (lat > M_PI / 2 - 1e-9) lat = M_PI / 2 - 1e-9;
    if (lat < -M_PI / 2 + 1e-9) lat = -M_PI / 2 + 1e-9;
    double sum = 0.0;
    for (int k = 0; k < PG_INSOL_STEPS; k++) {
        double lambda = 2.0 * M_PI * (k + 0.5) / PG_INSOL_STEPS;
        double dec = asin(sin(tilt) * sin(lambda));
        sum += daily_insolation(lat, dec, solar_constant_wm2);
    }
    return sum / PG_INSOL_STEPS;
}
