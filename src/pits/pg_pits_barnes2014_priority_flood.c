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
 * the front is a monotone radix heap on the heights alone (pg_pits_internal.h). */
#include "pg_pits_internal.h"

#include <stdlib.h>

/* The flood. With w (the counted fill), each level's heap cells go before its FIFO
 * cells, and w gets the breadth-first distance along the fill's flats in ulps:
 * - Every cell popped from the heap at level s is an exit of its flat (a cell of f = s
 *   with a lower neighbour or a sink neighbour): the cell that pushed it was a sink or
 *   lower. Conversely every exit is in the heap when level s begins: its lower
 *   neighbour was taken before any cell of value s (the heap pops in height order,
 *   and a level's FIFO drains before the next key), and the sinks go first (key
 *   -inf), so it was pushed from there, with key h = s.
 * - So the cells that reach the FIFO are exactly the flat cells that are not exits,
 *   and taking all of a level's exits first makes the FIFO a breadth-first search from
 *   all of them at once: w = s one ulp up per step from the nearest exit, the guess of
 *   pits_meps_from_fill, which pits_meps_check then verifies.
 * The heap's entries of the current level are those of its last key
 * (pits_rheap_level_left); peeking at its next key would break its invariant. Without w
 * the FIFO goes first (Barnes et al.'s order); the fill is the same. */
static inline int flood(const pg_pits_topo *t, float *h, uint8_t *st, pits_rheap *r, pits_fifo *pit,
                        float *w) {
    uint32_t nb[8];
    while ((r->size || !pits_fifo_empty(pit)) && !r->oom && !pit->oom) {
        uint32_t c;
        if (!pits_fifo_empty(pit) && (!w || !pits_rheap_level_left(r))) {
            c = pits_fifo_pop(pit);
        } else {
            uint64_t e = pits_rheap_pop(r);
            if (r->oom) break;
            c = pits_key_id(e);
        }
        float hc = st[c] == PITS_CLOSED ? h[c] : -INFINITY; /* sinks: outlets */
        float up = w && st[c] == PITS_CLOSED ? pits_up(w[c]) : 0;
        int k = pg_pits_neighbours(t, c, nb);
        for (int j = 0; j < k; j++) {
            uint32_t n = nb[j];
            if (st[n] != PITS_OPEN) continue;
            st[n] = PITS_CLOSED;
            if (h[n] <= hc) {
                h[n] = hc;
                if (w) w[n] = up;
                pits_fifo_push(pit, n);
            } else {
                if (w) w[n] = h[n];
                pits_rheap_push(r, pits_ord(h[n]), n);
            }
        }
    }
    return r->oom || pit->oom;
}

static pg_status fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o, pg_pits_result *res,
                      float *w, int *exact, pg_error *err) {
    pits_heap q = {0};
    pits_fifo pit = {0};
    uint8_t *st = NULL;
    uint64_t nsinks = 0;
    pg_status s = pits_begin(t, h, o, &st, &q, &nsinks, err);
    if (s) return s;
    /* the sinks (key -inf), then the front, in a radix heap: the minimal fill is
     * unique, so the order of equal heights does not matter (pg_pits_internal.h) */
    pits_rheap r = {0};
    for (size_t i = 0; i < q.n; i++)
        pits_rheap_push(&r, (uint32_t)(q.a[i] >> 32), pits_key_id(q.a[i]));
    pits_heap_free(&q); /* the sinks now live in r */
    int oom = q.oom || (w ? flood(t, h, st, &r, &pit, w) : flood(t, h, st, &r, &pit, NULL));
    pits_rheap_free(&r);
    pits_fifo_free(&pit);
    if (!oom && w) *exact = !pits_meps_check(t, h, st, w);
    pits_end(t, h, o, st);
    free(st);
    if (oom) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory in the flood queues");
    if (res) res->sinks = nsinks;
    return PG_OK;
}

pg_status pits_priority_flood_barnes2014(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                         pg_pits_result *res, pg_error *err) {
    return fill(t, h, o, res, NULL, NULL, err);
}

pg_status pits_priority_flood_barnes2014_eps(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                             pg_pits_result *res, float *w, int *exact,
                                             pg_error *err) {
    *exact = 0;
    return fill(t, h, o, res, w, exact, err);
}
