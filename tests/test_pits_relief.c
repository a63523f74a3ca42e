/* test_pits_relief.c - pit removal on real terrain: Marble's global relief (8 x 16
 * grey JPEG tiles, 10800 x 5400). At full resolution the depressions are counted
 * before and after epsilon fill and hybrid (after: 0). On the 2700 x 1350 metre grid
 * the exemplar loader makes (epsilon breach), and on that relief resampled to a
 * 6 x 256^2 cube sphere (all three), the independent checker confirms every cell
 * drains. Figures are printed for the
 * record; no timing is asserted. */
#include "pg_marble.h"
#include "pg_test.h"
#include "pits_checker.h"
#include "planetgen/pg_cube.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_image.h"
#include "planetgen/pg_pits.h"

#include <stdio.h>

static void test_full_resolution_relief(void **state) {
    (void)state;
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo);
    pg_exemplar ex;
    pg_error err = {0};
    assert_int_equal(pg_exemplar_load(&eo, &ex, &err), PG_OK);
    float sea_grey = ex.calib.sea_grey;
    pg_exemplar_free(&ex);
    pg_image img;
    assert_int_equal(pg_exemplar_assemble_relief(PG_MARBLE_RELIEF_DIR, PG_MARBLE_RELIEF_ROWS,
                                                 PG_MARBLE_RELIEF_COLS, &img, &err),
                     PG_OK);
    assert_int_equal(img.width, 10800);
    assert_int_equal(img.height, 5400);
    pg_pits_topo t;
    pg_pits_topo_grid(&t, (uint32_t)img.width, (uint32_t)img.height, NULL);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.has_sea_level = true;
    o.sea_level = sea_grey; /* raw grey heights: the calibration is monotone */
    pg_pits_stats before, after;
    assert_int_equal(pg_pits_stats_compute(&t, img.data, &o, NULL, &before, NULL), PG_OK);
    print_message("relief 10800x5400, sea grey %.1f: %llu depressions, %llu cells before\n",
                  sea_grey, (unsigned long long)before.depressions,
                  (unsigned long long)before.depression_cells);
    assert_true(before.depressions > 100);
    float *h = malloc(sizeof(float) * t.ncells);
    for (int m = 0; m < 3; m += 2) { /* fill and hybrid here; breach on the metre grid */
        memcpy(h, img.data, sizeof(float) * t.ncells);
        o.method = (pg_pits_method)m;
        o.epsilon = true;
        o.max_depth = 5;
        o.max_length = 50;
        pg_pits_result r;
        assert_int_equal(pg_pits_remove(&t, h, &o, &r, NULL), PG_OK);
        assert_int_equal(pg_pits_stats_compute(&t, h, &o, NULL, &after, NULL), PG_OK);
        print_message("%s: raised %llu, lowered %llu; after: %llu depressions\n",
                      pg_pits_method_name(o.method), (unsigned long long)r.raised,
                      (unsigned long long)r.lowered, (unsigned long long)after.depressions);
        assert_int_equal(after.depressions, 0);
        if (m == 0) assert_int_equal(r.lowered, 0);
        if (m == 2) assert_true(r.max_lower <= 5.0);
    }
    free(h);
    pg_image_free(&img);
}

static void test_relief_metres_and_planet(void **state) {
    (void)state;
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo);
    pg_exemplar ex;
    assert_int_equal(pg_exemplar_load(&eo, &ex, NULL), PG_OK);
    int w = ex.width, h = ex.height;
    pg_pits_opts o;
    pg_pits_opts_default(&o); /* breach with epsilon: the final pass's default */
    o.has_sea_level = true;
    o.sea_level = ex.sea_level;
    /* flat */
    pg_pits_topo t;
    pg_pits_topo_grid(&t, (uint32_t)w, (uint32_t)h, NULL);
    chk_graph g = chk_grid_graph(w, h);
    uint8_t *sk = chk_sinks(ex.elevation, g.n, 1, ex.sea_level, NULL, 0, w, h);
    assert_true(chk_undrained(&g, ex.elevation, sk, 0) > 0);
    float *a = malloc(sizeof(float) * g.n);
    memcpy(a, ex.elevation, sizeof(float) * g.n);
    assert_int_equal(pg_pits_remove(&t, a, &o, NULL, NULL), PG_OK);
    assert_int_equal(chk_undrained(&g, a, sk, 1), 0);
    pg_pits_stats st;
    assert_int_equal(pg_pits_stats_compute(&t, a, &o, NULL, &st, NULL), PG_OK);
    assert_int_equal(st.depressions, 0);
    free(a);
    free(sk);
    chk_graph_free(&g);
    /* planet */
    int N = 256;
    float *cube = malloc(sizeof(float) * 6 * N * N);
    assert_int_equal(
        pg_cube_from_equirect(PG_CUBE_EQUIANGULAR, N, NULL, ex.elevation, w, h, 1, 2, cube, NULL),
        PG_OK);
    pg_pits_topo_cube(&t, (uint32_t)N, NULL);
    g = geometric_cube_graph(N);
    sk = chk_sinks(cube, g.n, 1, ex.sea_level, NULL, 0, 0, 0);
    assert_int_equal(pg_pits_stats_compute(&t, cube, &o, NULL, &st, NULL), PG_OK);
    print_message("planet 6x256^2: %llu depressions before\n", (unsigned long long)st.depressions);
    assert_true(st.depressions > 0);
    for (int m = 0; m < 3; m++) {
        o.method = (pg_pits_method)m;
        o.max_depth = 100;
        o.max_length = 10;
        float *c = malloc(sizeof(float) * g.n);
        memcpy(c, cube, sizeof(float) * g.n);
        assert_int_equal(pg_pits_remove(&t, c, &o, NULL, NULL), PG_OK);
        assert_int_equal(chk_undrained(&g, c, sk, 1), 0);
        assert_int_equal(pg_pits_stats_compute(&t, c, &o, NULL, &st, NULL), PG_OK);
        assert_int_equal(st.depressions, 0);
        free(c);
    }
    free(sk);
    chk_graph_free(&g);
    free(cube);
    pg_exemplar_free(&ex);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_resolution_relief),
        cmocka_unit_test(test_relief_metres_and_planet),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
