/* pg_pits_descent_breach.c - breaching (and hybrid breaching) along the descent tree
 * of the minimal epsilon-surface: a form of pit removal that does not depend on any
 * flood order, so that tiles on different MPI ranks can compute it.
 *
 * Sources: the carving is Soille's (2004, Water Resources Research 40:W12509; as in
 * Scott & Dodgson 2021 §3.2): a channel from each pit, each cell just below the
 * previous one, until the channel meets lower ground. The limits are Lindsay's (2016,
 * Hydrological Processes 30(6):846-857): channels at most max_depth deep and
 * max_length cells long, depressions that would need more are filled. The tree is
 * new: Soille's channel follows the flood tree of a global priority queue, whose
 * shape depends on the order in which the whole planet is flooded. Here every
 * non-sink cell c has the parent
 *     P(c) = the neighbour n with the smallest (W(n), id(n)),
 * W the minimal epsilon-surface (pg_pits_planchon2002_minimal_eps.c), which is
 * unique, so P is a pure function of the heights. W(P(c)) < W(c) always, so following
 * P reaches a sink: through a depression P leads by the fewest steps to its spill
 * point, outside it down the steepest neighbour of W.
 *
 * The channels: every pit - a non-sink cell without a strictly lower neighbour (and,
 * without epsilon, one the minimal fill raises: drained flats stay flat) - starts a
 * token of value h(pit). A token at cell x with value v stops when x is a
 * sink or h(x) < v (lower ground); otherwise x is lowered to min(h(x), v) and the
 * token moves on to P(x) with value nextbelow(v) (with or without epsilon, as
 * Soille's carving; epsilon only decides whether the hybrid's fill is the minimal
 * fill or the minimal epsilon-surface). Where
 * tokens meet, the lowest wins: it carves everything the others would (the same path,
 * lower values) and stops no earlier. So each cell's result is
 *     v(x) = min(h(x) if x is a pit, min over children c that pass a token of below(v(c)))
 *     B(x) = min(h(x), v(x)),  and x passes a token iff v(x) <= h(x), x not a sink,
 * which one pass over the tree, children before parents (a count of unfinished
 * children per cell), computes in linear time. Hybrid: a cell may be lowered only if
 * h(x) - v(x) <= max_depth and its channel (lowered cells from the pit) is at most
 * max_length long; otherwise the token stops there, and the minimal (epsilon-)fill of
 * the carved surface fills what no channel drained. With max_length 0 nothing is
 * carved and the result is exactly the fill.
 *
 * Why B drains (strictly): a cell not lowered and not a pit has a lower
 * neighbour, which B only lowers further; a pit, or a lowered cell, passes a token
 * below its own value to its parent, which ends below it (lowered, or lower ground
 * where the token stopped, or a sink). Every value is a function of the heights and
 * the tree alone, so the result is unique: a tiling only changes the order of the
 * pass, never its outcome.
 * Preconditions: pits_begin marked the sinks; heights are not NaN (no-data is -inf). */
#include "pg_huge.h"
#include "pg_pits_internal.h"

#include <omp.h>
#include <stdlib.h>

typedef struct descent {
    const pg_pits_topo *t;
    float *h;
    const uint8_t *st;
    float *v;          /* first W, the minimal epsilon-surface; then the incoming tokens */
    const float *fill; /* without epsilon: the minimal fill, else NULL */
    uint8_t *slot;     /* the parent: which of the cell's neighbours, and PIT (1 byte) */
    uint8_t *pending;  /* children not yet passed */
    uint32_t *len;     /* hybrid: channel length of the winning token; NULL for breach */
    double max_depth, max_length;
    int eps;
    uint64_t channels;       /* cells that start a channel (the first cell a token lowers) */
    const double *sea_level; /* NULL without a sea level */
} descent;

/* slot[] holds the parent's index among the cell's neighbours, INNER when the cell is
 * inside its face (the parent is then at a fixed offset: no division to find it), and
 * PIT for a cell that starts a token (build_tree). */
enum { INNER = 0x40, PIT = 0x80 };

static uint32_t parent_of(const descent *d, uint32_t x) {
    const uint8_t s = d->slot[x];
    if (s & INNER) return (uint32_t)((int64_t)x + pits_inner_offset(d->t, s & 7));
    uint32_t nb[8];
    pg_pits_neighbours_slow(d->t, x, nb);
    return nb[s & 7];
}

/* For a non-sink cell i at (x, y) on its face, with v holding W: P(i), the neighbour
 * with the smallest (W, id) (sinks count as -inf), into d->slot, with PIT when i starts
 * a token: it has no strictly lower neighbour nor a sink neighbour, and without epsilon
 * the minimal fill (d->fill) raises it (drained flats need nothing). Returns P(i). */
static uint32_t pick_parent(descent *d, uint32_t i, uint32_t x, uint32_t y) {
    uint32_t nb[8];
    int k = pg_pits_neighbours_xy(d->t, i, x, y, nb), best_j = 0, lower = 0;
    uint64_t best = UINT64_MAX;
    const float hi = d->h[i];
    for (int j = 0; j < k; j++) {
        int closed = d->st[nb[j]] == PITS_CLOSED;
        uint64_t key = pits_key(closed ? d->v[nb[j]] : -INFINITY, nb[j]);
        if (key < best) best = key, best_j = j;
        lower |= !closed || d->h[nb[j]] < hi;
    }
    int pit = !lower && (!d->fill || d->fill[i] > hi);
    d->slot[i] = (uint8_t)(best_j | (pit ? PIT : 0) | (pits_inner(d->t, x, y) ? INNER : 0));
    return nb[best_j];
}

/* P(c) and the children counts (v holds W); then v becomes the tokens: pits get their
 * own, the other cells none (+inf). W is not needed after the tree. Each cell's parent
 * and token depend on the heights alone, so the loops run in parallel, a row at a time
 * (the row gives each cell's place on its face); the counts are sums (at most 8 per
 * cell), the same in any order. */
static void build_tree(descent *d) {
    const pg_pits_topo *t = d->t;
    const int64_t rows = (int64_t)pits_rows(t);
    const int par = omp_get_max_threads() > 1; /* else without the atomics' cost */
#pragma omp parallel for schedule(static) if (par)
    for (int64_t row = 0; row < rows; row++) {
        const uint32_t y = (uint32_t)(row % t->h), id0 = (uint32_t)row * t->w;
        for (uint32_t x = 0; x < t->w; x++) {
            if (d->st[id0 + x] != PITS_CLOSED) continue;
            uint32_t p = pick_parent(d, id0 + x, x, y);
            if (par) {
#pragma omp atomic update
                d->pending[p]++;
            } else {
                d->pending[p]++;
            }
        }
    }
    const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n; i++)
        d->v[i] = d->st[i] == PITS_CLOSED && (d->slot[i] & PIT) ? d->h[i] : INFINITY;
}

/* x is done: carve it if its token may, and pass the token on. */
static void settle(descent *d, uint32_t x, uint32_t p) {
    float to, pass;
    uint32_t plen, lx = d->len ? d->len[x] : 0;
    if (!pits_token(d->h[x], d->v[x], lx, d->max_depth, d->max_length, &to, &pass, &plen)) return;
    if (to < d->h[x] && lx == 0) d->channels++;
    d->h[x] = to;
    if (d->st[p] != PITS_CLOSED) return; /* a sink */
    if (d->len)
        pits_token_merge(&d->v[p], &d->len[p], pass, plen);
    else if (pass < d->v[p])
        d->v[p] = pass;
}

/* Children before parents, without a queue: a scan in id order settles every cell
 * whose children are all done, then climbs from it while each parent's last child was
 * the one just settled (pending is a count, so a parent is settled exactly once, after
 * all its children). A settled cell is marked DONE, which no count reaches (at most 8
 * children). The climbs stay among neighbours and the scan is sequential, where a
 * FIFO of pending cells jumped across memory (3.4 s of a 10 s breach on the hard DEM,
 * docs/pits.md) and held up to one id per cell. */
enum { DONE = 0xff };

static void sweep(descent *d) {
    for (uint64_t i = 0; i < d->t->ncells; i++) {
        if (d->st[i] != PITS_CLOSED || d->pending[i] != 0) continue;
        uint32_t x = (uint32_t)i;
        for (;;) {
            uint32_t p = parent_of(d, x);
            settle(d, x, p);
            d->pending[x] = DONE;
            if (d->st[p] != PITS_CLOSED || --d->pending[p] != 0) break;
            x = p;
        }
    }
}

/* Hybrid: the minimal (epsilon-)fill of the carved heights, with the same sinks
 * (choosing them again could pick a carved cell as the lowest). */
static int fill_rest(descent *d, pits_heap *q, float *w) {
    uint8_t *st = (uint8_t *)d->st;
    for (uint64_t i = 0; i < d->t->ncells; i++)
        if (st[i] == PITS_CLOSED) st[i] = PITS_OPEN;
    pits_heap_free(q);
    if (d->sea_level) /* the sea level decides the sinks, as in pg_mpi_pits_fill */
        for (uint64_t i = 0; i < d->t->ncells; i++)
            if (st[i] == PITS_OPEN && d->h[i] <= *d->sea_level) st[i] = PITS_SINK;
    pits_seed(d->t, st, q);
    if (q->oom || pits_meps_compute(d->t, d->h, NULL, st, q, w, d->eps)) return -1;
    for (uint64_t i = 0; i < d->t->ncells; i++)
        if (st[i] == PITS_CLOSED) d->h[i] = w[i];
    return 0;
}

/* fill_out: NULL, or where the minimal fill of the input goes (*exact as in
 * pits_breach_descent_fill). */
static pg_status descent_run(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                             pg_pits_result *res, float *fill_out, int *exact, pg_error *err) {
    pits_heap q = {0};
    uint64_t nsinks = 0;
    uint8_t *st = NULL;
    pg_status s = pits_begin(t, h, o, &st, &q, &nsinks, err);
    if (s) return s;
    const int hybrid = o->method == PG_PITS_HYBRID;
    descent d = {.t = t,
                 .h = h,
                 .st = st,
                 .max_depth = hybrid ? o->max_depth : INFINITY,
                 .max_length = hybrid ? o->max_length : INFINITY,
                 .eps = o->epsilon,
                 .sea_level = o->has_sea_level ? &o->sea_level : NULL};
    d.v = pg_huge_malloc(t->ncells * sizeof *d.v);
    d.slot = pg_huge_malloc(t->ncells);
    d.pending = pg_huge_calloc(t->ncells, 1);
    d.len = hybrid ? pg_huge_calloc(t->ncells, sizeof *d.len) : NULL;
    float *fill = o->epsilon ? NULL
                  : fill_out ? fill_out
                             : pg_huge_malloc(t->ncells * sizeof *fill);
    int oom = !d.v || !d.slot || !d.pending || (hybrid && !d.len) || (!o->epsilon && !fill);
    if (!oom && fill) { /* the minimal fill first, then the same sinks for W */
        oom = pits_meps_compute(t, h, NULL, st, &q, fill, 0);
        for (uint64_t i = 0; i < t->ncells; i++)
            if (st[i] == PITS_CLOSED) st[i] = PITS_OPEN;
        d.fill = fill;
        if (exact) *exact = 1;
    }
    if (!oom && !fill && fill_out) /* W and, along its tree, the minimal fill (checked) */
        oom = pits_meps_compute_fill(t, h, o, st, &q, d.v, fill_out, exact);
    else if (!oom)
        oom = pits_meps_compute(t, h, fill ? NULL : o, st, &q, d.v, 1);
    if (!oom) build_tree(&d);
    if (!oom) sweep(&d);
    if (!oom && hybrid) oom = fill_rest(&d, &q, d.v);
    pits_heap_free(&q);
    if (fill != fill_out) free(fill);
    free(d.v), free(d.slot), free(d.pending), free(d.len);
    pits_end(t, h, o, st);
    free(st);
    if (oom) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for breaching");
    if (res) res->sinks = nsinks, res->breaches = d.channels;
    return PG_OK;
}

pg_status pits_breach_descent(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                              pg_pits_result *res, pg_error *err) {
    return descent_run(t, h, o, res, NULL, NULL, err);
}

pg_status pits_breach_descent_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                   pg_pits_result *res, float *fill, int *exact, pg_error *err) {
    *exact = 0;
    return descent_run(t, h, o, res, fill, exact, err);
}
