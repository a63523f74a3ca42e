/* pg_plates_seed.c - the planet before the simulation: plates grown from hashed seeds,
 * their Euler poles and speeds, continental crust from hashed cores, hotspots, and the
 * age of the initial ocean floor.
 *
 * Plates (after the seeded growth of WorldEngine/platec and of Cortial et al. 2019,
 * section 3, here in closed form): each texel joins the plate k minimising
 * angle(warp(p), seed_k) / weight_k, a multiplicatively weighted Voronoi diagram on
 * the sphere. The weights (0.5..1.6) give a few large plates and several small ones,
 * like Earth's 7 major and about 8 minor; the warp, a smooth noise displacement of the
 * direction before the distance is taken, makes boundaries wander instead of running
 * along great circles. A plate whose cell the warp emptied gets the texel under its
 * seed, so no plate is empty.
 *
 * Continents are independent of plates (Earth's plates carry continents inside oceanic
 * crust): cores with hashed directions and sizes (the first core three times the mean,
 * so one large landmass forms, as Afro-Eurasia does), each a spherical cap scaled to
 * its share; the texel's score is min over cores of angle(warp'(p), core) / cap radius,
 * and the continental_share of the sphere's area with the lowest scores is continental
 * (an area-weighted quantile, so the share is exact up to one texel).
 *
 * Initial oceanic age grows with the distance from the initial divergent boundaries at
 * a half-spreading rate of 2.5 cm/yr (25 km/Myr), capped at 150 Myr: the ocean floor
 * starts with ridges and aged basins instead of a flat age. */
#include "pg_plates_internal.h"

#include <stdlib.h>
#include <string.h>

#define PG_PLATES_WARP 0.22
#define PG_PLATES_COAST_WARP 0.30
#define PG_PLATES_HALF_SPREAD_KM_MYR 30.0
#define PG_PLATES_MAX_AGE 60.0
#define PG_PLATES_CONTINENT_AGE 1000.0

static void pg_plates_warp(uint64_t seed, uint64_t stream, const double p[3], double amp,
                           double freq, int octaves, double out[3]) {
    for (int k = 0; k < 3; k++)
        out[k] = p[k] + amp * pg_plates_fbm(seed, stream + 4 * (uint64_t)k, p, freq, octaves);
    pg_vec3_normalize(out);
}

static void pg_plates_grow(const pg_plates_params *p, const pg_plates_grid *g, pg_plates_world *w,
                           uint8_t *plate) {
    double weight[PG_PLATES_MAX];
    for (int k = 0; k < p->plates; k++) {
        pg_plates_random_dir(p->seed, PG_PLATES_S_SEED, (uint64_t)k, w->plates[k].seed_dir);
        weight[k] = 0.5 + 1.1 * pg_plates_unit(p->seed, PG_PLATES_S_WEIGHT, (uint64_t)k);
    }
#pragma omp parallel for schedule(static)
    for (int64_t t = 0; t < g->count; t++) {
        double q[3];
        pg_plates_warp(p->seed, PG_PLATES_S_WARP, g->dir + 3 * t, PG_PLATES_WARP, 1.6, 3, q);
        int best = 0;
        double bs = INFINITY;
        for (int k = 0; k < p->plates; k++) {
            double s = pg_plates_angle(q, w->plates[k].seed_dir) / weight[k];
            if (s < bs) {
                bs = s;
                best = k;
            }
        }
        plate[t] = (uint8_t)best;
    }
    for (int k = 0; k < p->plates; k++) {
        int64_t t = pg_plates_grid_nearest(g, w->plates[k].seed_dir), c;
        for (c = 0; c < g->count && plate[c] != k; c++) {
        }
        if (c == g->count) plate[t] = (uint8_t)k;
    }
}

static void pg_plates_motion(const pg_plates_params *p, pg_plates_world *w) {
    for (int k = 0; k < p->plates; k++) {
        double pole[3];
        pg_plates_random_dir(p->seed, PG_PLATES_S_POLE, (uint64_t)k, pole);
        double cm_yr = 1.5 + 6.5 * pg_plates_unit(p->seed, PG_PLATES_S_SPEED, (uint64_t)k);
        double rate = cm_yr * 10.0 / p->radius_km; /* 1 cm/yr = 10 km/Myr */
        w->plates[k].speed_cm_yr = cm_yr;
        for (int i = 0; i < 3; i++)
            w->plates[k].omega[i] = pole[i] * rate;
    }
}

static pg_status pg_plates_continents(const pg_plates_params *p, const pg_plates_grid *g,
                                      uint8_t *crust, pg_error *err) {
    double core[32][3], radius[32], raw[32], sum = 0;
    for (int j = 0; j < p->continents; j++) {
        pg_plates_random_dir(p->seed, PG_PLATES_S_CORE, (uint64_t)j, core[j]);
        double u = pg_plates_unit(p->seed, PG_PLATES_S_CORE_SIZE, (uint64_t)j);
        raw[j] = j == 0 ? 2.0 : 0.15 + 1.2 * u * u;
        sum += raw[j];
    }
    for (int j = 0; j < p->continents; j++) {
        double f = fmin(0.45, p->continental_share * raw[j] / sum); /* cap area / sphere */
        radius[j] = acos(1 - 2 * f);
    }
    pg_plates_keyed *k = malloc(sizeof *k * (size_t)g->count);
    if (!k) return pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for continents");
#pragma omp parallel for schedule(static)
    for (int64_t t = 0; t < g->count; t++) {
        double q[3];
        pg_plates_warp(p->seed, PG_PLATES_S_SHAPE, g->dir + 3 * t, PG_PLATES_COAST_WARP, 2.2, 4, q);
        double s = INFINITY;
        for (int j = 0; j < p->continents; j++)
            s = fmin(s, pg_plates_angle(q, core[j]) / radius[j]);
        k[t].key = s;
        k[t].id = t;
    }
    qsort(k, (size_t)g->count, sizeof *k, pg_plates_keyed_cmp);
    double total = 0, acc = 0;
    for (int64_t t = 0; t < g->count; t++)
        total += g->area[t];
    memset(crust, PG_PLATES_OCEANIC, (size_t)g->count);
    for (int64_t i = 0; i < g->count && acc < p->continental_share * total; i++) {
        crust[k[i].id] = PG_PLATES_CONTINENTAL;
        acc += g->area[k[i].id];
    }
    free(k);
    return PG_OK;
}

static pg_status pg_plates_initial_age(const pg_plates_params *p, const pg_plates_grid *g,
                                       const pg_plates_world *w, pg_plates_state *s,
                                       pg_error *err) {
    uint8_t *kind = malloc((size_t)g->count);
    float *dist = malloc(sizeof(float) * (size_t)g->count);
    double(*omega)[3] = malloc(sizeof *omega * (size_t)p->plates);
    pg_status st = PG_OK;
    if (!kind || !dist || !omega) {
        st = pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for the initial ages");
        goto done;
    }
    for (int k = 0; k < p->plates; k++)
        memcpy(omega[k], w->plates[k].omega, sizeof omega[k]);
    st = pg_plates_classify(g->n, g->proj, s->plate, p->plates, (const double(*)[3])omega, kind,
                            err);
    if (st != PG_OK) goto done;
    for (int64_t t = 0; t < g->count; t++)
        kind[t] = kind[t] == PG_PLATES_DIVERGENT;
    st = pg_plates_grid_distance(g, kind, s->plate, dist, err);
    if (st != PG_OK) goto done;
    for (int64_t t = 0; t < g->count; t++) {
        double jitter = 0.85 + 0.3 * pg_plates_unit(p->seed, PG_PLATES_S_AGE, (uint64_t)t);
        double a = fmin(PG_PLATES_MAX_AGE, dist[t] / PG_PLATES_HALF_SPREAD_KM_MYR * jitter);
        s->age[t] = (float)(s->crust[t] == PG_PLATES_CONTINENTAL ? PG_PLATES_CONTINENT_AGE : a);
    }
done:
    free(kind);
    free(dist);
    free(omega);
    return st;
}

pg_status pg_plates_seed(const pg_plates_params *p, const pg_plates_grid *g, pg_plates_world *w,
                         pg_plates_state *s, pg_error *err) {
    pg_plates_grow(p, g, w, s->plate);
    pg_plates_motion(p, w);
    w->nhotspots = p->hotspots;
    for (int h = 0; h < p->hotspots; h++)
        pg_plates_random_dir(p->seed, PG_PLATES_S_HOTSPOT, (uint64_t)h, w->hotspot_dir[h]);
    pg_status st = pg_plates_continents(p, g, s->crust, err);
    if (st != PG_OK) return st;
    memset(s->relief, 0, sizeof(float) * (size_t)g->count);
    return pg_plates_initial_age(p, g, w, s, err);
}
