/* pg_plates.c - the plate model's entry points: parameters and their checks, the
 * caller-owned world, and the pipeline seed -> simulate -> relief (each stage in its
 * own file; the model is described in pg_plates_cortial2019.c and docs/world.md). */
#include "pg_plates_internal.h"

#include <stdlib.h>
#include <string.h>

void pg_plates_params_default(pg_plates_params *p) {
    memset(p, 0, sizeof *p);
    p->seed = 1;
    p->n = 64;
    p->proj = PG_CUBE_DEFAULT_PROJECTION;
    p->plates = 14;
    p->steps = 20;
    p->step_myr = 2.5;
    p->land_fraction = 0.29;
    p->continental_share = 0.45;
    p->continents = 8;
    p->hotspots = 6;
    p->radius_km = 6371;
}

void pg_plates_world_init(pg_plates_world *w) {
    memset(w, 0, sizeof *w);
}

void pg_plates_world_free(pg_plates_world *w) {
    free(w->elevation_m);
    free(w->crust);
    free(w->age_myr);
    free(w->plate);
    free(w->boundary);
    free(w->convergent_km);
    free(w->area_km2);
    free(w->plates);
    memset(w, 0, sizeof *w);
}

static pg_status pg_plates_check(const pg_plates_params *p, pg_error *err) {
    if (!p) return pg_error_set(err, PG_ERR_BADINPUT, "plates: no parameters");
    if (p->n < 8 || p->n > 1024)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: n = %lld is outside 8..1024",
                            (long long)p->n);
    if (p->proj != PG_CUBE_GNOMONIC && p->proj != PG_CUBE_EQUIANGULAR &&
        p->proj != PG_CUBE_EQUALAREA)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: proj = %d is not a projection",
                            (int)p->proj);
    if (p->plates < PG_PLATES_MIN || p->plates > PG_PLATES_MAX)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: plates = %d is outside %d..%d",
                            p->plates, PG_PLATES_MIN, PG_PLATES_MAX);
    if (p->steps < 0 || p->steps > 200)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: steps = %d is outside 0..200", p->steps);
    if (!(p->step_myr > 0 && p->step_myr <= 20))
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: step_myr = %g is outside (0, 20]",
                            p->step_myr);
    if (!(p->land_fraction > 0 && p->land_fraction < 1))
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: land_fraction = %g is outside (0, 1)",
                            p->land_fraction);
    if (!(p->continental_share > 0 && p->continental_share < 1))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "plates: continental_share = %g is outside (0, 1)",
                            p->continental_share);
    if (p->continents < 1 || p->continents > 32)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: continents = %d is outside 1..32",
                            p->continents);
    if (p->hotspots < 0 || p->hotspots > 32)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: hotspots = %d is outside 0..32",
                            p->hotspots);
    if (!(p->radius_km > 0 && isfinite(p->radius_km)))
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: radius_km = %g is not positive",
                            p->radius_km);
    return PG_OK;
}

static pg_status pg_plates_alloc(pg_plates_world *w, int64_t count, int np, pg_error *err) {
    size_t c = (size_t)count;
    w->elevation_m = malloc(sizeof(float) * c);
    w->crust = malloc(c);
    w->age_myr = malloc(sizeof(float) * c);
    w->plate = malloc(c);
    w->boundary = malloc(c);
    w->convergent_km = malloc(sizeof(float) * c);
    w->area_km2 = malloc(sizeof(float) * c);
    w->plates = calloc((size_t)np, sizeof *w->plates);
    if (w->elevation_m && w->crust && w->age_myr && w->plate && w->boundary && w->convergent_km &&
        w->area_km2 && w->plates)
        return PG_OK;
    return pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for %lld texels",
                        (long long)count);
}

static pg_status generate(const pg_plates_params *p, pg_plates_world *out, bool caps,
                          pg_error *err) {
    pg_status st = pg_plates_check(p, err);
    if (st != PG_OK) return st;
    if (!out) return pg_error_set(err, PG_ERR_BADINPUT, "plates: no output world");
    pg_plates_world_free(out);
    pg_plates_grid g;
    st = pg_plates_grid_init(&g, p->n, p->proj, p->radius_km, err);
    if (st != PG_OK) return st;
    pg_plates_state s = {malloc((size_t)g.count), malloc((size_t)g.count),
                         malloc(sizeof(float) * (size_t)g.count),
                         malloc(sizeof(float) * (size_t)g.count)};
    out->n = p->n;
    out->proj = p->proj;
    out->radius_km = p->radius_km;
    out->nplates = p->plates;
    st = pg_plates_alloc(out, g.count, p->plates, err);
    if (st == PG_OK && (!s.plate || !s.crust || !s.age || !s.relief))
        st = pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for the crust state");
    if (st == PG_OK) st = pg_plates_seed(p, &g, out, &s, err);
    if (st == PG_OK) st = pg_plates_simulate(p, &g, out, &s, caps, err);
    if (st == PG_OK) st = pg_plates_relief(p, &g, out, &s, err);
    if (st == PG_OK) {
        memcpy(out->area_km2, g.area, sizeof(float) * (size_t)g.count);
        for (int64_t t = 0; t < g.count; t++) {
            pg_plates_plate *pl = &out->plates[out->plate[t]];
            pl->area_km2 += g.area[t];
            if (out->crust[t] == PG_PLATES_CONTINENTAL) pl->continental_km2 += g.area[t];
        }
    }
    free(s.plate);
    free(s.crust);
    free(s.age);
    free(s.relief);
    pg_plates_grid_free(&g);
    if (st != PG_OK) pg_plates_world_free(out);
    return st;
}

pg_status pg_plates_generate(const pg_plates_params *p, pg_plates_world *out, pg_error *err) {
    return generate(p, out, true, err);
}

pg_status pg_plates_generate_uncapped(const pg_plates_params *p, pg_plates_world *out,
                                      pg_error *err) {
    return generate(p, out, false, err);
}
