/* pg_earthlike_compare.c - comparing the Earth-likeness figures of two planets
 * (pg_earthlike.h): Wasserstein-1 distances of their hypsometries and the
 * correlation of their zonal climate profiles. Typically one side is Earth itself,
 * measured once and cached.
 *
 * W1. For distributions on the line, W1(A, B) = integral over q in (0, 1) of
 * |F_A^-1(q) - F_B^-1(q)| (Vallender 1973, "Calculation of the Wasserstein distance
 * between probability distributions on the line": on the line the optimal coupling
 * matches quantiles). Both sides store F^-1 at the midpoints
 * (k + 1/2)/K, so the midpoint rule is the mean of the K absolute differences. It
 * is exact when one distribution is a shift of the other (every difference equals
 * the shift).
 *
 * ZONAL CORRELATION. Per terrain type, the Pearson correlation over the 18 latitude
 * bands of the type's area share; the mean over the types (see pg_earthlike.h for
 * why per type and how constant profiles count). */
#include "planetgen/pg_earthlike.h"

#include <math.h>

static double w1(const double *a, const double *b) {
    double s = 0;
    for (int k = 0; k < PG_EARTHLIKE_QUANTILES; k++)
        s += fabs(a[k] - b[k]);
    return s / PG_EARTHLIKE_QUANTILES; /* NaN if either side has no samples */
}

void pg_earthlike_w1(const pg_earthlike *a, const pg_earthlike *b, double *land_m,
                     double *ocean_m) {
    if (land_m) *land_m = w1(a->land_quantiles, b->land_quantiles);
    if (ocean_m) *ocean_m = w1(a->ocean_quantiles, b->ocean_quantiles);
}

/* Pearson correlation of column t of the two tables; NaN when both columns are
 * constant, 0 when one is. Variances below 1e-12 (shares of 1e-6 spread) count
 * as constant: rounding noise is not a profile. */
static double type_correlation(const pg_earthlike *a, const pg_earthlike *b, int t) {
    double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
    for (int i = 0; i < PG_EARTHLIKE_BANDS; i++)
        ma += a->zonal[i][t], mb += b->zonal[i][t];
    ma /= PG_EARTHLIKE_BANDS, mb /= PG_EARTHLIKE_BANDS;
    for (int i = 0; i < PG_EARTHLIKE_BANDS; i++) {
        double da = a->zonal[i][t] - ma, db = b->zonal[i][t] - mb;
        saa += da * da, sbb += db * db, sab += da * db;
    }
    const double flat = 1e-12 * PG_EARTHLIKE_BANDS;
    if (saa <= flat && sbb <= flat) return NAN;
    if (saa <= flat || sbb <= flat) return 0;
    return sab / sqrt(saa * sbb);
}

double pg_earthlike_zonal_correlation(const pg_earthlike *a, const pg_earthlike *b,
                                      double per_type[PG_TYPE_COUNT]) {
    double sum = 0;
    int used = 0;
    for (int t = 0; t < PG_TYPE_COUNT; t++) {
        double r = type_correlation(a, b, t);
        if (per_type) per_type[t] = r;
        if (!isnan(r)) sum += r, used++;
    }
    return used ? sum / used : NAN;
}
