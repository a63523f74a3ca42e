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

typedef struct dtree {
    pg_mpi_pits_grid *d;
    const float *orig; /* the heights before carving (owned and ring) */
    uint32_t *parent;  /* owned: local id of the parent (UINT32_MAX: none); ring: that of
                          its parent when it is an owned cell, else UINT32_MAX */
    float *pass;       /* token each cell passes to its parent, +inf for none */
    float *plen;       /* its channel length (a float, exact below 2^24, to share it) */
    float *v;          /* owned: incoming token */
    uint32_t *len;     /* owned: its channel length */
    uint8_t *pending;  /* owned: owned children not yet swept */
    uint8_t *pit;      /* owned: starts a token */
    double max_depth, max_length;
} dtree;

static int owned(const dtree *e, uint32_t l) {
    return l < e->d->g->nown;
}

#define DT_FOR_OWNED(e, id) PG_MPI_FOR_OWNED((e)->d->g, id)

/* Parents and pits of the owned cells: the neighbour with the smallest (W, global id);
 * W in w (owned and ring), heights in orig. */
static void dt_tree(dtree *e, const float *w) {
    const pg_mpi_pits_grid *d = e->d;
    const pg_mpi_tiling *g = d->g;
    uint32_t nb[8];
    DT_FOR_OWNED(e, id) {
        e->pass[id] = INFINITY, e->plen[id] = 0, e->parent[id] = UINT32_MAX, e->pit[id] = 0;
        if (e->orig[id] <= d->sea) continue;
        int k = pg_pits_neighbours(&g->t, id, nb), lower = 0;
        uint32_t best_ord = UINT32_MAX, best = UINT32_MAX;
        uint64_t best_gid = UINT64_MAX;
        for (int j = 0; j < k; j++) {
            int sk = e->orig[nb[j]] <= d->sea;
            uint32_t ord = pits_ord(sk ? -INFINITY : w[nb[j]]);
            lower |= sk || e->orig[nb[j]] < e->orig[id];
            if (ord > best_ord) continue;
            uint64_t gid = pg_mpi_gid(g, nb[j]); /* only on a tie or a new best */
            if (ord < best_ord || gid < best_gid) best_ord = ord, best_gid = gid, best = nb[j];
        }
        e->parent[id] = best;
        e->pit[id] = !lower;
    }
    for (size_t l = g->nown; l < g->nloc; l++) /* no token from the ring before an exchange */
        e->pass[l] = INFINITY, e->plen[l] = 0;
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

/* One round: returns -1 when out of memory, else whether an owned cell's token changed. */
static int dt_round(dtree *e, float *h) {
    const pg_mpi_pits_grid *d = e->d;
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
        int k = pg_pits_neighbours(&d->g->t, id, nb);
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
    while (!(bad = pg_mpi_max_int(e->d->g->m, bad)) && more) {
        int r = dt_round(e, h);
        bad = r < 0 || pg_mpi_ring_exchange(e->d->g, e->pass, sizeof *e->pass, err) ||
              pg_mpi_ring_exchange(e->d->g, e->plen, sizeof *e->plen, err);
        more = pg_mpi_max_int(e->d->g->m, r > 0);
        info->breach_rounds++;
    }
    return bad ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (breach rounds)")
               : PG_OK;
}

/* d->h: the local heights (ring not yet current). Peak: the heights, orig and W (12
 * bytes a cell) during the epsilon-fill, then heights, orig and the tree's arrays. */
static pg_status dt_run(pg_mpi_pits_grid *d, const pg_pits_opts *o, pg_mpi_pits_info *info,
                        pg_error *err) {
    const size_t nc = d->g->nloc + 1, no = d->g->nown + 1;
    float *orig = malloc(nc * sizeof *orig), *w = malloc(nc * sizeof *w);
    dtree e = {d, orig, NULL, NULL, NULL, NULL, NULL, NULL, NULL, INFINITY, INFINITY};
    if (o->method == PG_PITS_HYBRID) e.max_depth = o->max_depth, e.max_length = o->max_length;
    pg_status st = pg_mpi_max_int(d->g->m, !orig || !w) ? PG_ERR_NOMEM : PG_OK;
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL, f.epsilon = true;
    if (!st) st = pg_mpi_ring_exchange(d->g, d->h, sizeof *d->h, err); /* the ring's heights */
    if (!st) {
        memcpy(orig, d->h, d->g->nloc * sizeof *orig);
        memcpy(w, d->h, d->g->nloc * sizeof *w);
        pg_mpi_pits_info fi = {0};
        pg_mpi_pits_grid dw = {d->g, w, d->sea};
        st = pg_mpi_pits_fill_local(&dw, &f, &fi, err); /* W; its ring too */
        info->eps_rounds = fi.eps_rounds, info->max_label = fi.max_label;
    }
    if (!st) {
        e.parent = malloc(nc * sizeof(uint32_t)), e.pass = malloc(nc * sizeof(float));
        e.plen = malloc(nc * sizeof(float)), e.pit = malloc(no);
        if (pg_mpi_max_int(d->g->m, !e.parent || !e.pass || !e.plen || !e.pit)) st = PG_ERR_NOMEM;
    }
    if (!st) dt_tree(&e, w);
    free(w), w = NULL;
    if (!st) st = dt_ring_parents(&e, err);
    if (!st) {
        e.v = malloc(no * sizeof(float)), e.len = malloc(no * sizeof(uint32_t));
        e.pending = malloc(no);
        if (pg_mpi_max_int(d->g->m, !e.v || !e.len || !e.pending)) st = PG_ERR_NOMEM;
    }
    if (!st) st = dt_rounds(&e, d->h, info, err);
    free(orig), free(e.parent), free(e.pass), free(e.plen), free(e.v), free(e.len);
    free(e.pending), free(e.pit);
    if (!st && o->method == PG_PITS_HYBRID) { /* fill what no channel drained */
        f.epsilon = o->epsilon;
        pg_mpi_pits_info fi = {0};
        st = pg_mpi_pits_fill_local(d, &f, &fi, err);
    }
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
    pg_mpi_pits_grid d = {&g, malloc((g.nloc + 1) * sizeof(float)), o->sea_level};
    if (pg_mpi_max_int(m, !d.h)) {
        free(d.h), pg_mpi_tiling_free(&g);
        return pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory");
    }
    memset(info, 0, sizeof *info);
    pg_mpi_tiling_load(&g, h, d.h);
    double t_start = MPI_Wtime();
    st = dt_run(&d, o, info, err);
    info->breach_seconds = MPI_Wtime() - t_start;
    if (!st) pg_mpi_tiling_store(&g, d.h, h);
    free(d.h);
    pg_mpi_tiling_free(&g);
    return st;
}

#else

pg_status pg_mpi_pits_remove(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                             pg_mpi_pits_info *info, pg_error *err) {
    return pg_mpi_pits_fill(m, tiles, n, h, o, info, err);
}

#endif
