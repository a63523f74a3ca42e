/* pg_earthlike_shelf.c - how wide the continental shelf is along the coasts of a planet
 * (pg_earthlike.h: shelf_width_*), so that a shelf of one width round every continent
 * can be told from Earth's, which is narrow at active margins (tens of km off the Andes)
 * and wide on passive ones (hundreds of km off Argentina, Siberia, the North Sea).
 *
 * WHAT. A coast texel is a land texel (height > sea level) with a sea neighbour. Its
 * shelf width is the distance from it, through the sea, to the nearest texel deeper than
 * PG_EARTHLIKE_SHELF_BREAK_M below sea level: the conventional shelf break (Earth's lies
 * between about 100 and 200 m). The figures are quantiles of that width over the coast
 * texels that reach such depth; coast texels of shallow closed seas, which never do, are
 * counted apart.
 *
 * HOW. One breadth-first search in the 8-neighbour graph of the cube sphere (the graph
 * of the landmass census and the pit removal, across seams and cube corners), started
 * from every deep texel at once and stepping through sea texels only, gives every sea
 * texel its hop count to deep water; a coast texel takes one more than its nearest sea
 * neighbour. Hop counts of a breadth-first search do not depend on the order of the
 * queue, so the figures are the same for any thread count. A hop is counted as the
 * coast texel's own width (the square root of its area): the 8-neighbour hop count is
 * the chessboard distance, which under-counts a diagonal path by up to 1/sqrt(2) -
 * good enough for a distribution whose spread spans a factor of ten on Earth. */
#include "pg_earthlike_internal.h"

#include "pg_array.h"

#include "planetgen/pg_pits.h"

#include <math.h>
#include <stdlib.h>

#define SHELF_FAR UINT32_MAX

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double quantile_sorted(const double *v, size_t m, double q) {
    double x = q * (double)(m - 1);
    size_t i = (size_t)x;
    if (i + 1 >= m) return v[m - 1];
    return v[i] + (x - (double)i) * (v[i + 1] - v[i]);
}

/* Hop counts to deep water for every sea texel; SHELF_FAR for land and unreached sea. */
static void shelf_hops(const pg_pits_topo *t, const pg_planet *p, uint32_t *hops, uint32_t *queue) {
    int64_t nn = p->n * p->n;
    size_t head = 0, tail = 0;
    double deep = p->sea_level - PG_EARTHLIKE_SHELF_BREAK_M;
    for (uint32_t id = 0; id < t->ncells; id++) {
        float h = p->height[id / nn][id % nn];
        hops[id] = SHELF_FAR;
        if (h < deep) {
            hops[id] = 0;
            queue[tail++] = id;
        }
    }
    uint32_t nb[8];
    while (head < tail) {
        uint32_t id = queue[head++];
        int k = pg_pits_neighbours(t, id, nb);
        for (int j = 0; j < k; j++) {
            uint32_t q = nb[j];
            if (hops[q] != SHELF_FAR || p->height[q / nn][q % nn] > p->sea_level) continue;
            hops[q] = hops[id] + 1;
            queue[tail++] = q;
        }
    }
}

static double texel_width_km(const pg_earthlike_geom *g, uint32_t id) {
    uint64_t nn = (uint64_t)g->n * (uint64_t)g->n;
    int face = (int)(id / nn);
    double a = (double)g->weight[pg_earthlike_face_kind(face)][id - (uint64_t)face * nn];
    return sqrt(a * g->unit_m2) / 1000;
}

pg_status pg_earthlike_shelf(const pg_planet *p, const pg_earthlike_geom *g, pg_earthlike *out,
                             pg_error *err) {
    out->shelf_coast_texels = out->shelf_closed_texels = 0;
    out->shelf_width_p10_km = out->shelf_width_p50_km = out->shelf_width_p90_km = NAN;
    pg_pits_topo t;
    pg_status st = pg_pits_topo_cube(&t, (uint32_t)p->n, err);
    if (st) return st;
    int64_t nn = p->n * p->n;
    uint32_t *hops = malloc((size_t)t.ncells * sizeof *hops);
    uint32_t *queue = malloc((size_t)t.ncells * sizeof *queue);
    double *width = NULL;
    size_t m = 0, cap = 0;
    if (!hops || !queue) {
        st = pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory for the shelf");
        goto done;
    }
    shelf_hops(&t, p, hops, queue);
    uint32_t nb[8];
    for (uint32_t id = 0; id < t.ncells; id++) {
        if (!(p->height[id / nn][id % nn] > p->sea_level)) continue;
        uint32_t best = SHELF_FAR;
        int sea = 0, k = pg_pits_neighbours(&t, id, nb);
        for (int j = 0; j < k; j++) {
            uint32_t q = nb[j];
            if (p->height[q / nn][q % nn] > p->sea_level) continue;
            sea = 1;
            if (hops[q] < best) best = hops[q];
        }
        if (!sea) continue;
        out->shelf_coast_texels++;
        if (best == SHELF_FAR) {
            out->shelf_closed_texels++;
            continue;
        }
        if (PG_ARRAY_RESERVE(width, &cap, m + 1, NULL)) {
            st = pg_error_set(err, PG_ERR_NOMEM, "earthlike: out of memory for the shelf");
            goto done;
        }
        width[m++] = (double)(best + 1) * texel_width_km(g, id);
    }
    if (m > 0) {
        qsort(width, m, sizeof *width, cmp_double);
        out->shelf_width_p10_km = quantile_sorted(width, m, 0.1);
        out->shelf_width_p50_km = quantile_sorted(width, m, 0.5);
        out->shelf_width_p90_km = quantile_sorted(width, m, 0.9);
    }
done:
    free(width);
    free(queue);
    free(hops);
    return st;
}
