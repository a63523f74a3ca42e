/* pg_mpi_pits_stats_unionfind.c - depression statistics across ranks: local regions
 * joined by union-find on rank 0.
 *
 * Source: the single-process count, src/pits/pg_pits_stats.c (a depression is an
 * 8-connected region of cells that the minimal fill raises; volume and area against
 * the epsilon-fill), with the regions that cross rank boundaries joined by union-find
 * (R. E. Tarjan (1975), "Efficiency of a good but not linear set union algorithm",
 * JACM 22(2):215-225; path halving).
 * Membership (the minimal fill raises the cell) and the epsilon-fill come from the
 * distributed fills (pg_mpi_pits_barnes2016_fill.c, pg_mpi_pits_planchon2002_eps.c).
 * Each rank labels the depressions inside its tiles (a flood over its member cells),
 * sums each label's cells, area, volume and depth, and records a pair of labels
 * wherever two member cells in different ranks touch (the ring's labels come from their
 * owners). Rank 0 joins the pairs and counts the joined regions.
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
        uint32_t a = pits_sorted_index(sorted, nl, pairs[2 * k]),
                 b = pits_sorted_index(sorted, nl, pairs[2 * k + 1]);
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

/* Gather n doubles of every rank on rank 0. */
static double *gather_doubles(pg_mpi *m, const double *mine, size_t n, size_t *total, int *bad) {
    return pg_mpi_gather_root(m, mine, n, MPI_DOUBLE, sizeof(double), total, bad);
}

/* Label the member cells of this rank's tiles; one dlabel per local region. */
static int label_regions(const pg_mpi_pits_grid *d, const float *h, const float *efill,
                         const uint8_t *member, uint32_t *label, const pg_pits_area *area,
                         dlabel **out, size_t *nout) {
    const pg_mpi_tiling *g = &d->g;
    uint32_t *queue = malloc(((size_t)(g->t1 - g->t0) * g->ts * g->ts + 1) * sizeof *queue), nb[8];
    dlabel *lab = NULL;
    size_t nl = 0, cap = 0;
    int oom = !queue;
    PG_MPI_FOR_OWNED(g, id) {
        if (oom || !member[id] || label[id] != UINT32_MAX) continue;
        if ((oom = PG_ARRAY_RESERVE(lab, &cap, nl + 1, NULL) != PG_OK)) continue;
        dlabel L = {id, 0, 0, 0, 0};
        size_t head = 0, tail = 0;
        queue[tail++] = id, label[id] = id;
        while (head < tail) {
            uint32_t c = queue[head++];
            double a = stat_area(area, c), dep = (double)efill[c] - (double)h[c];
            L.cells++, L.area += a, L.volume += dep * a;
            if (dep > L.depth) L.depth = dep;
            int k = pg_pits_neighbours(g->t, c, nb);
            for (int j = 0; j < k; j++)
                if (pg_mpi_owned(g, nb[j]) && member[nb[j]] && label[nb[j]] == UINT32_MAX)
                    label[nb[j]] = id, queue[tail++] = nb[j];
        }
        lab[nl++] = L;
    }
    free(queue);
    *out = lab, *nout = nl;
    return oom;
}

/* Pairs of labels across rank boundaries, as doubles (label, label). */
static int cross_pairs(const pg_mpi_tiling *g, const uint8_t *member, const uint32_t *label,
                       double **out, size_t *nout) {
    size_t n = 0, cap = 0;
    double *v = NULL;
    uint32_t nb[8];
    int oom = 0;
    PG_MPI_FOR_OWNED(g, id) {
        if (!member[id]) continue;
        int k = pg_pits_neighbours(g->t, id, nb);
        for (int j = 0; j < k; j++) {
            if (pg_mpi_owned(g, nb[j]) || !member[nb[j]]) continue;
            if (oom || PG_ARRAY_RESERVE(v, &cap, n + 2, NULL) != PG_OK) {
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
    pg_mpi_pits_grid d;
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL, f.epsilon = false;
    pg_status st = pg_mpi_pits_check_fill(&f, err);
    const size_t nc = (size_t)6 * n * n;
    float *fill = malloc(nc * sizeof *fill), *efill = malloc(nc * sizeof *efill);
    uint8_t *member = calloc(nc, 1);
    uint32_t *label = malloc(nc * sizeof *label);
    if (!st && (!fill || !efill || !member || !label))
        st = pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory for statistics");
    if (!st) st = pg_mpi_pits_grid_init(&d, &topo, m, tiles, n, fill, o, err);
    memset(out, 0, sizeof *out);
    pg_mpi_pits_info info;
    const int me = pg_mpi_rank(m);
    if (!st) {
        memcpy(fill, h, nc * sizeof *fill);
        st = pg_mpi_pits_fill(m, tiles, n, fill, &f, &info, err);
    }
    if (!st) { /* the epsilon-fill: the same rounds as the fill's, from the plain fill */
        memcpy(efill, fill, nc * sizeof *efill);
        pg_mpi_pits_grid de = d;
        de.h = efill;
        st = pg_mpi_pits_eps_rounds(&de, &info, err);
    }
    double sinks = 0;
    if (!st) {
        PG_MPI_FOR_OWNED(&d.g, id) {
            member[id] = fill[id] > h[id];
            label[id] = UINT32_MAX;
            sinks += h[id] <= o->sea_level;
        }
        st = pg_mpi_ring_exchange(&d.g, member, 1, err);
    }
    dlabel *lab = NULL;
    double *pairs = NULL;
    size_t nl = 0, np = 0;
    int bad = st != PG_OK;
    bad = bad || label_regions(&d, h, efill, member, label, area, &lab, &nl);
    if (!pg_mpi_max_int(m, bad))
        bad = pg_mpi_ring_exchange(&d.g, label, sizeof *label, err) != PG_OK;
    bad = bad || cross_pairs(&d.g, member, label, &pairs, &np);
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
    if (!bad) MPI_Bcast(res, 6, MPI_DOUBLE, 0, pg_mpi_comm_of(m));
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

pg_status pg_mpi_pits_stats(pg_mpi *m, int tiles, uint32_t n, const float *h, const pg_pits_opts *o,
                            const pg_pits_area *area, pg_pits_stats *out, pg_error *err) {
    (void)m, (void)tiles, (void)n, (void)h, (void)o, (void)area, (void)out;
    return pg_error_set(err, PG_ERR_RUNTIME, "this planetgen was built without MPI");
}

#endif
