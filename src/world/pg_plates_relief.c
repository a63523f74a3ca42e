/* pg_plates_relief.c - from crust to elevation: ocean depth by age (Parsons and Sclater
 * 1977), continental platforms with shelves and slopes, trenches, rift valleys, the
 * tectonic relief accumulated by the simulation, and sea level by an area-weighted
 * quantile so that the requested share of the sphere is land.
 *
 * OCEAN. Depth grows with the square root of crust age, as a cooling half-space
 * (Parsons & Sclater 1977, J. Geophys. Res. 82(5): about 2500 + 350 sqrt(a) m), and
 * flattens for old crust as a cooling plate. We use the GDH1 fit of the same two-branch
 * form (Stein & Stein 1992, Nature 359): d(a) = 2600 + 365 sqrt(a) m for a < 20 Myr,
 * 5651 - 2473 exp(-0.0278 a) m beyond (continuous to 1 m at 20 Myr), so ridges stand
 * near -2.6 km and old basins flatten near -5.6 km; Parsons and Sclater's own plate
 * branch flattens near 6.4 km, deeper than the 5-6 km of Earth's old basins.
 *
 * CONTINENTS. A platform rising from -500 m at the crust boundary to +800 m inland with
 * an e-folding of 300 km, plus broad noise of +-700 m (features of about a radian: basins
 * and uplands).
 *
 * SHELVES. Earth's shelves are anything but even: none off the Andes, where the ocean
 * plate dives under the continent (an active margin), tens of km off most of Africa,
 * hundreds off Argentina, Siberia and north-west Europe (Harris et al. 2014,
 * "Geomorphology of the oceans", Marine Geology 352: passive margins' shelves average
 * 88 km, active margins' 31 km; the Siberian shelf is over 1000 km wide). So the flooded margin is
 * drawn, not left to the sea level: the continental texels within a width W of the ocean crust sit
 * at 60-170 m below sea level, W from broad noise (none on about half of the passive margins, up to
 * 1200 km), none within about 150 km of a convergent boundary and narrowed out to about 600 km
 * from it (the first continental texel lies one macro texel, about 140 km, inside the crust
 * boundary, so a W below that floods nothing). The continental slope is the
 * step from the last continental texel to the first oceanic one: the synthesis guide interpolates
 * it over one macro texel, and Earth's own material fills in the detail. (Averaging the texels on
 * both sides of the crust boundary, as before, put every coast inside a ring of slope depths two
 * macro texels wide, the same round every continent: a light-blue band of even width in the
 * albedo.)
 *
 * BOUNDARIES. Oceanic crust within ~100 km of a convergent boundary is deepened by up to
 * 2 km (the trench on the subducting side; the overriding side's arc uplift from the
 * simulation starts at the front and dominates there). Continental crust within ~150 km
 * of a divergent boundary is lowered by up to 700 m (a rift valley).
 *
 * SEA LEVEL. Ocean depths are depths below sea level (that is what Parsons and Sclater
 * fitted), so the ocean floor stays put and the continents float: their common offset is
 * the area-weighted quantile of continental elevations that makes land_fraction of the
 * sphere land (counting oceanic land, arcs and hotspot islands, as already there; the
 * shelves are left out and then set below it). A second quantile over the whole field
 * levels it exactly: sorted
 * by elevation, the level falls midway between the two texels where the area above
 * reaches land_fraction, so no texel sits at 0 and the share is exact to one texel. */
#include "pg_plates_internal.h"

#include <stdlib.h>
#include <string.h>

double pg_plates_ocean_depth(double age_myr) {
    double a = fmax(0, age_myr);
    if (a < 20) return 2600 + 365 * sqrt(a);
    return 5651 - 2473 * exp(-0.0278 * a);
}

/* The shelf: how far (km) continental crust is flooded inland of its boundary with
 * the ocean. Broad noise makes it none on about half of the passive margins and up to
 * PG_PLATES_SHELF_MAX_KM on the rest; an active margin (near a convergent boundary)
 * has none. Its depth below sea level: 180 - 120 f m by the same noise, 60-170 m where W
 * reaches a texel. */
#define PG_PLATES_SHELF_MAX_KM 1200.0

static double pg_plates_shelf_km(const pg_plates_params *p, const double *d, double conv_km,
                                 double *depth_m) {
    double n = pg_plates_fbm(p->seed, PG_PLATES_S_SHELF, d, 3.0, 3);
    double passive = 1 - exp(-(conv_km / 400) * (conv_km / 400));
    double f = fmin(1, fmax(0, 2.5 * n + 0.1));
    *depth_m = 180 - 120 * f;
    return PG_PLATES_SHELF_MAX_KM * f * passive;
}

static double pg_plates_raw(const pg_plates_params *p, const pg_plates_grid *g,
                            const pg_plates_state *s, int64_t t, double margin_km, double conv_km,
                            double div_km) {
    const double *d = g->dir + 3 * t;
    double noise = pg_plates_fbm(p->seed, PG_PLATES_S_RELIEF, d, 2.0, 4);
    if (s->crust[t] == PG_PLATES_CONTINENTAL) {
        double z = -500 + 1300 * (1 - exp(-margin_km / 300)) + 700 * noise + s->relief[t];
        return z - 700 * exp(-(div_km / 150) * (div_km / 150));
    }
    double z = -pg_plates_ocean_depth(s->age[t]) + 150 * noise + s->relief[t];
    return z - 2000 * exp(-(conv_km / 90) * (conv_km / 90));
}

/* The level at which the area of `z` above it is closest to `target` (km^2), counting only
 * texels with sel[t] (all when sel is NULL); `other` km^2 of land is already counted. */
static pg_status pg_plates_quantile(const pg_plates_grid *g, const float *z, const uint8_t *sel,
                                    uint8_t want, double target, double *level, pg_error *err) {
    pg_plates_keyed *k = malloc(sizeof *k * (size_t)g->count);
    if (!k) return pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for sea level");
    int64_t m = 0;
    for (int64_t t = 0; t < g->count; t++)
        if (!sel || sel[t] == want) k[m++] = (pg_plates_keyed){z[t], t};
    if (m == 0) {
        free(k);
        *level = 0;
        return PG_OK;
    }
    qsort(k, (size_t)m, sizeof *k, pg_plates_keyed_cmp);
    double above = 0;
    int64_t i = m - 1;
    while (i > 0 && above + g->area[k[i].id] <= target)
        above += g->area[k[i--].id];
    /* k[i+1..] is land; take texel i too when that lands closer to the target */
    if (target - above > above + g->area[k[i].id] - target && i > 0) i--;
    *level = target <= 0 ? k[m - 1].key + 1 : 0.5 * (k[i].key + k[i + 1 < m ? i + 1 : i].key);
    free(k);
    return PG_OK;
}

/* Continents float: their offset is chosen so that, with the ocean floor fixed below sea
 * level by its age, the land share is met; then the whole field is levelled exactly. */
static pg_status pg_plates_sea_level(const pg_plates_params *p, const pg_plates_grid *g,
                                     pg_plates_world *w, float *raw, const float *shelf,
                                     uint8_t *sel, pg_error *err) {
    double total = 0, ocean_land = 0, level;
    for (int64_t t = 0; t < g->count; t++) {
        total += g->area[t];
        if (w->crust[t] == PG_PLATES_OCEANIC && raw[t] > 0) ocean_land += g->area[t];
        sel[t] = w->crust[t] == PG_PLATES_CONTINENTAL && shelf[t] == 0;
    }
    pg_status st =
        pg_plates_quantile(g, raw, sel, 1, p->land_fraction * total - ocean_land, &level, err);
    if (st != PG_OK) return st;
    /* the shelf floods at its own depth below the sea level just found */
    for (int64_t t = 0; t < g->count; t++)
        w->elevation_m[t] = w->crust[t] != PG_PLATES_CONTINENTAL ? raw[t]
                            : shelf[t] > 0                       ? -shelf[t]
                                                                 : (float)(raw[t] - level);
    double fine;
    st = pg_plates_quantile(g, w->elevation_m, NULL, 0, p->land_fraction * total, &fine, err);
    if (st != PG_OK) return st;
    w->sea_level_m = level + fine;
    for (int64_t t = 0; t < g->count; t++)
        w->elevation_m[t] = (float)(w->elevation_m[t] - fine);
    return PG_OK;
}

pg_status pg_plates_relief(const pg_plates_params *p, const pg_plates_grid *g, pg_plates_world *w,
                           const pg_plates_state *s, pg_error *err) {
    size_t c = (size_t)g->count;
    float *margin = malloc(sizeof(float) * c), *div = malloc(sizeof(float) * c);
    float *shelf = malloc(sizeof(float) * c);
    uint8_t *src = malloc(3 * c);
    double(*omega)[3] = malloc(sizeof *omega * (size_t)p->plates);
    pg_status st = PG_OK;
    if (!margin || !div || !shelf || !src || !omega) {
        st = pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for the relief");
        goto done;
    }
    memcpy(w->plate, s->plate, c);
    memcpy(w->crust, s->crust, c);
    memcpy(w->age_myr, s->age, sizeof(float) * c);
    for (int k = 0; k < p->plates; k++)
        memcpy(omega[k], w->plates[k].omega, sizeof omega[k]);
    st = pg_plates_classify(g->n, g->proj, w->plate, p->plates, (const double(*)[3])omega,
                            w->boundary, err);
    /* three independent floods (serial each), at once: from the convergent and the
     * divergent boundaries and from the ocean */
    for (int64_t t = 0; t < g->count; t++) {
        src[t] = w->boundary[t] == PG_PLATES_CONVERGENT;
        src[c + t] = w->boundary[t] == PG_PLATES_DIVERGENT;
        src[2 * c + t] = w->crust[t] == PG_PLATES_OCEANIC;
    }
    if (st != PG_OK) goto done;
    float *to[3] = {w->convergent_km, div, margin};
    pg_status sk[3];
    pg_error e[3];
    memset(e, 0, sizeof e);
#pragma omp parallel for schedule(dynamic, 1)
    for (int j = 0; j < 3; j++)
        sk[j] = pg_plates_grid_distance(g, src + j * c, NULL, to[j], &e[j]);
    for (int j = 0; st == PG_OK && j < 3; j++)
        if (sk[j] != PG_OK) st = pg_error_set(err, sk[j], "%s", e[j].msg);
    if (st != PG_OK) goto done;
#pragma omp parallel for schedule(static)
    for (int64_t t = 0; t < g->count; t++) {
        double depth, width = pg_plates_shelf_km(p, g->dir + 3 * t, w->convergent_km[t], &depth);
        shelf[t] = s->crust[t] == PG_PLATES_CONTINENTAL && margin[t] <= width ? (float)depth : 0;
        margin[t] = (float)pg_plates_raw(p, g, s, t, margin[t], w->convergent_km[t], div[t]);
    }
    st = pg_plates_sea_level(p, g, w, margin, shelf, src, err);
done:
    free(margin);
    free(shelf);
    free(div);
    free(src);
    free(omega);
    return st;
}
