/* test_pits_gainpit.c - Gain-pit inside the flat synthesis: the pass hook runs at
 * every corrected level except the skipped finest ones and edits the offsets; run
 * down to the finest level it removes most of the depression volume of the
 * synthesized terrain; the final pass leaves no depression. */
#include "pg_test.h"
#include "planetgen/pg_pits_gainpit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

enum { FS = 64, OUT = 128 };

/* Rolling hills with scattered closed hollows and a sea: an exemplar full of pits. */
static pg_synth_exemplar *pitted_torus(void) {
    float *rgb = malloc(sizeof(float) * FS * FS * 3), *h = malloc(sizeof(float) * FS * FS);
    const double tau = 6.283185307179586;
    for (int y = 0; y < FS; y++)
        for (int x = 0; x < FS; x++) {
            double u = (double)x / FS, v = (double)y / FS;
            double e = 600 * sin(tau * (u + 2 * v)) + 400 * cos(tau * (3 * u - v)) +
                       150 * sin(tau * (5 * u + 7 * v)) + 2000; /* all land */
            /* five wide closed basins (they survive the coarse levels' blur) */
            for (int k = 0; k < 8; k++) {
                double cx = FS * (0.06 + 0.12 * k), cy = FS * (0.5 + 0.35 * sin(2.0 * k));
                double dx = x - cx, dy = y - fmod(cy + FS, FS);
                e -= 900 * exp(-(dx * dx + dy * dy) / (2 * 4.0 * 4.0));
            }
            size_t i = (size_t)y * FS + x;
            h[i] = (float)e;
            rgb[3 * i + 0] = (float)(0.3 + 0.2 * sin(tau * u));
            rgb[3 * i + 1] = (float)(0.4 + 0.0002 * e);
            rgb[3 * i + 2] = (float)(0.2 + 0.1 * cos(tau * v));
        }
    pg_synth_exemplar_params p;
    pg_synth_exemplar_params_default(&p);
    p.face_size = FS;
    p.levels = 3;
    p.min_separation = 0.1;
    pg_synth_exemplar *ex = NULL;
    pg_synth_prep_info info;
    pg_error err = {0};
    pg_status st = pg_synth_prepare_torus(rgb, h, FS, 0.0f, &p, "", &ex, &info, &err);
    if (st) fprintf(stderr, "%s\n", err.msg);
    assert_int_equal(st, PG_OK);
    free(rgb);
    free(h);
    return ex;
}

/* Synthesize, render heights, return the depressions before any final pass. */
static float *synth(const pg_synth_exemplar *ex, pg_pits_gainpit *gp, pg_pits_stats *st) {
    pg_synth_params p;
    pg_synth_params_default(&p);
    p.seed = 7;
    pg_synth_result r;
    pg_error err = {0};
    assert_int_equal(pg_synth_flat(ex, OUT, &p, gp ? pg_pits_gainpit_hook : NULL, gp, &r, &err),
                     PG_OK);
    float *h = malloc(sizeof(float) * OUT * OUT);
    pg_synth_render(ex, r.coords, r.offset, (size_t)OUT * OUT, NULL, h);
    pg_synth_result_free(&r);
    pg_pits_topo t;
    pg_pits_topo_grid(&t, OUT, OUT, NULL);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.open_edges = true;
    o.has_sea_level = true;
    o.sea_level = ex->sea_level;
    assert_int_equal(pg_pits_stats_compute(&t, h, &o, NULL, st, NULL), PG_OK);
    return h;
}

static void test_gainpit_hook(void **state) {
    (void)state;
    pg_synth_exemplar *ex = pitted_torus();
    pg_pits_stats plain, gain;
    float *h0 = synth(ex, NULL, &plain);
    pg_pits_gainpit gp;
    pg_pits_gainpit_init(&gp);
    float *h1 = synth(ex, &gp, &gain);
    print_message("without Gain-pit: %llu depressions, volume %.4g; with: %llu, volume %.4g "
                  "(%llu hook runs, %llu offsets changed)\n",
                  (unsigned long long)plain.depressions, plain.depression_volume_m3,
                  (unsigned long long)gain.depressions, gain.depression_volume_m3,
                  (unsigned long long)gp.runs, (unsigned long long)gp.changed);
    assert_int_equal(gp.err.status, PG_OK);
    assert_true(gp.runs >= 2); /* levels above the finest, every pass */
    assert_true(gp.changed > 0);
    assert_true(plain.depressions > 0);
    /* Gain-pit down to the finest level removes most of the depression volume. Not
     * all: the hook sees R = E_0(S) + V with E_0 the exemplar's local mean height
     * (pg_synth_level_height), while the rendered terrain uses the raw height. */
    pg_pits_gainpit all;
    pg_pits_gainpit_init(&all);
    all.skip_levels = 0;
    pg_pits_stats full;
    float *h2 = synth(ex, &all, &full);
    print_message("Gain-pit at every level: %llu depressions, volume %.4g\n",
                  (unsigned long long)full.depressions, full.depression_volume_m3);
    assert_true(all.runs > gp.runs);
    assert_true(full.depression_volume_m3 < 0.25 * plain.depression_volume_m3);
    free(h2);
    /* the final pass leaves nothing */
    pg_pits_topo t;
    pg_pits_topo_grid(&t, OUT, OUT, NULL);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.open_edges = true;
    o.has_sea_level = true;
    o.sea_level = ex->sea_level;
    assert_int_equal(pg_pits_remove(&t, h1, &o, NULL, NULL), PG_OK);
    pg_pits_stats after;
    assert_int_equal(pg_pits_stats_compute(&t, h1, &o, NULL, &after, NULL), PG_OK);
    assert_int_equal(after.depressions, 0);
    free(h0);
    free(h1);
    pg_synth_exemplar_free(ex);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_gainpit_hook)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
