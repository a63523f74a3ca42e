/* pg_plates_hypsometry.c - the macro relief given a target's hypsometry: a rank-preserving,
 * area-weighted remap of land heights onto the target's land quantiles and of ocean depths
 * onto its ocean quantiles (docs/world.md, "Hypsometry").
 *
 * WHY. The plates place continents, belts, trenches and ridges, but their heights come
 * from a handful of rules (a platform, arc uplift, an age-depth curve), whose distribution
 * is not Earth's: a world's land came out half as spread as Earth's (standard deviation
 * 450 m against 1009 m) and the synthesis, guided by it, inherited that. Matching the
 * distribution keeps everything the plates decided - which texel is land, which is higher
 * than which - and takes only the heights' distribution from the target, as a
 * histogram-matching step of texture synthesis does (Heeger & Bergen 1995, "Pyramid-based
 * texture analysis/synthesis", SIGGRAPH).
 *
 * HOW. Land texels (elevation > 0) are sorted by elevation (ties by texel id, so the order
 * is total and the result deterministic); texel i of cumulative area A_i (its own half
 * included) out of the land's A gets the target's land quantile at A_i / A, linearly
 * interpolated in the table. The ocean likewise. Land stays above 0 and ocean at or below
 * it, so the land fraction and every coast are unchanged.
 *
 * ICE SHEETS. Earth's hypsometry has its high tail partly in ice: the Antarctic and
 * Greenland sheets stand 2-3 km high on rock the plates would call lowland. The caller
 * may add an offset to the ranking key (the sheet's thickness), so that those texels take
 * high quantiles as Earth's ice does, and the high tail is not spread over the plates'
 * lowland uplands instead. */
#include "pg_plates_internal.h"

#include <math.h>
#include <stdlib.h>

static double quantile(const float *q, int n, double f) {
    double x = f * (n - 1);
    int i = (int)floor(x);
    if (i < 0) return q[0];
    if (i >= n - 1) return q[n - 1];
    return q[i] + (x - i) * (q[i + 1] - q[i]);
}

static pg_status remap(pg_plates_world *w, int land, const float *q, int nq, const float *off,
                       pg_error *err) {
    const int64_t count = 6 * w->n * w->n;
    pg_plates_keyed *k = malloc(sizeof *k * (size_t)count);
    if (!k) return pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for the hypsometry");
    int64_t m = 0;
    double total = 0;
    for (int64_t t = 0; t < count; t++)
        if ((w->elevation_m[t] > 0) == land) {
            k[m++] = (pg_plates_keyed){w->elevation_m[t] + (off ? off[t] : 0.0f), t};
            total += w->area_km2[t];
        }
    qsort(k, (size_t)m, sizeof *k, pg_plates_keyed_cmp);
    double below = 0;
    for (int64_t i = 0; i < m; i++) {
        double a = w->area_km2[k[i].id];
        double z = quantile(q, nq, (below + 0.5 * a) / total);
        below += a;
        /* land stays land, the sea stays sea: coasts are the plates' */
        w->elevation_m[k[i].id] = (float)(land ? fmax(z, 1.0) : fmin(z, 0.0));
    }
    free(k);
    return PG_OK;
}

static bool ascending(const float *q, int n) {
    for (int i = 1; i < n; i++)
        if (!(q[i] >= q[i - 1])) return false;
    return true;
}

pg_status pg_plates_match_hypsometry(pg_plates_world *w, const pg_plates_hypsometry *h,
                                     pg_error *err) {
    if (!w->elevation_m || !w->area_km2)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates hypsometry: no world");
    if (h->n < 2 || !h->land_m || !h->ocean_m || !ascending(h->land_m, h->n) ||
        !ascending(h->ocean_m, h->n))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "plates hypsometry: need two ascending tables of >= 2 quantiles");
    pg_status st = remap(w, 1, h->land_m, h->n, h->rank_offset_m, err);
    return st ? st : remap(w, 0, h->ocean_m, h->n, h->rank_offset_m, err);
}
