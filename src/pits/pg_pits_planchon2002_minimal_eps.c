/* pg_pits_planchon2002_minimal_eps.c - depression filling with a slope: the minimal
 * epsilon-surface, computed exactly in one flood.
 *
 * Source: O. Planchon & F. Darboux (2002), "A fast, simple and versatile algorithm to
 * fill the depressions of digital elevation models", Catena 46(2-3):159-176. Their
 * result is the lowest surface W above h on which every non-sink cell has a strictly
 * lower neighbour, with epsilon = one ulp (up = nextafterf towards +inf):
 *     W(c) = max(h(c), up(min over neighbours n of W(n)))   for every non-sink c,  (1)
 * sinks keep their height and take water at any height (they count as -inf in the
 * min). Planchon & Darboux reach it by sweeping (1) down from +inf until nothing
 * changes; this file computes it in one Dijkstra flood: W(c) is the least, over paths
 * from c to a sink, of the cost built backwards from the sink by w -> max(h, up(w)),
 * and that step never lowers w and never decreases when w grows, so cells can be
 * settled in nondecreasing W exactly as in Dijkstra's algorithm.
 *
 * Why this and not Barnes et al. 2014's epsilon variant: (1) has exactly ONE solution.
 * If W1 != W2 both solve it, take a cell c where they differ with the smallest
 * min(W1(c), W2(c)), say W1(c) < W2(c); c is not a sink; c's lowest neighbour n under
 * W1 has W1(n) < W1(c), so W2(n) = W1(n) by the choice of c, and (1) for W2 gives
 * W2(c) <= max(h(c), up(W2(n))) = W1(c): a contradiction. So any method that reaches a
 * fixed point of (1) produces the same bits - this flood on one process, or ranks
 * that flood their own tiles and exchange the ring around them until nothing changes
 * (src/mpi/pg_mpi_pits_planchon2002_eps.c). Barnes's epsilon flood also drains every
 * cell, but its FIFO settles a flat from the first rim cell it reaches, so its ulps
 * follow the flood order: a tile decomposition cannot reproduce them.
 * The same argument shows that W does not change when h is replaced by any surface F
 * with h <= F <= W, e.g. the minimal (plain) fill: the distributed version uses that.
 *
 * Preconditions: pits_begin marked the sinks and queued those touching non-sinks.
 * Speed: cells that already drain strictly keep their height and are closed by a
 * linear search first; only flats and depressions go through the flood.
 * Why it is correct: Dijkstra's invariant (a popped cell's value is final) holds for
 * monotone path costs that never decrease along a path; (1) is that cost. */
#include "pg_huge.h"
#include "pg_pits_internal.h"

#include <omp.h>
#include <stdlib.h>

/* Cells set to exactly up(w) of the cell being settled go to a FIFO instead of the
 * heap (Barnes et al. 2014's "improved" trick, which makes flats linear): the settled
 * values never decrease, so the FIFO is sorted, and no later cell can offer less than
 * up(w), so its cells' values are final. Merging it with the heap by height keeps the
 * Dijkstra order; the heap is a monotone radix heap (pg_pits_internal.h), since the
 * result is unique and so does not depend on the order of equal heights.
 * With the state array (by_state, one process): the settled values never decrease, so
 * neither does any cell's offer max(floor, up), and a cell's first offer is its final
 * value unless it was a source with a lower one. So a cell is closed when first
 * reached, as in Barnes's fill, and later neighbours skip it on a one-byte load of its
 * state instead of a four-byte load of its value (the flats of an integer DEM are
 * most of its cells; their BFS front's reads are what the flood waits on). Without it
 * (the distributed flood's settable cells, whose sources come back round the ring), a
 * neighbour is looked at only when its value exceeds up (else nothing can lower it). */
/* How far ahead in the FIFO, or in the heap's bucket of the current height, the rows
 * of a cell to be settled are fetched: the reads of its neighbours' states, floors and
 * values are what the flood waits on (docs/pits.md, "Hard DEM"). */
enum { AHEAD = 32 };

static inline void fetch_rows(const pits_meps *m, const uint8_t *st, const float *w, uint32_t f) {
    const uint32_t tw = m->t->w;
    const uint32_t a = f >= tw ? f - tw : f, b = f + tw < m->t->ncells ? f + tw : f;
    __builtin_prefetch(&st[a]), __builtin_prefetch(&st[f]), __builtin_prefetch(&st[b]);
    __builtin_prefetch(&m->floor[a]), __builtin_prefetch(&m->floor[b]);
    __builtin_prefetch(&w[a]), __builtin_prefetch(&w[b]);
}

static inline int meps_flood(pits_meps *m, pits_heap *q, const int by_state, float *fill) {
    pits_fifo fifo = {0};
    pits_rheap r = {0};
    uint32_t nb[8];
    float *w = m->w;
    const float *floor_ = m->floor;
    uint8_t *st = m->st;
    for (size_t i = 0; i < q->n && !r.oom; i++)
        pits_rheap_push(&r, (uint32_t)(q->a[i] >> 32), pits_key_id(q->a[i]));
    int seed_oom = q->oom;
    pits_heap_free(q); /* the sources now live in r: not both at once */
    q->oom = seed_oom;
    while ((r.size || !pits_fifo_empty(&fifo)) && !r.oom && !fifo.oom) {
        uint32_t c, kord;
        if (!pits_fifo_empty(&fifo) &&
            (!r.size || pits_ord(w[fifo.a[fifo.head]]) <= pits_rheap_top_key(&r))) {
            c = pits_fifo_pop(&fifo);
            kord = pits_ord(w[c]);
            if (by_state && fifo.head + AHEAD < fifo.tail)
                fetch_rows(m, st, w, fifo.a[fifo.head + AHEAD]);
        } else {
            uint64_t e = pits_rheap_pop(&r);
            if (r.oom) break;
            if (by_state && r.n[0] > AHEAD) /* bucket 0 pops from its end */
                fetch_rows(m, st, w, pits_key_id(r.b[0][r.n[0] - AHEAD]));
            c = pits_key_id(e);
            kord = (uint32_t)(e >> 32);
            if (by_state ? st[c] == PITS_DONE /* a source's first value, since lowered */
                         : m->settable(m->ctx, c) && kord != pits_ord(w[c]))
                continue; /* superseded by a lower value */
        }
        if (by_state) st[c] = PITS_DONE;
        float hk = pits_key_height((uint64_t)kord << 32);
        float up = m->plain ? hk : pits_up(hk); /* -inf: -FLT_MAX */
        float fc = fill ? fill[c] : 0;
        int k = pg_pits_neighbours(m->t, c, nb);
        for (int j = 0; j < k; j++) {
            const uint32_t n = nb[j];
            float cand;
            if (by_state) {
                const uint8_t sn = st[n];
                if (sn != PITS_OPEN && sn != PITS_SOURCE) continue; /* set, or never to be */
                st[n] = PITS_CLOSED;                                /* this offer is final... */
                cand = pits_maxf(floor_[n], up);
                if (sn == PITS_SOURCE && !(cand < w[n])) continue; /* ...unless its own is lower */
            } else {
                const float wn = w[n];
                if (!(wn > up)) continue; /* max(floor, up) >= up >= w[n]: no gain */
                if (!m->settable(m->ctx, n)) continue;
                cand = pits_maxf(floor_[n], up);
                if (!(cand < wn)) continue;
            }
            w[n] = cand;
            if (fill) fill[n] = pits_maxf(floor_[n], fc);
            if (cand == up)
                pits_fifo_push(&fifo, n);
            else
                pits_rheap_push(&r, pits_ord(cand), n);
        }
    }
    int oom = r.oom || fifo.oom;
    pits_fifo_free(&fifo);
    pits_rheap_free(&r);
    return oom ? -1 : 0;
}

int pits_meps_flood(pits_meps *m, pits_heap *q) {
    if (m->settable) return meps_flood(m, q, 0, NULL);
    return m->fill ? meps_flood(m, q, 1, m->fill) : meps_flood(m, q, 1, NULL);
}

/* Step 1, linear: a cell with a strictly descending path to a sink keeps its height
 * (W(c) = h(c) by induction along the path, since up(h(next)) <= h(c)). A search
 * from the sinks up strictly rising steps closes those cells - most of a DEM. */
static int close_drained(const pg_pits_topo *t, const float *h, uint8_t *st, const pits_heap *q) {
    pits_fifo f = {0};
    uint32_t nb[8];
    for (size_t i = 0; i < q->n; i++)
        pits_fifo_push(&f, pits_key_id(q->a[i]));
    while (!pits_fifo_empty(&f) && !f.oom) {
        uint32_t d = pits_fifo_pop(&f);
        float hd = st[d] == PITS_CLOSED ? h[d] : -INFINITY;
        int k = pg_pits_neighbours(t, d, nb);
        for (int j = 0; j < k; j++)
            if (st[nb[j]] == PITS_OPEN && h[nb[j]] > hd) {
                st[nb[j]] = PITS_CLOSED;
                pits_fifo_push(&f, nb[j]);
            }
    }
    int oom = f.oom;
    pits_fifo_free(&f);
    return oom;
}

/* Step 2: the flood over the rest (flats and depressions), seeded from its border. */
static int flood_rest(const pg_pits_topo *t, const float *h, uint8_t *st, float *w, int eps,
                      float *fill) {
    pits_heap q = {0};
    uint32_t nb[8];
    const uint64_t rows = pits_rows(t); /* a row at a time: no division */
    for (uint64_t row = 0; row < rows; row++)
        for (uint32_t x = 0, y = (uint32_t)(row % t->h); x < t->w; x++) {
            const uint32_t i = (uint32_t)(row * t->w) + x;
            w[i] = h[i];
            if (fill) fill[i] = h[i]; /* drained cells and sinks: their own height */
            if (st[i] != PITS_OPEN) continue;
            w[i] = INFINITY;
            int k = pg_pits_neighbours_xy(t, i, x, y, nb);
            for (int j = 0; j < k; j++)
                if (st[nb[j]] != PITS_OPEN) {
                    float v = st[nb[j]] == PITS_CLOSED ? h[nb[j]] : -INFINITY;
                    float cand = pits_maxf(h[i], eps ? pits_up(v) : v);
                    if (cand < w[i] && fill) fill[i] = pits_maxf(h[i], v);
                    w[i] = pits_minf(w[i], cand);
                }
            /* pits_meps_flood takes its sources in any order: no heap order needed */
            if (w[i] < INFINITY && (q.n < q.cap || (pits_heap_grow(&q), !q.oom)))
                q.a[q.n++] = pits_key(w[i], i);
        }
    for (size_t i = 0; i < q.n; i++) /* after the loop, which asks which cells are open */
        st[pits_key_id(q.a[i])] = PITS_SOURCE;
    pits_meps m = {t, w, h, NULL, NULL, !eps, fill, st};
    int oom = q.oom || pits_meps_flood(&m, &q);
    pits_heap_free(&q);
    return oom;
}

/* W on several threads: the minimal fill F in parallel tiles (Barnes 2016), then W
 * from F's flats (pits_meps_from_fill, its search shared among the threads and its
 * result checked against (1)). W is the one solution of (1), so it is the flood's W
 * bit for bit; only the time differs (the hard DEM, docs/pits.md: the flood is
 * serial). For st fresh from pits_begin (sinks marked, nothing closed) on an input h
 * without no-data (pits_begin would have made those cells -inf, which the fill's own
 * start cannot tell from heights); F's sinks are h's: a sink keeps its height and
 * every other cell only rises. Into fill (the minimal fill, wanted by the counts) when
 * not NULL. Returns 0 when w holds W; nonzero when it fails (the caller floods). */
static int by_fill(const pg_pits_topo *t, const float *h, const pg_pits_opts *o, uint8_t *st,
                   float *w, float *fill) {
    float *f = fill ? fill : pg_huge_malloc(t->ncells * sizeof *f);
    if (!f) return -1;
    memcpy(f, h, t->ncells * sizeof *f);
    pg_pits_opts fo = *o;
    fo.method = PG_PITS_FILL;
    fo.epsilon = 0;
    pg_error err = {0};
    int bad = pits_parallel_fill_barnes2016(t, f, &fo, NULL, &err) != PG_OK ||
              pits_meps_from_fill(t, f, st, w) != 0;
    if (!fill) free(f);
    return bad ? -1 : 0;
}

/* Whether W is worth computing by way of the fill (by_fill) rather than by the flood:
 * on three threads or more where the plain fill would run in tiles, when more than half
 * of the cells are left for the flood after the drained ones are closed (a DEM of
 * integer heights, whose flats and depressions are most of it; on a planet the ocean is
 * sinks and most land drains, and the flood is the quicker). On two threads the serial
 * flood, closing cells on first reach, is as fast as the tiled fill and the search over
 * its flats on two (the hard DEM, docs/pits.md); with more threads those scale and the
 * flood does not, which this machine of two cores cannot measure. */
static int fill_pays(const pg_pits_topo *t, const pg_pits_opts *o, const uint8_t *st) {
    if (!o || o->has_nodata || omp_get_max_threads() < 3 || !pits_tiled_fill(t, o)) return 0;
    const int64_t n = (int64_t)t->ncells;
    int64_t open = 0;
#pragma omp parallel for reduction(+ : open) schedule(static)
    for (int64_t i = 0; i < n; i++)
        open += st[i] == PITS_OPEN;
    return 2 * open > n;
}

static void reopen(const pg_pits_topo *t, uint8_t *st) {
    const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n; i++)
        if (st[i] == PITS_CLOSED) st[i] = PITS_OPEN;
}

static int meps_compute(const pg_pits_topo *t, const float *h, const pg_pits_opts *o, uint8_t *st,
                        const pits_heap *q, float *w, int eps, float *fill) {
    if (close_drained(t, h, st, q)) return -1;
    int done = 0; /* w holds W */
    if (eps && fill_pays(t, o, st)) {
        reopen(t, st); /* as pits_begin left it */
        done = by_fill(t, h, o, st, w, fill) == 0;
        if (!done && close_drained(t, h, st, q)) return -1;
    }
    if (!done && flood_rest(t, h, st, w, eps, fill)) return -1;
    const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n; i++)
        if (st[i] == PITS_OPEN || st[i] >= PITS_SOURCE) st[i] = PITS_CLOSED;
    return 0;
}

int pits_meps_compute(const pg_pits_topo *t, const float *h, const pg_pits_opts *o, uint8_t *st,
                      const pits_heap *q, float *w, int eps) {
    return meps_compute(t, h, o, st, q, w, eps, NULL);
}

/* The epsilon-surface from the minimal fill f, without a flood, for the depression
 * counts of a plain fill (pg_pits_remove_counted). On f every cell drains without
 * ascending, so W on a flat of f (connected cells of one height s) is, in the usual
 * case, s at the flat's exits (cells with a lower neighbour or a sink neighbour) and
 * one ulp more per step away from them: a breadth-first search from the exits.
 * That is a guess when heights differ by only a few ulps (a neighbouring flat's ulps
 * may then reach s), so it is checked: W must satisfy (1) with floor f at every cell,
 * in one parallel pass. (1) has exactly one solution, and it is the same for the floor
 * h and for any floor between h and W (the file's opening comment), so a W that
 * passes is the epsilon-surface of the fill's input, bit for bit. Returns 0 then;
 * nonzero when the check fails or memory runs out (the caller then floods). */
static uint32_t bits_of(float v) {
    uint32_t u;
    memcpy(&u, &v, 4);
    return u;
}

/* w's cells, read and written by several threads: a cell the search reaches from two
 * cells of one level gets the same value from both (below), so the races are benign;
 * relaxed atomics make them defined. */
static inline float load_w(const float *w) {
    float v;
    __atomic_load(w, &v, __ATOMIC_RELAXED);
    return v;
}

static inline void store_w(float *w, float v) {
    __atomic_store(w, &v, __ATOMIC_RELAXED);
}

/* Expands cell c of a level into its unreached neighbours, which get up and join the
 * thread's list for the next level. */
static inline void expand(const pg_pits_topo *t, float *w, uint32_t c, pits_fifo *next) {
    uint32_t nb[8];
    float up = pits_up(load_w(&w[c]));
    int k = pg_pits_neighbours(t, c, nb);
    for (int j = 0; j < k; j++)
        if (load_w(&w[nb[j]]) == INFINITY) {
            store_w(&w[nb[j]], up);
            pits_fifo_push(next, nb[j]);
        }
}

/* The flats' cells by breadth-first search from their exits (w == f), a level at a
 * time, each level's cells shared among the threads. The exits give their flats' cells
 * next to them one ulp; the search goes on from those, which are not exits: such a
 * cell has no lower neighbour, and an unreached neighbour (not an exit either) none
 * lower than it, so the two are level and the search reads only w. A cell first
 * reached at level L (its distance from its flat's exits) gets up applied L times to
 * its flat's height, whichever cell of level L - 1 reaches it: so the values do not
 * depend on the thread count, and pits_meps_check verifies them anyway. A level is
 * each thread's list of the cells it reached; small levels run on one thread.
 * Returns nonzero when out of memory. */
static int flat_search(const pg_pits_topo *t, const float *f, const uint8_t *st, float *w) {
    const int64_t n = (int64_t)t->ncells;
    const int nt = omp_get_max_threads();
    pits_fifo *lv = calloc(2 * (size_t)nt, sizeof *lv); /* two levels of nt lists */
    if (!lv) return -1;
#pragma omp parallel num_threads(nt)
    {
        pits_fifo *my = &lv[omp_get_thread_num()];
        uint32_t nb[8];
#pragma omp for schedule(static)
        for (int64_t i = 0; i < n; i++) {
            if (st[i] != PITS_OPEN || load_w(&w[i]) != f[i]) continue;
            float up = pits_up(f[i]);
            int k = pg_pits_neighbours(t, (uint32_t)i, nb);
            for (int j = 0; j < k; j++)
                if (load_w(&w[nb[j]]) == INFINITY && f[nb[j]] == f[i]) {
                    store_w(&w[nb[j]], up);
                    pits_fifo_push(my, nb[j]);
                }
        }
    }
    int oom = 0;
    for (int level = 0;; level ^= 1) {
        pits_fifo *cur = lv + level * nt, *next = lv + (level ^ 1) * nt;
        size_t m = 0;
        for (int i = 0; i < nt; i++)
            m += cur[i].tail, oom |= cur[i].oom;
        if (oom || !m) break;
#pragma omp parallel num_threads(nt) if (m >= 4096)
        {
            pits_fifo *my = &next[omp_get_thread_num()];
            for (int i = 0; i < nt; i++) {
                const int64_t ni = (int64_t)cur[i].tail;
#pragma omp for schedule(static) nowait
                for (int64_t k = 0; k < ni; k++)
                    expand(t, w, cur[i].a[k], my);
            }
        }
        for (int i = 0; i < nt; i++)
            cur[i].head = cur[i].tail = 0;
    }
    for (int i = 0; i < 2 * nt; i++)
        pits_fifo_free(&lv[i]);
    free(lv);
    return oom;
}

int pits_meps_from_fill(const pg_pits_topo *t, const float *f, const uint8_t *st, float *w) {
    const int64_t n = (int64_t)t->ncells;
    int64_t bad = 0;
#pragma omp parallel for reduction(+ : bad) schedule(static)
    for (int64_t i = 0; i < n; i++) {
        if (st[i] != PITS_OPEN) {
            w[i] = f[i];
            continue;
        }
        uint32_t nb[8];
        int k = pg_pits_neighbours(t, (uint32_t)i, nb), exit = 0;
        for (int j = 0; j < k; j++)
            exit |= st[nb[j]] != PITS_OPEN || f[nb[j]] < f[i];
        w[i] = exit ? f[i] : INFINITY; /* +inf: not reached yet */
        bad += f[i] == INFINITY;       /* would look unreached */
    }
    if (bad) return -1;
    return flat_search(t, f, st, w) ? -1 : pits_meps_check(t, f, st, w) ? -1 : 0;
}

int pits_meps_check(const pg_pits_topo *t, const float *f, const uint8_t *st, float *w) {
    const int64_t n = (int64_t)t->ncells;
    int64_t bad = 0;
#pragma omp parallel for reduction(+ : bad) schedule(static)
    for (int64_t i = 0; i < n; i++) {
        if (st[i] >= PITS_SINK) { /* not read below: sinks count as -inf */
            w[i] = f[i];
            continue;
        }
        uint32_t nb[8];
        int k = pg_pits_neighbours(t, (uint32_t)i, nb);
        float m = INFINITY;
        for (int j = 0; j < k; j++)
            m = pits_minf(m, st[nb[j]] >= PITS_SINK ? -INFINITY : w[nb[j]]);
        bad += bits_of(w[i]) != bits_of(pits_maxf(f[i], pits_up(m)));
    }
    return bad != 0;
}

/* The minimal fill along the flood's tree: a set cell takes max(h, the fill of the cell
 * that set it), a drained cell or a sink its own height, so each value is the highest
 * ground on one path to a sink, never below the minimal fill f. It is f exactly when it
 * solves f(c) = max(h(c), min over neighbours f(n)) at every cell of the flood (sinks
 * count as -inf): f is the LARGEST solution. For if some solution F had F(c) > f(c),
 * take the next cell n on c's path to a sink whose highest ground is f(c): n is not a
 * sink (F(c) would be h(c) <= f(c)), F(n) >= F(c) since F(c) > h(c), and f(n) <= f(c),
 * so n has F(n) > f(n) as well, and so on down to the sink: a contradiction. 0 when it
 * holds. Parallel, linear. fill_rhs is the right side at cell i. */
static inline float fill_rhs(const pg_pits_topo *t, const float *h, const uint8_t *st,
                             const float *fill, int64_t i) {
    uint32_t nb[8];
    int k = pg_pits_neighbours(t, (uint32_t)i, nb);
    float m = INFINITY;
    for (int j = 0; j < k; j++)
        m = pits_minf(m, st[nb[j]] >= PITS_SINK ? -INFINITY : fill[nb[j]]);
    return pits_maxf(h[i], m);
}

static int fill_check(const pg_pits_topo *t, const float *h, const uint8_t *st, const float *fill) {
    const int64_t n = (int64_t)t->ncells;
    int64_t bad = 0;
#pragma omp parallel for reduction(+ : bad) schedule(static)
    for (int64_t i = 0; i < n; i++)
        if (st[i] < PITS_SINK) bad += bits_of(fill[i]) != bits_of(fill_rhs(t, h, st, fill, i));
    return bad != 0;
}

/* Checks the tree's fill as fill_check does and, where it fails, lowers it to the minimal
 * fill f. The tree of W (1) and the minimal fill's paths part where two spills of a depression
 * differ by less than the epsilon ramp to them: W drains a cell over the nearer spill, f over the
 * lower one. That is a handful of cells in millions (4 to 35 on the default planets), so instead of
 * a second fill of the whole surface (docs/pits.md, "Metrics") a Dijkstra search lowers only them:
 * the tree's fill F is a supersolution of f's equation, F(c) = max(h(c), F(parent)) >= max(h(c),
 * min over neighbours F(n)), with F >= f (each F(c) is the highest ground on a real path). The
 * search starts from the cells where F exceeds its own equation's right side and sets each cell at
 * most once, in nondecreasing value (an offer max(h, v) is never below the value v it came from),
 * to the least path value it can reach; when it stops, F solves the equation everywhere and is
 * still a path value at every cell, so F <= f (f is the largest solution) and F >= f: F = f,
 * whatever the order of the search. Returns 0 when F is f (at once when the first scan finds every
 * cell equal to its right side; after a search, checked again by fill_check); -1 when some cell
 * lies below its right side (not a supersolution: the caller falls back to a fill of its own) or
 * memory ran out. Serial after one parallel scan. The argument holds for the fill along any tree
 * towards the sinks, not only W's (test_pits_grid checks random trees). */
int pits_fill_repair(const pg_pits_topo *t, const float *h, const uint8_t *st, float *fill) {
    const int64_t n = (int64_t)t->ncells;
    pits_heap q = {0};
    int64_t below = 0;
#pragma omp parallel for reduction(+ : below) schedule(static)
    for (int64_t i = 0; i < n; i++) {
        if (st[i] >= PITS_SINK) continue;
        const float want = fill_rhs(t, h, st, fill, i);
        if (want < fill[i]) {
#pragma omp critical(pits_fill_repair)
            pits_heap_push(&q, pits_key(want, (uint32_t)i));
        } else if (bits_of(want) != bits_of(fill[i])) {
            below++;
        }
    }
    /* nothing above its right side and nothing below: the scan was fill_check's pass,
     * and it held (the common case: no second pass over the planet) */
    if (!below && !q.oom && !q.n) return 0;
    while (!below && !q.oom && q.n) {
        const uint64_t key = pits_heap_pop(&q);
        const uint32_t c = pits_key_id(key);
        const float v = pits_key_height(key);
        if (!(v < fill[c])) continue; /* set already, as low or lower */
        fill[c] = v;
        uint32_t nb[8];
        int k = pg_pits_neighbours(t, c, nb);
        for (int j = 0; j < k; j++) {
            if (st[nb[j]] >= PITS_SINK) continue;
            const float cand = pits_maxf(h[nb[j]], v);
            if (cand < fill[nb[j]]) pits_heap_push(&q, pits_key(cand, nb[j]));
        }
    }
    const int failed = below || q.oom;
    pits_heap_free(&q);
    return failed || fill_check(t, h, st, fill) ? -1 : 0;
}

/* The tree's fill checked, and repaired where the check fails (pits_fill_repair's scan
 * is the check): 1 when fill is the minimal fill of h. */
static int fill_exact(const pg_pits_topo *t, const float *h, const uint8_t *st, float *fill) {
    return !pits_fill_repair(t, h, st, fill);
}

/* floor: NULL, or a copy of h that stays the input, so that the surface goes straight
 * into h instead of a buffer of its own (the counted removal has that copy anyway). */
static pg_status eps_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                          pg_pits_result *res, const float *floor, float *fill, int *exact,
                          pg_error *err) {
    pits_heap q = {0};
    uint8_t *st = NULL;
    uint64_t nsinks = 0;
    pg_status s = pits_begin(t, h, o, &st, &q, &nsinks, err);
    if (s) return s;
    const float *in = floor ? floor : h; /* no-data cells are not read: sinks */
    float *w = floor ? h : pg_huge_malloc(t->ncells * sizeof *w);
    int oom = !w || meps_compute(t, in, o, st, &q, w, 1, fill);
    if (!oom && fill) *exact = fill_exact(t, in, st, fill);
    for (uint64_t i = 0; !oom && !floor && i < t->ncells; i++)
        if (st[i] == PITS_CLOSED) h[i] = w[i];
    pits_heap_free(&q);
    pits_end(t, h, o, st);
    free(st);
    if (!floor) free(w);
    if (oom) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory in the flood queues");
    if (res) res->sinks = nsinks;
    return PG_OK;
}

pg_status pits_minimal_eps_planchon2002(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                        pg_pits_result *res, pg_error *err) {
    return eps_fill(t, h, o, res, NULL, NULL, NULL, err);
}

pg_status pits_minimal_eps_planchon2002_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                             pg_pits_result *res, const float *in, float *fill,
                                             int *exact, pg_error *err) {
    *exact = 0;
    return eps_fill(t, h, o, res, in, fill, exact, err);
}

int pits_meps_compute_fill(const pg_pits_topo *t, const float *h, const pg_pits_opts *o,
                           uint8_t *st, const pits_heap *q, float *w, float *fill, int *exact) {
    *exact = 0;
    if (meps_compute(t, h, o, st, q, w, 1, fill)) return -1;
    *exact = fill_exact(t, h, st, fill);
    return 0;
}
