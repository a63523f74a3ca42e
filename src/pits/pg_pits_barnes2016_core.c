/* pg_pits_barnes2016_core.c - the tile flood and the label-graph solve of Barnes (2016),
 * shared by the threaded fill and the MPI fill.
 *
 * Source: R. Barnes (2016), "Parallel Priority-Flood depression filling for trillion
 * cell digital elevation models on desktops or clusters", Computers & Geosciences
 * 96:56-68; its distributed form: the same author's "Flexibly distributed
 * Priority-Flood depression filling for teracell DEMs" (arXiv:1608.04431).
 *
 * Step 1 (pits_b16_flood_tile): a Priority-Flood (Barnes et al. 2014, improved: cells
 * in pits go through a FIFO) that sees only the tile, seeded with the tile's sinks that
 * touch a non-sink (label OUTLET) and with every perimeter cell (a cell with a
 * neighbour in another tile) under its own label. Every cell joins the label of the
 * cell it was flooded from and is raised to that cell's level.
 * Step 2, during the flood: where two labels meet inside the tile, the edge
 * max(W(a), W(b)); for every pair of neighbouring cells in two tiles, max(h(a), h(b))
 * (sinks count as -inf), recorded as a cell pair for the caller to label.
 * Step 3 (pits_b16_solve): a minimax Dijkstra from the outlet over the label graph
 * gives each label the lowest level at which its water reaches a sink. (Step 4, each
 * cell to max(h, level(label)), and the way the graph is gathered are the callers'.)
 *
 * Preconditions: a plain fill (no epsilon); sinks are never raised and count as
 * outlets at any height; label arrays start at 0 on the tile's cells; label ids below
 * 2^32 (ncells < 2^32 - 2).
 * Why it is correct (Barnes 2016, section 3): the minimal fill of a cell is the
 * minimax height over its paths to a sink. Inside a tile such a path ends at a sink or
 * leaves the tile through a perimeter cell; the in-tile flood gives the minimax to its
 * label's seed, and the label graph composes these segments exactly, since every
 * crossing between labels is an edge with its spill height. The minimal fill is
 * unique, so neither the tiling, the label numbering, nor the order of the edges
 * changes a bit of the result. */
#include "pg_pits_barnes2016_core.h"
#include "pg_array.h"

#include <stdlib.h>

void pits_b16_edge_push(pits_b16_edges *v, uint32_t a, uint32_t b, float w) {
    if (a == b) return;
    if (PG_ARRAY_RESERVE(v->e, &v->cap, v->n + 1, NULL) != PG_OK) {
        v->oom = 1;
        return;
    }
    if (a > b) {
        uint32_t t = a;
        a = b, b = t;
    }
    v->e[v->n++] = (pits_b16_edge){a, b, w};
}

static int cmp_edge(const void *x, const void *y) {
    const pits_b16_edge *a = x, *b = y;
    if (a->a != b->a) return a->a < b->a ? -1 : 1;
    if (a->b != b->b) return a->b < b->b ? -1 : 1;
    return a->w < b->w ? -1 : a->w > b->w;
}

void pits_b16_edges_compact(pits_b16_edges *v) {
    if (!v->n) return;
    qsort(v->e, v->n, sizeof *v->e, cmp_edge);
    size_t k = 1;
    for (size_t i = 1; i < v->n; i++)
        if (v->e[i].a != v->e[k - 1].a || v->e[i].b != v->e[k - 1].b) v->e[k++] = v->e[i];
    v->n = k;
}

/* Seed the heap with the tile's cells in id order: sinks touching one of its non-sinks
 * (label OUTLET), perimeter cells under their own labels; cross-tile pairs to cross. */
static void seed_tile(pits_b16_tile *g, pits_rheap *q, pits_b16_edges *cross) {
    const uint32_t run = g->w ? g->c1 - g->c0 : g->hi - g->lo, stride = g->w ? g->w : run;
    uint32_t nb[8];
    for (uint32_t row = g->lo; row < g->hi; row += stride)
        for (uint32_t id = row; id < row + run; id++) {
            int k = pg_pits_neighbours(g->t, id, nb), outside = 0, open = 0;
            for (int j = 0; j < k; j++) {
                int out = !pits_b16_inside(g, nb[j]);
                outside |= out;
                open |= !out && !pits_b16_sink(g, nb[j]);
                /* a pair of cells in two tiles, recorded once, from the lower id */
                if (out && nb[j] > id)
                    pits_b16_edge_push(cross, id, nb[j],
                                       pits_maxf(pits_b16_eff(g, id), pits_b16_eff(g, nb[j])));
            }
            if (pits_b16_sink(g, id)) {
                g->label[id] = PITS_B16_OUTLET;
                if (open) pits_rheap_push(q, pits_ord(-INFINITY), id);
            } else if (outside) {
                g->label[id] = g->next_label ? g->next_label++ : 2 + id;
                pits_rheap_push(q, pits_ord(g->h[id]), id);
            }
        }
}

/* Spill edges pass through a small direct-mapped cache keyed by the label pair, which
 * keeps each pair's lowest height: a boundary between two labels is met once per
 * neighbouring cell pair (on the hard DEM of docs/pits.md, ten million times for a
 * few hundred thousand pairs). An entry leaves for ev when another pair takes its
 * slot, and all of them at the end. The solve reads only each pair's lowest height,
 * so the cache changes the edge list, never the levels. */
enum { EDGE_CACHE = 4096 };

typedef struct edge_cache {
    pits_b16_edge e[EDGE_CACHE]; /* a == b: empty */
} edge_cache;

static inline void cache_push(edge_cache *c, pits_b16_edges *ev, uint32_t a, uint32_t b, float w) {
    if (a > b) {
        uint32_t t = a;
        a = b, b = t;
    }
    pits_b16_edge *s = &c->e[(a * 0x9e3779b1u ^ b * 0x85ebca77u) >> 20];
    if (s->a == a && s->b == b) {
        if (w < s->w) s->w = w;
        return;
    }
    if (s->a != s->b) pits_b16_edge_push(ev, s->a, s->b, s->w);
    *s = (pits_b16_edge){a, b, w};
}

static void cache_flush(edge_cache *c, pits_b16_edges *ev) {
    for (size_t i = 0; i < EDGE_CACHE; i++)
        if (c->e[i].a != c->e[i].b) pits_b16_edge_push(ev, c->e[i].a, c->e[i].b, c->e[i].w);
}

int pits_b16_flood_tile(pits_b16_tile *g, pits_b16_edges *ev, pits_b16_edges *cross) {
    pits_fifo pit = {0};
    edge_cache *cache = calloc(1, sizeof *cache);
    if (!cache) return 1;
    /* the order of equal heights changes the labels but not the result (the fill is
     * unique), so the front is a radix heap on the heights (pg_pits_internal.h) */
    pits_rheap r = {0};
    seed_tile(g, &r, cross);
    uint32_t nb[8];
    while ((r.size || !pits_fifo_empty(&pit)) && !r.oom && !pit.oom && !ev->oom && !cross->oom) {
        uint32_t c = !pits_fifo_empty(&pit) ? pits_fifo_pop(&pit) : pits_key_id(pits_rheap_pop(&r));
        if (r.oom) break;
        float wc = pits_b16_eff(g, c);
        uint32_t lc = g->label[c];
        int k = pg_pits_neighbours(g->t, c, nb);
        for (int j = 0; j < k; j++) {
            uint32_t n = nb[j];
            if (!pits_b16_inside(g, n)) continue;
            uint32_t ln = g->label[n];
            if (ln) {
                if (ln != lc) cache_push(cache, ev, lc, ln, pits_maxf(wc, pits_b16_eff(g, n)));
                continue;
            }
            g->label[n] = lc;
            if (g->h[n] <= wc) {
                g->h[n] = wc;
                pits_fifo_push(&pit, n);
            } else {
                pits_rheap_push(&r, pits_ord(g->h[n]), n);
            }
        }
    }
    cache_flush(cache, ev);
    free(cache);
    int oom = r.oom || pit.oom || ev->oom || cross->oom;
    pits_rheap_free(&r);
    pits_fifo_free(&pit);
    return oom;
}

/* The label graph in both directions, grouped by label (compressed rows). */
static int adjacency(const pits_b16_edges *ev, size_t nev, size_t nl, uint32_t **start_out,
                     pits_b16_edge **adj_out) {
    size_t total = 0;
    for (size_t i = 0; i < nev; i++)
        total += ev[i].n;
    uint32_t *start = calloc(nl + 1, sizeof *start), *fill = malloc((nl + 1) * sizeof *fill);
    pits_b16_edge *adj = malloc((2 * total + 1) * sizeof *adj);
    int oom = !start || !adj || !fill;
    for (size_t i = 0; !oom && i < nev; i++)
        for (size_t k = 0; k < ev[i].n; k++) {
            start[ev[i].e[k].a + 1]++;
            start[ev[i].e[k].b + 1]++;
        }
    for (size_t l = 0; !oom && l < nl; l++)
        start[l + 1] += start[l];
    if (!oom) memcpy(fill, start, nl * sizeof *fill);
    for (size_t i = 0; !oom && i < nev; i++)
        for (size_t k = 0; k < ev[i].n; k++) {
            pits_b16_edge e = ev[i].e[k];
            adj[fill[e.a]++] = e;
            adj[fill[e.b]++] = (pits_b16_edge){e.b, e.a, e.w};
        }
    free(fill);
    if (oom) free(start), free(adj), start = NULL, adj = NULL;
    *start_out = start, *adj_out = adj;
    return oom;
}

int pits_b16_solve(const pits_b16_edges *ev, size_t nev, size_t nl, uint32_t source, float *level) {
    uint32_t *start;
    pits_b16_edge *adj;
    pits_heap q = {0};
    for (size_t l = 0; l < nl; l++)
        level[l] = INFINITY;
    if (adjacency(ev, nev, nl, &start, &adj)) return 1;
    if (source < nl) {
        level[source] = -INFINITY;
        pits_heap_push(&q, pits_key(-INFINITY, source));
    }
    /* keys: (level, label index); stale entries are skipped */
    while (q.n && !q.oom) {
        uint64_t key = pits_heap_pop(&q);
        uint32_t l = pits_key_id(key);
        if (pits_key(level[l], l) != key) continue;
        for (uint32_t k = start[l]; k < start[l + 1]; k++) {
            float w = pits_maxf(level[l], adj[k].w);
            if (w < level[adj[k].b]) {
                level[adj[k].b] = w;
                pits_heap_push(&q, pits_key(w, adj[k].b));
            }
        }
    }
    int oom = q.oom;
    pits_heap_free(&q);
    free(start), free(adj);
    return oom;
}

static int cmp_u64(const void *x, const void *y) {
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return a < b ? -1 : a > b;
}

size_t pits_sort_unique_u64(uint64_t *a, size_t n) {
    if (!n) return 0;
    qsort(a, n, sizeof *a, cmp_u64);
    size_t k = 1;
    for (size_t i = 1; i < n; i++)
        if (a[i] != a[k - 1]) a[k++] = a[i];
    return k;
}

size_t pits_sorted_index_u64(const uint64_t *a, size_t n, uint64_t v) {
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (a[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}
