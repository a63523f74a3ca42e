/* pg_mpi_pits_planchon2002_eps.c - the minimal epsilon-surface across ranks, in rounds
 * of local floods and ring exchanges.
 *
 * Source: O. Planchon & F. Darboux (2002), "A fast, simple and versatile algorithm to
 * fill the depressions of digital elevation models", Catena 46(2-3):159-176; the
 * single-process form and its uniqueness proof: src/pits/pg_pits_planchon2002_minimal_eps.c.
 * The minimal epsilon-surface W is the unique solution of
 *     W(c) = max(F(c), up(min over neighbours W(n)))
 * with F the plain fill (pg_mpi_pits_barnes2016_fill.c; any F with h <= F <= W gives
 * the same W). Each round, every rank floods its own cells from the ring and its sinks
 * with that equation (a Dijkstra flood, pits_meps_flood; ring cells are fixed
 * sources), then receives the ring's new values.
 * Preconditions: d->h (tile-local, pg_mpi_comm.h) holds F on this rank's tiles; sinks
 * are the cells at or below the sea level. The floods run on local ids (their heap
 * keys pack 32-bit local ids: the result does not depend on the order of equal keys).
 * Why it is correct: the ring starts at +inf (no known way out), so every value is the
 * cost of a real path, an upper bound of W that only falls, and a way out reaches a
 * cell after as many rounds as its best path crosses rank boundaries; when no rank's
 * cells change, every cell satisfies the equation, whose only solution is W. (Starting
 * from F, a lower bound, also converges, but a flat on a boundary then climbs by one
 * ulp per round on both sides: 74 rounds on the default planet instead of a handful;
 * docs/mpi.md, "Pit removal across ranks".) */
#include "pg_mpi_pits.h"

#ifdef PG_HAVE_MPI

#include "pg_pits_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct eps_ctx {
    const pg_mpi_pits_grid *d;
    uint8_t *closed; /* owned cells already at their floor this round */
} eps_ctx;

static int eps_settable(const void *ctx, uint32_t id) {
    const eps_ctx *e = ctx;
    return id < e->d->g->nown && !pg_mpi_pits_sink(e->d, id) && !e->closed[id];
}

/* A cell's value as a way out: sinks take water at any height. */
static float eps_value(const pg_mpi_pits_grid *d, uint32_t id) {
    return pg_mpi_pits_sink(d, id) ? -INFINITY : d->h[id];
}

/* Step 1 of a round, linear: owned cells with a strictly descending chain (in floor)
 * to a sink or to a ring cell below them keep their floor (as in the serial
 * pg_pits_planchon2002_minimal_eps.c); q gets nothing, the FIFO does the work. */
static int eps_close(const pg_mpi_pits_grid *d, eps_ctx *e, const float *floor_) {
    pits_fifo f = {0};
    uint32_t nb[8];
    PG_MPI_FOR_OWNED(d->g, id) {
        e->closed[id] = 0;
        if (pg_mpi_pits_sink(d, id)) continue;
        d->h[id] = INFINITY;
        int nn = pg_pits_neighbours(&d->g->t, id, nb);
        for (int j = 0; j < nn; j++)
            if ((nb[j] >= d->g->nown || pg_mpi_pits_sink(d, nb[j])) &&
                eps_value(d, nb[j]) < floor_[id]) {
                e->closed[id] = 1;
                d->h[id] = floor_[id];
                pits_fifo_push(&f, id);
                break;
            }
    }
    while (!pits_fifo_empty(&f) && !f.oom) {
        uint32_t c = pits_fifo_pop(&f);
        int nn = pg_pits_neighbours(&d->g->t, c, nb);
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
 * of memory, else 0. */
static int eps_round(const pg_mpi_pits_grid *d, eps_ctx *e, const float *floor_) {
    pits_heap q = {0};
    uint32_t nb[8];
    int oom = eps_close(d, e, floor_);
    PG_MPI_FOR_OWNED(d->g, id) { /* step 2: the rest, from its border */
        if (oom || !eps_settable(e, id)) continue;
        float w = INFINITY;
        int nn = pg_pits_neighbours(&d->g->t, id, nb);
        for (int j = 0; j < nn; j++) /* fixed: sinks, the ring, closed cells */
            if (!eps_settable(e, nb[j]))
                w = pits_minf(w, pits_maxf(floor_[id], pits_up(eps_value(d, nb[j]))));
        d->h[id] = w;
        if (w < INFINITY) pits_heap_push(&q, pits_key(w, id));
    }
    pits_meps m = {&d->g->t, d->h, floor_, eps_settable, e, 0, NULL, NULL};
    oom = oom || q.oom || pits_meps_flood(&m, &q);
    pits_heap_free(&q);
    return oom ? -1 : 0;
}

/* A later round: the ring's values only fell, so flood on from the owned cells next to
 * ring cells that fell (before: every value before the exchange); the others keep
 * their values, which are upper bounds the flood only lowers. Returns -1 when out of
 * memory. */
static int eps_update(const pg_mpi_pits_grid *d, eps_ctx *e, const float *floor_,
                      const float *before) {
    pits_heap q = {0};
    uint32_t nb[8];
    PG_MPI_FOR_OWNED(d->g, id) {
        if (!eps_settable(e, id)) continue;
        int nn = pg_pits_neighbours(&d->g->t, id, nb);
        float w = d->h[id];
        for (int j = 0; j < nn; j++)
            if (nb[j] >= d->g->nown && d->h[nb[j]] < before[nb[j]])
                w = pits_minf(w, pits_maxf(floor_[id], pits_up(eps_value(d, nb[j]))));
        if (w < d->h[id]) {
            d->h[id] = w;
            pits_heap_push(&q, pits_key(w, id));
        }
    }
    pits_meps m = {&d->g->t, d->h, floor_, eps_settable, e, 0, NULL, NULL};
    int oom = q.oom || pits_meps_flood(&m, &q);
    pits_heap_free(&q);
    return oom ? -1 : 0;
}

/* Did any owned cell change since `before`? */
static int owned_changed(const pg_mpi_pits_grid *d, const float *before) {
    int changed = 0;
    PG_MPI_FOR_OWNED(d->g, id) {
        changed |= memcmp(&d->h[id], &before[id], sizeof(float)) != 0;
    }
    return changed;
}

/* Start the ring from above: +inf (no known way out) except at sinks. */
static void ring_from_above(const pg_mpi_pits_grid *d) {
    for (size_t l = d->g->nown; l < d->g->nloc; l++)
        if (!pg_mpi_pits_sink(d, (uint32_t)l)) d->h[l] = INFINITY;
}

pg_status pg_mpi_pits_eps_rounds(pg_mpi_pits_grid *d, pg_mpi_pits_info *info, pg_error *err) {
    double t_start = MPI_Wtime();
    const size_t nc = d->g->nloc, no = d->g->nown;
    float *floor_ = malloc((no + 1) * sizeof *floor_); /* owned cells only */
    float *before = malloc((nc + 1) * sizeof *before);
    eps_ctx e = {d, calloc(no + 1, 1)};
    int bad = !floor_ || !e.closed || !before, more = 1;
    if (!bad) memcpy(floor_, d->h, no * sizeof *floor_);
    if (!bad) ring_from_above(d);
    if (!bad) memcpy(before, d->h, nc * sizeof *before);
    while (!(bad = pg_mpi_max_int(d->g->m, bad)) && more) {
        int r =
            info->eps_rounds == 0 ? eps_round(d, &e, floor_) : eps_update(d, &e, floor_, before);
        int changed = r >= 0 && owned_changed(d, before);
        if (r >= 0) memcpy(before, d->h, nc * sizeof *before);
        bad = r < 0 || pg_mpi_ring_exchange(d->g, d->h, sizeof *d->h, err) != PG_OK;
        more = pg_mpi_max_int(d->g->m, changed);
        info->eps_rounds++;
    }
    free(floor_), free(e.closed), free(before);
    info->eps_seconds = MPI_Wtime() - t_start;
    return bad ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (epsilon rounds)")
               : PG_OK;
}

#endif
