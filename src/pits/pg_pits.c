/* pg_pits.c - the public entry points of pit removal: options, method names and
 * citations, dispatch to the algorithm files, the change summary, and the Gain-pit
 * offset correction (Scott & Dodgson 2021 §5: R' = remove(R), offsets += R' - R). */
#include "pg_huge.h"
#include "pg_pits_internal.h"

#include <omp.h>
#include <stdlib.h>

void pg_pits_opts_default(pg_pits_opts *o) {
    memset(o, 0, sizeof *o);
    o->method = PG_PITS_BREACH;
    o->epsilon = true;
    o->max_depth = INFINITY;
    o->max_length = INFINITY;
    o->nodata = NAN;
}

static const char *const NAMES[] = {"fill", "breach", "hybrid"};

bool pg_pits_method_parse(const char *s, pg_pits_method *m) {
    for (int i = 0; s && i < 3; i++) {
        if (!strcmp(s, NAMES[i])) {
            *m = (pg_pits_method)i;
            return true;
        }
    }
    return false;
}

const char *pg_pits_method_name(pg_pits_method m) {
    return (unsigned)m < 3 ? NAMES[m] : "unknown";
}

const char *pg_pits_method_citation(pg_pits_method m) {
    switch (m) {
    case PG_PITS_FILL:
        return "Improved Priority-Flood fill: Barnes, Lehman & Mulla (2014), Computers & "
               "Geosciences 62:117-127; with epsilon, the minimal epsilon-surface of Planchon & "
               "Darboux (2002), Catena 46:159-176";
    case PG_PITS_BREACH:
        return "breaching by flood order: Soille (2004), Water Resources Research 40:W12509, "
               "as in Scott & Dodgson (2021) section 3.2";
    case PG_PITS_HYBRID:
        return "selective breaching (hybrid): Lindsay (2016), Hydrological Processes "
               "30(6):846-857";
    }
    return "unknown method";
}

const char *pg_pits_citation(const pg_pits_opts *o) {
    if (o->method == PG_PITS_FILL || !o->descent) return pg_pits_method_citation(o->method);
    if (o->method == PG_PITS_BREACH)
        return "breaching along the descent tree of the minimal epsilon-surface (no flood "
               "order): Soille (2004), Water Resources Research 40:W12509, carving, on the "
               "surface of Planchon & Darboux (2002), Catena 46:159-176";
    if (o->method == PG_PITS_HYBRID)
        return "selective breaching (hybrid) along the descent tree of the minimal "
               "epsilon-surface (no flood order): Lindsay (2016), Hydrological Processes "
               "30(6):846-857, limits on Soille (2004) carving";
    return pg_pits_method_citation(o->method);
}

int pits_tiled_fill(const pg_pits_topo *t, const pg_pits_opts *o) {
    return t->ncells < (UINT64_C(1) << 31) &&
           (o->tile_rows > 0 || (omp_get_max_threads() > 1 && t->ncells >= 4096));
}

static pg_status dispatch(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                          pg_pits_result *res, pg_error *err) {
    switch (o->method) {
    case PG_PITS_FILL:
        if (o->epsilon) return pits_minimal_eps_planchon2002(t, h, o, res, err);
        if (pits_tiled_fill(t, o)) return pits_parallel_fill_barnes2016(t, h, o, res, err);
        return pits_priority_flood_barnes2014(t, h, o, res, err, NULL);
    case PG_PITS_BREACH:
        if (o->descent) return pits_breach_descent(t, h, o, res, err);
        return pits_breach_soille2004(t, h, o, res, err);
    case PG_PITS_HYBRID:
        if (o->descent) return pits_breach_descent(t, h, o, res, err);
        return pits_hybrid_lindsay2016(t, h, o, res, err);
    }
    return pg_error_set(err, PG_ERR_BADINPUT, "pits: unknown method %d", (int)o->method);
}

/* Count raised/lowered cells between before and after (no-data cells are equal). */
static void summarise(const pg_pits_topo *t, const float *before, const float *after,
                      pg_pits_result *res) {
    uint64_t up = 0, down = 0;
    double maxup = 0, maxdown = 0;
    const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for reduction(+ : up, down) reduction(max : maxup, maxdown)
    for (int64_t i = 0; i < n; i++) {
        double d = (double)after[i] - (double)before[i];
        if (after[i] > before[i]) {
            up++;
            if (d > maxup) maxup = d;
        } else if (after[i] < before[i]) {
            down++;
            if (-d > maxdown) maxdown = -d;
        }
    }
    res->raised = up;
    res->lowered = down;
    res->max_raise = maxup;
    res->max_lower = maxdown;
}

pg_status pg_pits_remove(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                         pg_pits_result *res, pg_error *err) {
    pg_status s = pits_validate(t, o, err);
    if (s) return s;
    pg_pits_result local = {0};
    float *before = NULL;
    if (res) {
        before = pg_huge_malloc(t->ncells * sizeof *before);
        if (!before) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory");
        memcpy(before, h, t->ncells * sizeof *before);
    }
    s = dispatch(t, h, o, &local, err);
    if (!s && res) {
        summarise(t, before, h, &local);
        *res = local;
    }
    free(before);
    return s;
}

pg_status pg_pits_correct_offsets(const pg_pits_topo *t, const float *recon, float *offsets,
                                  const pg_pits_opts *o, pg_pits_result *res, pg_error *err) {
    pg_status s = pits_validate(t, o, err);
    if (s) return s;
    float *r = pg_huge_malloc(t->ncells * sizeof *r);
    if (!r) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory");
    memcpy(r, recon, t->ncells * sizeof *r);
    pg_pits_result local = {0};
    s = dispatch(t, r, o, &local, err);
    if (!s) {
        const int64_t n = (int64_t)t->ncells;
#pragma omp parallel for schedule(static)
        for (int64_t i = 0; i < n; i++)
            if (r[i] != recon[i] && !isnan(recon[i])) offsets[i] += r[i] - recon[i];
        if (res) {
            summarise(t, recon, r, &local);
            *res = local;
        }
    }
    free(r);
    return s;
}

/* The minimal fill (eps 0) or epsilon-fill (eps 1) of h into out. */
static pg_status fill_of(const pg_pits_topo *t, const float *h, const pg_pits_opts *o, int eps,
                         float *out, pg_error *err) {
    pg_pits_opts f = *o;
    f.method = PG_PITS_FILL;
    f.epsilon = eps;
    pg_pits_result r = {0};
    memcpy(out, h, t->ncells * sizeof *out);
    return dispatch(t, out, &f, &r, err);
}

/* The depression counts of the result h: 0 when the certificate of pits_drains_by
 * holds (potential: order when given, else p, else h itself), else the full count. */
static pg_status count_after(const pg_pits_topo *t, float *h, const pg_pits_opts *o, const float *p,
                             const uint32_t *order, const pg_pits_area *area, pg_pits_stats *after,
                             pg_error *err) {
    uint8_t *st = NULL;
    uint64_t nsinks = 0;
    pg_status s = pits_begin(t, h, o, &st, NULL, &nsinks, err); /* no-data: -inf for now */
    if (s) return s;
    int ok = pits_drains_by(t, h, st, p ? p : h, order);
    pits_end(t, h, o, st);
    free(st);
    if (!ok) return pg_pits_stats_compute(t, h, o, area, after, err);
    memset(after, 0, sizeof *after);
    after->sinks = nsinks;
    return PG_OK;
}

/* The counts after a plain fill f made by the tiled fill (tiles asked for), which keeps
 * no closing order: the epsilon-surface of its input from f's flats
 * (pits_meps_from_fill). When that checks out, every cell got its value from an exit
 * of its flat, so each has a path along its flat to a cell with a lower neighbour or a
 * sink neighbour, and f has no depression; otherwise the full count. */
static pg_status count_after_tiled_fill(const pg_pits_topo *t, float *f, const pg_pits_opts *o,
                                        const pg_pits_area *area, pg_pits_stats *after,
                                        pg_error *err) {
    float *w = pg_huge_malloc(t->ncells * sizeof *w);
    if (!w) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory");
    int exact = 0;
    uint64_t nsinks = 0;
    pg_status s = pits_eps_from_fill(t, f, o, w, &exact, &nsinks, err);
    free(w);
    if (s || !exact) return s ? s : count_after(t, f, o, NULL, NULL, area, after, err);
    memset(after, 0, sizeof *after);
    after->sinks = nsinks;
    return PG_OK;
}

pg_status pg_pits_remove_counted(const pg_pits_topo *t, float *h, const pg_pits_opts *o,
                                 const pg_pits_area *area, pg_pits_result *res,
                                 pg_pits_stats *before, pg_pits_stats *after, pg_error *err) {
    pg_status s = pits_validate(t, o, err);
    if (s) return s;
    const size_t n = t->ncells;
    const int plain_fill = o->method == PG_PITS_FILL && !o->epsilon;
    const int eps_fill = o->method == PG_PITS_FILL && o->epsilon;
    const int descent = o->method != PG_PITS_FILL && o->descent;
    const int soille = o->method == PG_PITS_BREACH && !o->descent;
    const int lindsay = o->method == PG_PITS_HYBRID && !o->descent;
    /* a plain fill runs serially unless tiles are asked for: the check after the
     * tiled fill costs more than its threads save (docs/pits.md, "Metrics") */
    const int serial_fill = plain_fill && o->tile_rows <= 0;
    float *in = pg_huge_malloc(n * sizeof *in), *fill = NULL;
    uint32_t *order = NULL;
    if (!in) return pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory");
    memcpy(in, h, n * sizeof *in);
    const int need_fill = !plain_fill; /* every other method counts from the minimal fill */
    if (need_fill) fill = pg_huge_malloc(n * sizeof *fill);
    if (serial_fill) /* zeroed: every value the certificate reads is defined */
        order = pg_huge_calloc(n, sizeof *order);
    if ((need_fill && !fill) || (serial_fill && !order))
        s = pg_error_set(err, PG_ERR_NOMEM, "pits: out of memory");
    pg_pits_result local = {0};
    /* the removal, keeping what its floods computed about the input (docs/pits.md,
     * "Metrics"): a plain fill is the input's minimal fill, and the serial one keeps
     * the order in which it closed the cells; the epsilon floods (the epsilon fill's,
     * the descent tree's) give the minimal fill as well, checked, and Soille's and
     * Lindsay's floods give it exactly */
    int have_fill = 0; /* the removal gave the minimal fill */
    if (!s && descent)
        s = pits_breach_descent_fill(t, h, o, &local, fill, &have_fill, err);
    else if (!s && eps_fill)
        s = pits_minimal_eps_planchon2002_fill(t, h, o, &local, in, fill, &have_fill, err);
    else if (!s && soille)
        s = pits_breach_soille2004_fill(t, h, o, &local, fill, err), have_fill = 1;
    else if (!s && lindsay)
        s = pits_hybrid_lindsay2016_fill(t, h, o, &local, fill, err), have_fill = 1;
    else if (!s && serial_fill)
        s = pits_priority_flood_barnes2014(t, h, o, &local, err, order);
    else if (!s)
        s = dispatch(t, h, o, &local, err);
    if (!s && !plain_fill) summarise(t, in, h, &local);
    /* otherwise (a check refused) the minimal fill comes from its own flood */
    if (!s && need_fill && !have_fill) s = fill_of(t, in, o, 0, fill, err);
    if (!s) s = pits_stats_from_fill(t, in, plain_fill ? h : fill, area, local.sinks, before, err);
    if (!s && plain_fill) { /* what summarise would find: a fill raises exactly the
                             * cells the count labels, by fill - h, and lowers none */
        local.raised = before->depression_cells;
        local.max_raise = before->max_depth_m;
        local.lowered = 0;
        local.max_lower = 0;
    }
    free(in);
    free(fill);
    if (!s && plain_fill && !serial_fill)
        s = count_after_tiled_fill(t, h, o, area, after, err);
    else if (!s)
        s = count_after(t, h, o, NULL, order, area, after, err);
    free(order);
    if (!s && res) *res = local;
    return s;
}
