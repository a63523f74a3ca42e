/* pg_drainage.c - flow accumulation and the drainage-network measures on any receiver
 * graph (pg_drainage.h; docs/inspect.md, "Drainage network").
 *
 * Accumulation: every cell starts with its own area; a cell passes its total to its
 * receiver once all its donors have passed theirs. Counting donors and starting from
 * the cells that have none (Kahn 1962, topological sorting) visits each cell once:
 * O(n). A cell that is never passed lies on a cycle (or drains into one), which a
 * receiver graph must not have, so it is reported. The order is fixed by the ids, so
 * the sums - and every figure - are the same on every run.
 *
 * While a cell passes its total on, its receiver remembers its main donor (largest
 * accumulation, ties to the lowest id); both numbers are final at that point, because
 * a cell is passed only after all its donors. The main stream of a mouth is then the
 * chain of main donors, walked upstream to a cell without donors. Over all mouths these
 * chains are disjoint, so the walks cost O(n) as well.
 *
 * Hack's law (Hack 1957) is fitted by ordinary least squares of ln L on ln A, the usual
 * estimator (e.g. Rigon et al. 1996, "On Hack's law", Water Resour. Res. 32). Only
 * basins that reach the sea are fitted: a pit basin is a closed depression, not a
 * river network. Sums over cells run serially in id order (thread-count independent). */
#include "pg_huge.h"
#include "planetgen/pg_drainage.h"

#include <math.h>
#include <stdlib.h>

void pg_drainage_opts_default(pg_drainage_opts *o) {
    o->river_threshold_km2 = 1e4;
    o->hack_min_area_km2 = 1e4;
}

static int finite_nonneg(float v) {
    return isfinite(v) && v >= 0.0f;
}

static pg_status check_graph(const pg_drainage_graph *g, const pg_drainage_opts *o, pg_error *err) {
    if (!g->receiver || !g->area_km2 || !g->length_km || !g->flags)
        return pg_error_set(err, PG_ERR_BADINPUT, "drainage: missing graph arrays");
    if (g->ncell >= (UINT64_C(1) << 31))
        return pg_error_set(err, PG_ERR_BADINPUT, "drainage: %llu cells, at most 2^31 - 1",
                            (unsigned long long)g->ncell);
    if (!(o->river_threshold_km2 > 0) || !(o->hack_min_area_km2 > 0) ||
        !isfinite(o->river_threshold_km2) || !isfinite(o->hack_min_area_km2))
        return pg_error_set(err, PG_ERR_BADINPUT, "drainage: thresholds must be finite and > 0");
    for (uint64_t i = 0; i < g->ncell; i++) {
        int32_t r = g->receiver[i];
        if (r < -1 || (int64_t)r >= (int64_t)g->ncell || (uint64_t)r == i)
            return pg_error_set(err, PG_ERR_BADINPUT, "drainage: cell %llu has receiver %d",
                                (unsigned long long)i, (int)r);
        if (r >= 0 && !(g->flags[i] & PG_DRAINAGE_LAND))
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "drainage: sea cell %llu has a receiver (sea is an outlet)",
                                (unsigned long long)i);
        if (!finite_nonneg(g->area_km2[i]) || !finite_nonneg(g->length_km[i]))
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "drainage: cell %llu has a negative or non-finite area or length",
                                (unsigned long long)i);
    }
    return PG_OK;
}

/* Work arrays: donor counts still to come, accumulation, main donors. */
typedef struct acc_work {
    uint32_t *ndonor;
    double *acc;
    int32_t *main_donor;
} acc_work;

static void work_free(acc_work *w) {
    free(w->ndonor), free(w->acc), free(w->main_donor);
}

static pg_status work_alloc(acc_work *w, uint64_t n, pg_error *err) {
    size_t m = n ? (size_t)n : 1;
    w->ndonor = pg_huge_calloc(m, sizeof *w->ndonor);
    w->acc = pg_huge_malloc(m * sizeof *w->acc);
    w->main_donor = pg_huge_malloc(m * sizeof *w->main_donor);
    if (w->ndonor && w->acc && w->main_donor) return PG_OK;
    work_free(w);
    return pg_error_set(err, PG_ERR_NOMEM, "drainage: out of memory for %llu cells",
                        (unsigned long long)n);
}

/* Is donor d a better main donor of its receiver than the current one, c? */
static int better_donor(const double *acc, int32_t d, int32_t c) {
    return c < 0 || acc[d] > acc[c] || (acc[d] == acc[c] && d < c);
}

/* Pass cell j's total on, then its receiver's if j was its last donor, and so on
 * downstream; returns the number of cells passed. DONE marks a passed cell. */
#define DONE UINT32_MAX

static uint64_t pass_down(const pg_drainage_graph *g, acc_work *w, int32_t j) {
    uint64_t k = 0;
    for (;;) {
        int32_t r = g->receiver[j];
        w->ndonor[j] = DONE, k++;
        if (r < 0) return k;
        w->acc[r] += w->acc[j];
        if (better_donor(w->acc, j, w->main_donor[r])) w->main_donor[r] = j;
        if (--w->ndonor[r] != 0) return k;
        j = r;
    }
}

/* Kahn's algorithm, depth first: from each source in id order, follow the flow down as
 * far as every donor is done. Downstream cells are near in memory, so this touches far
 * fewer cache lines than a FIFO queue. Returns the number of cells passed (ncell
 * unless there is a cycle). */
static uint64_t accumulate(const pg_drainage_graph *g, acc_work *w) {
    const uint64_t n = g->ncell;
    for (uint64_t i = 0; i < n; i++) {
        w->acc[i] = g->area_km2[i];
        w->main_donor[i] = -1;
        if (g->receiver[i] >= 0) w->ndonor[g->receiver[i]]++;
    }
    uint64_t done = 0;
    for (uint64_t i = 0; i < n; i++)
        if (w->ndonor[i] == 0) done += pass_down(g, w, (int32_t)i);
    return done;
}

static int is_land(const pg_drainage_graph *g, uint64_t i) {
    return (g->flags[i] & PG_DRAINAGE_LAND) != 0;
}

/* A mouth: a land cell that leaves the land (into the sea, or out of the domain). */
static int is_mouth(const pg_drainage_graph *g, uint64_t i) {
    int32_t r = g->receiver[i];
    if (r >= 0) return !is_land(g, (uint64_t)r);
    return (g->flags[i] & PG_DRAINAGE_OUTLET) != 0;
}

static int is_pit(const pg_drainage_graph *g, uint64_t i) {
    return g->receiver[i] < 0 && !(g->flags[i] & PG_DRAINAGE_OUTLET);
}

static double main_stream_km(const pg_drainage_graph *g, const acc_work *w, int32_t mouth) {
    double len = 0;
    for (int32_t c = mouth; c >= 0; c = w->main_donor[c])
        len += g->length_km[c];
    return len;
}

/* Least-squares sums of (x, y) = (ln A, ln L). */
typedef struct fit_sums {
    double n, sx, sy, sxx, syy, sxy;
} fit_sums;

static void fit_add(fit_sums *f, double x, double y) {
    f->n += 1, f->sx += x, f->sy += y;
    f->sxx += x * x, f->syy += y * y, f->sxy += x * y;
}

static void fit_finish(const fit_sums *f, pg_drainage_stats *st) {
    st->hack_basins = (uint64_t)f->n;
    st->hack_exponent = st->hack_coefficient = st->hack_r2 = NAN;
    if (f->n < 3) return;
    double vxx = f->sxx - f->sx * f->sx / f->n, vyy = f->syy - f->sy * f->sy / f->n;
    double vxy = f->sxy - f->sx * f->sy / f->n;
    if (!(vxx > 0)) return;
    double h = vxy / vxx;
    st->hack_exponent = h;
    st->hack_coefficient = exp((f->sy - h * f->sx) / f->n);
    st->hack_r2 = vyy > 0 ? vxy * vxy / (vxx * vyy) : 1.0;
}

static void basin_stats(const pg_drainage_graph *g, const pg_drainage_opts *o, const acc_work *w,
                        pg_drainage_stats *st) {
    fit_sums f = {0};
    double closed = 0;
    for (uint64_t i = 0; i < g->ncell; i++) {
        if (!is_land(g, i)) continue;
        double a = w->acc[i];
        st->land_cells++;
        st->land_area_km2 += g->area_km2[i];
        if (a >= o->river_threshold_km2) {
            st->river_cells++;
            st->river_length_km += g->length_km[i];
        }
        int mouth = is_mouth(g, i), pit = is_pit(g, i);
        if (!mouth && !pit) continue;
        st->mouths += (uint64_t)mouth;
        st->pits += (uint64_t)pit;
        if (pit) closed += a;
        if (a > st->largest_basin_km2) st->largest_basin_km2 = a;
        if (!mouth || a < o->hack_min_area_km2) continue;
        double len = main_stream_km(g, w, (int32_t)i);
        if (len > 0) fit_add(&f, log(a), log(len));
    }
    fit_finish(&f, st);
    double land = st->land_area_km2;
    st->drainage_density_per_km = land > 0 ? st->river_length_km / land : NAN;
    st->largest_basin_land_share = land > 0 ? st->largest_basin_km2 / land : NAN;
    st->closed_land_share = land > 0 ? closed / land : NAN;
}

pg_status pg_drainage_compute(const pg_drainage_graph *g, const pg_drainage_opts *o, float *acc_km2,
                              pg_drainage_stats *st, pg_error *err) {
    pg_drainage_opts def;
    if (!o) pg_drainage_opts_default(&def), o = &def;
    *st = (pg_drainage_stats){0};
    pg_status s = check_graph(g, o, err);
    if (s) return s;
    acc_work w;
    if ((s = work_alloc(&w, g->ncell, err))) return s;
    if (accumulate(g, &w) != g->ncell) {
        work_free(&w);
        return pg_error_set(err, PG_ERR_BADINPUT, "drainage: the receiver graph has a cycle");
    }
    basin_stats(g, o, &w, st);
    if (acc_km2)
        for (uint64_t i = 0; i < g->ncell; i++)
            acc_km2[i] = (float)w.acc[i];
    work_free(&w);
    return PG_OK;
}
