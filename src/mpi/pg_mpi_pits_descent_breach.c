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
    return pg_mpi_owned(&e->d->g, id);
}

#define DT_FOR_OWNED(e, id) PG_MPI_FOR_OWNED(&(e)->d->g, id)

/* Parents and pits of the owned cells; W in w (owned and ring), heights in orig. */
static void dt_tree(dtree *e, const float *w) {
    const pg_mpi_pits_grid *d = e->d;
    uint32_t nb[8];
    DT_FOR_OWNED(e, id) {
        e->pass[id] = INFINITY, e->plen[id] = 0, e->parent[id] = UINT32_MAX;
        if (e->orig[id] <= d->sea) continue;
        int k = pg_pits_neighbours(d->g.t, id, nb), lower = 0;
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
        int k = pg_pits_neighbours(d->g.t, id, nb);
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
    while (!(bad = pg_mpi_max_int(e->d->g.m, bad)) && more) {
        int r = dt_round(e, h);
        bad = r < 0 || pg_mpi_ring_exchange(&e->d->g, e->pass, sizeof *e->pass, err) ||
              pg_mpi_ring_exchange(&e->d->g, e->plen, sizeof *e->plen, err);
        more = pg_mpi_max_int(e->d->g.m, r > 0);
        info->breach_rounds++;
    }
    return bad ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (breach rounds)")
               : PG_OK;
}

static pg_status dt_run(pg_mpi_pits_grid *d, const pg_pits_opts *o, pg_mpi_pits_info *info,
                        pg_error *err) {
    const size_t nc = d->g.t->ncells;
    float *orig = malloc(nc * sizeof *orig), *w = malloc(nc * sizeof *w);
    dtree e = {d,
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
    pg_status st = pg_mpi_max_int(d->g.m, oom) ? PG_ERR_NOMEM : PG_OK;
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL, f.epsilon = true;
    if (!st) st = pg_mpi_ring_exchange(&d->g, d->h, sizeof *d->h, err); /* the ring's heights */
    if (!st) {
        memcpy(orig, d->h, nc * sizeof *orig);
        memcpy(w, d->h, nc * sizeof *w);
        pg_mpi_pits_info fi = {0};
        st = pg_mpi_pits_fill(d->g.m, d->g.T, d->g.n, w, &f, &fi, err); /* W; its ring too */
        if (!st) st = pg_mpi_ring_exchange(&d->g, w, sizeof *w, err);
        info->eps_rounds = fi.eps_rounds;
    }
    if (!st) dt_tree(&e, w);
    if (!st) st = pg_mpi_ring_exchange(&d->g, e.parent, sizeof *e.parent, err);
    if (!st) st = dt_rounds(&e, d->h, info, err);
    if (!st && o->method == PG_PITS_HYBRID) { /* fill what no channel drained */
        f.epsilon = o->epsilon;
        pg_mpi_pits_info fi = {0};
        st = pg_mpi_pits_fill(d->g.m, d->g.T, d->g.n, d->h, &f, &fi, err);
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
    pg_mpi_pits_grid d;
    pg_status st = pg_mpi_pits_grid_init(&d, &topo, m, tiles, n, h, o, err);
    if (st) return st;
    memset(info, 0, sizeof *info);
    double t_start = MPI_Wtime();
    st = dt_run(&d, o, info, err);
    info->breach_seconds = MPI_Wtime() - t_start;
    return st;
}

#else

pg_status pg_mpi_pits_remove(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                             pg_mpi_pits_info *info, pg_error *err) {
    return pg_mpi_pits_fill(m, tiles, n, h, o, info, err);
}

#endif
