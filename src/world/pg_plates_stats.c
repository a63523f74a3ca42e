/* pg_plates_stats.c - summary figures of a plate world, area-weighted on the sphere,
 * against Earth's (docs/world.md): land share, landmasses (8-connected components of
 * land found by an explicit-stack flood fill over the texel graph), the mountain-belt
 * share (land above 2000 m within 500 km of a convergent boundary), hypsometric means. */
#include "pg_plates_internal.h"

#include <stdlib.h>
#include <string.h>

static void pg_plates_landmasses(const pg_plates_world *w, const pg_plates_grid *g, int64_t *stack,
                                 int32_t *label, double *largest, int *big, double big_km2) {
    memset(label, 0xff, sizeof(int32_t) * (size_t)g->count);
    *largest = 0;
    *big = 0;
    int32_t next = 0;
    for (int64_t t0 = 0; t0 < g->count; t0++) {
        if (w->elevation_m[t0] <= 0 || label[t0] >= 0) continue;
        double area = 0;
        int64_t top = 0;
        stack[top++] = t0;
        label[t0] = next;
        while (top > 0) {
            int64_t t = stack[--top];
            area += w->area_km2[t];
            for (int d = 0; d < 8; d++) {
                int64_t q = g->nbr[8 * t + d];
                if (w->elevation_m[q] > 0 && label[q] < 0) {
                    label[q] = next;
                    stack[top++] = q;
                }
            }
        }
        next++;
        *largest = fmax(*largest, area);
        *big += area >= big_km2;
    }
}

pg_status pg_plates_stats_compute(const pg_plates_world *w, pg_plates_stats *s, pg_error *err) {
    if (!w || !s || !w->elevation_m)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: stats need a generated world");
    memset(s, 0, sizeof *s);
    pg_plates_grid g;
    pg_status st = pg_plates_grid_init(&g, w->n, w->proj, w->radius_km, err);
    if (st != PG_OK) return st;
    int64_t *stack = malloc(sizeof(int64_t) * (size_t)g.count);
    int32_t *label = malloc(sizeof(int32_t) * (size_t)g.count);
    double *plate_area = calloc((size_t)w->nplates, sizeof(double));
    if (!stack || !label || !plate_area) {
        st = pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for stats");
        goto done;
    }
    double total = 0, land = 0, land_h = 0, ocean = 0, ocean_d = 0, high = 0, high_belt = 0;
    for (int64_t t = 0; t < g.count; t++) {
        double a = w->area_km2[t], z = w->elevation_m[t];
        total += a;
        plate_area[w->plate[t]] += a;
        s->boundary_kinds[w->boundary[t] & 3]++;
        if (z > 0) {
            land += a;
            land_h += a * z;
            if (z > 2000) {
                high += a;
                if (w->convergent_km[t] <= 500) high_belt += a;
            }
        } else {
            ocean += a;
            ocean_d -= a * z;
        }
    }
    for (int k = 0; k < w->nplates; k++)
        s->largest_plate_share = fmax(s->largest_plate_share, plate_area[k] / total);
    double largest;
    double big_km2 = 1e6 * (w->radius_km / 6371) * (w->radius_km / 6371);
    pg_plates_landmasses(w, &g, stack, label, &largest, &s->landmasses_1e6km2, big_km2);
    s->land_fraction = land / total;
    s->largest_land_share = land > 0 ? largest / land : 0;
    s->mountain_belt_share = high > 0 ? high_belt / high : 1;
    s->high_land_fraction = land > 0 ? high / land : 0;
    s->land_mean_m = land > 0 ? land_h / land : 0;
    s->ocean_mean_depth_m = ocean > 0 ? ocean_d / ocean : 0;
done:
    free(stack);
    free(label);
    free(plate_area);
    pg_plates_grid_free(&g);
    return st;
}
