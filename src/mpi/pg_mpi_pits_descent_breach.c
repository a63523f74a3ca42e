/* pg_mpi_pits_descent_breach.c - breach and hybrid along the descent tree, across ranks.
 *
 * Source: the single-process form, src/pits/pg_pits_descent_breach.c (Soille's carving,
 * P. Soille (2004), "Optimal removal of spurious pits in grid digital elevation models",
 * Water Resources Research 40:W12509, and Lindsay's limits, J. B. Lindsay (2016),
 * "Efficient hybrid breaching-filling sink removal methods for flow path enforcement in
 * digital elevation models", Hydrological Processes 30(6):846-857, along the descent
 * tree of the minimal epsilon-surface W; docs/pits.md).
 * The tree (each cell's parent: the neighbour with the smallest (W, id)) and the pits
 * are computed by each rank for its own cells from a ring of W and of the heights; W
 * comes from the distributed epsilon-fill (pg_mpi_pits_barnes2016_fill.c). The tokens
 * then flow children-first as in the serial pass, in rounds: each round every rank
 * sweeps its cells, taking the tokens its ring cells passed into them last round, and
 * sends the tokens its cells pass to other ranks' cells. The hybrid then runs the
 * distributed fill on the carved heights.
 * Every array is tile-local (pg_mpi_comm.h); the tie-break of the tree compares 64-bit
 * global ids, and the ring's parents cross ranks as global ids.
 * Preconditions: o->descent and o->epsilon, a sea level (the sinks), no lakes, no
 * no-data; only the rank's own tiles of h need be valid.
 * Why it is correct: tokens only get lower from round to round (a new token can only
 * win), so the rounds stop, and then every cell holds the tree recursion's unique
 * value: the serial result, bit for bit (docs/mpi.md, "Pit removal across ranks"). */
#include "pg_mpi_pits.h"

#include <stdlib.h>

#ifdef PG_HAVE_MPI

#include "pg_pits_internal.h"

#include <string.h>

/* A token as a ring cell passes it: its value and its channel length (a float, exact
 * below 2^24, so the pair is one 8-byte word to exchange). */
typedef struct dtoken {
    float pass, len;
} dtoken;

typedef struct dtree {
    pg_mpi_pits_grid *d; /* h: the heights before carving (owned and ring), carved last */
    uint32_t *parent;    /* owned: local id of the parent (UINT32_MAX: none); ring: that of
                            its parent when it is an owned cell, else UINT32_MAX */
    float *v;            /* owned: incoming token */
    uint32_t *len;       /* owned: its channel length; hybrid only (without a length limit
                            the lengths change no height, so breach keeps none) */
    uint8_t *pending;    /* owned: owned children not yet swept */
    uint8_t *pit;        /* owned: starts a token */
    dtoken *ring;        /* ring (nring): the token each ring cell passed last round */
    dtoken *got;         /* ring: this round's, as received */
    double max_depth, max_length;
} dtree;

static int owned(const dtree *e, uint32_t l) {
    return l < e->d->g->nown;
}

#define DT_FOR_OWNED(e, id) PG_MPI_FOR_OWNED((e)->d->g, id)

/* Parents and pits of the owned cells: the neighbour with the smallest (W, global id);
 * W in w (owned and ring), heights in d->h. */
static void dt_tree(dtree *e, const float *w) {
    const pg_mpi_pits_grid *d = e->d;
    const pg_mpi_tiling *g = d->g;
    const float *h = d->h;
    uint32_t nb[8];
    DT_FOR_OWNED(e, id) {
        e->parent[id] = UINT32_MAX, e->pit[id] = 0;
        if (h[id] <= d->sea) continue;
        int k = pg_pits_neighbours(&g->t, id, nb), lower = 0;
        uint32_t best_ord = UINT32_MAX, best = UINT32_MAX;
        uint64_t best_gid = UINT64_MAX;
        for (int j = 0; j < k; j++) {
            int sk = h[nb[j]] <= d->sea;
            uint32_t ord = pits_ord(sk ? -INFINITY : w[nb[j]]);
            lower |= sk || h[nb[j]] < h[id];
            if (ord > best_ord) continue;
            uint64_t gid = pg_mpi_gid(g, nb[j]); /* only on a tie or a new best */
            if (ord < best_ord || gid < best_gid) best_ord = ord, best_gid = gid, best = nb[j];
        }
        e->parent[id] = best;
        e->pit[id] = !lower;
    }
    for (uint32_t k = 0; k < g->nring; k++) /* no token from the ring before an exchange */
        e->ring[k] = (dtoken){INFINITY, 0};
}

/* The ring's parents: the owners send them as global ids; each becomes the local id
 * of one of this rank's cells, or UINT32_MAX. */
static void pack_parent(const void *ctx, uint32_t l, void *out) {
    const dtree *e = ctx;
    uint64_t p = e->parent[l] == UINT32_MAX ? UINT64_MAX : pg_mpi_gid(e->d->g, e->parent[l]);
    memcpy(out, &p, sizeof p);
}

static pg_status dt_ring_parents(dtree *e, pg_error *err) {
    const pg_mpi_tiling *g = e->d->g;
    uint64_t *rp = malloc(((size_t)g->nring + 1) * sizeof *rp);
    pg_status st = rp ? pg_mpi_ring_exchange_packed(g, sizeof *rp, pack_parent, e, rp, err)
                      : pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (parents)");
    for (uint32_t k = 0; !st && k < g->nring; k++) {
        uint32_t p = UINT32_MAX;
        if (rp[k] != UINT64_MAX && rp[k] >= g->base && (rp[k] - g->base) % g->stride == 0) {
            p = pg_mpi_local_of(g, (rp[k] - g->base) / g->stride);
            if (p != UINT32_MAX && !owned(e, p)) p = UINT32_MAX;
        }
        e->parent[g->nown + k] = p;
    }
    free(rp);
    return st;
}

/* The token an owned cell passes to its parent, from its incoming token: the same
 * function the sweep applies, so nothing per cell needs keeping for the exchange. */
static dtoken dt_pass(const dtree *e, uint32_t id, float *to) {
    dtoken t = {INFINITY, 0};
    uint32_t plen = 0;
    float pass = INFINITY;
    if (e->parent[id] != UINT32_MAX && pits_token(e->d->h[id], e->v[id], e->len ? e->len[id] : 0,
                                                  e->max_depth, e->max_length, to, &pass, &plen))
        t.pass = pass, t.len = (float)plen;
    return t;
}

static void pack_token(const void *ctx, uint32_t l, void *out) {
    float to;
    dtoken t = dt_pass(ctx, l, &to);
    memcpy(out, &t, sizeof t);
}

/* Where tokens meet, the lowest wins (pits_token_merge); without lengths, the value. */
static void dt_merge(dtree *e, uint32_t id, float pass, uint32_t plen) {
    if (e->len)
        pits_token_merge(&e->v[id], &e->len[id], pass, plen);
    else if (pass < e->v[id])
        e->v[id] = pass;
}

/* One round, from the ring's tokens of the last one: every owned cell's incoming token.
 * Returns -1 when out of memory, else 0. */
static int dt_round(dtree *e) {
    const pg_mpi_pits_grid *d = e->d;
    const float *h = d->h;
    const uint32_t nown = d->g->nown;
    uint32_t nb[8];
    DT_FOR_OWNED(e, id) {
        e->v[id] = e->pit[id] ? h[id] : INFINITY;
        if (e->len) e->len[id] = 0;
        e->pending[id] = 0;
    }
    DT_FOR_OWNED(e, id) { /* children: owned ones count, ring ones bring last round's token */
        if (e->parent[id] == UINT32_MAX) continue;
        if (owned(e, e->parent[id]) && h[e->parent[id]] > d->sea) e->pending[e->parent[id]]++;
        int k = pg_pits_neighbours(&d->g->t, id, nb);
        for (int j = 0; j < k; j++)
            if (!owned(e, nb[j]) && e->parent[nb[j]] == id && e->ring[nb[j] - nown].pass < INFINITY)
                dt_merge(e, id, e->ring[nb[j] - nown].pass, (uint32_t)e->ring[nb[j] - nown].len);
    }
    pits_fifo f = {0};
    DT_FOR_OWNED(e, id) {
        if (e->parent[id] != UINT32_MAX && e->pending[id] == 0) pits_fifo_push(&f, id);
    }
    while (!pits_fifo_empty(&f) && !f.oom) {
        uint32_t x = pits_fifo_pop(&f), p = e->parent[x];
        float to;
        dtoken t = dt_pass(e, x, &to);
        if (!owned(e, p) || h[p] <= d->sea) continue;
        if (t.pass < INFINITY) dt_merge(e, p, t.pass, (uint32_t)t.len);
        if (--e->pending[p] == 0) pits_fifo_push(&f, p);
    }
    int oom = f.oom;
    pits_fifo_free(&f);
    return oom ? -1 : 0;
}

/* Breach only (no limits): a ring cell's lower token into its owned parent x, carried
 * on down the tree while it lowers what each cell passes. Without limits, what a cell
 * passes only falls as its incoming token falls, and its incoming token is the least
 * of its children's, so lowering it is the whole update a full round would make. */
static void dt_lower(dtree *e, uint32_t x, float pass) {
    const pg_mpi_pits_grid *d = e->d;
    while (x != UINT32_MAX && owned(e, x) && d->h[x] > d->sea && pass < e->v[x]) {
        float to;
        float before = dt_pass(e, x, &to).pass;
        e->v[x] = pass;
        pass = dt_pass(e, x, &to).pass;
        if (!(pass < before)) return;
        x = e->parent[x];
    }
}

/* The ring's tokens after a round; *changed when any differs from the last round's.
 * A round is a function of the ring's tokens alone, so when no rank's ring changed the
 * next round would repeat this one: the tokens are final. Breach applies the change
 * here (dt_lower): tokens only fall from round to round, so the next round's result is
 * this one's with the lower ring tokens carried down. */
static pg_status dt_ring_tokens(dtree *e, int *changed, pg_error *err) {
    const pg_mpi_tiling *g = e->d->g;
    pg_status st = pg_mpi_ring_exchange_packed(g, sizeof(dtoken), pack_token, e, e->got, err);
    *changed = 0;
    for (uint32_t k = 0; !st && k < g->nring; k++) {
        if (e->got[k].pass == e->ring[k].pass && e->got[k].len == e->ring[k].len) continue;
        *changed = 1;
        if (!e->len && e->got[k].pass < e->ring[k].pass)
            dt_lower(e, e->parent[g->nown + k], e->got[k].pass);
        e->ring[k] = e->got[k];
    }
    return st;
}

/* The first round sweeps every cell; then breach carries each change down as it
 * arrives, and the hybrid (whose limits can stop a lower token) sweeps again. */
static pg_status dt_rounds(dtree *e, pg_mpi_pits_info *info, pg_error *err) {
    int bad = 0, more = 1, sweep = 1;
    while (!(bad = pg_mpi_max_int(e->d->g->m, bad)) && more) {
        int changed = 0;
        bad = (sweep && dt_round(e) < 0) || dt_ring_tokens(e, &changed, err);
        sweep = e->len != NULL;
        more = pg_mpi_max_int(e->d->g->m, changed);
        info->breach_rounds++;
    }
    return bad ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (breach rounds)")
               : PG_OK;
}

/* The carving: every owned cell that a final token lowers takes its value. */
static void dt_carve(dtree *e) {
    DT_FOR_OWNED(e, id) {
        float to;
        if (dt_pass(e, id, &to).pass < INFINITY) e->d->h[id] = to;
    }
}

/* W, the minimal epsilon-surface of this rank's tiles of the planet array h, in a new
 * local array (ring current); NULL when out of memory or on error. */
static float *dt_surface(const pg_mpi_tiling *g, const float *h, const pg_pits_opts *o,
                         pg_mpi_pits_info *info, pg_status *st, pg_error *err) {
    pg_mpi_pits_grid w = {g, malloc((g->nloc + 1) * sizeof(float)), o->sea_level};
    *st = pg_mpi_max_int(g->m, !w.h) ? PG_ERR_NOMEM : PG_OK;
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL, f.epsilon = true;
    if (!*st) {
        pg_mpi_tiling_load(g, h, w.h);
        pg_mpi_pits_info fi = {0};
        *st = pg_mpi_pits_fill_local(&w, &f, &fi, err);
        info->eps_rounds = fi.eps_rounds, info->max_label = fi.max_label;
        info->flood_seconds = fi.flood_seconds, info->solve_seconds = fi.solve_seconds;
        info->eps_seconds = fi.eps_seconds, info->edges = fi.edges, info->labels = fi.labels;
    }
    if (*st) free(w.h), w.h = NULL;
    return w.h;
}

/* h: the planet-sized heights, of which this rank's tiles are read and carved. The
 * peak, per owned cell: W and the fill's buffers (13 bytes), then W, the heights, the
 * parents and pits (13), then the heights, parents, pits, tokens and counts (14; 18
 * with the hybrid's lengths); the rings' arrays are small. */
static pg_status dt_run(const pg_mpi_tiling *g, float *h, const pg_pits_opts *o,
                        pg_mpi_pits_info *info, pg_error *err) {
    const size_t nc = g->nloc + 1, no = g->nown + 1, nr = (size_t)g->nring + 1;
    pg_status st;
    float *w = dt_surface(g, h, o, info, &st, err);
    pg_mpi_pits_grid d = {g, NULL, o->sea_level};
    dtree e = {&d, NULL, NULL, NULL, NULL, NULL, NULL, NULL, INFINITY, INFINITY};
    if (o->method == PG_PITS_HYBRID) e.max_depth = o->max_depth, e.max_length = o->max_length;
    if (!st) {
        d.h = malloc(nc * sizeof *d.h), e.parent = malloc(nc * sizeof(uint32_t));
        e.pit = malloc(no), e.ring = malloc(nr * sizeof(dtoken));
        e.got = malloc(nr * sizeof(dtoken));
        if (pg_mpi_max_int(g->m, !d.h || !e.parent || !e.pit || !e.ring || !e.got))
            st = PG_ERR_NOMEM;
    }
    if (!st) {
        pg_mpi_tiling_load(g, h, d.h);
        st = pg_mpi_ring_exchange(g, d.h, sizeof *d.h, err); /* the ring's heights */
    }
    if (!st) dt_tree(&e, w);
    free(w), w = NULL;
    if (!st) st = dt_ring_parents(&e, err);
    if (!st) {
        e.v = malloc(no * sizeof(float)), e.pending = malloc(no);
        if (o->method == PG_PITS_HYBRID) e.len = malloc(no * sizeof(uint32_t));
        if (pg_mpi_max_int(g->m, !e.v || !e.pending || (o->method == PG_PITS_HYBRID && !e.len)))
            st = PG_ERR_NOMEM;
    }
    if (!st) st = dt_rounds(&e, info, err);
    if (!st) dt_carve(&e);
    free(e.parent), free(e.v), free(e.len), free(e.pending), free(e.pit), free(e.ring), free(e.got);
    if (!st && o->method == PG_PITS_HYBRID) { /* fill what no channel drained */
        pg_pits_opts f = *o;
        f.method = PG_PITS_FILL;
        pg_mpi_pits_info fi = {0};
        st = pg_mpi_pits_fill_local(&d, &f, &fi, err);
    }
    if (!st) pg_mpi_tiling_store(g, d.h, h);
    free(d.h);
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
    pg_mpi_tiling g;
    pg_status st = pg_mpi_tiling_init(&g, m, tiles, n, err);
    if (st) return st;
    memset(info, 0, sizeof *info);
    double t_start = MPI_Wtime();
    st = dt_run(&g, h, o, info, err);
    info->breach_seconds = MPI_Wtime() - t_start;
    pg_mpi_tiling_free(&g);
    return st;
}

#else

pg_status pg_mpi_pits_remove(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                             pg_mpi_pits_info *info, pg_error *err) {
    return pg_mpi_pits_fill(m, tiles, n, h, o, info, err);
}

#endif
