/* pg_earthlike_novelty.c - how much of a planet's land/ocean layout is Earth's own,
 * in place (pg_earthlike.h, pg_earthlike_novelty).
 *
 * For each texel, planet land = height > p->sea_level; Earth land = the exemplar's
 * elevation, bilinear at the texel centre's geodetic latitude and longitude on the
 * planet's ellipsoid (the same reading of the exemplar as pg_planet_from_exemplar's
 * pg_cube_from_equirect), > ex->sea_level. With texel areas as weights:
 *     agreement = share where both are land or both ocean,
 *     chance    = f_p f_e + (1 - f_p)(1 - f_e), the expected agreement of two
 *                 independent layouts with land fractions f_p and f_e,
 *     kappa     = (agreement - chance) / (1 - chance) (Cohen 1960, "A coefficient of
 *                 agreement for nominal scales"), novelty = 1 - kappa,
 *     chance_zonal = the same expectation per 1-degree latitude bin, area-weighted:
 *                 two layouts independent GIVEN latitude, kappa_zonal likewise.
 * Earth itself has agreement ~1 (only coastline texels differ by resampling). Earth
 * turned 180 degrees in longitude keeps its latitude profile (Antarctica, the
 * Southern Ocean, the Arctic Ocean stay put), so its agreement is above `chance`
 * (0.67 against 0.59 at N = 64) but equal to `chance_zonal`: kappa_zonal separates
 * "copies Earth's layout" from "shares Earth's zonal land profile". Areas are the
 * fixed-point texel areas of pg_earthlike_geom.c summed as integers, so the figures
 * do not depend on the thread count. */
#include "pg_earthlike_internal.h"
#include "planetgen/pg_equirect.h"

#include <math.h>
#include <string.h>

/* Areas per 1-degree latitude bin: all, planet land, Earth land, both land. */
enum { ALL, PLANET, EARTH, BOTH, NSUMS };

static void row_sums(const pg_planet *p, const pg_exemplar *ex, const pg_earthlike_geom *g,
                     int64_t row, uint64_t (*s)[NSUMS]) {
    int64_t n = g->n, y = row % n;
    int face = (int)(row / n), kind = pg_earthlike_face_kind(face);
    double v = (2.0 * (double)y + 1) / (double)n - 1, rad2deg = 180 / M_PI;
    for (int64_t x = 0; x < n; x++) {
        double d[3], u = (2.0 * (double)x + 1) / (double)n - 1;
        pg_cube_to_dir(p->projection, face, u, v, d);
        double lat = pg_earthlike_geodetic_lat(&p->ellipsoid, d), lon = atan2(d[1], d[0]) * rad2deg;
        float e;
        pg_equirect_sample(ex->elevation, ex->width, ex->height, 1, lat, lon, &e);
        size_t i = (size_t)(y * n + x);
        uint64_t w = g->weight[kind][i], *b = s[g->bin[kind][i]];
        int pl = p->height[face][i] > p->sea_level, el = e > ex->sea_level;
        b[ALL] += w;
        b[PLANET] += pl ? w : 0;
        b[EARTH] += el ? w : 0;
        b[BOTH] += pl && el ? w : 0;
    }
}

/* Agreement and chance of sums s, as fractions of s[ALL]. */
static void agree(const uint64_t *s, double *agreement, double *chance, double *fp, double *fe) {
    double all = (double)s[ALL];
    *fp = (double)s[PLANET] / all, *fe = (double)s[EARTH] / all;
    *agreement = (double)(s[ALL] - s[PLANET] - s[EARTH] + 2 * s[BOTH]) / all;
    *chance = *fp * *fe + (1 - *fp) * (1 - *fe);
}

static double kappa(double agreement, double chance) {
    return chance < 1 ? (agreement - chance) / (1 - chance) : NAN;
}

static void figures(uint64_t (*bins)[NSUMS], pg_earthlike_novelty *out) {
    uint64_t tot[NSUMS] = {0};
    for (int b = 0; b < PG_EL_BINS; b++)
        for (int k = 0; k < NSUMS; k++)
            tot[k] += bins[b][k];
    agree(tot, &out->agreement, &out->chance, &out->planet_land_fraction,
          &out->earth_land_fraction);
    out->kappa = kappa(out->agreement, out->chance);
    out->novelty = 1 - out->kappa;
    double cz = 0;
    for (int b = 0; b < PG_EL_BINS; b++) {
        if (!bins[b][ALL]) continue;
        double a, c, fp, fe;
        agree(bins[b], &a, &c, &fp, &fe);
        cz += c * (double)bins[b][ALL] / (double)tot[ALL];
    }
    out->chance_zonal = cz;
    out->kappa_zonal = kappa(out->agreement, cz);
}

pg_status pg_earthlike_novelty_compute(const pg_planet *p, const pg_exemplar *ex,
                                       pg_earthlike_novelty *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    if (!ex->elevation || ex->width < 1 || ex->height < 1)
        return pg_error_set(err, PG_ERR_BADINPUT, "earthlike: empty exemplar");
    if (p->n < 1) return pg_error_set(err, PG_ERR_BADINPUT, "earthlike: empty planet");
    pg_earthlike_geom g;
    pg_status st = pg_earthlike_geom_init(&g, p, err);
    if (st) return st;
    uint64_t bins[PG_EL_BINS][NSUMS];
    memset(bins, 0, sizeof bins);
    int64_t rows = PG_CUBE_NFACES * p->n;
    /* integer sums: the reduction's order does not matter */
#pragma omp parallel for schedule(static) reduction(+ : bins[:PG_EL_BINS][:NSUMS])
    for (int64_t row = 0; row < rows; row++)
        row_sums(p, ex, &g, row, bins);
    figures(bins, out);
    pg_earthlike_geom_free(&g);
    return PG_OK;
}
