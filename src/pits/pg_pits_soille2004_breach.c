/* pg_pits_soille2004_breach.c - depression breaching by flood order.
 *
 * Source: P. Soille (2004), "Optimal removal of spurious pits in grid digital
 * elevation models", Water Resources Research 40(12), W12509; in the form given by
 * J. J. Scott & N. A. Dodgson (2021), "Example-based terrain synthesis with pit
 * removal", Computers & Graphics, §3.2 (and Scott's thesis §4.1.2).
 *
 * Scott & Dodgson's version floods from the sinks with a priority queue on height;
 * each newly reached cell n records the cell p it was reached from (the flow map
 * F(n) = p). When n is lower than p (n lies in a pit), the path p, F(p), F(F(p)), ...
 * is carved: every cell on it is lowered to the next float below both T(n) and the
 * previous path cell, until a cell already low enough or a sink is reached.
 *
 * This file computes the same carving in linear time. Observation: the flood
 * tree F and the pop order depend only on the original heights (a cell is pushed
 * with its own, never yet lowered, height, and carving only touches cells already
 * popped). Carving enforces, along every tree edge child -> parent, "parent below
 * child", lowering only parents. The final heights are therefore the fixed point
 *     T'(x) = T(x)              if no child forces it,
 *     T'(x) = nextbelow(m)      with m the lowest final child height, if m < T(x)
 *                               (epsilon: if m <= T(x), i.e. flats are carved too),
 * which one sweep over the cells in REVERSE pop order computes, since every child is
 * popped after its parent. With epsilon this is the largest surface below T with
 * every parent strictly below its children, which is exactly what the walks
 * converge to (each walk lowers just enough). The walk-back version re-walks
 * channels once per pit cell (quadratic on wide flats); this sweep touches each tree
 * edge once.
 *
 * Preconditions: pits_begin seeded the queue; heights are not NaN.
 * Why it is correct: every non-sink cell x has the tree path x, F(x), ... to a sink;
 * after the sweep each parent is strictly below (epsilon) or not above (plain) each
 * child, so that path descends (the last step enters a sink, an outlet). Heights
 * only go down. Ties pop in (height, id) order, so the result is deterministic. */
#include "pg_huge.h"
#include "pg_pits_internal.h"

#include <stdlib.h>

typedef struct breach_state {
    uint8_t *st;       /* cell state; PITS_SINK cells are never lowered */
    uint8_t *children; /* bit j: neighbour slot j of the cell is its child in F */
    uint32_t *order;   /* pop order */
    uint64_t norder;
} breach_state;

/* The flood: builds the tree (as child bitmasks) and the pop order; with fill, also
 * the minimal fill of h: the highest key popped so far, at each cell as it pops.
 * Why: the keys pop in order, and a cell pushed by p pops before any key above its
 * own h, so by induction the running maximum at c is the highest ground on c's tree
 * path to a sink, which is at least c's fill; and at most, since at the pop of the
 * cell x with that maximum, c's lowest path to a sink had a cell y in the queue (the
 * first not yet popped: the sinks pop first, key -inf), so h(x) <= h(y) <= fill(c).
 * No arithmetic, so it is exact: Barnes et al. 2014's minimal fill, the same value at
 * every cell and the same bits except for the sign of a zero. Where a fill is zero,
 * Priority-Flood keeps an unraised cell's own zero and gives a raised cell the zero of
 * the neighbour that closed it; this maximum (ties give the popped height) keeps a
 * cell's own zero too, but gives a raised cell the zero of the last zero-height cell
 * popped, anywhere in the flood. The counts compare values, so they agree. */
static int flood(const pg_pits_topo *t, const float *h, breach_state *b, pits_heap *q,
                 float *fill) {
    uint32_t nb[8];
    float level = -INFINITY;
    while (q->n) {
        uint32_t c = pits_key_id(pits_heap_pop(q));
        b->order[b->norder++] = c;
        if (fill && b->st[c] == PITS_CLOSED) fill[c] = level = pits_maxf(level, h[c]);
        int k = pg_pits_neighbours(t, c, nb);
        uint8_t kids = 0;
        for (int j = 0; j < k; j++) {
            uint32_t n = nb[j];
            if (b->st[n] != PITS_OPEN) continue;
            b->st[n] = PITS_CLOSED;
            kids |= (uint8_t)(1u << j);
            pits_heap_push(q, pits_key(h[n], n));
        }
        b->children[c] = kids;
        if (q->oom) return -1;
    }
    return 0;
}

/* The reverse sweep: lower each parent below its lowest child. */
static void carve(const pg_pits_topo *t, float *h, const breach_state *b, int eps) {
    uint32_t nb[8];
    for (uint64_t i = b->norder; i-- > 0;) {
        uint32_t x = b->order[i];
        uint8_t kids = b->children[x];
        if (!kids || b->st[x] != PITS_CLOSED) continue;
        int k = pg_pits_neighbours(t, x, nb);
        float m = INFINITY;
        for (int j = 0; j < k; j++)
            if ((kids >> j) & 1u && h[nb[j]] < m) m = h[nb[j]];
        if (m < h[x] || (eps && m == h[x])) h[x] = pits_down(m);
    }
}

static pg_status breach(const pg_pits_topo *t, float *h, const pg_pits_opts *o, pg_pits_result *res,
                        float *fill, pg_error *err) {
    pits_heap q = {0};
    breach_state b = {0};
    uint64_t nsinks = 0;
    pg_status s = pits_begin(t, h, o, &b.st, &q, &nsinks, err);
    if (s) return s;
    b.children = pg_huge_calloc(t->ncells, 1);
    b.order = pg_huge_malloc(t->ncells * sizeof *b.order);
    if (fill) pits_fill_sinks(t, h, b.st, fill);
    if (!b.children || !b.order || flood(t, h, &b, &q, fill)) {
        s = pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for breaching %llu cells",
                         (unsigned long long)t->ncells);
    } else {
        carve(t, h, &b, o->epsilon);
        if (res) res->sinks = nsinks;
    }
    pits_heap_free(&q);
    pits_end(t, h, o, b.st);
    free(b.st);
    free(b.children);
    free(b.order);
    return s;
}

pg_status pits_breach_soille2004(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                 pg_pits_result *res, pg_error *err) {
    return breach(t, h, o, res, NULL, err);
}

pg_status pits_breach_soille2004_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                      pg_pits_result *res, float *fill, pg_error *err) {
    return breach(t, h, o, res, fill, err);
}
