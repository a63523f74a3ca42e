/* pg_pits_gainpit.c - Gain-pit: pit removal between the correction passes of the
 * synthesis (Scott & Dodgson 2021 §5), as a pass hook for the flat driver.
 *
 * Idea: the synthesis stores, per texel, an exemplar coordinate S and an offset V;
 * its heights are R = E_s(S) + V. Correction introduces pits at every level. The
 * hook removes them from R (one pass over the whole level, border as outlet) and
 * folds the change into V, so the next pass and the next level start pit-free and
 * the coarse drainage is inherited by the fine levels. See pg_pits_gainpit.h. */
#include "planetgen/pg_pits_gainpit.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

void pg_pits_gainpit_init(pg_pits_gainpit *g) {
    memset(g, 0, sizeof *g);
    pg_pits_opts_default(&g->opts);
    g->opts.open_edges = true;
    g->skip_levels = 1;
}

void pg_pits_gainpit_hook(void *user, const pg_synth_exemplar *ex, int scale, int pass, uint32_t *S,
                          float *V, int res, ptrdiff_t stride) {
    pg_pits_gainpit *g = user;
    (void)pass;
    if (scale < g->skip_levels || g->err.status != PG_OK) return;
    double t0 = omp_get_wtime();
    size_t n = (size_t)res * res;
    float *R = malloc(n * sizeof *R), *off = malloc(n * sizeof *off);
    pg_pits_topo t;
    if (!R || !off) {
        pg_error_set(&g->err, PG_ERR_NOMEM, "pits: out of memory in the Gain-pit hook");
    } else if (pg_pits_topo_grid(&t, (uint32_t)res, (uint32_t)res, &g->err) == PG_OK) {
        for (int y = 0; y < res; y++)
            for (int x = 0; x < res; x++) {
                ptrdiff_t k = (ptrdiff_t)y * stride + x;
                off[(size_t)y * res + x] = V[k];
                R[(size_t)y * res + x] = pg_synth_level_height(ex, scale, S[k]) + V[k];
            }
        pg_pits_opts o = g->opts;
        o.has_sea_level = true;
        o.sea_level = ex->sea_level;
        pg_pits_result r;
        if (pg_pits_correct_offsets(&t, R, off, &o, &r, &g->err) == PG_OK) {
            for (int y = 0; y < res; y++)
                for (int x = 0; x < res; x++)
                    V[(ptrdiff_t)y * stride + x] = off[(size_t)y * res + x];
            g->runs++;
            g->changed += r.raised + r.lowered;
        }
    }
    free(R);
    free(off);
    g->seconds += omp_get_wtime() - t0;
}
