/* pg_pits_sinks.c - the common start of every flood: validating options, choosing the
 * sinks and seeding the priority queue, plus the out-of-line growth of the queues
 * (through pg_array.h, the one growable-array helper).
 *
 * Sinks are the outlets water leaves the terrain through: cells at or below the sea
 * level, lake cells, no-data cells and (flat grids with open_edges) the border. A
 * sphere has no border, so with no ocean and no lakes the single lowest cell (ties:
 * smallest id) becomes the sink and everything drains to it. Only sinks that touch a
 * non-sink are queued: the interior of an ocean never reaches the front of the heap,
 * which keeps the seeding cost proportional to the coastline.
 *
 * Entering a sink is always allowed, whatever its height: an outlet takes the water
 * away (the sea, a lake, the world beyond the map's edge). So every algorithm treats
 * a sink as if it were at -inf: sinks are queued first (in id order) and no cell is
 * raised or carved because of a sink's own height. This matters for lakes and map
 * edges; ocean sinks are below every land cell anyway. */
#include "pg_huge.h"
#include "pg_pits_internal.h"

#include "pg_array.h"

#include <stdio.h>
#include <stdlib.h>

void pits_heap_free(pits_heap *q) {
    free(q->a);
    q->a = NULL;
    q->n = q->cap = 0;
}

void pits_heap_grow(pits_heap *q) {
    if (PG_ARRAY_RESERVE(q->a, &q->cap, q->n + 1, NULL)) q->oom = 1;
}

static void sift_down(uint64_t *a, size_t n, size_t i) {
    uint64_t k = a[i];
    for (;;) {
        size_t c = 4 * i + 1, best = c;
        if (c >= n) break;
        size_t end = c + 4 < n ? c + 4 : n;
        for (size_t j = c + 1; j < end; j++)
            if (a[j] < a[best]) best = j;
        if (a[best] >= k) break;
        a[i] = a[best];
        i = best;
    }
    a[i] = k;
}

void pits_heap_heapify(pits_heap *q) {
    if (q->n < 2) return;
    for (size_t i = (q->n - 2) / 4 + 1; i-- > 0;)
        sift_down(q->a, q->n, i);
}

void pits_rheap_free(pits_rheap *r) {
    for (int i = 0; i < 33; i++)
        free(r->b[i]);
    memset(r, 0, sizeof *r);
}

void pits_rheap_grow(pits_rheap *r, int bucket) {
    if (PG_ARRAY_RESERVE(r->b[bucket], &r->cap[bucket], r->n[bucket] + 1, NULL)) r->oom = 1;
}

void pits_rheap_release(pits_rheap *r, int bucket) {
    free(r->b[bucket]);
    r->b[bucket] = NULL;
    r->cap[bucket] = 0;
}

void pits_fifo_free(pits_fifo *f) {
    free(f->a);
    f->a = NULL;
    f->head = f->tail = f->cap = 0;
}

/* When at least half the array has been popped, move the live part down instead of
 * growing: a long search (pg_pits_planchon2002_minimal_eps.c closes most of a planet
 * in one) would otherwise keep every cell it ever queued, 4 bytes per cell. */
void pits_fifo_grow(pits_fifo *f) {
    if (f->head >= f->cap / 2 && f->head > 0) {
        memmove(f->a, f->a + f->head, (f->tail - f->head) * sizeof *f->a);
        f->tail -= f->head;
        f->head = 0;
        return;
    }
    if (PG_ARRAY_RESERVE(f->a, &f->cap, f->tail + 1, NULL)) f->oom = 1;
}

pg_status pits_validate(const pg_pits_topo *t, const pg_pits_opts *o, pg_error *err) {
    if (!t || !o || t->ncells == 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "pits: missing topology or options");
    /* Cells after the blocks have no neighbours the topology could give: the flood, its
     * seeding and the counts ask every reachable cell's (pg_pits.h, pg_pits_topo_blocks) */
    if (t->kind == PG_PITS_BLOCKS && t->extra)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits: a blocks topology with %u cells after its blocks has no "
                            "neighbours for them; removal and counts need every cell's",
                            t->extra);
    if (o->method < PG_PITS_FILL || o->method > PG_PITS_HYBRID)
        return pg_error_set(err, PG_ERR_BADINPUT, "pits: unknown method %d", (int)o->method);
    if (!(o->max_depth >= 0))
        return pg_error_set(err, PG_ERR_BADINPUT, "pits: --max-depth must be >= 0, got %g",
                            o->max_depth);
    if (!(o->max_length >= 0))
        return pg_error_set(err, PG_ERR_BADINPUT, "pits: --max-length must be >= 0, got %g",
                            o->max_length);
    if (o->has_sea_level && !isfinite(o->sea_level))
        return pg_error_set(err, PG_ERR_BADINPUT, "pits: --sea-level must be finite");
    return PG_OK;
}

static void sink_if_open(uint8_t *st, uint64_t i, uint64_t *count) {
    if (st[i] == PITS_OPEN) st[i] = PITS_SINK, (*count)++; /* a corner met twice counts once */
}

/* With open edges, the border cells that are neither no-data nor sinks already become
 * sinks: a pass over the perimeter only, so the pass over every cell needs no division
 * to find its row and column. */
static uint64_t mark_border(const pg_pits_topo *t, uint8_t *st) {
    uint64_t count = 0;
    const uint64_t w = t->w, h = t->h;
    for (uint64_t x = 0; x < w; x++)
        sink_if_open(st, x, &count), sink_if_open(st, (h - 1) * w + x, &count);
    for (uint64_t y = 0; y < h; y++)
        sink_if_open(st, y * w, &count), sink_if_open(st, y * w + w - 1, &count);
    return count;
}

/* Marks sinks and no-data; returns the number of sinks or sets err on NaN. */
static pg_status mark_sinks(const pg_pits_topo *t, float *h, const pg_pits_opts *o, uint8_t *st,
                            uint64_t *nsinks, pg_error *err) {
    const int64_t n = (int64_t)t->ncells;
    int64_t bad = -1;
    uint64_t count = 0;
    const int edges = o->open_edges && t->kind == PG_PITS_GRID;
    double sea = o->has_sea_level ? o->sea_level : -INFINITY;
#pragma omp parallel for reduction(+ : count) reduction(max : bad) schedule(static)
    for (int64_t i = 0; i < n; i++) {
        float v = h[i];
        uint8_t s = PITS_OPEN;
        if (isnan(v) || (o->has_nodata && v == o->nodata)) {
            if (!o->has_nodata) {
                if (bad < 0) bad = i;
            } else {
                s = PITS_NODATA;
                h[i] = -INFINITY;
            }
        } else if (v <= sea || (o->lakes && o->lakes[i])) {
            s = PITS_SINK;
        }
        st[i] = s;
        count += s != PITS_OPEN;
    }
    if (bad >= 0) {
        /* report the first NaN cell, deterministically */
        for (int64_t i = 0; i < n; i++)
            if (isnan(h[i]))
                return pg_error_set(err, PG_ERR_BADINPUT,
                                    "pits: cell %lld (x %lld, y %lld) is NaN/no-data and no "
                                    "no-data value was stated",
                                    (long long)i, (long long)(i % t->w), (long long)(i / t->w));
    }
    if (edges) count += mark_border(t, st);
    *nsinks = count;
    return PG_OK;
}

static void lowest_cell_sink(const pg_pits_topo *t, const float *h, uint8_t *st) {
    uint64_t best = UINT64_MAX;
    for (uint64_t i = 0; i < t->ncells; i++) {
        uint64_t k = pits_key(h[i], (uint32_t)i);
        if (k < best) best = k;
    }
    st[pits_key_id(best)] = PITS_SINK;
}

/* Queue every sink with a non-sink neighbour, in id order, then heapify. */
void pits_seed(const pg_pits_topo *t, const uint8_t *st, pits_heap *q) {
    uint32_t nb[8];
    for (uint64_t i = 0; i < t->ncells; i++) {
        if (st[i] == PITS_OPEN) continue;
        int k = pg_pits_neighbours(t, (uint32_t)i, nb), touches = 0;
        for (int j = 0; j < k; j++)
            touches |= st[nb[j]] == PITS_OPEN;
        if (!touches) continue;
        if (q->n == q->cap) {
            pits_heap_grow(q);
            if (q->oom) return;
        }
        q->a[q->n++] = pits_key(-INFINITY, (uint32_t)i); /* all outlets are equal */
    }
    pits_heap_heapify(q);
}

void pits_fill_sinks(const pg_pits_topo *t, const float *h, const uint8_t *st, float *fill) {
    const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n; i++)
        if (st[i] != PITS_OPEN) fill[i] = h[i];
}

pg_status pits_begin(const pg_pits_topo *t, float *h, const pg_pits_opts *o, uint8_t **state,
                     pits_heap *q, uint64_t *nsinks, pg_error *err) {
    pg_status s = pits_validate(t, o, err);
    if (s) return s;
    uint8_t *st = pg_huge_malloc(t->ncells);
    if (!st)
        return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for %llu cells",
                            (unsigned long long)t->ncells);
    s = mark_sinks(t, h, o, st, nsinks, err);
    if (s) {
        free(st);
        return s;
    }
    if (*nsinks == 0) {
        lowest_cell_sink(t, h, st);
        *nsinks = 1;
    }
    if (q) pits_seed(t, st, q);
    if (q && q->oom) {
        free(st);
        pits_heap_free(q);
        return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for the priority queue");
    }
    *state = st;
    return PG_OK;
}

void pits_end(const pg_pits_topo *t, float *h, const pg_pits_opts *o, const uint8_t *state) {
    if (!o->has_nodata) return;
    const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n; i++)
        if (state[i] == PITS_NODATA) h[i] = o->nodata;
}
