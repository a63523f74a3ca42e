/* pg_pits_internal.h - machinery shared by the pit-removal algorithms (not public API).
 *
 * The flood priority is the pair (height, global id), packed into one uint64 so the
 * heap compares plain integers: the high 32 bits are the float's bits mapped to an
 * order-preserving unsigned integer, the low 32 bits the cell id. Equal heights
 * therefore pop in id order, which makes every result a pure function of the input.
 *
 * Cell states live in one byte per cell (PITS_OPEN/CLOSED/SINK/NODATA); a sink is
 * closed from the start and is never modified. */
#ifndef PG_PITS_INTERNAL_H
#define PG_PITS_INTERNAL_H

#include "planetgen/pg_pits.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

enum { PITS_OPEN = 0, PITS_CLOSED = 1, PITS_SINK = 2, PITS_NODATA = 3 };
/* Only inside the minimal epsilon-surface's flood (pg_pits_planchon2002_minimal_eps.c),
 * which turns them into PITS_CLOSED before it returns: a source not yet reached by the
 * flood, and a cell the flood has settled. */
enum { PITS_SOURCE = 4, PITS_DONE = 5 };

/* The rows of w cells that make up the topology's cells, for loops that walk them a row
 * at a time (each row's cells know their place on the face without a division). Every
 * cell is in one: blocks with cells after them are refused (pits_validate). */
static inline uint64_t pits_rows(const pg_pits_topo *t) {
    return t->w ? t->ncells / t->w : 0;
}

/* Whether a cell is inside its face (not on a face or grid border): its neighbours are
 * then id + pits_inner_offset(t, j), j in pg_pits_neighbours' order. */
static inline int pits_inner(const pg_pits_topo *t, uint32_t x, uint32_t y) {
    return x - 1u < t->w - 2u && y - 1u < t->h - 2u;
}

static inline int64_t pits_inner_offset(const pg_pits_topo *t, int j) {
    const int64_t w = t->w;
    const int64_t off[8] = {-w - 1, -w, -w + 1, -1, 1, w - 1, w, w + 1};
    return off[j];
}

static inline uint32_t pits_ord(float f) {
    uint32_t u;
    memcpy(&u, &f, 4);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

static inline uint64_t pits_key(float h, uint32_t id) {
    return ((uint64_t)pits_ord(h) << 32) | id;
}

static inline uint32_t pits_key_id(uint64_t k) {
    return (uint32_t)k;
}

/* The height a key was made from (the inverse of pits_ord). */
static inline float pits_key_height(uint64_t k) {
    uint32_t o = (uint32_t)(k >> 32), u = (o & 0x80000000u) ? (o & 0x7fffffffu) : ~o;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* nextafterf(v, +inf) and nextafterf(v, -inf) for non-NaN v, bit for bit, without the
 * library call (they run once per cell in the floods): the ordered bits of a float
 * step by one per ulp, except across zero, where both zeros go to the smallest
 * denormal of the other sign's side. */
static inline float pits_up(float v) {
    uint32_t u;
    memcpy(&u, &v, 4);
    if ((u & 0x7fffffffu) == 0)
        u = 1; /* +-0 -> +denorm_min */
    else if (!(u & 0x80000000u))
        u += u != 0x7f800000u; /* +inf stays */
    else
        u--; /* negative: towards zero (-denorm_min -> -0) */
    memcpy(&v, &u, 4);
    return v;
}

static inline float pits_down(float v) {
    uint32_t u;
    memcpy(&u, &v, 4);
    if ((u & 0x7fffffffu) == 0)
        u = 0x80000001u; /* +-0 -> -denorm_min */
    else if (u & 0x80000000u)
        u += u != 0xff800000u; /* -inf stays */
    else
        u--; /* positive: towards zero (denorm_min -> +0) */
    memcpy(&v, &u, 4);
    return v;
}

/* fmaxf and fminf for non-NaN arguments as glibc computes them (the second argument
 * wins ties, so max(+0, -0) is -0), inlined. */
static inline float pits_maxf(float a, float b) {
    return a > b ? a : b;
}

static inline float pits_minf(float a, float b) {
    return a < b ? a : b;
}

/* Room for `need` elements of elem bytes in the array a of capacity *cap (doubling,
 * from `first` when empty): returns the array, perhaps moved, or NULL when out of
 * memory (then a is still valid and *cap unchanged). */

/* ---- 4-ary min-heap of keys ---- */
typedef struct pits_heap {
    uint64_t *a;
    size_t n, cap;
    int oom;
} pits_heap;

void pits_heap_free(pits_heap *q);
void pits_heap_grow(pits_heap *q);
void pits_heap_heapify(pits_heap *q);

static inline void pits_heap_push(pits_heap *q, uint64_t k) {
    if (q->n == q->cap) {
        pits_heap_grow(q);
        if (q->oom) return;
    }
    size_t i = q->n++;
    while (i > 0) {
        size_t p = (i - 1) >> 2;
        if (q->a[p] <= k) break;
        q->a[i] = q->a[p];
        i = p;
    }
    q->a[i] = k;
}

static inline uint64_t pits_heap_pop(pits_heap *q) {
    uint64_t top = q->a[0], k = q->a[--q->n];
    size_t n = q->n, i = 0;
    for (;;) {
        size_t c = 4 * i + 1;
        if (c >= n) break;
        size_t best = c;
        size_t end = c + 4 < n ? c + 4 : n;
        for (size_t j = c + 1; j < end; j++)
            if (q->a[j] < q->a[best]) best = j;
        if (q->a[best] >= k) break;
        q->a[i] = q->a[best];
        i = best;
    }
    if (n) q->a[i] = k;
    return top;
}

/* ---- monotone radix heap of (height, id) ----
 *
 * For floods whose result does not depend on the order of equal heights (the minimal
 * fill and the minimal epsilon-surface are unique; the tiled fill's labels are
 * resolved by the label graph): the key is only the height's ordered bits
 * (pits_ord), and keys are popped in nondecreasing order while every push is at
 * least the last key popped (a Dijkstra or Priority-Flood front only rises).
 * Layout: bucket 0 holds the entries whose key equals `last` (the last key taken
 * out); bucket i >= 1 those whose key first differs from `last` in bit i - 1 from
 * the top, i.e. 32 - clz(key ^ last) = i. Entries are (key << 32 | id).
 * Invariant: every key >= last, so a bucket's entries all exceed those of the
 * buckets below it. Popping from an empty bucket 0 takes the first non-empty bucket,
 * makes its smallest key the new `last`, and spreads its entries into lower buckets
 * (each entry only ever moves down, at most 32 times, usually once or twice): a
 * sequential scan instead of a binary heap's log n cache misses per operation
 * (Ahuja, Mehlhorn, Orlin & Tarjan 1990, "Faster algorithms for the shortest path
 * problem", J. ACM 37(2):213-223, the one-level radix heap). Equal keys pop in no
 * particular order. */
typedef struct pits_rheap {
    uint64_t *b[33];
    size_t n[33], cap[33];
    size_t size;
    uint32_t min[33]; /* each non-empty bucket's smallest key */
    uint64_t used;    /* bit i: bucket i is not empty */
    uint32_t last;
    int oom;
} pits_rheap;

void pits_rheap_free(pits_rheap *r);
void pits_rheap_grow(pits_rheap *r, int bucket);
/* Frees an emptied bucket's storage, so that the buckets' capacities add up to about
 * the entries they hold, not to each bucket's largest size so far. */
void pits_rheap_release(pits_rheap *r, int bucket);

static inline int pits_rheap_bucket(uint32_t key, uint32_t last) {
    return key == last ? 0 : 32 - __builtin_clz(key ^ last);
}

static inline void pits_rheap_push(pits_rheap *r, uint32_t key, uint32_t id) {
    int i = pits_rheap_bucket(key, r->last);
    if (r->n[i] == r->cap[i]) {
        pits_rheap_grow(r, i);
        if (r->oom) return;
    }
    if (!r->n[i] || key < r->min[i]) r->min[i] = key;
    r->b[i][r->n[i]++] = (uint64_t)key << 32 | id;
    r->used |= 1ull << i;
    r->size++;
}

/* The first non-empty bucket above bucket 0 (r->size > r->n[0]). */
static inline int pits_rheap_first(const pits_rheap *r) {
    return __builtin_ctzll(r->used & ~1ull);
}

/* Refill bucket 0 from the first non-empty bucket (r->size > 0). */
static inline void pits_rheap_refill(pits_rheap *r) {
    const int i = pits_rheap_first(r);
    uint64_t *e = r->b[i];
    size_t n = r->n[i];
    r->last = r->min[i];
    r->n[i] = 0;
    r->used &= ~(1ull << i);
    for (size_t k = 0; k < n; k++) { /* every entry goes to a bucket below i */
        const uint32_t key = (uint32_t)(e[k] >> 32);
        int j = pits_rheap_bucket(key, r->last);
        if (r->n[j] == r->cap[j]) {
            pits_rheap_grow(r, j);
            if (r->oom) return; /* the caller stops on oom; entries may be lost */
        }
        if (!r->n[j] || key < r->min[j]) r->min[j] = key;
        r->b[j][r->n[j]++] = e[k];
        r->used |= 1ull << j;
    }
    if (r->cap[i] > 4096) pits_rheap_release(r, i); /* its entries now live below */
}

/* The smallest key (ordered bits) without removing it; the heap is not empty. It
 * leaves `last` alone: a flood that merges the heap with a FIFO of its own (the
 * minimal epsilon-surface) may take a smaller value from the FIFO next and push keys
 * below the heap's smallest, which must still be >= last. So an empty bucket 0 is
 * not refilled here: the first non-empty bucket's smallest key is the heap's, and
 * each bucket keeps its own (pushes lower it, a refill sets it anew). */
static inline uint32_t pits_rheap_top_key(const pits_rheap *r) {
    return r->n[0] ? r->last : r->min[pits_rheap_first(r)];
}

/* Removes one entry with the smallest key: returns (key << 32 | id). */
static inline uint64_t pits_rheap_pop(pits_rheap *r) {
    if (!r->n[0]) pits_rheap_refill(r);
    if (r->oom) return 0;
    r->size--;
    if (r->n[0] == 1) r->used &= ~1ull;
    return r->b[0][--r->n[0]];
}

/* ---- FIFO of ids, reset whenever it drains ---- */
typedef struct pits_fifo {
    uint32_t *a;
    size_t head, tail, cap;
    int oom;
} pits_fifo;

void pits_fifo_free(pits_fifo *f);
void pits_fifo_grow(pits_fifo *f);

static inline void pits_fifo_push(pits_fifo *f, uint32_t id) {
    if (f->tail == f->cap) {
        pits_fifo_grow(f);
        if (f->oom) return;
    }
    f->a[f->tail++] = id;
}

static inline int pits_fifo_empty(const pits_fifo *f) {
    return f->head == f->tail;
}

static inline uint32_t pits_fifo_pop(pits_fifo *f) {
    uint32_t id = f->a[f->head++];
    if (f->head == f->tail) f->head = f->tail = 0;
    return id;
}

/* ---- the shared start of every flood ---- */

/* Validates o against t, allocates state[ncells], marks sinks (sea level, lakes,
 * open edges, no-data; else the lowest cell), replaces no-data heights by -inf and
 * pushes every sink that touches a non-sink into the heap. */
pg_status pits_begin(const pg_pits_topo *t, float *h, const pg_pits_opts *o, uint8_t **state,
                     pits_heap *q, uint64_t *nsinks, pg_error *err);

/* (q may be NULL: no seeding, for floods that seed themselves.) */

/* Puts the no-data value back into the cells marked PITS_NODATA. */
void pits_end(const pg_pits_topo *t, float *h, const pg_pits_opts *o, const uint8_t *state);

pg_status pits_validate(const pg_pits_topo *t, const pg_pits_opts *o, pg_error *err);

/* ---- the minimal epsilon-surface (pg_pits_planchon2002_minimal_eps.c) ---- */

/* One Dijkstra flood for W(c) = max(floor(c), up(min over neighbours W(n))).
 * w: the sources' values (read through their keys) and, for every cell the flood may
 * set, a start value (+inf, or an upper bound); out: W on those cells. settable(ctx,
 * id) says whether the flood may set a cell (not a sink, inside the region); NULL:
 * st is the state array, in which the cells to set are PITS_OPEN (w = +inf) or
 * PITS_SOURCE (the sources, w their value) and the others are never read for w; the
 * flood leaves its cells PITS_CLOSED or PITS_DONE. q holds
 * the sources' keys (height -inf for sinks), in any order (q->a is read, then freed:
 * q is empty on return). Returns nonzero when out of memory. */
typedef struct pits_meps {
    const pg_pits_topo *t;
    float *w;
    const float *floor;
    int (*settable)(const void *ctx, uint32_t id);
    const void *ctx;
    int plain;   /* up(w) = w: the minimal (plain) fill instead */
    float *fill; /* NULL, or each set cell's max(floor, fill of the cell that set it) */
    uint8_t *st; /* without settable: the cells' states, PITS_OPEN for those to set */
} pits_meps;

int pits_meps_flood(pits_meps *m, pits_heap *q);

/* The minimal epsilon-surface of h (eps = 0: the minimal fill) into w, h unchanged:
 * st and q as pits_begin left them (sinks marked, the sinks touching non-sinks
 * queued; pits_seed queues them again); on return every non-sink cell is
 * PITS_CLOSED. o: the options pits_begin marked st with, when st holds exactly its
 * sinks, so that the surface may come from a parallel fill instead of the flood
 * (same bits); NULL: the flood. Returns nonzero when out of memory, and then st may
 * still hold the flood's own states (PITS_SOURCE, PITS_DONE): fit only to be freed. */
int pits_meps_compute(const pg_pits_topo *t, const float *h, const pg_pits_opts *o, uint8_t *st,
                      const pits_heap *q, float *w, int eps);
/* The same with eps = 1, and the minimal fill of h along the flood's tree into fill;
 * *exact says whether it checked out as the minimal fill (else the caller floods for
 * it). Returns nonzero when out of memory. */
int pits_meps_compute_fill(const pg_pits_topo *t, const float *h, const pg_pits_opts *o,
                           uint8_t *st, const pits_heap *q, float *w, float *fill, int *exact);
/* The epsilon-surface of a plain fill's input from the fill f (states st from
 * pits_begin on f) into w, by distances on f's flats, checked against (1): 0 when w
 * is exact, nonzero when the check failed or memory ran out (then flood instead). */
int pits_meps_from_fill(const pg_pits_topo *t, const float *f, const uint8_t *st, float *w);
/* Whether w solves (1) with floor f at every cell of the flood (st below PITS_SINK;
 * sinks count as -inf): 0 when it does, so that w is the epsilon-surface of any input
 * between f's input and w. Sets w = f at the sinks and no-data cells. Parallel. */
int pits_meps_check(const pg_pits_topo *t, const float *f, const uint8_t *st, float *w);
/* Lowers fill, a supersolution of the minimal fill's equation whose every value is the
 * highest ground on some path to a sink (a fill along any tree towards the sinks), to
 * the minimal fill of h, touching only the cells above it (st as pits_begin marked it,
 * OPEN or CLOSED elsewhere). Precondition, not checked: fill is nowhere below the
 * minimal fill (path values never are). 0 when done and checked (at once, after one
 * parallel scan, when fill already is the minimal fill); -1 when some cell lies
 * below its equation's right side (not a supersolution) or memory ran out (fill is then
 * partly lowered). */
int pits_fill_repair(const pg_pits_topo *t, const float *h, const uint8_t *st, float *fill);
/* Queue every sink with a non-sink (PITS_OPEN) neighbour, as pits_begin does. */
void pits_seed(const pg_pits_topo *t, const uint8_t *st, pits_heap *q);
/* fill = h at every cell that is not OPEN: the minimal fill there, for the floods that
 * record the rest as they pop (not every sink is queued, so not every sink pops). */
void pits_fill_sinks(const pg_pits_topo *t, const float *h, const uint8_t *st, float *fill);

/* ---- the descent tree's tokens (pg_pits_descent_breach.c) ---- */

/* A cell of height hx receives the token (v, len): returns 1 when the cell is carved
 * to *to (<= hx) and passes (*pass, *plen) to its parent, 0 when the token stops
 * there (lower ground, a limit) or there is none (v = +inf). */
static inline int pits_token(float hx, float v, uint32_t len, double max_depth, double max_length,
                             float *to, float *pass, uint32_t *plen) {
    if (!(v <= hx)) return 0;
    uint32_t l = v < hx ? len + 1 : len;
    if ((double)hx - (double)v > max_depth || (double)l > max_length) return 0;
    *to = v;
    *pass = pits_down(v);
    *plen = l;
    return 1;
}

/* Where tokens meet, the lowest wins (ties: the shorter channel). */
static inline void pits_token_merge(float *v, uint32_t *len, float pass, uint32_t plen) {
    if (pass < *v || (pass == *v && plen < *len)) {
        *v = pass;
        *len = plen;
    }
}

/* ---- depression counts (pg_pits_stats.c) ---- */

/* Counts the 8-connected regions of the cells with dep[] == 1 into st (cells, area,
 * volume fill - h, deepest), marking them 2. Returns nonzero when out of memory. */
int pits_count_regions(const pg_pits_topo *t, const float *h, uint8_t *dep, const float *fill,
                       const pg_pits_area *area, pg_pits_stats *st);
/* The figures of pg_pits_stats_compute from h's minimal fill. */
pg_status pits_stats_from_fill(const pg_pits_topo *t, const float *h, const float *fill,
                               const pg_pits_area *area, uint64_t nsinks, pg_pits_stats *st,
                               pg_error *err);
/* The epsilon-surface of a minimal fill f's input into w, from f's flats
 * (pits_meps_from_fill), and f's sink count: *exact = 1 when the surface checks out,
 * and w is then the epsilon-fill's bit for bit; 0 leaves w undefined for the caller to
 * flood. f is left as it was. */
pg_status pits_eps_from_fill(const pg_pits_topo *t, float *f, const pg_pits_opts *o, float *w,
                             int *exact, uint64_t *nsinks, pg_error *err);
/* Whether h (states st from pits_begin) certainly has no depression: every OPEN cell
 * has a neighbour that is not OPEN, or one lower in the potential (order when not NULL,
 * else p) whose h is not higher. */
int pits_drains_by(const pg_pits_topo *t, const float *h, const uint8_t *st, const float *p,
                   const uint32_t *order);

/* The algorithms; h is modified in place. order (ncells, zeroed by the caller, or
 * NULL): for each non-sink cell, the place (from 1) in which the flood closed it, a
 * potential for pits_drains_by; the sinks keep their 0. */
pg_status pits_priority_flood_barnes2014(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                         pg_pits_result *res, pg_error *err, uint32_t *order);
pg_status pits_minimal_eps_planchon2002(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                        pg_pits_result *res, pg_error *err);
/* The same epsilon-fill, and with it the minimal (plain) fill of its input into fill
 * (ncells floats), along the flood's own tree: *exact = 1 when that checks out
 * (the file's fill_check), else fill is undefined and the caller floods. in: a copy of
 * h as given, which the flood reads while it writes the surface into h. */
pg_status pits_minimal_eps_planchon2002_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                             pg_pits_result *res, const float *in, float *fill,
                                             int *exact, pg_error *err);
pg_status pits_breach_descent(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                              pg_pits_result *res, pg_error *err);
/* The same breach, and with it the minimal fill of its input into fill (ncells
 * floats): without epsilon it is the tree's own first flood; with it, the epsilon
 * flood's tree gives it, *exact = 1 when that checks out, else fill is undefined. */
pg_status pits_breach_descent_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                   pg_pits_result *res, float *fill, int *exact, pg_error *err);
pg_status pits_breach_soille2004(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                 pg_pits_result *res, pg_error *err);
/* The same breach, and with it the minimal fill of its input into fill (ncells
 * floats; exact: no check needed, the file says why). */
pg_status pits_breach_soille2004_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                      pg_pits_result *res, float *fill, pg_error *err);
/* Whether the plain fill runs in tiles (Barnes 2016; pg_pits.c): several threads or
 * o->tile_rows set; the tiled fill's labels (< ncells + one tile) must fit in 32 bits. */
int pits_tiled_fill(const pg_pits_topo *t, const pg_pits_opts *o);
pg_status pits_parallel_fill_barnes2016(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                        pg_pits_result *res, pg_error *err);
pg_status pits_hybrid_lindsay2016(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                  pg_pits_result *res, pg_error *err);
/* The same hybrid, and with it the minimal fill of its input into fill (ncells
 * floats; exact as Soille's, the file says why). */
pg_status pits_hybrid_lindsay2016_fill(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                       pg_pits_result *res, float *fill, pg_error *err);

#endif
