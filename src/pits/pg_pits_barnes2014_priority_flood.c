/* pg_pits_barnes2014_priority_flood.c - depression filling by "Improved Priority-Flood".
 *
 * Source: R. Barnes, C. Lehman, D. Mulla (2014), "Priority-Flood: An optimal
 * depression-filling and watershed-labeling algorithm for digital elevation models",
 * Computers & Geosciences 62:117-127, Algorithm 2 (improved, plain FIFO for cells in
 * pits); as used by Scott & Dodgson 2021 §3.1. Fill WITH epsilon is not this file's
 * Algorithm 3 but the minimal epsilon-surface (pg_pits_planchon2002_minimal_eps.c):
 * Algorithm 3's ulps follow the flood order, the minimal surface's do not.
 *
 * Idea: flood the terrain from the sinks inwards in order of height. The priority
 * queue always yields the lowest cell c on the boundary of the flooded (closed)
 * region, so c's height is the lowest level at which water from an unvisited
 * neighbour n could leave through c. If n is not higher than c, n lies in a pit: it
 * is raised to c's height and, since every
 * cell it reaches next is then at that same spill level, it goes to a plain FIFO
 * instead of the heap - the "improved" part, which removes the log factor for cells
 * inside pits.
 *
 * Preconditions: pits_begin has marked the sinks and queued the sinks touching
 * non-sinks; no NaN heights (no-data is -inf by then).
 * Why it is correct: by induction over the pop order, every closed cell has a
 * non-ascending path to a sink through closed cells (h[c] is final when c is
 * popped). Plain fill is the minimal such surface: a cell is raised only to the
 * lowest spill height through which its region connects to a sink (Barnes et al.,
 * Theorem 1), which the exact-fill test checks against a slow iterative reference.
 * The result is unique, so the order in which equal heights pop does not matter:
 * the front is a monotone radix heap on the heights alone (pg_pits_internal.h).
 * The order in which cells are closed is kept on request: each cell is closed from a
 * neighbour closed before it and not higher, which is the certificate the counts
 * check after the fill (pits_drains_by) where the flats would need a search. */
#include "pg_pits_internal.h"

#include <stdlib.h>

/* The flood; keep (0 or 1, a constant at each call) says whether to number the closed
 * cells in order, so the plain flood's loop carries neither the test nor the counter. */
static inline pg_status flood(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                              pg_pits_result *res, pg_error *err, uint32_t *order, const int keep) {
    pits_heap q = {0};
    pits_fifo pit = {0};
    uint8_t *st = NULL;
    uint64_t nsinks = 0;
    pg_status s = pits_begin(t, h, o, &st, &q, &nsinks, err);
    if (s) return s;
    /* the sinks, then the front, in a radix heap: the minimal fill is unique, so the
     * order of equal heights does not matter (pg_pits_internal.h) */
    pits_rheap r = {0};
    for (size_t i = 0; i < q.n; i++)
        pits_rheap_push(&r, (uint32_t)(q.a[i] >> 32), pits_key_id(q.a[i]));
    pits_heap_free(&q); /* the sinks now live in r */
    uint32_t nb[8], closed = 0;
    while ((r.size || !pits_fifo_empty(&pit)) && !r.oom && !pit.oom) {
        uint32_t c = !pits_fifo_empty(&pit) ? pits_fifo_pop(&pit) : pits_key_id(pits_rheap_pop(&r));
        if (r.oom) break;
        float hc = st[c] == PITS_CLOSED ? h[c] : -INFINITY; /* sinks: outlets */
        int k = pg_pits_neighbours(t, c, nb);
        for (int j = 0; j < k; j++) {
            uint32_t n = nb[j];
            if (st[n] != PITS_OPEN) continue;
            st[n] = PITS_CLOSED;
            if (keep) order[n] = ++closed;
            if (h[n] <= hc) {
                h[n] = hc;
                pits_fifo_push(&pit, n);
            } else {
                pits_rheap_push(&r, pits_ord(h[n]), n);
            }
        }
    }
    q.oom |= r.oom;
    pits_rheap_free(&r);
    int oom = q.oom || pit.oom;
    pits_heap_free(&q);
    pits_fifo_free(&pit);
    pits_end(t, h, o, st);
    free(st);
    if (oom) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory in the flood queues");
    if (res) res->sinks = nsinks;
    return PG_OK;
}

pg_status pits_priority_flood_barnes2014(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                         pg_pits_result *res, pg_error *err, uint32_t *order) {
    return order ? flood(t, h, o, res, err, order, 1) : flood(t, h, o, res, err, NULL, 0);
}
