/* pg_mpi_pits_stats_unionfind.c - depression statistics across ranks: local regions
 * joined by union-find on rank 0.
 *
 * Source: the single-process count, src/pits/pg_pits_stats.c (a depression is an
 * 8-connected region of cells that the minimal fill raises; its volume the water that
 * fill holds), with the regions that cross rank boundaries joined by union-find
 * (R. E. Tarjan (1975), "Efficiency of a good but not linear set union algorithm",
 * JACM 22(2):215-225; path halving).
 * Membership (the minimal fill raises the cell) and the volumes come from the
 * distributed fill (pg_mpi_pits_barnes2016_fill.c).
 * Each rank labels the depressions inside its tiles (a flood over its member cells),
 * sums each label's cells, area, volume and depth, and records a pair of labels
 * wherever two member cells in different ranks touch (the ring's labels come from their
 * owners). Rank 0 joins the pairs and counts the joined regions.
 * Every array is tile-local (pg_mpi_comm.h); a region's label is the 64-bit global id
 * of its first cell, and the pairs that cross ranks are pairs of those.
 * Preconditions: as for the distributed fill (a sea level, no lakes, no no-data, an
 * ocean); only the rank's own tiles of h need be valid.
 * Why it is correct: the joined regions are exactly the serial 8-connected member
 * sets, so the count is the serial one, and so are the cell count and the deepest
 * cell. Areas and volumes are summed in another order, so their last bits may differ
 * from the serial figures (docs/mpi.md, "Pit removal across ranks"). */
#include "pg_mpi_pits.h"

#include <stdlib.h>

#ifdef PG_HAVE_MPI

#include "pg_pits_barnes2016_core.h"
#include "pg_array.h"

#include <string.h>

/* A region of this rank: its label (the global id of its first cell) and its sums;
 * five 64-bit words to gather. */
typedef struct dlabel {
    uint64_t label;
    double cells, area, volume, depth;
} dlabel;

static double stat_area(const pg_pits_area *a, uint64_t id) {
    if (!a) return 1.0;
    if (a->per_cell) return a->per_cell[id];
    return a->fn ? a->fn(a->ctx, (uint32_t)id) : a->constant; /* fn: below 2^32 cells */
}

static uint32_t uf_find(uint32_t *p, uint32_t x) {
    while (p[x] != x)
        x = p[x] = p[p[x]];
    return x;
}

/* Rank 0: join the labels (sorted by value) over the pairs; the number of regions, -1
 * when out of memory. */
static double join_labels(const dlabel *lab, size_t nl, const uint64_t *pairs, size_t np) {
    uint32_t *parent = malloc((nl + 1) * sizeof *parent);
    uint64_t *sorted = malloc((nl + 1) * sizeof *sorted);
    double regions = -1;
    if (!parent || !sorted || nl >= UINT32_MAX) goto done;
    for (size_t i = 0; i < nl; i++)
        parent[i] = (uint32_t)i, sorted[i] = lab[i].label;
    for (size_t k = 0; k < np; k++) {
        size_t a = pits_sorted_index_u64(sorted, nl, pairs[2 * k]),
               b = pits_sorted_index_u64(sorted, nl, pairs[2 * k + 1]);
        if (a < nl && b < nl) parent[uf_find(parent, (uint32_t)a)] = uf_find(parent, (uint32_t)b);
    }
    regions = 0;
    for (size_t i = 0; i < nl; i++)
        regions += uf_find(parent, (uint32_t)i) == i;
done:
    free(parent), free(sorted);
    return regions;
}

static int cmp_dlabel(const void *x, const void *y) {
    uint64_t a = ((const dlabel *)x)->label, b = ((const dlabel *)y)->label;
    return a < b ? -1 : a > b;
}

/* Label the member cells of this rank's tiles (region index per owned cell, UINT32_MAX
 * for none); one dlabel per local region. h: the caller's planet array (owned cells
 * only are read), fill: local. */
static int label_regions(const pg_mpi_pits_grid *d, const float *h, const float *fill,
                         const uint8_t *member, uint32_t *region, const pg_pits_area *area,
                         dlabel **out, size_t *nout) {
    const pg_mpi_tiling *g = d->g;
    uint32_t *queue = malloc(((size_t)g->nown + 1) * sizeof *queue), nb[8];
    dlabel *lab = NULL;
    size_t nl = 0, cap = 0;
    int oom = !queue;
    PG_MPI_FOR_OWNED(g, id) {
        if (oom || !member[id] || region[id] != UINT32_MAX) continue;
        if ((oom = PG_ARRAY_RESERVE(lab, &cap, nl + 1, NULL) != PG_OK) || nl >= UINT32_MAX - 1)
            continue;
        dlabel L = {pg_mpi_gid(g, id), 0, 0, 0, 0};
        size_t head = 0, tail = 0;
        queue[tail++] = id, region[id] = (uint32_t)nl;
        while (head < tail) {
            uint32_t c = queue[head++];
            uint64_t cube = pg_mpi_cube_id(g, c);
            double a = stat_area(area, cube), dep = (double)fill[c] - (double)h[cube];
            L.cells++, L.area += a, L.volume += dep * a;
            if (dep > L.depth) L.depth = dep;
            int k = pg_pits_neighbours(&g->t, c, nb);
            for (int j = 0; j < k; j++)
                if (nb[j] < g->nown && member[nb[j]] && region[nb[j]] == UINT32_MAX)
                    region[nb[j]] = (uint32_t)nl, queue[tail++] = nb[j];
        }
        lab[nl++] = L;
    }
    free(queue);
    *out = lab, *nout = nl;
    return oom;
}

typedef struct label_ctx {
    const uint32_t *region;
    const dlabel *lab;
} label_ctx;

/* A cell's region label for the ring (UINT64_MAX: not a member). */
static void pack_label(const void *ctx, uint32_t l, void *out) {
    const label_ctx *c = ctx;
    uint64_t v = c->region[l] == UINT32_MAX ? UINT64_MAX : c->lab[c->region[l]].label;
    memcpy(out, &v, sizeof v);
}

/* Pairs of labels across rank boundaries (label, label); ring: the ring's labels. */
static int cross_pairs(const pg_mpi_tiling *g, const uint8_t *member, const uint32_t *region,
                       const dlabel *lab, const uint64_t *ring, uint64_t **out, size_t *nout) {
    size_t n = 0, cap = 0;
    uint64_t *v = NULL;
    uint32_t nb[8];
    int oom = 0;
    PG_MPI_FOR_OWNED(g, id) {
        if (!member[id]) continue;
        int k = pg_pits_neighbours(&g->t, id, nb);
        for (int j = 0; j < k; j++) {
            if (nb[j] < g->nown || !member[nb[j]]) continue;
            if (oom || PG_ARRAY_RESERVE(v, &cap, n + 2, NULL) != PG_OK) {
                oom = 1;
                continue;
            }
            v[n++] = lab[region[id]].label, v[n++] = ring[nb[j] - g->nown];
        }
    }
    *out = v, *nout = n;
    return oom;
}

/* The local arrays: the plain fill; membership. */
typedef struct stats_bufs {
    float *fill;
    uint8_t *member;
    uint32_t *region;
    uint64_t *ring;
} stats_bufs;

static void stats_bufs_free(stats_bufs *b) {
    free(b->fill), free(b->member), free(b->region), free(b->ring);
}

/* A certificate that the heights d->h (ring current) have no depression: every owned
 * cell above the sea has a neighbour at or below it, or strictly lower (pits_drains_by
 * with p = h: a walk along such neighbours falls strictly, so it ends at the sea, and
 * the minimal fill raises nothing). What a removal with epsilon leaves passes it in one
 * linear scan, as the single process's search does (pg_pits_stats.c, no_depression);
 * a failed certificate proves nothing, and the full count follows. Counts the owned
 * sinks into *sinks. */
static int certify_drains(const pg_mpi_pits_grid *d, double *sinks) {
    uint32_t nb[8];
    int ok = 1;
    PG_MPI_FOR_OWNED(d->g, id) {
        if (pg_mpi_pits_sink(d, id)) {
            *sinks += 1;
            continue;
        }
        int k = pg_pits_neighbours(&d->g->t, id, nb), lower = 0;
        for (int j = 0; j < k && !lower; j++)
            lower = pg_mpi_pits_sink(d, nb[j]) || d->h[nb[j]] < d->h[id];
        ok &= lower;
    }
    return ok;
}

pg_status pg_mpi_pits_stats(pg_mpi *m, int tiles, uint32_t n, const float *h, const pg_pits_opts *o,
                            const pg_pits_area *area, pg_pits_stats *out, pg_error *err) {
    pg_mpi_tiling g;
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL, f.epsilon = false;
    memset(out, 0, sizeof *out);
    pg_status st = pg_mpi_pits_check_fill(&f, err);
    if (!st && area && !area->per_cell && area->fn && (uint64_t)6 * n * n > UINT32_MAX)
        st = pg_error_set(err, PG_ERR_BADINPUT,
                          "pits (MPI): an area function takes 32-bit cell ids: give per-cell "
                          "areas or a constant above 2^32 cells");
    if (!st) st = pg_mpi_tiling_init(&g, m, tiles, n, err);
    if (st) return st;
    const size_t nc = g.nloc + 1, no = g.nown + 1;
    stats_bufs b = {malloc(nc * sizeof(float)), malloc(nc), NULL, NULL};
    if (pg_mpi_max_int(m, !b.fill || !b.member))
        st = pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory for statistics");
    pg_mpi_pits_info info;
    const int me = pg_mpi_rank(m);
    pg_mpi_pits_grid d = {&g, b.fill, o->sea_level};
    double sinks = 0;
    if (!st) { /* first the certificate: all figures 0 when it holds on every rank */
        pg_mpi_tiling_load(&g, h, b.fill);
        st = pg_mpi_ring_exchange(&g, b.fill, sizeof(float), err);
        int drains = !st && certify_drains(&d, &sinks);
        if (!pg_mpi_max_int(m, st != PG_OK) && !pg_mpi_max_int(m, !drains)) {
            out->sinks = (uint64_t)pg_mpi_sum_double(m, sinks);
            stats_bufs_free(&b);
            pg_mpi_tiling_free(&g);
            return PG_OK;
        }
        sinks = 0;
    }
    if (!st) {
        pg_mpi_tiling_load(&g, h, b.fill);
        st = pg_mpi_pits_fill_local(&d, &f, &info, err);
    }
    if (!st) {
        PG_MPI_FOR_OWNED(&g, id) {
            float hc = h[pg_mpi_cube_id(&g, id)];
            b.member[id] = b.fill[id] > hc;
            sinks += hc <= o->sea_level;
        }
    }
    if (!st) st = pg_mpi_ring_exchange(&g, b.member, 1, err);
    dlabel *lab = NULL;
    uint64_t *pairs = NULL;
    size_t nl = 0, np = 0;
    int bad = st != PG_OK;
    if (!bad) {
        b.region = malloc(no * sizeof *b.region), b.ring = malloc((g.nring + 1) * sizeof *b.ring);
        bad = !b.region || !b.ring;
        for (uint32_t l = 0; !bad && l < g.nown; l++)
            b.region[l] = UINT32_MAX;
    }
    bad = bad || label_regions(&d, h, b.fill, b.member, b.region, area, &lab, &nl);
    if (!pg_mpi_max_int(m, bad)) {
        label_ctx lc = {b.region, lab};
        bad = pg_mpi_ring_exchange_packed(&g, sizeof(uint64_t), pack_label, &lc, b.ring, err) !=
              PG_OK;
    }
    bad = bad || cross_pairs(&g, b.member, b.region, lab, b.ring, &pairs, &np);
    bad = pg_mpi_max_int(m, bad);
    size_t tl = 0, tp = 0;
    dlabel *all_lab = bad ? NULL : pg_mpi_gather_root(m, lab, nl * 5, MPI_UINT64_T, 8, &tl, &bad);
    uint64_t *all_pairs = bad ? NULL : pg_mpi_gather_root(m, pairs, np, MPI_UINT64_T, 8, &tp, &bad);
    double res[6] = {0};
    if (!bad && me == 0) {
        size_t nL = tl / 5;
        qsort(all_lab, nL, sizeof *all_lab, cmp_dlabel);
        res[0] = join_labels(all_lab, nL, all_pairs, tp / 2);
        for (size_t i = 0; i < nL; i++) {
            res[1] += all_lab[i].cells, res[2] += all_lab[i].area, res[3] += all_lab[i].volume;
            if (all_lab[i].depth > res[4]) res[4] = all_lab[i].depth;
        }
    }
    if (!bad) MPI_Bcast(res, 6, MPI_DOUBLE, 0, pg_mpi_comm_of(m));
    sinks = bad ? 0 : pg_mpi_sum_double(m, sinks);
    out->depressions = (uint64_t)res[0], out->depression_cells = (uint64_t)res[1];
    out->depression_area_m2 = res[2], out->depression_volume_m3 = res[3];
    out->max_depth_m = res[4], out->sinks = (uint64_t)sinks;
    stats_bufs_free(&b);
    free(lab), free(pairs), free(all_lab), free(all_pairs);
    pg_mpi_tiling_free(&g);
    if (!st && (bad || res[0] < 0))
        st = pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory for statistics");
    return st;
}

#else

pg_status pg_mpi_pits_stats(pg_mpi *m, int tiles, uint32_t n, const float *h, const pg_pits_opts *o,
                            const pg_pits_area *area, pg_pits_stats *out, pg_error *err) {
    (void)m, (void)tiles, (void)n, (void)h, (void)o, (void)area, (void)out;
    return pg_error_set(err, PG_ERR_RUNTIME, "this planetgen was built without MPI");
}

#endif
