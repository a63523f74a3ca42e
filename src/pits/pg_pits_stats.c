/* pg_pits_stats.c - counting depressions: how many closed basins a height field has,
 * their area and their volume.
 *
 * A depression is an 8-connected region of cells that the minimal fill (plain
 * Priority-Flood, Barnes et al. 2014) raises, and its volume is the water that fill
 * holds there (docs/pits.md, "Metrics"): the sum of (fill - h) * area over its cells.
 * The minimal fill, not the epsilon-fill, decides both: the epsilon-fill also lifts
 * drained flats by ulps to give them a slope, but water already leaves them, and its
 * ulps hold no water either. This makes the count 0 after every method here, plain or
 * epsilon, and needs one fill only. Regions are found with a FIFO flood through the
 * same neighbour interface, so a basin straddling a face seam counts once. */
#include "pg_huge.h"
#include "pg_pits_internal.h"

#include <stdlib.h>

static double cell_area(const pg_pits_area *a, uint32_t id) {
    if (!a) return 1.0;
    if (a->per_cell) return a->per_cell[id];
    if (a->fn) return a->fn(a->ctx, id);
    return a->constant;
}

/* Flood one depression from cell s through the cells with dep[] == 1 (marking them 2);
 * adds its figures to st. Cells in id order of their region's first cell, breadth
 * first within a region: the sums are added in the same order whoever built dep. */
static void scan_region(const pg_pits_topo *t, const float *h, const float *fill,
                        const pg_pits_area *area, uint8_t *dep, pits_fifo *q, uint32_t s,
                        pg_pits_stats *st) {
    uint32_t nb[8];
    pits_fifo_push(q, s);
    dep[s] = 2;
    while (!pits_fifo_empty(q) && !q->oom) {
        uint32_t c = pits_fifo_pop(q);
        double a = cell_area(area, c), d = (double)fill[c] - (double)h[c];
        st->depression_cells++;
        st->depression_area_m2 += a;
        st->depression_volume_m3 += d * a;
        if (d > st->max_depth_m) st->max_depth_m = d;
        int k = pg_pits_neighbours(t, c, nb);
        for (int j = 0; j < k; j++)
            if (dep[nb[j]] == 1) {
                dep[nb[j]] = 2;
                pits_fifo_push(q, nb[j]);
            }
    }
    st->depressions++;
}

int pits_count_regions(const pg_pits_topo *t, const float *h, uint8_t *dep, const float *fill,
                       const pg_pits_area *area, pg_pits_stats *st) {
    pits_fifo q = {0};
    for (uint64_t i = 0; i < t->ncells && !q.oom; i++)
        if (dep[i] == 1) scan_region(t, h, fill, area, dep, &q, (uint32_t)i, st);
    int oom = q.oom;
    pits_fifo_free(&q);
    return oom;
}

pg_status pg_pits_cube_face_areas(pg_cube_projection p, uint32_t n, double radius, double *areas,
                                  pg_error *err) {
    pg_cube_grid g;
    pg_status s = pg_cube_grid_init(&g, p, (int)n, 1, err);
    if (s) return s;
#pragma omp parallel for schedule(static)
    for (int64_t y = 0; y < (int64_t)n; y++)
        for (int64_t x = 0; x < (int64_t)n; x++) {
            double c00[3], c10[3], c11[3], c01[3];
            pg_cube_corner_dir(&g, 0, x, y, c00);
            pg_cube_corner_dir(&g, 0, x + 1, y, c10);
            pg_cube_corner_dir(&g, 0, x + 1, y + 1, c11);
            pg_cube_corner_dir(&g, 0, x, y + 1, c01);
            areas[y * n + x] = radius * radius *
                               (pg_cube_spherical_triangle(c00, c10, c11) +
                                pg_cube_spherical_triangle(c00, c11, c01));
        }
    return PG_OK;
}

double pg_pits_cube_area_fn(void *ctx, uint32_t id) {
    const pg_pits_cube_areas *a = ctx;
    return a->face[id % (a->n * a->n)];
}

/* The minimal fill of h into *out (allocated), its sink count into *nsinks. */
static pg_status fill_copy(const pg_pits_topo *t, const float *h, const pg_pits_opts *o,
                           float **out, uint64_t *nsinks, pg_error *err) {
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL;
    f.epsilon = 0;
    float *c = pg_huge_malloc(t->ncells * sizeof *c);
    if (!c) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for statistics");
    memcpy(c, h, t->ncells * sizeof *c);
    pg_pits_result res = {0};
    pg_status s = pg_pits_remove(t, c, &f, &res, err);
    *nsinks = res.sinks;
    if (s) {
        free(c);
        return s;
    }
    *out = c;
    return PG_OK;
}

pg_status pits_eps_from_fill(const pg_pits_topo *t, float *f, const pg_pits_opts *o, float *w,
                             int *exact, uint64_t *nsinks, pg_error *err) {
    pg_pits_opts fo = *o;
    fo.method = PG_PITS_FILL;
    fo.epsilon = 0;
    uint8_t *st = NULL;
    *exact = 0;
    pg_status s = pits_begin(t, f, &fo, &st, NULL, nsinks, err); /* no-data: -inf for now */
    if (s) return s;
    *exact = pits_meps_from_fill(t, f, st, w) == 0;
    pits_end(t, f, &fo, st);
    free(st);
    return PG_OK;
}

/* Whether h has no depression at all, in one linear search: from the sinks, step to
 * every neighbour at least as high as the cell stepped from (sinks count as -inf).
 * Every cell reached has a non-ascending path to a sink, so the minimal fill leaves
 * it. Conversely, if the fill raises no cell, every cell is reached: take an
 * unreached cell c of least height; its path to a sink that stays <= h(c) leaves the
 * unreached cells somewhere, from a cell y of height h(c) (all of them are >= h(c) by
 * the choice of c and <= h(c) by the path) into a reached cell z with h(z) <= h(y),
 * and the search would have stepped from z to y. So "all reached" is exactly "no
 * depression", and then every figure is 0: what a pit removal leaves, checked at
 * the cost of one search instead of two floods. Sets *none; *nsinks gets the sink
 * count as the fills report it. */
static pg_status no_depression(const pg_pits_topo *t, const float *h, const pg_pits_opts *o,
                               int *none, uint64_t *nsinks, pg_error *err) {
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL;
    float *c = pg_huge_malloc(t->ncells * sizeof *c); /* pits_begin writes -inf into no-data */
    if (!c) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for statistics");
    memcpy(c, h, t->ncells * sizeof *c);
    uint8_t *st = NULL;
    pits_heap q = {0};
    pg_status s = pits_begin(t, c, &f, &st, &q, nsinks, err);
    if (s) {
        free(c);
        return s;
    }
    pits_fifo fifo = {0};
    uint64_t reached = *nsinks;
    uint32_t nb[8];
    for (size_t i = 0; i < q.n; i++)
        pits_fifo_push(&fifo, pits_key_id(q.a[i]));
    while (!pits_fifo_empty(&fifo) && !fifo.oom) {
        uint32_t d = pits_fifo_pop(&fifo);
        float hd = st[d] == PITS_CLOSED ? c[d] : -INFINITY;
        int k = pg_pits_neighbours(t, d, nb);
        for (int j = 0; j < k; j++)
            if (st[nb[j]] == PITS_OPEN && c[nb[j]] >= hd) {
                st[nb[j]] = PITS_CLOSED;
                reached++;
                pits_fifo_push(&fifo, nb[j]);
            }
    }
    int oom = fifo.oom;
    *none = reached == t->ncells;
    pits_fifo_free(&fifo);
    pits_heap_free(&q);
    free(st);
    free(c);
    return oom ? pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for statistics") : PG_OK;
}

/* A certificate that h has no depression, checked cell by cell: if every OPEN cell has
 * a neighbour that is not OPEN (a sink: water leaves there), or one lower in a
 * potential and not higher in h, then from any cell a walk along such neighbours
 * strictly lowers the potential, so it ends, and only at a sink; h never rises on the
 * way, so the minimal fill raises no cell. The potential is order when given, else p.
 * With p = h this is "every cell has a strictly lower neighbour", what an epsilon
 * result has everywhere; for a plain fill's flats, p the epsilon-surface of its input,
 * or order the order in which the serial flood closed the cells (each cell is closed
 * from a neighbour closed before it and not higher). A false answer proves nothing
 * (the caller then counts); a true one is exact, whoever computed the potential.
 * Linear, parallel, no queue. */
/* Whether cell i passes the certificate, its neighbours nb[0..k). */
static inline int drains_cell(const float *h, const uint8_t *st, const float *p,
                              const uint32_t *order, uint64_t i, const uint32_t *nb, int k) {
    for (int j = 0; j < k; j++) {
        uint32_t m = nb[j];
        int lower = order ? order[m] < order[i] : p[m] < p[i];
        if (st[m] != PITS_OPEN || (lower && h[m] <= h[i])) return 1;
    }
    return 0;
}

/* Whether neighbour m passes for cell i (no branch: see row_bad). */
#define PITS_PASSES(m)                                                                             \
    ((st[m] != PITS_OPEN) | ((by_order ? order[m] < order[i] : p[m] < p[i]) & (h[m] <= h[i])))

/* The cells x in [1, w - 1) of the row starting at id r, whose rows above and below are
 * in the same face: how many fail. The 8 neighbours are fixed offsets, and the test
 * has no branch and no early exit, so the compiler vectorises it along the row (the
 * same answer as drains_cell, which stops at the first neighbour that passes). */
static inline int64_t row_bad(const float *h, const uint8_t *st, const float *p,
                              const uint32_t *order, const int by_order, uint64_t r, uint64_t w) {
    int64_t bad = 0;
    for (uint64_t i = r + 1; i < r + w - 1; i++) {
        int ok = (st[i] != PITS_OPEN) | PITS_PASSES(i - w - 1) | PITS_PASSES(i - w) |
                 PITS_PASSES(i - w + 1) | PITS_PASSES(i - 1) | PITS_PASSES(i + 1) |
                 PITS_PASSES(i + w - 1) | PITS_PASSES(i + w) | PITS_PASSES(i + w + 1);
        bad += !ok;
    }
    return bad;
}
#undef PITS_PASSES

int pits_drains_by(const pg_pits_topo *t, const float *h, const uint8_t *st, const float *p,
                   const uint32_t *order) {
    int64_t bad = 0;
    const uint32_t w = t->w, fh = t->h;
    const int64_t rows = (int64_t)(t->ncells / w);
    /* row by row: the interior of a row in row_bad, its ends and the rows at a face's
     * edge through pg_pits_neighbours */
#pragma omp parallel for reduction(+ : bad) schedule(static)
    for (int64_t r = 0; r < rows; r++) {
        const uint32_t y = (uint32_t)(r % fh);
        const uint64_t row = (uint64_t)r * w;
        const int inner = y - 1u < fh - 2u && w > 2;
        if (inner)
            bad +=
                order ? row_bad(h, st, NULL, order, 1, row, w) : row_bad(h, st, p, NULL, 0, row, w);
        for (uint32_t x = 0; x < w; x++) {
            if (inner && x == 1) x = w - 1; /* the interior is done */
            const uint64_t i = row + x;
            if (st[i] != PITS_OPEN) continue;
            uint32_t nb[8];
            int k = pg_pits_neighbours(t, (uint32_t)i, nb);
            bad += !drains_cell(h, st, p, order, i, nb, k);
        }
    }
    return bad == 0;
}

/* dep[i] = 1 where the minimal fill raises cell i, else 0 (no-data cells are equal). */
static void mark_raised(uint64_t n, const float *h, const float *fill, uint8_t *dep) {
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < (int64_t)n; i++)
        dep[i] = fill[i] > h[i];
}

pg_status pits_stats_from_fill(const pg_pits_topo *t, const float *h, const float *fill,
                               const pg_pits_area *area, uint64_t nsinks, pg_pits_stats *st,
                               pg_error *err) {
    memset(st, 0, sizeof *st);
    st->sinks = nsinks;
    uint8_t *dep = pg_huge_malloc(t->ncells);
    if (!dep) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for statistics");
    mark_raised(t->ncells, h, fill, dep);
    int oom = pits_count_regions(t, h, dep, fill, area, st);
    free(dep);
    return oom ? pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory for statistics") : PG_OK;
}

/* The counts from h's own minimal fill. */
static pg_status compute_from_own_fill(const pg_pits_topo *t, const float *h, const pg_pits_opts *o,
                                       const pg_pits_area *area, pg_pits_stats *st, pg_error *err) {
    memset(st, 0, sizeof *st);
    uint64_t nsinks = 0;
    float *fill = NULL;
    pg_status s = fill_copy(t, h, o, &fill, &nsinks, err);
    if (!s) s = pits_stats_from_fill(t, h, fill, area, nsinks, st, err);
    free(fill);
    return s;
}

pg_status pg_pits_stats_compute(const pg_pits_topo *t, const float *h, const pg_pits_opts *o,
                                const pg_pits_area *area, pg_pits_stats *st, pg_error *err) {
    memset(st, 0, sizeof *st);
    int none = 0;
    pg_status s = no_depression(t, h, o, &none, &st->sinks, err);
    if (s || none) return s;
    return compute_from_own_fill(t, h, o, area, st, err);
}
