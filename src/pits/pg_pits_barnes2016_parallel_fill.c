/* pg_pits_barnes2016_parallel_fill.c - plain depression filling in parallel, by tiles.
 *
 * Source: R. Barnes (2016), "Parallel Priority-Flood depression filling for trillion
 * cell digital elevation models on desktops or clusters", Computers & Geosciences
 * 96:56-68 (its three stages, in shared memory).
 *
 * Idea. Cut the cells into tiles (runs of whole rows: ids [lo, hi)). Stage 1, one
 * tile per thread: a Priority-Flood (Barnes et al. 2014) that sees only the tile,
 * seeded with the tile's sinks (label 1, the outlet) and with every perimeter cell
 * (a cell with a neighbour in another tile), each under its own label. Every cell
 * joins the label of the cell it was flooded from and is filled to the level of its
 * label's seed. Where two labels touch, the pair's spill height max(W(a), W(b)) is
 * an edge of a label graph; so is every pair of neighbouring perimeter cells in two
 * different tiles. Stage 2: a minimax Dijkstra over the label graph from the outlet
 * gives each label the lowest level at which its water reaches a sink. Stage 3, in
 * parallel: every cell becomes max(W(c), level(label(c))).
 *
 * Preconditions: plain (non-epsilon) fill; state[] holds the sinks (pits_begin's
 * marking); sinks count as outlets at any height, as in the serial flood.
 * Why it is correct (Barnes 2016, §3): the minimal fill of a cell is the minimax
 * height over paths to a sink. Inside a tile that path ends at a sink or leaves the
 * tile through a perimeter cell; the in-tile flood gives the minimax to its label's
 * seed, and the label graph composes these segments exactly (every crossing between
 * labels is an edge with its spill height). The minimal fill is unique, so the
 * result is bit-identical to the serial fill for any tiling and thread count; the
 * tests compare them on random grids with many small tiles. */
#include "pg_pits_internal.h"

#include <omp.h>
#include <stdlib.h>

enum { OUTLET = 1 };

typedef struct pf_edge {
    uint32_t a, b;
    float w;
} pf_edge;

typedef struct edge_vec {
    pf_edge *e;
    size_t n, cap;
    int oom;
} edge_vec;

static void edge_push(edge_vec *v, uint32_t a, uint32_t b, float w) {
    if (v->n == v->cap) {
        size_t cap = v->cap ? v->cap * 2 : 1024;
        pf_edge *e = realloc(v->e, cap * sizeof *e);
        if (!e) {
            v->oom = 1;
            return;
        }
        v->e = e;
        v->cap = cap;
    }
    v->e[v->n++] = (pf_edge){a, b, w};
}

typedef struct tiling {
    const pg_pits_topo *t;
    float *h;           /* in: heights; after stage 1: W (in-tile fill) */
    const uint8_t *st;  /* sinks */
    uint32_t *label;    /* 0 = not yet reached */
    uint64_t tile_size; /* cells per tile (whole rows) */
    uint32_t ntiles;
    uint32_t bound; /* labels per tile: at least its perimeter cell count */
} tiling;

/* Ids [lo, hi) of a tile. */
typedef struct span {
    uint32_t lo, hi;
} span;

static span tile_span(const tiling *g, uint32_t tile) {
    uint64_t lo = (uint64_t)tile * g->tile_size, hi = lo + g->tile_size;
    return (span){(uint32_t)lo, (uint32_t)(hi < g->t->ncells ? hi : g->t->ncells)};
}

static int inside(span s, uint32_t id) {
    return id >= s.lo && id < s.hi;
}

static float eff(const tiling *g, uint32_t id) {
    return g->st[id] == PITS_CLOSED || g->st[id] == PITS_OPEN ? g->h[id] : -INFINITY;
}

/* Seeds of one tile: its sinks touching open cells, and its perimeter cells, which
 * get labels 2 + tile*bound + k. Cross-tile pairs go to `cross` as cell ids; they
 * become label pairs once every tile has labelled its perimeter. */
static void seed_tile(tiling *g, uint32_t tile, pits_heap *q, edge_vec *cross) {
    span sp = tile_span(g, tile);
    uint32_t nb[8], next = 2 + tile * g->bound;
    for (uint32_t id = sp.lo; id < sp.hi; id++) {
        int k = pg_pits_neighbours(g->t, id, nb), outside = 0, open = 0;
        for (int j = 0; j < k; j++) {
            int out = !inside(sp, nb[j]);
            outside |= out;
            open |= !out && g->st[nb[j]] == PITS_OPEN;
            /* cross-tile pair, recorded once from the lower id */
            if (out && nb[j] > id) edge_push(cross, id, nb[j], fmaxf(eff(g, id), eff(g, nb[j])));
        }
        if (g->st[id] != PITS_OPEN) {
            g->label[id] = OUTLET;
            if (open) pits_heap_push(q, pits_key(-INFINITY, id));
        } else if (outside) {
            g->label[id] = next++;
            pits_heap_push(q, pits_key(g->h[id], id));
        }
    }
}

/* Stage 1 on one tile: Improved Priority-Flood with labels and spill edges. */
static int flood_tile(tiling *g, uint32_t tile, edge_vec *ev, edge_vec *cross) {
    pits_heap q = {0};
    pits_fifo pit = {0};
    seed_tile(g, tile, &q, cross);
    span sp = tile_span(g, tile);
    uint32_t nb[8];
    while (q.n || !pits_fifo_empty(&pit)) {
        uint32_t c = !pits_fifo_empty(&pit) ? pits_fifo_pop(&pit) : pits_key_id(pits_heap_pop(&q));
        float wc = eff(g, c);
        uint32_t lc = g->label[c];
        int k = pg_pits_neighbours(g->t, c, nb);
        for (int j = 0; j < k; j++) {
            uint32_t n = nb[j];
            if (!inside(sp, n)) continue;
            uint32_t ln = g->label[n];
            if (ln) {
                if (ln != lc) edge_push(ev, lc, ln, fmaxf(wc, eff(g, n)));
                continue;
            }
            g->label[n] = lc;
            if (g->h[n] <= wc) {
                g->h[n] = wc;
                pits_fifo_push(&pit, n);
            } else {
                pits_heap_push(&q, pits_key(g->h[n], n));
            }
        }
        if (q.oom || pit.oom || ev->oom) break;
    }
    int oom = q.oom || pit.oom || ev->oom;
    pits_heap_free(&q);
    pits_fifo_free(&pit);
    return oom;
}

/* Turn the cross-tile cell pairs into label pairs (perimeter labels are final). */
static void label_cross_edges(const tiling *g, edge_vec *cross) {
    for (size_t k = 0; k < cross->n; k++) {
        cross->e[k].a = g->label[cross->e[k].a];
        cross->e[k].b = g->label[cross->e[k].b];
    }
}

/* Stage 2: minimax levels of all labels from the outlet (nl = 2 + ntiles*bound). */
static int solve_levels(const tiling *g, edge_vec *ev, uint32_t nev, float *level) {
    size_t nl = 2 + (size_t)g->ntiles * g->bound, total = 0;
    for (uint32_t i = 0; i < nev; i++)
        total += ev[i].n;
    uint32_t *start = calloc(nl + 1, sizeof *start);
    pf_edge *adj = malloc((2 * total + 1) * sizeof *adj);
    pits_heap q = {0};
    if (!start || !adj) {
        free(start);
        free(adj);
        return 1;
    }
    for (uint32_t i = 0; i < nev; i++)
        for (size_t k = 0; k < ev[i].n; k++) {
            start[ev[i].e[k].a + 1]++;
            start[ev[i].e[k].b + 1]++;
        }
    for (size_t l = 0; l < nl; l++)
        start[l + 1] += start[l];
    uint32_t *fillp = malloc(nl * sizeof *fillp);
    if (!fillp) {
        free(start);
        free(adj);
        return 1;
    }
    memcpy(fillp, start, nl * sizeof *fillp);
    for (uint32_t i = 0; i < nev; i++)
        for (size_t k = 0; k < ev[i].n; k++) {
            pf_edge e = ev[i].e[k];
            adj[fillp[e.a]++] = e;
            adj[fillp[e.b]++] = (pf_edge){e.b, e.a, e.w};
        }
    free(fillp);
    for (size_t l = 0; l < nl; l++)
        level[l] = INFINITY;
    level[OUTLET] = -INFINITY;
    /* keys: (level, label); label ids fit in 32 bits because ncells < 2^32 - 2 */
    pits_heap_push(&q, pits_key(-INFINITY, OUTLET));
    while (q.n && !q.oom) {
        uint64_t key = pits_heap_pop(&q);
        uint32_t l = pits_key_id(key);
        if (pits_key(level[l], l) != key) continue; /* stale entry */
        for (uint32_t k = start[l]; k < start[l + 1]; k++) {
            float w = fmaxf(level[l], adj[k].w);
            if (w < level[adj[k].b]) {
                level[adj[k].b] = w;
                pits_heap_push(&q, pits_key(w, adj[k].b));
            }
        }
    }
    int oom = q.oom;
    pits_heap_free(&q);
    free(start);
    free(adj);
    return oom;
}

static uint32_t choose_tiles(const pg_pits_topo *t, const pg_pits_opts *o, uint64_t *tile_size) {
    uint64_t rows = t->ncells / t->w;
    uint64_t per = o->tile_rows > 0 ? (uint64_t)o->tile_rows : rows / 16;
    if (per < 64 && o->tile_rows <= 0) per = 64;
    if (per < 1) per = 1;
    if (per > rows) per = rows;
    *tile_size = per * t->w;
    return (uint32_t)((t->ncells + *tile_size - 1) / *tile_size);
}

/* Perimeter cells of a strip of whole rows lie in its first or last row, in the
 * first or last column (cube seams), or in a face's first or last row: a strip of
 * r rows meets at most r/h + 2 faces. */
static uint32_t perimeter_bound(const pg_pits_topo *t, uint64_t tile_size) {
    uint64_t rows = tile_size / t->w;
    uint64_t b = (uint64_t)t->w * (2 * (rows / t->h) + 6) + 2 * rows;
    return (uint32_t)(b < tile_size ? b : tile_size);
}

pg_status pits_parallel_fill_barnes2016(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                        pg_pits_result *res, pg_error *err) {
    uint8_t *st = NULL;
    uint64_t nsinks = 0;
    pg_status s = pits_begin(t, h, o, &st, NULL, &nsinks, err);
    if (s) return s;
    tiling g = {t, h, st, calloc(t->ncells, sizeof(uint32_t)), 0, 0, 0};
    g.ntiles = choose_tiles(t, o, &g.tile_size);
    g.bound = perimeter_bound(t, g.tile_size);
    /* ev[0..ntiles) in-tile spill edges, ev[ntiles..2*ntiles) cross-tile pairs */
    edge_vec *ev = calloc(2 * (size_t)g.ntiles, sizeof *ev);
    float *level = malloc((2 + (size_t)g.ntiles * g.bound) * sizeof *level);
    int oom = !g.label || !ev || !level;
    if (!oom) {
#pragma omp parallel for schedule(dynamic, 1) reduction(| : oom)
        for (int64_t tile = 0; tile < (int64_t)g.ntiles; tile++)
            oom |= flood_tile(&g, (uint32_t)tile, &ev[tile], &ev[g.ntiles + tile]);
    }
    for (uint32_t i = 0; !oom && i < g.ntiles; i++)
        label_cross_edges(&g, &ev[g.ntiles + i]);
    if (!oom) oom = solve_levels(&g, ev, 2 * g.ntiles, level);
    if (!oom) {
        const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for schedule(static)
        for (int64_t i = 0; i < n; i++)
            if (st[i] == PITS_OPEN && level[g.label[i]] > h[i]) h[i] = level[g.label[i]];
    }
    for (uint32_t i = 0; ev && i < 2 * g.ntiles; i++)
        free(ev[i].e);
    free(ev);
    free(level);
    free(g.label);
    pits_end(t, h, o, st);
    free(st);
    if (oom) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory in the parallel fill");
    if (res) res->sinks = nsinks;
    return PG_OK;
}
