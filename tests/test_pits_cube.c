/* test_pits_cube.c - pit removal on the cube sphere: the seam neighbours agree with
 * an independent geometric construction (7 at the cube corners), a depression
 * straddling a face seam and one at a cube corner are removed by every method, a
 * planet without ocean drains to its single lowest texel, the counts taken with the
 * removal agree with the separate counts (the certificates across seams and corners),
 * and the Gain-pit offset update reproduces the pit-free heights. */
#include "pg_test.h"
#include "pits_checker.h"
#include "planetgen/pg_cube.h"
#include "planetgen/pg_pits.h"
#include "pg_pits_internal.h"

#include <stdio.h>

static int cmp_u32(const void *a, const void *b) {
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

static void test_topology_matches_geometry(void **state) {
    (void)state;
    int sizes[] = {2, 3, 4, 7, 16};
    for (int s = 0; s < 5; s++) {
        int N = sizes[s];
        pg_pits_topo t;
        assert_int_equal(pg_pits_topo_cube(&t, (uint32_t)N, NULL), PG_OK);
        chk_graph g = geometric_cube_graph(N);
        int sevens = 0;
        for (uint32_t id = 0; id < g.n; id++) {
            uint32_t a[8], b[8];
            int k = pg_pits_neighbours(&t, id, a);
            assert_int_equal(k, g.cnt[id]);
            sevens += k == 7;
            memcpy(b, &g.nb[(size_t)id * 8], sizeof(uint32_t) * k);
            qsort(a, (size_t)k, 4, cmp_u32);
            qsort(b, (size_t)k, 4, cmp_u32);
            assert_memory_equal(a, b, sizeof(uint32_t) * k);
            for (int j = 0; j < k; j++) {
                assert_true(a[j] != id);
                if (j) assert_true(a[j] != a[j - 1]);
            }
        }
        assert_int_equal(sevens, 24); /* 8 cube corners x 3 faces */
        chk_graph_free(&g);
    }
}

/* A smooth planet rising to the north, with an ocean around the south pole. */
static float *planet(const pg_pits_topo *t, int N) {
    float *h = malloc(sizeof(float) * t->ncells);
    pg_cube_grid g;
    pg_cube_grid_init(&g, PG_CUBE_EQUIANGULAR, N, 1, NULL);
    for (uint32_t i = 0; i < t->ncells; i++) {
        double d[3];
        pg_cube_texel_dir(&g, i, d);
        h[i] = (float)(1000.0 * (d[2] + 0.8));
    }
    return h;
}

/* Lower every texel within `radius` (unit-sphere distance) of direction c to 10 m
 * below its lowest rim cell: a closed basin. */
static int dig(float *h, const pg_pits_topo *t, int N, const double c[3], double radius) {
    pg_cube_grid g;
    pg_cube_grid_init(&g, PG_CUBE_EQUIANGULAR, N, 1, NULL);
    int cells = 0, faces = 0;
    double len = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    for (uint32_t i = 0; i < t->ncells; i++) {
        double d[3];
        pg_cube_texel_dir(&g, i, d);
        double dd = 0;
        for (int k = 0; k < 3; k++)
            dd += (d[k] - c[k] / len) * (d[k] - c[k] / len);
        if (sqrt(dd) < radius) {
            h[i] = 50.0f + (float)(i % 7);
            cells++;
            faces |= 1 << (i / ((uint32_t)N * N));
        }
    }
    return __builtin_popcount((unsigned)faces) * 1000 + cells;
}

static void check_all_methods(const pg_pits_topo *t, int N, const float *dem, int has_sea,
                              uint64_t expect_before) {
    chk_graph g = geometric_cube_graph(N);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.has_sea_level = has_sea;
    o.sea_level = 0;
    pg_pits_stats st, st0;
    assert_int_equal(pg_pits_stats_compute(t, dem, &o, NULL, &st0, NULL), PG_OK);
    assert_int_equal(st0.depressions, expect_before);
    st = st0;
    uint8_t *sk = chk_sinks(dem, g.n, has_sea, 0, NULL, 0, 0, 0);
    assert_true(chk_undrained(&g, dem, sk, 0) > 0);
    for (int m = 0; m < 3; m++)
        for (int k = 0; k < 4; k++) { /* epsilon or not; flood tree or descent tree */
            int eps = k % 2;
            if (k >= 2 && m == PG_PITS_FILL) continue;
            float *h = malloc(sizeof(float) * g.n);
            memcpy(h, dem, sizeof(float) * g.n);
            o.method = (pg_pits_method)m;
            o.epsilon = eps;
            o.descent = k >= 2;
            o.max_depth = 200;
            o.max_length = 3;
            pg_pits_result r;
            assert_int_equal(pg_pits_remove(t, h, &o, &r, NULL), PG_OK);
            assert_int_equal(chk_undrained(&g, h, sk, eps), 0);
            assert_int_equal(pg_pits_stats_compute(t, h, &o, NULL, &st, NULL), PG_OK);
            assert_int_equal(st.depressions, 0);
            assert_true(r.raised + r.lowered > 0);
            { /* the counts with the removal: the same result and figures */
                float *c = malloc(sizeof(float) * g.n);
                memcpy(c, dem, sizeof(float) * g.n);
                pg_pits_stats before, after;
                assert_int_equal(
                    pg_pits_remove_counted(t, c, &o, NULL, NULL, &before, &after, NULL), PG_OK);
                assert_memory_equal(c, h, sizeof(float) * g.n);
                assert_memory_equal(&before, &st0, sizeof before);
                assert_memory_equal(&after, &st, sizeof after);
                free(c);
            }
            if (m == 0 && !eps) { /* the serial fill's closing order certifies it */
                float *c = malloc(sizeof(float) * g.n);
                uint32_t *order = calloc(g.n, sizeof(uint32_t));
                memcpy(c, dem, sizeof(float) * g.n);
                assert_int_equal(pits_priority_flood_barnes2014(t, c, &o, NULL, NULL, order),
                                 PG_OK);
                uint8_t *cs = NULL;
                uint64_t ns = 0;
                assert_int_equal(pits_begin(t, c, &o, &cs, NULL, &ns, NULL), PG_OK);
                assert_true(pits_drains_by(t, c, cs, NULL, order));
                assert_false(pits_drains_by(t, dem, cs, NULL, order)); /* the pitted input */
                free(cs);
                free(order);
                free(c);
            }
            if (m == 0 && !eps) { /* tiled parallel fill (tiles span face seams) */
                float *p = malloc(sizeof(float) * g.n);
                memcpy(p, dem, sizeof(float) * g.n);
                o.tile_rows = 5;
                assert_int_equal(pg_pits_remove(t, p, &o, NULL, NULL), PG_OK);
                o.tile_rows = 0;
                assert_memory_equal(p, h, sizeof(float) * g.n);
                free(p);
            }
            free(h);
        }
    free(sk);
    chk_graph_free(&g);
}

static void test_seam_depression(void **state) {
    (void)state;
    int N = 24;
    pg_pits_topo t;
    pg_pits_topo_cube(&t, (uint32_t)N, NULL);
    float *h = planet(&t, N);
    /* the midpoint of the seam between +X and +Y, a bit north of the equator */
    double c[3] = {1, 1, 0.3};
    int code = dig(h, &t, N, c, 0.15);
    assert_true(code / 1000 == 2); /* it really straddles two faces */
    check_all_methods(&t, N, h, 1, 1);
    free(h);
}

static void test_corner_depression(void **state) {
    (void)state;
    int N = 24;
    pg_pits_topo t;
    pg_pits_topo_cube(&t, (uint32_t)N, NULL);
    float *h = planet(&t, N);
    double c[3] = {1, 1, 1}; /* the corner where +X, +Y and +Z meet */
    int code = dig(h, &t, N, c, 0.12);
    assert_true(code / 1000 == 3);
    check_all_methods(&t, N, h, 1, 1);
    free(h);
}

/* No ocean: everything drains to the single lowest texel. */
static void test_no_ocean_drains_to_lowest(void **state) {
    (void)state;
    int N = 16;
    pg_pits_topo t;
    pg_pits_topo_cube(&t, (uint32_t)N, NULL);
    float *dem = malloc(sizeof(float) * t.ncells);
    for (uint32_t i = 0; i < t.ncells; i++)
        dem[i] = (float)((i * 2654435761u) >> 20) + 100.0f; /* noise: full of pits */
    uint32_t lo = 0;
    for (uint32_t i = 1; i < t.ncells; i++)
        if (dem[i] < dem[lo]) lo = i;
    chk_graph g = geometric_cube_graph(N);
    uint8_t *sk = calloc(g.n, 1);
    sk[lo] = 1;
    for (int m = 0; m < 3; m++) {
        float *h = malloc(sizeof(float) * t.ncells);
        memcpy(h, dem, sizeof(float) * t.ncells);
        pg_pits_opts o;
        pg_pits_opts_default(&o);
        o.method = (pg_pits_method)m;
        o.max_depth = 1000;
        o.max_length = 4;
        pg_pits_result r;
        assert_int_equal(pg_pits_remove(&t, h, &o, &r, NULL), PG_OK);
        assert_int_equal(r.sinks, 1);
        assert_true(h[lo] == dem[lo]);
        assert_int_equal(chk_undrained(&g, h, sk, 1), 0);
        free(h);
    }
    free(sk);
    chk_graph_free(&g);
    free(dem);
}

/* Gain-pit: offsets += R' - R, so exemplar + offsets reconstructs R' (to rounding). */
static void test_gain_pit_offsets(void **state) {
    (void)state;
    int N = 16;
    pg_pits_topo t;
    pg_pits_topo_cube(&t, (uint32_t)N, NULL);
    float *E = planet(&t, N), *V = calloc(t.ncells, sizeof(float));
    float *R = malloc(sizeof(float) * t.ncells), *Rp = malloc(sizeof(float) * t.ncells);
    for (uint32_t i = 0; i < t.ncells; i++)
        V[i] = 6.0f * ((float)((i * 40503u) % 97) - 48.0f);
    for (uint32_t i = 0; i < t.ncells; i++)
        R[i] = E[i] + V[i];
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.has_sea_level = true;
    o.sea_level = 0;
    memcpy(Rp, R, sizeof(float) * t.ncells);
    assert_int_equal(pg_pits_remove(&t, Rp, &o, NULL, NULL), PG_OK);
    pg_pits_result r;
    assert_int_equal(pg_pits_correct_offsets(&t, R, V, &o, &r, NULL), PG_OK);
    assert_true(r.lowered > 0);
    for (uint32_t i = 0; i < t.ncells; i++)
        assert_true(fabsf(E[i] + V[i] - Rp[i]) <= 1e-3f * (1.0f + fabsf(Rp[i])));
    free(E);
    free(V);
    free(R);
    free(Rp);
}

/* Texel areas tile the sphere: 6 faces sum to 4 pi R^2, and texels differ in size. */
static void test_face_areas(void **state) {
    (void)state;
    uint32_t n = 64;
    double *a = malloc(sizeof(double) * n * n), sum = 0, lo = INFINITY, hi = 0;
    assert_int_equal(pg_pits_cube_face_areas(PG_CUBE_EQUIANGULAR, n, 1000.0, a, NULL), PG_OK);
    for (uint32_t i = 0; i < n * n; i++) {
        sum += a[i];
        lo = fmin(lo, a[i]);
        hi = fmax(hi, a[i]);
    }
    assert_true(fabs(6 * sum - 4 * M_PI * 1e6) < 1e-9 * 4 * M_PI * 1e6);
    assert_true(hi / lo > 1.1);
    pg_pits_cube_areas ca = {a, n};
    assert_true(pg_pits_cube_area_fn(&ca, 5 * n * n + 7) == a[7]);
    free(a);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_topology_matches_geometry),
        cmocka_unit_test(test_seam_depression),
        cmocka_unit_test(test_corner_depression),
        cmocka_unit_test(test_no_ocean_drains_to_lowest),
        cmocka_unit_test(test_gain_pit_offsets),
        cmocka_unit_test(test_face_areas),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
