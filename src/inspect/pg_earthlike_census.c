/* pg_earthlike_census.c - the landmass census of a planet (pg_earthlike.h): how many
 * landmasses, how big, how the sizes fall off with rank.
 *
 * A landmass is a connected component of land texels (height > sea level) in the
 * 8-neighbour graph of the cube sphere, the same graph the pit removal uses
 * (pg_pits_neighbours on pg_pits_topo_cube: 8 neighbours across face seams, 7 at the
 * eight cube-corner texels). A continent straddling a seam or covering a cube corner
 * is therefore one landmass. Components are found by breadth-first search from each
 * land texel not yet reached, in global id order: every land texel is enqueued
 * exactly once (it is cleared from the to-do mask when enqueued), so the search is
 * O(texels) and its areas are integer sums of the fixed-point texel areas of
 * pg_earthlike_geom.c, exact and independent of visiting order.
 *
 * Rank-size: sorting the landmasses of at least 1e4 km^2 by decreasing area, the
 * least-squares slope of ln(area) on ln(rank) (Zipf's law would give -1; Earth
 * reprojected at N = 1024 measures -2.17: its sizes fall off faster). */
#include "pg_earthlike_internal.h"

#include "pg_array.h"

#include "planetgen/pg_pits.h"

#include <math.h>
#include <stdlib.h>

typedef struct census_work {
    const pg_pits_topo *t;
    const pg_earthlike_geom *g;
    uint8_t *unvisited; /* 1: land not yet enqueued */
    uint32_t *queue;
} census_work;

static uint64_t texel_weight(const pg_earthlike_geom *g, uint32_t id) {
    uint64_t nn = (uint64_t)g->n * (uint64_t)g->n;
    int face = (int)(id / nn);
    return g->weight[pg_earthlike_face_kind(face)][id - (uint64_t)face * nn];
}

/* Area (weight units) of the landmass containing land texel s. */
static uint64_t flood(census_work *c, uint32_t s) {
    size_t head = 0, tail = 0;
    uint64_t area = 0;
    uint32_t nb[8];
    c->queue[tail++] = s;
    c->unvisited[s] = 0;
    while (head < tail) {
        uint32_t id = c->queue[head++];
        area += texel_weight(c->g, id);
        int k = pg_pits_neighbours(c->t, id, nb);
        for (int j = 0; j < k; j++)
            if (c->unvisited[nb[j]]) {
                c->unvisited[nb[j]] = 0;
                c->queue[tail++] = nb[j];
            }
    }
    return area;
}

static int cmp_desc(const void *a, const void *b) {
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x < y) - (x > y);
}

/* Least-squares slope of ln(area) on ln(rank), areas sorted decreasing. */
static double rank_size_slope(const uint64_t *area, size_t m) {
    if (m < 3) return NAN;
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < m; i++) {
        double x = log((double)(i + 1)), y = log((double)area[i]);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    double dm = (double)m;
    return (sxy - sx * sy / dm) / (sxx - sx * sx / dm);
}

static void summarise(uint64_t *area, size_t count, double unit_m2, pg_earthlike *out) {
    qsort(area, count, sizeof *area, cmp_desc);
    double all = 0;
    size_t m4 = 0, m6 = 0;
    for (size_t i = 0; i < count; i++) {
        double km2 = (double)area[i] * unit_m2 / 1e6;
        all += (double)area[i];
        m4 += km2 >= 1e4, m6 += km2 >= 1e6;
    }
    out->landmasses = count;
    out->landmasses_1e4 = m4;
    out->landmasses_1e6 = m6;
    out->largest_landmass_km2 = count ? (double)area[0] * unit_m2 / 1e6 : 0;
    out->largest_landmass_share = count ? (double)area[0] / all : NAN;
    out->rank_size_slope = rank_size_slope(area, m4);
}

/* Flood every landmass; *area gets their areas (caller frees). */
static pg_status flood_all(census_work *c, uint64_t **area, size_t *count, pg_error *err) {
    size_t cap = 0;
    *count = 0;
    *area = NULL;
    if (PG_ARRAY_RESERVE(*area, &cap, 64, NULL))
        return pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory for landmasses");
    for (uint64_t id = 0; id < c->t->ncells; id++) {
        if (!c->unvisited[id]) continue;
        if (PG_ARRAY_RESERVE(*area, &cap, *count + 1, NULL))
            return pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory");
        (*area)[(*count)++] = flood(c, (uint32_t)id);
    }
    return PG_OK;
}

pg_status pg_earthlike_census(const pg_planet *p, const pg_earthlike_geom *g, pg_earthlike *out,
                              pg_error *err) {
    pg_pits_topo t;
    pg_status st = pg_pits_topo_cube(&t, (uint32_t)p->n, err);
    if (st) return st;
    int64_t nn = p->n * p->n, land = 0;
    census_work c = {&t, g, malloc(t.ncells), NULL};
    if (!c.unvisited)
        return pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory for landmasses");
#pragma omp parallel for schedule(static) reduction(+ : land)
    for (int64_t id = 0; id < (int64_t)t.ncells; id++) {
        c.unvisited[id] = p->height[id / nn][id % nn] > p->sea_level;
        land += c.unvisited[id];
    }
    c.queue = malloc((size_t)(land ? land : 1) * sizeof *c.queue);
    uint64_t *area = NULL;
    size_t count = 0;
    st = c.queue ? flood_all(&c, &area, &count, err)
                 : pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory for landmasses");
    if (st == PG_OK) summarise(area, count, g->unit_m2, out);
    free(area);
    free(c.queue);
    free(c.unvisited);
    return st;
}
