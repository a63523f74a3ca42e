/* pg_pits_lindsay2016_hybrid.c - hybrid pit removal by selective breaching.
 *
 * Source: J. B. Lindsay (2016), "Efficient hybrid breaching-filling sink removal
 * methods for flow path enforcement in digital elevation models", Hydrological
 * Processes 30(6):846-857, the selective-breaching mode; as used by Scott & Dodgson
 * 2021 §3.3 (Scott's thesis §4.1.3).
 *
 * Idea: flood from the sinks as in Priority-Flood. When the flood, coming from a cell
 * c that was itself not filled, first reaches a pit cell n (lower than c), trace
 * the channel a breach would carve: c,
 * F(c), ... each lowered to the next float below the previous one, until a cell is
 * already low enough or a sink is reached (Soille's walk, as in Scott & Dodgson
 * §3.2). If that channel is at most max_length cells long and lowers no cell more
 * than max_depth below its ORIGINAL height, carve it; otherwise fill n (raise it to
 * c) and flood the rest of the pit from it with the FIFO of Barnes et al. 2014, which
 * fills the whole depression to its spill level. Flats (n equal to c) need no
 * channel and are left alone. With epsilon, the minimal epsilon-surface
 * (pg_pits_planchon2002_minimal_eps.c) is then laid over the result, with the same
 * sinks: it gives the flats and the filled basins their ulps of slope and changes
 * nothing that already drains strictly.
 *
 * Preconditions: pits_begin seeded the queue; heights are not NaN.
 * Why it is correct: every closed cell has a path to a sink through its flow parent
 * F that never ascends: a carved channel keeps the
 * invariant because every lowered cell is put just below its predecessor on the
 * path, a filled cell is put at/above its parent, and cells whose parents are lowered
 * only gain slope. The depth test uses the original heights, so no cell ever ends
 * lower than max_depth below where it started; channels are at most max_length.
 * With max_length 0 no channel is ever carved and the result is exactly the fill.
 *
 * The minimal fill of the input comes with the flood on request (the depression
 * counts, pg_pits_remove_counted): the highest input height popped so far, at each
 * cell as it pops, as in pg_pits_soille2004_breach.c. Why it holds here too: the heap
 * keys are input heights, and the FIFO and the channels only ever queue cells at or
 * below the level already reached, which pop before any higher key; so, as in
 * Priority-Flood, a cell still open when the level reaches L has no path to a sink
 * below L, and a cell reached from c is at most c's fill or its own height. Same
 * values; the same bits but for the sign of a zero, as there. */
#include "pg_huge.h"
#include "pg_pits_internal.h"

#include <stdlib.h>

typedef struct hybrid {
    const pg_pits_topo *t;
    float *h;
    const float *orig;
    uint8_t *st;
    uint32_t *parent;
    uint8_t *filled; /* 1: raised by the fill (popped from the FIFO) */
    float *fill;     /* NULL, or the minimal fill of the input (the running maximum) */
    double max_depth, max_length;
    uint64_t breaches, fills;
} hybrid;

static int low_enough(const hybrid *s, uint32_t cur, float target) {
    return s->st[cur] != PITS_CLOSED || s->h[cur] <= target;
}

/* Can the channel from c down to below h[n] be carved within the limits? */
static int channel_fits(const hybrid *s, uint32_t c, float target) {
    double len = 0;
    for (uint32_t cur = c; !low_enough(s, cur, target); cur = s->parent[cur]) {
        target = pits_down(target);
        if (++len > s->max_length) return 0;
        if ((double)s->orig[cur] - (double)target > s->max_depth) return 0;
    }
    return 1;
}

static void carve(hybrid *s, uint32_t c, float target) {
    for (uint32_t cur = c; !low_enough(s, cur, target); cur = s->parent[cur]) {
        target = pits_down(target);
        s->h[cur] = target;
    }
}

/* Decide what to do with a newly reached cell n coming from c. */
static void visit(hybrid *s, uint32_t c, int c_filled, uint32_t n, pits_heap *q, pits_fifo *pit) {
    float hc = s->st[c] == PITS_CLOSED ? s->h[c] : -INFINITY, hn = s->h[n];
    s->st[n] = PITS_CLOSED;
    s->parent[n] = c;
    if (hn > hc || (hn == hc && !c_filled)) {
        pits_heap_push(q, pits_key(hn, n));
        return;
    }
    int in_pit = hn < pits_minf(hc, s->orig[c]);
    if (in_pit && !c_filled && channel_fits(s, c, hn)) {
        carve(s, c, hn);
        s->breaches++;
        pits_heap_push(q, pits_key(hn, n));
        return;
    }
    if (in_pit && !c_filled) s->fills++;
    /* a pit cell starts (or continues) a fill */
    s->h[n] = hc;
    s->filled[n] = (uint8_t)(c_filled || in_pit);
    pits_fifo_push(pit, n);
}

static int run(hybrid *s, pits_heap *q) {
    pits_fifo pit = {0};
    uint32_t nb[8];
    float level = -INFINITY;
    while (q->n || !pits_fifo_empty(&pit)) {
        uint32_t c = !pits_fifo_empty(&pit) ? pits_fifo_pop(&pit) : pits_key_id(pits_heap_pop(q));
        if (s->fill && s->st[c] == PITS_CLOSED) s->fill[c] = level = pits_maxf(level, s->orig[c]);
        int k = pg_pits_neighbours(s->t, c, nb);
        for (int j = 0; j < k; j++)
            if (s->st[nb[j]] == PITS_OPEN) visit(s, c, s->filled[c], nb[j], q, &pit);
        if (q->oom || pit.oom) break;
    }
    int oom = q->oom || pit.oom;
    pits_fifo_free(&pit);
    return oom ? -1 : 0;
}

/* Epsilon: the minimal epsilon-surface over the result, with the same sinks (orig
 * is free again and holds it). */
static int slope(hybrid *s, pits_heap *q, float *w) {
    for (uint64_t i = 0; i < s->t->ncells; i++)
        if (s->st[i] == PITS_CLOSED) s->st[i] = PITS_OPEN;
    pits_heap_free(q);
    pits_seed(s->t, s->st, q);
    if (q->oom || pits_meps_compute(s->t, s->h, NULL, s->st, q, w, 1)) return -1;
    for (uint64_t i = 0; i < s->t->ncells; i++)
        if (s->st[i] == PITS_CLOSED) s->h[i] = w[i];
    return 0;
}

static pg_status hybrid_run(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                            pg_pits_result *res, float *fill, pg_error *err) {
    pits_heap q = {0};
    hybrid s = {t, h, NULL, NULL, NULL, NULL, fill, o->max_depth, o->max_length, 0, 0};
    uint64_t nsinks = 0;
    pg_status st = pits_begin(t, h, o, &s.st, &q, &nsinks, err);
    if (st) return st;
    float *orig = pg_huge_malloc(t->ncells * sizeof *orig);
    s.parent = pg_huge_malloc(t->ncells * sizeof *s.parent);
    s.filled = pg_huge_calloc(t->ncells, 1);
    if (orig) memcpy(orig, h, t->ncells * sizeof *orig);
    s.orig = orig;
    if (fill) pits_fill_sinks(t, h, s.st, fill);
    if (!orig || !s.parent || !s.filled || run(&s, &q) || (o->epsilon && slope(&s, &q, orig))) {
        st = pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for hybrid on %llu cells",
                          (unsigned long long)t->ncells);
    } else if (res) {
        res->sinks = nsinks;
        res->breaches = s.breaches;
        res->fills = s.fills;
    }
    pits_heap_free(&q);
    pits_end(t, h, o, s.st);
    free(s.st);
    free(orig);
    free(s.parent);
    free(s.filled);
    return st;
}

pg_status pits_hybrid_lindsay2016(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                  pg_pits_result *res, pg_error *err) {
    return hybrid_run(t, h, o, res, NULL, err);
}

pg_status pits_hybrid_lindsay2016_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                       pg_pits_result *res, float *fill, pg_error *err) {
    return hybrid_run(t, h, o, res, fill, err);
}
