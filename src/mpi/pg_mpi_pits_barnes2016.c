/* pg_mpi_pits_barnes2016.c - distributed depression filling on the cube sphere.
 *
 * Source: R. Barnes (2016), "Flexibly distributed Priority-Flood depression filling
 * for teracell DEMs" (arXiv:1608.04431; Computers & Geosciences 96). Its four steps,
 * with the ranks of pg_mpi.h owning cube tiles:
 *   1. each rank floods each of its tiles alone (Improved Priority-Flood, Barnes et al.
 *      2014), seeded with the tile's sinks (label OUTLET) and with every perimeter cell
 *      (a cell with a neighbour in another tile) under its own label 2 + cell id;
 *      every cell joins the label it was flooded from;
 *   2. it builds the graph of spill elevations over those labels: where two labels
 *      meet inside a tile, max(W(a), W(b)); for every pair of neighbouring cells in two
 *      tiles, max(h(a), h(b)) (sinks count as -inf) - the neighbour's height comes from
 *      a one-cell ring exchange, its label is known without asking (2 + id, or OUTLET);
 *   3. rank 0 gathers the (small: perimeter-sized) graph and solves it: a minimax
 *      Dijkstra from OUTLET gives each label the lowest level at which its water
 *      reaches a sink;
 *   4. rank 0 broadcasts the levels, and every rank raises its cells to the level of
 *      their label: h = max(h, level(label)).
 * Preconditions: plain fill (no epsilon), sinks = cells at or below the sea level (no
 * lakes, no no-data), at least one sink on the planet (the serial fill would otherwise
 * pick the lowest cell, a global choice). Why it is correct: as the in-process version
 * (pg_pits_barnes2016_parallel_fill.c): the minimal fill of a cell is the minimax
 * height of its paths to a sink; inside a tile the flood gives the minimax to its
 * label's seed, and the graph composes the segments exactly. The minimal fill is
 * unique, so every owned cell comes out bit-identical to pg_pits_remove's plain fill
 * (the test compares them for 1, 2 and 4 ranks).
 * With epsilon: the minimal epsilon-surface W (pg_pits_planchon2002_minimal_eps.c) is
 * the unique solution of W(c) = max(F(c), up(min over neighbours W(n))) with F the
 * plain fill just computed. Each round, every rank floods its own cells from the ring
 * and its sinks with that equation (a Dijkstra flood; ring cells are fixed sources),
 * then receives the ring's new values. The ring starts at +inf (no known way out):
 * every value is then the cost of a real path, an upper bound of W that only falls,
 * and a way out reaches a cell after as many rounds as its best path crosses rank
 * boundaries; when no rank's cells change, every cell satisfies the equation, whose
 * only solution is W. (Starting from F, a lower bound, also converges, but a flat on
 * a boundary then climbs by one ulp per round on both sides: 74 rounds on the default
 * planet instead of a handful.) */
#include "planetgen/pg_mpi.h"

#include "pg_pits_internal.h"

#include <stdlib.h>

#ifdef PG_HAVE_MPI

#include <limits.h>
#include <mpi.h>

enum { OUTLET = 1 };

typedef struct fedge {
    uint32_t a, b;
    float w;
} fedge;

typedef struct fedges {
    fedge *e;
    size_t n, cap;
    int oom;
} fedges;

static void fedge_push(fedges *v, uint32_t a, uint32_t b, float w) {
    if (a == b) return;
    if (v->n == v->cap) {
        size_t cap = v->cap ? 2 * v->cap : 4096;
        fedge *e = realloc(v->e, cap * sizeof *e);
        if (!e) {
            v->oom = 1;
            return;
        }
        v->e = e, v->cap = cap;
    }
    if (a > b) {
        uint32_t t = a;
        a = b, b = t;
    }
    v->e[v->n++] = (fedge){a, b, w};
}

static int cmp_fedge(const void *x, const void *y) {
    const fedge *a = x, *b = y;
    if (a->a != b->a) return a->a < b->a ? -1 : 1;
    if (a->b != b->b) return a->b < b->b ? -1 : 1;
    return a->w < b->w ? -1 : a->w > b->w;
}

/* Keep the lowest spill height of each label pair: the graph's answer is the same. */
static void fedge_compact(fedges *v) {
    if (!v->n) return;
    qsort(v->e, v->n, sizeof *v->e, cmp_fedge);
    size_t k = 1;
    for (size_t i = 1; i < v->n; i++)
        if (v->e[i].a != v->e[k - 1].a || v->e[i].b != v->e[k - 1].b) v->e[k++] = v->e[i];
    v->n = k;
}

typedef struct dfill {
    pg_mpi *m;
    const pg_pits_topo *t;
    int T;
    uint32_t n, ts;
    float *h;
    double sea;
    uint32_t *label;
    int ln, lts; /* log2 of n and ts when both are powers of two, else -1 */
} dfill;

/* The tile of a cell: called for every neighbour of every cell, so shifts when the
 * sizes allow (divisions took a third of the distributed fill's time). */
static int tile_of(const dfill *d, uint32_t id) {
    uint32_t T = (uint32_t)d->T;
    if (d->ln >= 0) {
        uint32_t f = id >> (2 * d->ln), y = (id >> d->ln) & (d->n - 1), x = id & (d->n - 1);
        return (int)(f * T * T + (y >> d->lts) * T + (x >> d->lts));
    }
    uint32_t per = d->n * d->n, f = id / per, y = id % per / d->n, x = id % d->n;
    return (int)(f * T * T + y / d->ts * T + x / d->ts);
}

static int log2_exact(uint32_t v) {
    int l = 0;
    while ((1u << l) < v)
        l++;
    return (1u << l) == v ? l : -1;
}

static uint32_t tile_cell(const dfill *d, int t, uint32_t x, uint32_t y) {
    uint32_t T = (uint32_t)d->T, f = (uint32_t)t / (T * T), tx = (uint32_t)t % T,
             ty = (uint32_t)t / T % T;
    return f * d->n * d->n + (ty * d->ts + y) * d->n + tx * d->ts + x;
}

/* Every cell id of the tiles [t0, t1): tile by tile, row by row. */
#define FOR_TILE_CELLS(d, t0, t1, id)                                                              \
    for (int t_ = (t0); t_ < (t1); t_++)                                                           \
        for (uint32_t y_ = 0; y_ < (d)->ts; y_++)                                                  \
            for (uint32_t x_ = 0, id = tile_cell((d), t_, 0, y_); x_ < (d)->ts;                    \
                 x_++, id = tile_cell((d), t_, x_, y_))

static bool sink(const dfill *d, uint32_t id) {
    return d->h[id] <= d->sea;
}

static float eff(const dfill *d, uint32_t id) {
    return sink(d, id) ? -INFINITY : d->h[id];
}

/* The label a perimeter cell has after step 1, known to every rank. */
static uint32_t perimeter_label(const dfill *d, uint32_t id) {
    return sink(d, id) ? OUTLET : 2 + id;
}

/* ---- the ring of heights around a rank's tiles ---- */

typedef struct ids {
    uint32_t *a;
    size_t n, cap;
    int oom;
} ids;

static void ids_push(ids *v, uint32_t i) {
    if (v->n == v->cap) {
        size_t cap = v->cap ? 2 * v->cap : 1024;
        uint32_t *a = realloc(v->a, cap * sizeof *a);
        if (!a) {
            v->oom = 1;
            return;
        }
        v->a = a, v->cap = cap;
    }
    v->a[v->n++] = i;
}

static int cmp_u32(const void *x, const void *y) {
    uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
    return a < b ? -1 : a > b;
}

static void ids_unique(ids *v) {
    if (!v->n) return;
    qsort(v->a, v->n, sizeof *v->a, cmp_u32);
    size_t k = 1;
    for (size_t i = 1; i < v->n; i++)
        if (v->a[i] != v->a[k - 1]) v->a[k++] = v->a[i];
    v->n = k;
}

/* Cells outside rank q's tiles that neighbour them: into recv[owner] when q is this
 * rank, into send[q] for those this rank owns. */
static void ring_of(const dfill *d, int q, ids *send, ids *recv) {
    const int P = pg_mpi_size(d->m), me = pg_mpi_rank(d->m), nt = 6 * d->T * d->T;
    const int t0 = pg_mpi_tile_first(nt, P, q), t1 = pg_mpi_tile_first(nt, P, q + 1);
    uint32_t nb[8];
    for (int t = t0; t < t1; t++)
        for (uint32_t y = 0; y < d->ts; y++)
            for (uint32_t x = 0; x < d->ts; x++) {
                if (y > 0 && y + 1 < d->ts && x == 1) x = d->ts - 1; /* perimeter only */
                uint32_t id = tile_cell(d, t, x, y);
                int k = pg_pits_neighbours(d->t, id, nb);
                for (int j = 0; j < k; j++) {
                    int o = pg_mpi_tile_owner(nt, P, tile_of(d, nb[j]));
                    if (o == q) continue;
                    if (q == me && o != me) ids_push(&recv[o], nb[j]);
                    if (q != me && o == me) ids_push(&send[q], nb[j]);
                }
            }
}

/* Every rank's ring cells get their owners' values of arr (elements of elem bytes). */
static pg_status exchange_cells(dfill *d, void *arr, size_t elem, pg_error *err) {
    const int P = pg_mpi_size(d->m);
    unsigned char *a = arr;
    ids *send = calloc((size_t)P, sizeof *send), *recv = calloc((size_t)P, sizeof *recv);
    MPI_Request *req = malloc(2 * (size_t)P * sizeof *req);
    unsigned char **buf = calloc(2 * (size_t)P, sizeof *buf);
    int oom = !send || !recv || !req || !buf, nreq = 0;
    for (int q = 0; !oom && q < P; q++)
        ring_of(d, q, send, recv);
    for (int q = 0; !oom && q < P; q++) {
        ids_unique(&send[q]);
        ids_unique(&recv[q]);
        oom |= send[q].oom | recv[q].oom;
        buf[q] = malloc((send[q].n + 1) * elem);
        buf[P + q] = malloc((recv[q].n + 1) * elem);
        oom |= !buf[q] || !buf[P + q];
    }
    for (int q = 0; !oom && q < P; q++) {
        if (send[q].n) {
            for (size_t k = 0; k < send[q].n; k++)
                memcpy(buf[q] + k * elem, a + (size_t)send[q].a[k] * elem, elem);
            MPI_Isend(buf[q], (int)(send[q].n * elem), MPI_BYTE, q, 11, MPI_COMM_WORLD,
                      &req[nreq++]);
        }
        if (recv[q].n)
            MPI_Irecv(buf[P + q], (int)(recv[q].n * elem), MPI_BYTE, q, 11, MPI_COMM_WORLD,
                      &req[nreq++]);
    }
    if (!oom) MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE);
    for (int q = 0; !oom && q < P; q++) {
        pg_mpi_note_pits_bytes(d->m, (double)(send[q].n * elem));
        for (size_t k = 0; k < recv[q].n; k++)
            memcpy(a + (size_t)recv[q].a[k] * elem, buf[P + q] + k * elem, elem);
    }
    for (int q = 0; send && recv && buf && q < P; q++) {
        free(send[q].a), free(recv[q].a);
        free(buf[q]), free(buf[P + q]);
    }
    free(send), free(recv), free(req), free(buf);
    return oom ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (ring)") : PG_OK;
}

static pg_status exchange_ring(dfill *d, pg_error *err) {
    return exchange_cells(d, d->h, sizeof *d->h, err);
}

/* ---- step 1 and 2: one tile ---- */

static bool in_tile(const dfill *d, int t, uint32_t id) {
    return tile_of(d, id) == t;
}

static void seed_tile(dfill *d, int t, pits_heap *q, fedges *ev) {
    uint32_t nb[8];
    for (uint32_t y = 0; y < d->ts; y++)
        for (uint32_t x = 0; x < d->ts; x++) {
            uint32_t id = tile_cell(d, t, x, y);
            int k = pg_pits_neighbours(d->t, id, nb), outside = 0, open = 0;
            for (int j = 0; j < k; j++) {
                int out = !in_tile(d, t, nb[j]);
                outside |= out;
                open |= !out && !sink(d, nb[j]);
                /* a pair of cells in two tiles, recorded once, from the lower id */
                if (out && nb[j] > id)
                    fedge_push(ev, perimeter_label(d, id), perimeter_label(d, nb[j]),
                               fmaxf(eff(d, id), eff(d, nb[j])));
            }
            if (sink(d, id)) {
                d->label[id] = OUTLET;
                if (open) pits_heap_push(q, pits_key(-INFINITY, id));
            } else if (outside) {
                d->label[id] = 2 + id;
                pits_heap_push(q, pits_key(d->h[id], id));
            }
        }
}

static int flood_tile(dfill *d, int t, fedges *ev) {
    pits_heap q = {0};
    pits_fifo pit = {0};
    seed_tile(d, t, &q, ev);
    uint32_t nb[8];
    while (q.n || !pits_fifo_empty(&pit)) {
        uint32_t c = !pits_fifo_empty(&pit) ? pits_fifo_pop(&pit) : pits_key_id(pits_heap_pop(&q));
        float wc = eff(d, c);
        uint32_t lc = d->label[c];
        int k = pg_pits_neighbours(d->t, c, nb);
        for (int j = 0; j < k; j++) {
            uint32_t n = nb[j];
            if (!in_tile(d, t, n)) continue;
            if (d->label[n]) {
                if (d->label[n] != lc) fedge_push(ev, lc, d->label[n], fmaxf(wc, eff(d, n)));
                continue;
            }
            d->label[n] = lc;
            if (d->h[n] <= wc) {
                d->h[n] = wc;
                pits_fifo_push(&pit, n);
            } else {
                pits_heap_push(&q, pits_key(d->h[n], n));
            }
        }
        if (q.oom || pit.oom || ev->oom) break;
    }
    int oom = q.oom || pit.oom || ev->oom;
    pits_heap_free(&q);
    pits_fifo_free(&pit);
    return oom;
}

/* ---- step 3: rank 0 solves the label graph ---- */

static uint32_t label_index(const uint32_t *labels, size_t n, uint32_t l) {
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (labels[mid] < l)
            lo = mid + 1;
        else
            hi = mid;
    }
    return (uint32_t)lo;
}

/* Minimax levels of the labels (sorted, unique) over the edges, from OUTLET. */
static int solve(const fedge *e, size_t ne, const uint32_t *labels, size_t nl, float *level) {
    uint32_t *start = calloc(nl + 1, sizeof *start);
    fedge *adj = malloc((2 * ne + 1) * sizeof *adj);
    uint32_t *fill = malloc((nl + 1) * sizeof *fill);
    pits_heap q = {0};
    int oom = !start || !adj || !fill;
    for (size_t k = 0; !oom && k < ne; k++) {
        start[label_index(labels, nl, e[k].a) + 1]++;
        start[label_index(labels, nl, e[k].b) + 1]++;
    }
    for (size_t l = 0; !oom && l < nl; l++)
        start[l + 1] += start[l];
    if (!oom) memcpy(fill, start, nl * sizeof *fill);
    for (size_t k = 0; !oom && k < ne; k++) {
        uint32_t a = label_index(labels, nl, e[k].a), b = label_index(labels, nl, e[k].b);
        adj[fill[a]++] = (fedge){a, b, e[k].w};
        adj[fill[b]++] = (fedge){b, a, e[k].w};
    }
    for (size_t l = 0; l < nl; l++)
        level[l] = INFINITY;
    if (!oom && nl && labels[0] == OUTLET) {
        level[0] = -INFINITY;
        pits_heap_push(&q, pits_key(-INFINITY, 0));
    }
    while (!oom && q.n && !q.oom) {
        uint64_t key = pits_heap_pop(&q);
        uint32_t l = pits_key_id(key);
        if (pits_key(level[l], l) != key) continue; /* stale */
        for (uint32_t k = start[l]; k < start[l + 1]; k++) {
            float w = fmaxf(level[l], adj[k].w);
            if (w < level[adj[k].b]) {
                level[adj[k].b] = w;
                pits_heap_push(&q, pits_key(w, adj[k].b));
            }
        }
    }
    oom |= q.oom;
    pits_heap_free(&q);
    free(start), free(adj), free(fill);
    return oom;
}

/* Gather every rank's edges on rank 0 (as 3 words each). */
static fedge *gather_edges(dfill *d, const fedges *ev, size_t *total, int *oom) {
    const int P = pg_mpi_size(d->m), me = pg_mpi_rank(d->m);
    int mine = ev->n * 3 > INT_MAX ? -1 : (int)(ev->n * 3);
    int *counts = me == 0 ? calloc(2 * (size_t)P, sizeof *counts) : NULL;
    MPI_Gather(&mine, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    fedge *all = NULL;
    long long sum = 0;
    if (me == 0) {
        for (int q = 0; counts && q < P; q++) {
            if (counts[q] < 0) *oom = 1;
            counts[P + q] = (int)sum;
            sum += counts[q];
        }
        if (sum > INT_MAX) *oom = 1;
        all = *oom || !counts ? NULL : malloc(((size_t)sum / 3 + 1) * sizeof *all);
        if (!all) *oom = 1;
    }
    int bad = *oom;
    MPI_Bcast(&bad, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!bad)
        MPI_Gatherv(ev->e, mine, MPI_UINT32_T, all, counts, counts ? counts + P : NULL,
                    MPI_UINT32_T, 0, MPI_COMM_WORLD);
    if (!bad && me != 0) pg_mpi_note_pits_bytes(d->m, 4.0 * mine);
    *oom = bad;
    *total = (size_t)sum / 3;
    free(counts);
    return all;
}

/* Rank 0: solve, then broadcast (labels, levels). Every rank returns them. */
static int solve_and_share(dfill *d, const fedges *ev, uint32_t **labels_out, float **levels_out,
                           size_t *nl_out) {
    size_t ne = 0, nl = 0;
    int oom = 0;
    fedge *all = gather_edges(d, ev, &ne, &oom);
    uint32_t *labels = NULL;
    float *levels = NULL;
    if (!oom && pg_mpi_rank(d->m) == 0) {
        labels = malloc((2 * ne + 1) * sizeof *labels);
        oom = !labels;
        for (size_t k = 0; !oom && k < ne; k++)
            labels[2 * k] = all[k].a, labels[2 * k + 1] = all[k].b;
        ids v = {labels, oom ? 0 : 2 * ne, 2 * ne, 0};
        ids_unique(&v);
        nl = v.n;
        levels = oom ? NULL : malloc((nl + 1) * sizeof *levels);
        oom = oom || !levels || solve(all, ne, labels, nl, levels);
    }
    free(all);
    unsigned long long n64 = nl;
    int bad = oom;
    MPI_Bcast(&bad, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Bcast(&n64, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    if (!bad && n64 > INT_MAX) bad = 1;
    nl = (size_t)n64;
    if (!bad && pg_mpi_rank(d->m) != 0) {
        labels = malloc((nl + 1) * sizeof *labels);
        levels = malloc((nl + 1) * sizeof *levels);
    }
    int local_bad = !bad && (!labels || !levels);
    MPI_Allreduce(&local_bad, &oom, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (!bad && !oom) {
        MPI_Bcast(labels, (int)nl, MPI_UINT32_T, 0, MPI_COMM_WORLD);
        MPI_Bcast(levels, (int)nl, MPI_FLOAT, 0, MPI_COMM_WORLD);
        if (pg_mpi_rank(d->m) == 0) /* what rank 0 sends to each of the others */
            pg_mpi_note_pits_bytes(d->m, 8.0 * (double)nl * (pg_mpi_size(d->m) - 1));
    }
    *labels_out = labels, *levels_out = levels, *nl_out = nl;
    return bad || oom;
}

/* ---- epsilon: rounds of local floods to the minimal epsilon-surface ---- */

typedef struct eps_ctx {
    const dfill *d;
    int t0, t1;
    uint8_t *closed; /* owned cells already at their floor this round */
} eps_ctx;

/* Is the cell in one of the tiles [t0, t1) (this rank's)? */
static int in_tiles(const dfill *d, int t0, int t1, uint32_t id) {
    int t = tile_of(d, id);
    return t >= t0 && t < t1;
}

static int eps_owned(const eps_ctx *e, uint32_t id) {
    return in_tiles(e->d, e->t0, e->t1, id);
}

static int eps_settable(const void *ctx, uint32_t id) {
    const eps_ctx *e = ctx;
    return eps_owned(e, id) && !sink(e->d, id) && !e->closed[id];
}

/* A cell's value as a way out: sinks take water at any height. */
static float eps_value(const dfill *d, uint32_t id) {
    return sink(d, id) ? -INFINITY : d->h[id];
}

/* Step 1 of a round, linear: owned cells with a strictly descending chain (in floor)
 * to a sink or to a ring cell below them keep their floor (as in the serial
 * pg_pits_planchon2002_minimal_eps.c); q gets nothing, the FIFO does the work. */
static int eps_close(const dfill *d, eps_ctx *e, const float *floor_) {
    pits_fifo f = {0};
    uint32_t nb[8];
    FOR_TILE_CELLS(d, e->t0, e->t1, id) {
        e->closed[id] = 0;
        if (sink(d, id)) continue;
        d->h[id] = INFINITY;
        int nn = pg_pits_neighbours(d->t, id, nb);
        for (int j = 0; j < nn; j++)
            if ((!eps_owned(e, nb[j]) || sink(d, nb[j])) && eps_value(d, nb[j]) < floor_[id]) {
                e->closed[id] = 1;
                d->h[id] = floor_[id];
                pits_fifo_push(&f, id);
                break;
            }
    }
    while (!pits_fifo_empty(&f) && !f.oom) {
        uint32_t c = pits_fifo_pop(&f);
        int nn = pg_pits_neighbours(d->t, c, nb);
        for (int j = 0; j < nn; j++)
            if (eps_settable(e, nb[j]) && floor_[c] < floor_[nb[j]]) {
                e->closed[nb[j]] = 1;
                d->h[nb[j]] = floor_[nb[j]];
                pits_fifo_push(&f, nb[j]);
            }
    }
    int oom = f.oom;
    pits_fifo_free(&f);
    return oom;
}

/* One round: flood this rank's cells from the ring and the sinks. Returns -1 when out
 * of memory, else whether any owned cell changed. */
static int eps_round(dfill *d, eps_ctx *e, const float *floor_) {
    pits_heap q = {0};
    uint32_t nb[8];
    int oom = eps_close(d, e, floor_);
    FOR_TILE_CELLS(d, e->t0, e->t1, id) { /* step 2: the rest, from its border */
        if (oom || !eps_settable(e, id)) continue;
        float w = INFINITY;
        int nn = pg_pits_neighbours(d->t, id, nb);
        for (int j = 0; j < nn; j++) /* fixed: sinks, the ring, closed cells */
            if (!eps_settable(e, nb[j]))
                w = fminf(w, fmaxf(floor_[id], pits_up(eps_value(d, nb[j]))));
        d->h[id] = w;
        if (w < INFINITY) pits_heap_push(&q, pits_key(w, id));
    }
    pits_meps m = {d->t, d->h, floor_, eps_settable, e, 0};
    oom = oom || q.oom || pits_meps_flood(&m, &q);
    pits_heap_free(&q);
    return oom ? -1 : 0;
}

/* A later round: the ring's values only fell, so flood on from the owned cells next to
 * ring cells that fell (before: every value before the exchange); the others keep
 * their values, which are upper bounds the flood only lowers. Returns -1 when out of
 * memory. */
static int eps_update(dfill *d, eps_ctx *e, const float *floor_, const float *before) {
    pits_heap q = {0};
    uint32_t nb[8];
    FOR_TILE_CELLS(d, e->t0, e->t1, id) {
        if (!eps_settable(e, id)) continue;
        int nn = pg_pits_neighbours(d->t, id, nb);
        float w = d->h[id];
        for (int j = 0; j < nn; j++)
            if (!eps_owned(e, nb[j]) && d->h[nb[j]] < before[nb[j]])
                w = fminf(w, fmaxf(floor_[id], pits_up(eps_value(d, nb[j]))));
        if (w < d->h[id]) {
            d->h[id] = w;
            pits_heap_push(&q, pits_key(w, id));
        }
    }
    pits_meps m = {d->t, d->h, floor_, eps_settable, e, 0};
    int oom = q.oom || pits_meps_flood(&m, &q);
    pits_heap_free(&q);
    return oom ? -1 : 0;
}

/* Did any owned cell change since `before`? */
static int owned_changed(const dfill *d, int t0, int t1, const float *before) {
    int changed = 0;
    FOR_TILE_CELLS(d, t0, t1, id) {
        changed |= memcmp(&d->h[id], &before[id], sizeof(float)) != 0;
    }
    return changed;
}

/* Start the ring from above: +inf (no known way out) except at sinks. Only the ring is
 * visited: the cells beyond it hold whatever the caller left there (in generate,
 * nothing: they are never written), so they must not even be read. */
static void ring_from_above(dfill *d, int t0, int t1) {
    uint32_t nb[8];
    FOR_TILE_CELLS(d, t0, t1, id) {
        int nn = pg_pits_neighbours(d->t, id, nb);
        for (int j = 0; j < nn; j++)
            if (!in_tiles(d, t0, t1, nb[j]) && !sink(d, nb[j])) d->h[nb[j]] = INFINITY;
    }
}

static pg_status eps_rounds(dfill *d, int t0, int t1, pg_mpi_pits_info *info, pg_error *err) {
    double t_start = MPI_Wtime();
    float *floor_ = malloc(d->t->ncells * sizeof *floor_); /* only owned cells are read */
    float *before = malloc(d->t->ncells * sizeof *before);
    eps_ctx e = {d, t0, t1, calloc(d->t->ncells, 1)};
    int bad = !floor_ || !e.closed || !before, more = 1;
    if (!bad) memcpy(floor_, d->h, d->t->ncells * sizeof *floor_);
    if (!bad) ring_from_above(d, t0, t1);
    if (!bad) memcpy(before, d->h, d->t->ncells * sizeof *before);
    while (!(bad = pg_mpi_max_int(d->m, bad)) && more) {
        int r =
            info->eps_rounds == 0 ? eps_round(d, &e, floor_) : eps_update(d, &e, floor_, before);
        int changed = r >= 0 && owned_changed(d, t0, t1, before);
        if (r >= 0) memcpy(before, d->h, d->t->ncells * sizeof *before);
        bad = r < 0 || exchange_ring(d, err) != PG_OK;
        more = pg_mpi_max_int(d->m, changed);
        info->eps_rounds++;
    }
    free(floor_), free(e.closed), free(before);
    info->eps_seconds = MPI_Wtime() - t_start;
    return bad ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (epsilon rounds)")
               : PG_OK;
}

/* ---- the whole ---- */

/* The cube topology and the tiling of n texels per face edge into tiles x tiles. */
static pg_status dfill_init(dfill *d, pg_pits_topo *topo, pg_mpi *m, int tiles, uint32_t n,
                            float *h, const pg_pits_opts *o, pg_error *err) {
    pg_status st = pg_pits_topo_cube(topo, n, err);
    if (!st && (tiles < 1 || n % (uint32_t)tiles))
        st = pg_error_set(err, PG_ERR_BADINPUT, "pits (MPI): %u texels do not split into %d tiles",
                          n, tiles);
    if (!st) {
        *d = (dfill){m, topo, tiles, n, n / (uint32_t)tiles, h, o->sea_level, NULL, -1, -1};
        d->ln = log2_exact(n), d->lts = log2_exact(d->ts);
        if (d->lts < 0) d->ln = -1;
    }
    return st;
}

static pg_status check(const pg_pits_opts *o, pg_error *err) {
    if (o->method != PG_PITS_FILL || !o->has_sea_level || o->lakes || o->has_nodata)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits (MPI): the distributed fill needs the fill method "
                            "with a sea level, no lakes and no no-data");
    return PG_OK;
}

pg_status pg_mpi_pits_fill(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                           pg_mpi_pits_info *info, pg_error *err) {
    pg_pits_topo topo;
    dfill d;
    pg_status st = check(o, err);
    if (!st) st = dfill_init(&d, &topo, m, tiles, n, h, o, err);
    if (st) return st;
    const int nt = 6 * tiles * tiles, P = pg_mpi_size(m), me = pg_mpi_rank(m);
    const int t0 = pg_mpi_tile_first(nt, P, me), t1 = pg_mpi_tile_first(nt, P, me + 1);
    memset(info, 0, sizeof *info);
    /* every rank must see a sink somewhere (the serial fill's fallback is global) */
    double sinks = 0;
    for (int t = t0; t < t1; t++)
        for (uint32_t y = 0; y < d.ts; y++)
            for (uint32_t x = 0; x < d.ts; x++)
                sinks += sink(&d, tile_cell(&d, t, x, y));
    if (pg_mpi_sum_double(m, sinks) == 0)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits (MPI): no cell at or below the sea level: the distributed "
                            "fill needs an ocean");
    st = exchange_ring(&d, err);
    if (pg_mpi_max_int(m, st != PG_OK))
        return st ? st : pg_error_set(err, PG_ERR_RUNTIME, "pits (MPI): another rank failed");
    d.label = calloc(topo.ncells, sizeof *d.label); /* only the owned tiles are touched */
    fedges ev = {0};
    int oom = !d.label;
    double t_start = MPI_Wtime();
    for (int t = t0; !oom && t < t1; t++)
        oom = flood_tile(&d, t, &ev);
    if (!oom) fedge_compact(&ev);
    info->flood_seconds = MPI_Wtime() - t_start;
    info->edges = (double)ev.n;
    oom = pg_mpi_max_int(m, oom);
    uint32_t *labels = NULL;
    float *levels = NULL;
    size_t nl = 0;
    t_start = MPI_Wtime();
    if (!oom) oom = solve_and_share(&d, &ev, &labels, &levels, &nl);
    info->solve_seconds = MPI_Wtime() - t_start;
    info->labels = (double)nl;
    for (int t = t0; !oom && t < t1; t++)
        for (uint32_t y = 0; y < d.ts; y++)
            for (uint32_t x = 0; x < d.ts; x++) {
                uint32_t id = tile_cell(&d, t, x, y), l = d.label[id];
                if (sink(&d, id)) continue;
                float lv = levels[label_index(labels, nl, l)];
                if (lv > h[id] && lv < INFINITY) h[id] = lv, info->raised++;
            }
    free(ev.e), free(d.label), free(labels), free(levels);
    if (oom) return pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory");
    return o->epsilon ? eps_rounds(&d, t0, t1, info, err) : PG_OK;
}

/* ---- breach and hybrid along the descent tree (pg_pits_descent_breach.c) ----
 * The tree (each cell's parent: the neighbour with the smallest (W, id)) and the pits
 * are computed by each rank for its own cells from a ring of W and of the heights.
 * The tokens then flow children-first as in the serial pass, in rounds: each round
 * every rank sweeps its cells, taking the tokens its ring cells passed into them last
 * round, and sends the tokens its cells pass to other ranks' cells. Tokens only get
 * lower from round to round (a new token can only win), so the rounds stop, and then
 * every cell holds the tree recursion's unique value: the serial result. */

typedef struct dtree {
    dfill *d;
    int t0, t1;
    const float *orig; /* the heights before carving (owned and ring) */
    uint32_t *parent;  /* every owned and ring cell's parent (ring: from its owner) */
    float *pass;       /* token each cell passes to its parent, +inf for none */
    float *plen;       /* its channel length (a float, exact below 2^24, to share it) */
    float *v;          /* owned: incoming token */
    uint32_t *len;     /* owned: its channel length */
    uint8_t *pending;  /* owned: owned children not yet swept */
    uint8_t *pit;      /* owned: starts a token */
    double max_depth, max_length;
} dtree;

static int owned(const dtree *e, uint32_t id) {
    return in_tiles(e->d, e->t0, e->t1, id);
}

#define DT_FOR_OWNED(e, id) FOR_TILE_CELLS((e)->d, (e)->t0, (e)->t1, id)

/* Parents and pits of the owned cells; W in w (owned and ring), heights in orig. */
static void dt_tree(dtree *e, const float *w) {
    const dfill *d = e->d;
    uint32_t nb[8];
    DT_FOR_OWNED(e, id) {
        e->pass[id] = INFINITY, e->plen[id] = 0, e->parent[id] = UINT32_MAX;
        if (e->orig[id] <= d->sea) continue;
        int k = pg_pits_neighbours(d->t, id, nb), lower = 0;
        uint64_t best = UINT64_MAX;
        for (int j = 0; j < k; j++) {
            int sk = e->orig[nb[j]] <= d->sea;
            uint64_t key = pits_key(sk ? -INFINITY : w[nb[j]], nb[j]);
            if (key < best) best = key;
            lower |= sk || e->orig[nb[j]] < e->orig[id];
        }
        e->parent[id] = pits_key_id(best);
        e->pit[id] = !lower;
        for (int j = 0; j < k; j++) /* ring cells bring no token before the first exchange */
            if (!owned(e, nb[j])) e->pass[nb[j]] = INFINITY, e->plen[nb[j]] = 0;
    }
}

/* One round: returns -1 when out of memory, else whether an owned cell's token changed. */
static int dt_round(dtree *e, float *h) {
    const dfill *d = e->d;
    uint32_t nb[8];
    DT_FOR_OWNED(e, id) {
        h[id] = e->orig[id];
        e->v[id] = e->pit[id] ? e->orig[id] : INFINITY;
        e->len[id] = 0;
        e->pending[id] = 0;
    }
    DT_FOR_OWNED(e, id) { /* children: owned ones count, ring ones bring last round's token */
        if (e->parent[id] == UINT32_MAX) continue;
        if (owned(e, e->parent[id]) && e->orig[e->parent[id]] > d->sea) e->pending[e->parent[id]]++;
        int k = pg_pits_neighbours(d->t, id, nb);
        for (int j = 0; j < k; j++)
            if (!owned(e, nb[j]) && e->parent[nb[j]] == id && e->pass[nb[j]] < INFINITY)
                pits_token_merge(&e->v[id], &e->len[id], e->pass[nb[j]], (uint32_t)e->plen[nb[j]]);
    }
    pits_fifo f = {0};
    DT_FOR_OWNED(e, id) {
        if (e->parent[id] != UINT32_MAX && e->pending[id] == 0) pits_fifo_push(&f, id);
    }
    int changed = 0;
    while (!pits_fifo_empty(&f) && !f.oom) {
        uint32_t x = pits_fifo_pop(&f), p = e->parent[x], plen = 0;
        float to, pass = INFINITY;
        if (pits_token(h[x], e->v[x], e->len[x], e->max_depth, e->max_length, &to, &pass, &plen))
            h[x] = to;
        changed |= pass != e->pass[x] || (float)plen != e->plen[x];
        e->pass[x] = pass, e->plen[x] = (float)plen;
        if (!owned(e, p) || e->orig[p] <= d->sea) continue;
        if (pass < INFINITY) pits_token_merge(&e->v[p], &e->len[p], pass, plen);
        if (--e->pending[p] == 0) pits_fifo_push(&f, p);
    }
    int oom = f.oom;
    pits_fifo_free(&f);
    return oom ? -1 : changed;
}

static pg_status dt_rounds(dtree *e, float *h, pg_mpi_pits_info *info, pg_error *err) {
    int bad = 0, more = 1;
    while (!(bad = pg_mpi_max_int(e->d->m, bad)) && more) {
        int r = dt_round(e, h);
        bad = r < 0 || exchange_cells(e->d, e->pass, sizeof *e->pass, err) ||
              exchange_cells(e->d, e->plen, sizeof *e->plen, err);
        more = pg_mpi_max_int(e->d->m, r > 0);
        info->breach_rounds++;
    }
    return bad ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (breach rounds)")
               : PG_OK;
}

static pg_status dt_run(dfill *d, int t0, int t1, const pg_pits_opts *o, pg_mpi_pits_info *info,
                        pg_error *err) {
    const size_t nc = d->t->ncells;
    float *orig = malloc(nc * sizeof *orig), *w = malloc(nc * sizeof *w);
    dtree e = {d,
               t0,
               t1,
               orig,
               malloc(nc * sizeof(uint32_t)),
               malloc(nc * sizeof(float)),
               malloc(nc * sizeof(float)),
               malloc(nc * sizeof(float)),
               malloc(nc * sizeof(uint32_t)),
               malloc(nc),
               calloc(nc, 1),
               INFINITY,
               INFINITY};
    if (o->method == PG_PITS_HYBRID) e.max_depth = o->max_depth, e.max_length = o->max_length;
    int oom =
        !orig || !w || !e.parent || !e.pass || !e.plen || !e.v || !e.len || !e.pending || !e.pit;
    pg_status st = pg_mpi_max_int(d->m, oom) ? PG_ERR_NOMEM : PG_OK;
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL, f.epsilon = true;
    if (!st) st = exchange_ring(d, err); /* the ring's heights */
    if (!st) {
        memcpy(orig, d->h, nc * sizeof *orig);
        memcpy(w, d->h, nc * sizeof *w);
        pg_mpi_pits_info fi = {0};
        st = pg_mpi_pits_fill(d->m, d->T, d->n, w, &f, &fi, err); /* W; its ring too */
        if (!st) st = exchange_cells(d, w, sizeof *w, err);
        info->eps_rounds = fi.eps_rounds;
    }
    if (!st) dt_tree(&e, w);
    if (!st) st = exchange_cells(d, e.parent, sizeof *e.parent, err);
    if (!st) st = dt_rounds(&e, d->h, info, err);
    if (!st && o->method == PG_PITS_HYBRID) { /* fill what no channel drained */
        f.epsilon = o->epsilon;
        pg_mpi_pits_info fi = {0};
        st = pg_mpi_pits_fill(d->m, d->T, d->n, d->h, &f, &fi, err);
    }
    free(orig), free(w), free(e.parent), free(e.pass), free(e.plen), free(e.v), free(e.len);
    free(e.pending), free(e.pit);
    if (st == PG_ERR_NOMEM && !err->msg[0]) pg_error_set(err, st, "pits (MPI): out of memory");
    return st;
}

pg_status pg_mpi_pits_remove(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                             pg_mpi_pits_info *info, pg_error *err) {
    if (o->method == PG_PITS_FILL) return pg_mpi_pits_fill(m, tiles, n, h, o, info, err);
    if (!o->descent || !o->epsilon || !o->has_sea_level || o->lakes || o->has_nodata)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits (MPI): distributed breach and hybrid need the descent tree, "
                            "epsilon, a sea level, no lakes and no no-data");
    pg_pits_topo topo;
    dfill d;
    pg_status st = dfill_init(&d, &topo, m, tiles, n, h, o, err);
    if (st) return st;
    const int nt = 6 * tiles * tiles, P = pg_mpi_size(m), me = pg_mpi_rank(m);
    memset(info, 0, sizeof *info);
    double t_start = MPI_Wtime();
    st = dt_run(&d, pg_mpi_tile_first(nt, P, me), pg_mpi_tile_first(nt, P, me + 1), o, info, err);
    info->breach_seconds = MPI_Wtime() - t_start;
    return st;
}

/* ---- depression statistics (pg_pits_stats_compute, distributed) ----
 * Membership (the minimal fill raises the cell) and the epsilon-fill come from the
 * distributed fills. Each rank labels the depressions inside its tiles (a flood over
 * its member cells), sums each label's cells, area, volume and depth, and records a
 * pair of labels wherever two member cells in different ranks touch (the ring's
 * labels come from their owners). Rank 0 joins the pairs (union-find) and counts the
 * joined regions: the serial count, since the serial regions are the same 8-connected
 * member sets. Areas and volumes are summed in another order, so their last bits may
 * differ from the serial figures; the counts and the deepest cell do not. */

typedef struct dlabel {
    double label, cells, area, volume, depth;
} dlabel;

static double stat_area(const pg_pits_area *a, uint32_t id) {
    if (!a) return 1.0;
    if (a->per_cell) return a->per_cell[id];
    return a->fn ? a->fn(a->ctx, id) : a->constant;
}

static uint32_t uf_find(uint32_t *p, uint32_t x) {
    while (p[x] != x)
        x = p[x] = p[p[x]];
    return x;
}

/* Rank 0: join the labels (sorted by value) over the pairs; the number of regions. */
static double join_labels(const dlabel *lab, size_t nl, const uint32_t *pairs, size_t np) {
    uint32_t *parent = malloc((nl + 1) * sizeof *parent), *sorted = malloc((nl + 1) * 4);
    double regions = 0;
    if (!parent || !sorted) goto done;
    for (size_t i = 0; i < nl; i++)
        parent[i] = (uint32_t)i, sorted[i] = (uint32_t)lab[i].label;
    for (size_t k = 0; k < np; k++) {
        uint32_t a = label_index(sorted, nl, pairs[2 * k]),
                 b = label_index(sorted, nl, pairs[2 * k + 1]);
        if (a < nl && b < nl) parent[uf_find(parent, a)] = uf_find(parent, b);
    }
    for (size_t i = 0; i < nl; i++)
        regions += uf_find(parent, (uint32_t)i) == i;
done:
    free(parent), free(sorted);
    return regions;
}

static int cmp_dlabel(const void *x, const void *y) {
    double a = ((const dlabel *)x)->label, b = ((const dlabel *)y)->label;
    return a < b ? -1 : a > b;
}

/* Gather n items of `words` doubles (or uint32 pairs as doubles) on rank 0. */
static double *gather_doubles(pg_mpi *m, const double *mine, size_t n, size_t *total, int *bad) {
    const int P = pg_mpi_size(m), me = pg_mpi_rank(m);
    int cnt = n > INT_MAX ? -1 : (int)n;
    int *counts = me == 0 ? calloc(2 * (size_t)P, sizeof *counts) : NULL;
    MPI_Gather(&cnt, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    long long sum = 0;
    double *all = NULL;
    if (me == 0) {
        for (int q = 0; counts && q < P; q++) {
            if (counts[q] < 0) *bad = 1;
            counts[P + q] = (int)sum;
            sum += counts[q];
        }
        if (!counts || sum > INT_MAX) *bad = 1;
        all = *bad ? NULL : malloc(((size_t)sum + 1) * sizeof *all);
        if (!all) *bad = 1;
    }
    MPI_Bcast(bad, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!*bad)
        MPI_Gatherv(mine, cnt, MPI_DOUBLE, all, counts, counts ? counts + P : NULL, MPI_DOUBLE, 0,
                    MPI_COMM_WORLD);
    if (!*bad && me != 0) pg_mpi_note_pits_bytes(m, 8.0 * cnt);
    free(counts);
    *total = (size_t)sum;
    return all;
}

/* Room for `need` elements in *a (capacity *cap, doubling); nonzero when out of memory. */
static int grow(void **a, size_t *cap, size_t need, size_t elem) {
    if (need <= *cap) return 0;
    size_t c = *cap ? 2 * *cap : 1024;
    while (c < need)
        c *= 2;
    void *g = realloc(*a, c * elem);
    if (!g) return 1;
    *a = g, *cap = c;
    return 0;
}

/* Label the member cells of this rank's tiles; one dlabel per local region. */
static int label_regions(dfill *d, int t0, int t1, const float *h, const float *efill,
                         const uint8_t *member, uint32_t *label, const pg_pits_area *area,
                         dlabel **out, size_t *nout) {
    dtree e = {.d = d, .t0 = t0, .t1 = t1};
    uint32_t *queue = malloc(((size_t)(t1 - t0) * d->ts * d->ts + 1) * sizeof *queue), nb[8];
    dlabel *lab = NULL;
    size_t nl = 0, cap = 0;
    int oom = !queue;
    DT_FOR_OWNED(&e, id) {
        if (oom || !member[id] || label[id] != UINT32_MAX) continue;
        if ((oom = grow((void **)&lab, &cap, nl + 1, sizeof *lab))) continue;
        dlabel L = {id, 0, 0, 0, 0};
        size_t head = 0, tail = 0;
        queue[tail++] = id, label[id] = id;
        while (head < tail) {
            uint32_t c = queue[head++];
            double a = stat_area(area, c), dep = (double)efill[c] - (double)h[c];
            L.cells++, L.area += a, L.volume += dep * a;
            if (dep > L.depth) L.depth = dep;
            int k = pg_pits_neighbours(d->t, c, nb);
            for (int j = 0; j < k; j++)
                if (owned(&e, nb[j]) && member[nb[j]] && label[nb[j]] == UINT32_MAX)
                    label[nb[j]] = id, queue[tail++] = nb[j];
        }
        lab[nl++] = L;
    }
    free(queue);
    *out = lab, *nout = nl;
    return oom;
}

/* Pairs of labels across rank boundaries, as doubles (label, label). */
static int cross_pairs(dfill *d, int t0, int t1, const uint8_t *member, const uint32_t *label,
                       double **out, size_t *nout) {
    dtree e = {.d = d, .t0 = t0, .t1 = t1};
    size_t n = 0, cap = 0;
    double *v = NULL;
    uint32_t nb[8];
    int oom = 0;
    DT_FOR_OWNED(&e, id) {
        if (!member[id]) continue;
        int k = pg_pits_neighbours(d->t, id, nb);
        for (int j = 0; j < k; j++) {
            if (owned(&e, nb[j]) || !member[nb[j]]) continue;
            if (oom || grow((void **)&v, &cap, n + 2, sizeof *v)) {
                oom = 1;
                continue;
            }
            v[n++] = label[id], v[n++] = label[nb[j]];
        }
    }
    *out = v, *nout = n;
    return oom;
}

pg_status pg_mpi_pits_stats(pg_mpi *m, int tiles, uint32_t n, const float *h, const pg_pits_opts *o,
                            const pg_pits_area *area, pg_pits_stats *out, pg_error *err) {
    pg_pits_topo topo;
    dfill d;
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL, f.epsilon = false;
    pg_status st = check(&f, err);
    const size_t nc = (size_t)6 * n * n;
    float *fill = malloc(nc * sizeof *fill), *efill = malloc(nc * sizeof *efill);
    uint8_t *member = calloc(nc, 1);
    uint32_t *label = malloc(nc * sizeof *label);
    if (!st && (!fill || !efill || !member || !label))
        st = pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory for statistics");
    if (!st) st = dfill_init(&d, &topo, m, tiles, n, fill, o, err);
    memset(out, 0, sizeof *out);
    pg_mpi_pits_info info;
    const int nt = 6 * tiles * tiles, P = pg_mpi_size(m), me = pg_mpi_rank(m);
    const int t0 = pg_mpi_tile_first(nt, P, me), t1 = pg_mpi_tile_first(nt, P, me + 1);
    if (!st) {
        memcpy(fill, h, nc * sizeof *fill);
        st = pg_mpi_pits_fill(m, tiles, n, fill, &f, &info, err);
    }
    if (!st) { /* the epsilon-fill: the same rounds as the fill's, from the plain fill */
        memcpy(efill, fill, nc * sizeof *efill);
        dfill de = d;
        de.h = efill;
        st = eps_rounds(&de, t0, t1, &info, err);
    }
    dtree e = {.d = &d, .t0 = t0, .t1 = t1};
    double sinks = 0;
    if (!st) {
        DT_FOR_OWNED(&e, id) {
            member[id] = fill[id] > h[id];
            label[id] = UINT32_MAX;
            sinks += h[id] <= o->sea_level;
        }
        st = exchange_cells(&d, member, 1, err);
    }
    dlabel *lab = NULL;
    double *pairs = NULL;
    size_t nl = 0, np = 0;
    int bad = st != PG_OK;
    bad = bad || label_regions(&d, t0, t1, h, efill, member, label, area, &lab, &nl);
    if (!pg_mpi_max_int(m, bad)) bad = exchange_cells(&d, label, sizeof *label, err) != PG_OK;
    bad = bad || cross_pairs(&d, t0, t1, member, label, &pairs, &np);
    bad = pg_mpi_max_int(m, bad);
    size_t tl = 0, tp = 0;
    double *all_lab = bad ? NULL : gather_doubles(m, (const double *)lab, nl * 5, &tl, &bad);
    double *all_pairs = bad ? NULL : gather_doubles(m, pairs, np, &tp, &bad);
    double res[6] = {0};
    if (!bad && me == 0) {
        dlabel *L = (dlabel *)all_lab;
        size_t nL = tl / 5;
        qsort(L, nL, sizeof *L, cmp_dlabel);
        uint32_t *pr = malloc((tp + 1) * sizeof *pr);
        for (size_t k = 0; pr && k < tp; k++)
            pr[k] = (uint32_t)all_pairs[k];
        res[0] = pr ? join_labels(L, nL, pr, tp / 2) : -1;
        for (size_t i = 0; i < nL; i++) {
            res[1] += L[i].cells, res[2] += L[i].area, res[3] += L[i].volume;
            if (L[i].depth > res[4]) res[4] = L[i].depth;
        }
        free(pr);
    }
    if (!bad) MPI_Bcast(res, 6, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    sinks = bad ? 0 : pg_mpi_sum_double(m, sinks);
    out->depressions = (uint64_t)res[0], out->depression_cells = (uint64_t)res[1];
    out->depression_area_m2 = res[2], out->depression_volume_m3 = res[3];
    out->max_depth_m = res[4], out->sinks = (uint64_t)sinks;
    free(fill), free(efill), free(member), free(label), free(lab), free(pairs);
    free(all_lab), free(all_pairs);
    if (!st && (bad || res[0] < 0))
        st = pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory for statistics");
    return st;
}

#else

pg_status pg_mpi_pits_fill(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                           pg_mpi_pits_info *info, pg_error *err) {
    (void)m, (void)tiles, (void)n, (void)h, (void)o, (void)info;
    return pg_error_set(err, PG_ERR_RUNTIME, "this planetgen was built without MPI");
}

pg_status pg_mpi_pits_remove(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                             pg_mpi_pits_info *info, pg_error *err) {
    return pg_mpi_pits_fill(m, tiles, n, h, o, info, err);
}

pg_status pg_mpi_pits_stats(pg_mpi *m, int tiles, uint32_t n, const float *h, const pg_pits_opts *o,
                            const pg_pits_area *area, pg_pits_stats *out, pg_error *err) {
    (void)m, (void)tiles, (void)n, (void)h, (void)o, (void)area, (void)out;
    return pg_error_set(err, PG_ERR_RUNTIME, "this planetgen was built without MPI");
}

#endif
