/* pg_mpi_pits_barnes2016_fill.c - distributed depression filling on the cube sphere.
 *
 * Source: R. Barnes (2016), "Flexibly distributed Priority-Flood depression filling
 * for teracell DEMs" (arXiv:1608.04431; Computers & Geosciences 96). Its four steps,
 * with the ranks of pg_mpi.h owning cube tiles:
 *   1. each rank floods each of its tiles alone (Improved Priority-Flood, Barnes et al.
 *      2014), seeded with the tile's sinks (label OUTLET) and with every perimeter cell
 *      (a cell with a neighbour in another tile) under its own label 2 + global id;
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
 * Steps 1-3 are the core shared with the threaded fill (src/pits/pg_pits_barnes2016_core.c);
 * this file distributes them. With epsilon, the plain fill is then lifted to the
 * minimal epsilon-surface in rounds (pg_mpi_pits_planchon2002_eps.c).
 * Every array is tile-local (pg_mpi_comm.h); labels and the graph's label ids are
 * 64-bit global ids (2 + the cell's global id), the flood itself runs on 32-bit local
 * ids (2 + local id, mapped to the global label when the edges are recorded).
 * Preconditions: plain fill (no epsilon), sinks = cells at or below the sea level (no
 * lakes, no no-data), at least one sink on the planet (the serial fill would otherwise
 * pick the lowest cell, a global choice); only the rank's own tiles of h need be valid.
 * Why it is correct: as the in-process version (pg_pits_barnes2016_parallel_fill.c):
 * the minimal fill of a cell is the minimax height of its paths to a sink; inside a
 * tile the flood gives the minimax to its label's seed, and the graph composes the
 * segments exactly. The minimal fill is unique, so every owned cell comes out
 * bit-identical to pg_pits_remove's plain fill (the test compares them for 1, 2 and 4
 * ranks; docs/mpi.md, "Pit removal across ranks"). */
#include "pg_mpi_pits.h"

#include <stdlib.h>

#ifdef PG_HAVE_MPI

#include "pg_pits_barnes2016_core.h"

#include <limits.h>
#include <string.h>

/* An edge of the spill graph between global labels (3 words of 64 bits to gather). */
typedef struct gedge {
    uint64_t a, b;
    float w;
    uint32_t pad;
} gedge;

typedef struct gedges {
    gedge *e;
    size_t n, cap;
    int oom;
} gedges;

static void gedge_push(gedges *v, uint64_t a, uint64_t b, float w) {
    if (a == b) return;
    if (v->n == v->cap) {
        size_t cap = v->cap ? 2 * v->cap : 1024;
        gedge *e = realloc(v->e, cap * sizeof *e);
        if (!e) {
            v->oom = 1;
            return;
        }
        v->e = e, v->cap = cap;
    }
    if (a > b) {
        uint64_t t = a;
        a = b, b = t;
    }
    v->e[v->n++] = (gedge){a, b, w, 0};
}

static int cmp_gedge(const void *x, const void *y) {
    const gedge *a = x, *b = y;
    if (a->a != b->a) return a->a < b->a ? -1 : 1;
    if (a->b != b->b) return a->b < b->b ? -1 : 1;
    return a->w < b->w ? -1 : a->w > b->w;
}

/* Sort by (a, b, w) and keep each pair's lowest w. */
static void gedges_compact(gedges *v) {
    if (!v->n) return;
    qsort(v->e, v->n, sizeof *v->e, cmp_gedge);
    size_t k = 1;
    for (size_t i = 1; i < v->n; i++)
        if (v->e[i].a != v->e[k - 1].a || v->e[i].b != v->e[k - 1].b) v->e[k++] = v->e[i];
    v->n = k;
}

/* The label a perimeter cell (local id l) has after step 1, known to every rank. */
static uint64_t perimeter_label(const pg_mpi_pits_grid *d, uint32_t l) {
    return pg_mpi_pits_sink(d, l) ? PITS_B16_OUTLET : 2 + pg_mpi_gid(d->g, l);
}

/* The global label of a tile flood's local label (OUTLET or 2 + local id). */
static uint64_t global_label(const pg_mpi_pits_grid *d, uint32_t label) {
    return label == PITS_B16_OUTLET ? PITS_B16_OUTLET : 2 + pg_mpi_gid(d->g, label - 2);
}

/* Steps 1 and 2 on local tile i: the shared flood, then its edges as global label
 * pairs into ev. A pair of cells in two ranks is recorded by both; the one with the
 * higher global id drops it. */
static int flood_tile(pg_mpi_pits_grid *d, uint32_t *label, uint32_t i, gedges *ev,
                      pits_b16_edges *in, pits_b16_edges *cross) {
    const pg_mpi_tiling *g = d->g;
    const uint32_t per = g->ts * g->ts;
    pits_b16_tile b = {.t = &g->t,
                       .h = d->h,
                       .label = label,
                       .sea = d->sea,
                       .lo = i * per,
                       .hi = i * per + per,
                       .wshift = -1};
    in->n = cross->n = 0;
    int oom = pits_b16_flood_tile(&b, in, cross);
    if (!oom) pits_b16_edges_compact(in); /* the tile's label pairs, once each */
    for (size_t k = 0; !oom && k < in->n; k++)
        gedge_push(ev, global_label(d, in->e[k].a), global_label(d, in->e[k].b), in->e[k].w);
    for (size_t k = 0; !oom && k < cross->n; k++) {
        uint32_t a = cross->e[k].a, c = cross->e[k].b; /* a < c: c may be a ring cell */
        if (c >= g->nown && pg_mpi_gid(g, c) < pg_mpi_gid(g, a)) continue;
        gedge_push(ev, perimeter_label(d, a), perimeter_label(d, c), cross->e[k].w);
    }
    return oom || ev->oom;
}

/* Rank 0: the sorted labels of the gathered edges, the edges renumbered to their
 * indices, and the levels; frees all as soon as the indices are made. Nonzero when
 * out of memory. */
static int solve_root(gedge *all, size_t ne, uint64_t **labels_out, float **levels_out,
                      size_t *nl_out) {
    uint64_t *labels = malloc((2 * ne + 1) * sizeof *labels);
    pits_b16_edge *idx = malloc((ne + 1) * sizeof *idx);
    float *levels = NULL;
    size_t nl = 0;
    int oom = !labels || !idx;
    for (size_t k = 0; !oom && k < ne; k++)
        labels[2 * k] = all[k].a, labels[2 * k + 1] = all[k].b;
    if (!oom) nl = pits_sort_unique_u64(labels, 2 * ne);
    oom = oom || nl >= UINT32_MAX; /* the solve's label indices are 32-bit */
    for (size_t k = 0; !oom && k < ne; k++)
        idx[k] = (pits_b16_edge){(uint32_t)pits_sorted_index_u64(labels, nl, all[k].a),
                                 (uint32_t)pits_sorted_index_u64(labels, nl, all[k].b), all[k].w};
    free(all);
    if (!oom && nl < 2 * ne) { /* keep only the distinct labels */
        uint64_t *shrunk = realloc(labels, (nl + 1) * sizeof *labels);
        if (shrunk) labels = shrunk;
    }
    levels = oom ? NULL : malloc((nl + 1) * sizeof *levels);
    uint32_t source = nl && labels[0] == PITS_B16_OUTLET ? 0 : UINT32_MAX;
    pits_b16_edges one = {idx, ne, ne, 0};
    oom = oom || !levels || pits_b16_solve(&one, 1, nl, source, levels);
    free(idx);
    *labels_out = labels, *levels_out = levels, *nl_out = nl;
    return oom;
}

/* A label and its level, as rank 0 sends them to the label's owner (16 bytes). */
typedef struct glevel {
    uint64_t label;
    float level;
    uint32_t pad;
} glevel;

/* The rank that owns a label's seed cell (label = 2 + global id). */
static int label_owner(const pg_mpi_tiling *g, uint64_t label) {
    const int P = pg_mpi_size(g->m), nt = 6 * g->T * g->T;
    return pg_mpi_tile_owner(nt, P, pg_mpi_tile_of(g, (label - 2 - g->base) / g->stride));
}

/* Rank 0: every label's level, grouped by owner (each group sorted by label), with
 * the byte counts and offsets of the groups. Nonzero when out of memory or a group
 * exceeds 2^31 - 1 bytes. */
static int group_by_owner(const pg_mpi_tiling *g, const uint64_t *labels, const float *levels,
                          size_t nl, glevel **out, int *counts, int *displs) {
    const int P = pg_mpi_size(g->m);
    size_t *fill = calloc((size_t)P + 1, sizeof *fill);
    glevel *v = malloc((nl + 1) * sizeof *v);
    int bad = !fill || !v;
    for (size_t k = 0; !bad && k < nl; k++)
        if (labels[k] != PITS_B16_OUTLET) fill[label_owner(g, labels[k]) + 1]++;
    for (int q = 0; !bad && q < P; q++) {
        bad |= fill[q + 1] * sizeof *v > INT_MAX || fill[q] * sizeof *v > INT_MAX;
        counts[q] = (int)(fill[q + 1] * sizeof *v);
        fill[q + 1] += fill[q];
        displs[q] = (int)(fill[q] * sizeof *v);
    }
    for (size_t k = 0; !bad && k < nl; k++)
        if (labels[k] != PITS_B16_OUTLET)
            v[fill[label_owner(g, labels[k])]++] = (glevel){labels[k], levels[k], 0};
    free(fill);
    if (bad) free(v), v = NULL;
    *out = v;
    return bad;
}

/* Step 3: gather on rank 0 and solve; then rank 0 sends each rank the levels of its
 * own labels only (a rank's cells carry the labels of its own perimeter cells, or the
 * outlet), so no rank holds the whole label table. Every rank returns its labels
 * (sorted) and their levels. */
static int solve_and_share(const pg_mpi_tiling *g, const gedges *ev, glevel **mine_out,
                           size_t *nmine_out, double *nl_out, uint64_t *max_label) {
    pg_mpi *m = g->m;
    const MPI_Comm comm = pg_mpi_comm_of(m);
    const int P = pg_mpi_size(m), me = pg_mpi_rank(m);
    MPI_Datatype edge_t;
    MPI_Type_contiguous(3, MPI_UINT64_T, &edge_t); /* counts in edges, not words */
    MPI_Type_commit(&edge_t);
    size_t ne = 0, nl = 0;
    int bad = 0;
    gedge *all = pg_mpi_gather_root(m, ev->e, ev->n, edge_t, sizeof(gedge), &ne, &bad);
    MPI_Type_free(&edge_t);
    uint64_t *labels = NULL;
    float *levels = NULL;
    glevel *byowner = NULL, *mine = NULL;
    int *counts = calloc(2 * (size_t)P + 1, sizeof *counts), mycount = 0;
    if (!bad && me == 0) {
        bad = solve_root(all, ne, &labels, &levels, &nl); /* frees all */
        bad = bad || !counts || group_by_owner(g, labels, levels, nl, &byowner, counts, counts + P);
        *max_label = nl ? labels[nl - 1] : 0;
    } else {
        free(all);
    }
    free(labels), free(levels);
    MPI_Bcast(&bad, 1, MPI_INT, 0, comm);
    unsigned long long sh[2] = {nl, *max_label};
    MPI_Bcast(sh, 2, MPI_UNSIGNED_LONG_LONG, 0, comm);
    *nl_out = (double)sh[0], *max_label = sh[1];
    if (!bad) MPI_Scatter(counts, 1, MPI_INT, &mycount, 1, MPI_INT, 0, comm);
    mine = bad ? NULL : malloc((size_t)mycount + sizeof *mine);
    bad = pg_mpi_max_int(m, bad || !mine);
    if (!bad) {
        MPI_Scatterv(byowner, counts, counts + P, MPI_BYTE, mine, mycount, MPI_BYTE, 0, comm);
        if (me == 0) /* what rank 0 sends to the others */
            pg_mpi_note_pits_bytes(m, (double)(sh[0] * sizeof *mine) - (double)counts[0]);
    }
    free(byowner), free(counts);
    if (bad) free(mine), mine = NULL;
    *mine_out = mine, *nmine_out = bad ? 0 : (size_t)mycount / sizeof *mine;
    return bad;
}

pg_status pg_mpi_pits_check_fill(const pg_pits_opts *o, pg_error *err) {
    if (o->method != PG_PITS_FILL || !o->has_sea_level || o->lakes || o->has_nodata)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits (MPI): the distributed fill needs the fill method "
                            "with a sea level, no lakes and no no-data");
    return PG_OK;
}

/* Every rank must see a sink somewhere (the serial fill's fallback is global). */
static pg_status check_ocean(const pg_mpi_pits_grid *d, pg_error *err) {
    double sinks = 0;
    PG_MPI_FOR_OWNED(d->g, l) {
        sinks += pg_mpi_pits_sink(d, l);
    }
    if (pg_mpi_sum_double(d->g->m, sinks) == 0)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits (MPI): no cell at or below the sea level: the distributed "
                            "fill needs an ocean");
    return PG_OK;
}

/* Steps 1 and 2 over this rank's tiles, into ev (compacted). Nonzero when out of memory. */
static int flood_tiles(pg_mpi_pits_grid *d, uint32_t *label, gedges *ev) {
    pits_b16_edges in = {0}, cross = {0};
    int oom = !label;
    for (uint32_t i = 0; !oom && i < (uint32_t)(d->g->t1 - d->g->t0); i++)
        oom = flood_tile(d, label, i, ev, &in, &cross);
    free(in.e), free(cross.e);
    if (!oom) gedges_compact(ev);
    return oom;
}

/* The level of a label of this rank (mine: its labels, sorted): the outlet's is -inf. */
static float level_of(const glevel *mine, size_t n, uint64_t label) {
    if (label == PITS_B16_OUTLET) return -INFINITY;
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (mine[mid].label < label)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && mine[lo].label == label ? mine[lo].level : INFINITY;
}

/* Step 4: raise this rank's cells to their label's level. */
static void apply_levels(pg_mpi_pits_grid *d, const uint32_t *label, const glevel *mine, size_t n,
                         pg_mpi_pits_info *info) {
    PG_MPI_FOR_OWNED(d->g, l) {
        if (pg_mpi_pits_sink(d, l)) continue;
        float lv = level_of(mine, n, global_label(d, label[l]));
        if (lv > d->h[l] && lv < INFINITY) d->h[l] = lv, info->raised++;
    }
}

pg_status pg_mpi_pits_fill_local(pg_mpi_pits_grid *d, const pg_pits_opts *o, pg_mpi_pits_info *info,
                                 pg_error *err) {
    pg_mpi *m = d->g->m;
    memset(info, 0, sizeof *info);
    pg_status st = check_ocean(d, err);
    if (st) return st;
    st = pg_mpi_ring_exchange(d->g, d->h, sizeof *d->h, err);
    if (pg_mpi_max_int(m, st != PG_OK))
        return st ? st : pg_error_set(err, PG_ERR_RUNTIME, "pits (MPI): another rank failed");
    uint32_t *label = calloc((size_t)d->g->nown + 1, sizeof *label);
    gedges ev = {0};
    double t_start = MPI_Wtime();
    int oom = flood_tiles(d, label, &ev);
    info->flood_seconds = MPI_Wtime() - t_start;
    info->edges = (double)ev.n;
    oom = pg_mpi_max_int(m, oom);
    glevel *mine = NULL;
    size_t nmine = 0;
    t_start = MPI_Wtime();
    if (!oom) oom = solve_and_share(d->g, &ev, &mine, &nmine, &info->labels, &info->max_label);
    info->solve_seconds = MPI_Wtime() - t_start;
    free(ev.e);
    if (!oom) apply_levels(d, label, mine, nmine, info);
    free(label), free(mine);
    if (oom) return pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory");
    if (o->epsilon) return pg_mpi_pits_eps_rounds(d, info, err);
    return pg_mpi_ring_exchange(d->g, d->h, sizeof *d->h, err);
}

pg_status pg_mpi_pits_fill(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                           pg_mpi_pits_info *info, pg_error *err) {
    pg_mpi_tiling g;
    pg_status st = pg_mpi_pits_check_fill(o, err);
    if (!st) st = pg_mpi_tiling_init(&g, m, tiles, n, err);
    if (st) return st;
    pg_mpi_pits_grid d = {&g, malloc((g.nloc + 1) * sizeof(float)), o->sea_level};
    if (!d.h) st = pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory");
    if (pg_mpi_max_int(m, st != PG_OK)) {
        free(d.h), pg_mpi_tiling_free(&g);
        return st ? st : pg_error_set(err, PG_ERR_RUNTIME, "pits (MPI): another rank failed");
    }
    pg_mpi_tiling_load(&g, h, d.h);
    st = pg_mpi_pits_fill_local(&d, o, info, err);
    if (!st) pg_mpi_tiling_store(&g, d.h, h);
    free(d.h);
    pg_mpi_tiling_free(&g);
    return st;
}

#else

pg_status pg_mpi_pits_fill(pg_mpi *m, int tiles, uint32_t n, float *h, const pg_pits_opts *o,
                           pg_mpi_pits_info *info, pg_error *err) {
    (void)m, (void)tiles, (void)n, (void)h, (void)o, (void)info;
    return pg_error_set(err, PG_ERR_RUNTIME, "this planetgen was built without MPI");
}

#endif
