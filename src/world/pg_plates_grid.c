/* pg_plates_grid.c - the cube sphere as a graph for the plate model: texel centres,
 * texel areas and reach (centre to farthest corner), 8-neighbour adjacency across seams,
 * nearest texel of a direction, and multi-source shortest paths (Dijkstra 1959) over
 * that graph.
 *
 * Texel areas are exact on the sphere: each texel is split into two spherical
 * triangles of its corner directions (pg_cube_spherical_triangle), so the areas add up
 * to 4 pi R^2 up to rounding. Neighbours come from pg_cube_wrap, the exact integer
 * seam map, so a path never jumps. Path lengths along the graph overestimate
 * great-circle distances by at most the octagonal-metric factor (about 8%), which is
 * good enough for distance-based uplift profiles and the 500 km mountain-belt radius. */
#include "pg_plates_internal.h"

#include <stdlib.h>
#include <string.h>

static int64_t pg_plates_pow2_divisor(int64_t n) {
    int64_t s = 1;
    while (n % (2 * s) == 0 && 2 * s <= 8192)
        s *= 2;
    return s;
}

/* The texel's area on the unit sphere; *reach gets the largest angle from centre to a corner. */
static double pg_plates_texel_area(pg_cube_projection proj, int64_t n, int face, int64_t x,
                                   int64_t y, const double centre[3], double *reach) {
    double c[4][3];
    double u0 = 2.0 * (double)x / (double)n - 1, u1 = 2.0 * (double)(x + 1) / (double)n - 1;
    double v0 = 2.0 * (double)y / (double)n - 1, v1 = 2.0 * (double)(y + 1) / (double)n - 1;
    pg_cube_to_dir(proj, face, u0, v0, c[0]);
    pg_cube_to_dir(proj, face, u1, v0, c[1]);
    pg_cube_to_dir(proj, face, u1, v1, c[2]);
    pg_cube_to_dir(proj, face, u0, v1, c[3]);
    *reach = 0;
    for (int k = 0; k < 4; k++) {
        double a = pg_plates_angle(centre, c[k]);
        *reach = a > *reach ? a : *reach;
    }
    return pg_cube_spherical_triangle(c[0], c[1], c[2]) +
           pg_cube_spherical_triangle(c[0], c[2], c[3]);
}

pg_status pg_plates_grid_init(pg_plates_grid *g, int64_t n, pg_cube_projection proj,
                              double radius_km, pg_error *err) {
    memset(g, 0, sizeof *g);
    pg_cube_grid cg;
    int64_t s = pg_plates_pow2_divisor(n);
    if (pg_cube_grid_init(&cg, proj, (int)(n / s), (int)s, err) != PG_OK) return err->status;
    g->n = n;
    g->count = 6 * n * n;
    g->proj = proj;
    g->radius_km = radius_km;
    g->dir = malloc(sizeof(double) * 3 * (size_t)g->count);
    g->area = malloc(sizeof(float) * (size_t)g->count);
    g->nbr = malloc(sizeof(int64_t) * 8 * (size_t)g->count);
    g->nlen = malloc(sizeof(float) * 8 * (size_t)g->count);
    pg_status fs = pg_cube_texel_finder_init(&g->find, proj, n, err);
    if (!g->dir || !g->area || !g->nbr || !g->nlen || fs) {
        pg_plates_grid_free(g);
        return pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for a %lld^2 cube grid",
                            (long long)n);
    }
    double r2 = radius_km * radius_km, reach = 0;
#pragma omp parallel for schedule(static) reduction(max : reach)
    for (int64_t t = 0; t < g->count; t++) {
        int face = (int)(t / (n * n));
        int64_t x = t % n, y = (t / n) % n;
        double rt;
        pg_cube_texel_dir(&cg, t, g->dir + 3 * t);
        g->area[t] = (float)(pg_plates_texel_area(proj, n, face, x, y, g->dir + 3 * t, &rt) * r2);
        reach = rt > reach ? rt : reach;
    }
    g->texel_reach = reach;
#pragma omp parallel for schedule(static)
    for (int64_t t = 0; t < g->count; t++) {
        int face = (int)(t / (n * n));
        int64_t x = t % n, y = (t / n) % n;
        for (int d = 0; d < 8; d++) {
            int dx, dy, rot;
            pg_cube_dir_offset((pg_cube_dir)d, &dx, &dy);
            int64_t q = pg_cube_wrap(&cg, face, x + dx, y + dy, &rot);
            g->nbr[8 * t + d] = q;
            g->nlen[8 * t + d] =
                (float)(pg_plates_angle(g->dir + 3 * t, g->dir + 3 * q) * radius_km);
        }
    }
    return PG_OK;
}

void pg_plates_grid_free(pg_plates_grid *g) {
    free(g->dir);
    free(g->area);
    free(g->nbr);
    free(g->nlen);
    pg_cube_texel_finder_free(&g->find);
    memset(g, 0, sizeof *g);
}

int64_t pg_plates_grid_nearest(const pg_plates_grid *g, const double d[3]) {
    if (g->find.n == g->n) return pg_cube_texel_find(&g->find, d);
    pg_cube_texel_finder f = {g->proj, g->n, NULL, NULL}; /* a grid without its tables */
    return pg_cube_texel_find(&f, d);
}

/* A binary min-heap of (distance, texel), each entry one 64-bit word: the distance's
 * float bits above the texel id. Distances are >= 0, and the bits of non-negative
 * floats order as their values, so comparing words orders by distance, then by texel
 * id on ties: pops are unique, and one compare and one move per step replace two. */
typedef struct pg_plates_heap {
    uint64_t *e;
    int64_t size;
} pg_plates_heap;

_Static_assert(sizeof(float) == sizeof(uint32_t), "a heap entry packs a float's bits");

static uint64_t pg_plates_entry(float key, int64_t id) {
    uint32_t bits;
    memcpy(&bits, &key, sizeof bits);
    return (uint64_t)bits << 32 | (uint64_t)id;
}

static void pg_plates_push(pg_plates_heap *h, float key, int64_t id) {
    uint64_t x = pg_plates_entry(key, id);
    int64_t i = h->size++;
    while (i > 0 && x < h->e[(i - 1) / 2]) {
        h->e[i] = h->e[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->e[i] = x;
}

static void pg_plates_pop(pg_plates_heap *h, float *key, int64_t *id) {
    uint64_t top = h->e[0], x = h->e[--h->size];
    uint32_t bits = (uint32_t)(top >> 32);
    memcpy(key, &bits, sizeof *key);
    *id = (int64_t)(top & 0xffffffffu);
    int64_t i = 0;
    for (;;) {
        int64_t l = 2 * i + 1, m = i;
        uint64_t v = x;
        if (l < h->size && h->e[l] < v) m = l, v = h->e[l];
        if (l + 1 < h->size && h->e[l + 1] < v) m = l + 1, v = h->e[l + 1];
        if (m == i) break;
        h->e[i] = v;
        i = m;
    }
    h->e[i] = x;
}

pg_status pg_plates_grid_distance(const pg_plates_grid *g, const uint8_t *src, const uint8_t *plate,
                                  float *dist, pg_error *err) {
    /* Each texel is pushed at most once per improvement over 8 edges: 9 * count bounds
     * the heap. */
    if (g->count > (int64_t)UINT32_MAX)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: %lld texels are too many",
                            (long long)g->count);
    pg_plates_heap h = {malloc(sizeof(uint64_t) * 9 * (size_t)g->count), 0};
    if (!h.e) return pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for distances");
    for (int64_t t = 0; t < g->count; t++) {
        dist[t] = src[t] ? 0.0f : INFINITY;
        if (src[t]) pg_plates_push(&h, 0.0f, t);
    }
    while (h.size > 0) {
        float d;
        int64_t t;
        pg_plates_pop(&h, &d, &t);
        if (d > dist[t]) continue;
        for (int k = 0; k < 8; k++) {
            int64_t q = g->nbr[8 * t + k];
            if (plate && plate[q] != plate[t]) continue;
            float nd = d + g->nlen[8 * t + k];
            if (nd < dist[q]) {
                dist[q] = nd;
                pg_plates_push(&h, nd, q);
            }
        }
    }
    free(h.e);
    return PG_OK;
}

int pg_plates_keyed_cmp(const void *a, const void *b) {
    const pg_plates_keyed *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->id < y->id ? -1 : (x->id > y->id);
}
