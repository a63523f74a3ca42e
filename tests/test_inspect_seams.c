/* test_inspect_seams.c - the face-seam statistics of pg_inspect.h on constructed planets
 * whose answer is known: a field that is a smooth function of direction has no seams
 * (face_seam_ratio and tile_edge_ratio ~1); the same field with one face turned a
 * quarter about its centre breaks the four seams of that face; tiles offset by their
 * own constants show at tile edges and not at face seams; a seamless field whose detail
 * is stronger next to the face edges than inside fools the pooled ratio and not the
 * local one; one seam broken alone is the one named as the worst. */
#include "pg_test.h"

#include "planetgen/pg_inspect.h"
#include "planetgen/pg_synth.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

static double unit(uint64_t salt, uint64_t k, int i) {
    return pg_synth_hash(salt, 0, 0, (long)k, i, 0) / 4294967296.0;
}

/* A band-limited field on the sphere: a sum of 24 plane waves with hashed directions
 * and phases, wavelength ~ 1/12 of the radius (several texels at N = 128). */
static double field(const double d[3], uint64_t salt) {
    double s = 0;
    for (int k = 0; k < 24; k++) {
        double w[3], len = 0;
        for (int i = 0; i < 3; i++) {
            w[i] = unit(salt, (uint64_t)k, i) * 2 - 1;
            len += w[i] * w[i];
        }
        len = sqrt(len);
        double ph = 6.2832 * unit(salt, (uint64_t)k, 7);
        s += cos(75.0 * (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / len + ph);
    }
    return s / 24;
}

static void make_planet(pg_planet *p, int tiles, int tile_size) {
    pg_error err = {0};
    assert_int_equal(
        pg_planet_alloc(p, PG_CUBE_EQUIANGULAR, tiles, tile_size, pg_ellipsoid_sphere(), &err),
        PG_OK);
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, p->projection, tiles, tile_size, &err), PG_OK);
    int64_t n = p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < n * n; i++) {
            double d[3];
            pg_cube_texel_dir(&g, f * n * n + i, d);
            p->height[f][i] = (float)(1000 * field(d, 1));
            for (int c = 0; c < 3; c++)
                p->albedo[f][3 * i + c] = (float)(0.5 + 0.2 * field(d, 2 + (uint64_t)c));
        }
}

/* Turn face f's content a quarter about its centre: (x, y) <- (y, n-1-x). */
static void turn_face(pg_planet *p, int f) {
    int64_t n = p->n;
    float *h = malloc((size_t)(n * n) * sizeof *h), *a = malloc((size_t)(n * n) * 3 * sizeof *a);
    assert_non_null(h);
    assert_non_null(a);
    memcpy(h, p->height[f], (size_t)(n * n) * sizeof *h);
    memcpy(a, p->albedo[f], (size_t)(n * n) * 3 * sizeof *a);
    for (int64_t y = 0; y < n; y++)
        for (int64_t x = 0; x < n; x++) {
            int64_t src = x * n + (n - 1 - y);
            p->height[f][y * n + x] = h[src];
            memcpy(p->albedo[f] + 3 * (y * n + x), a + 3 * src, 3 * sizeof *a);
        }
    free(h);
    free(a);
}

/* Break the one seam along face f's +x edge: the texels of its last 2 columns take
 * hashed values, so pairs across that seam (and just inside it) differ, and of the
 * other seams' pairs only the 2 at each end of that column. Returns the face across
 * that edge. */
static int break_one_seam(pg_planet *p, int f) {
    const int64_t n = p->n;
    for (int64_t y = 0; y < n; y++)
        for (int64_t x = n - 2; x < n; x++) {
            const size_t i = (size_t)(y * n + x);
            p->height[f][i] += (float)(2000 * (unit(9, i, 0) - 0.5));
            for (int c = 0; c < 3; c++)
                p->albedo[f][3 * i + c] += (float)(0.8 * (unit(9, i, 1 + c) - 0.5));
        }
    pg_cube_grid g;
    pg_error err = {0};
    assert_int_equal(pg_cube_grid_init(&g, p->projection, 1, (int)n, &err), PG_OK);
    int rot;
    return (int)(pg_cube_wrap(&g, f, n, n / 2, &rot) / (n * n));
}

/* The smooth planet of 4 x 32 per face edge and its seam statistics. */
static void smooth_seams(pg_planet *p, pg_inspect_seams *r) {
    pg_error err = {0};
    make_planet(p, 4, 32);
    assert_int_equal(pg_inspect_seams_compute(p, r, &err), PG_OK);
}

static void assert_seam(const pg_inspect_seam_stat *st, int f, int g) {
    assert_int_equal(st->worst_seam_faces[0], f < g ? f : g);
    assert_int_equal(st->worst_seam_faces[1], f < g ? g : f);
}

static void test_worst_seam_named(void **s) {
    (void)s;
    /* a quarter-turn seam of a polar face, and a seam between two equatorial faces */
    const int broken[2] = {PG_CUBE_FACE_NZ, PG_CUBE_FACE_PY};
    for (int k = 0; k < 2; k++) {
        pg_planet p;
        pg_inspect_seams r;
        smooth_seams(&p, &r);
        const double smooth = r.worst_seam_ratio;
        print_message("smooth: worst seam %s/%s %.3f, local %.3f\n",
                      pg_cube_face_name(r.worst_seam_faces[0]),
                      pg_cube_face_name(r.worst_seam_faces[1]), smooth, r.worst_seam_ratio_local);
        /* one seam's pairs measure the field across that seam alone, so a seamless
         * field's seams spread about the pooled figure; against their own ground they
         * do not */
        assert_true(smooth < 2);
        assert_true(fabs(r.worst_seam_ratio_local - 1) < 0.2);
        const int f = broken[k], g = break_one_seam(&p, f);
        assert_int_not_equal(g, f);
        pg_error err = {0};
        assert_int_equal(pg_inspect_seams_compute(&p, &r, &err), PG_OK);
        print_message("%s's +x edge broken (across it %s): worst seam %s/%s (%s) %.3f, local "
                      "%.3f; all seams %.3f\n",
                      pg_cube_face_name(f), pg_cube_face_name(g),
                      pg_cube_face_name(r.worst_seam_faces[0]),
                      pg_cube_face_name(r.worst_seam_faces[1]), r.worst_seam_field,
                      r.worst_seam_ratio, r.worst_seam_ratio_local, r.face_seam_ratio);
        assert_seam(&r.height, f, g), assert_seam(&r.albedo, f, g);
        assert_int_equal(r.worst_seam_faces[0], r.height.worst_seam_faces[0]);
        assert_int_equal(r.worst_seam_faces[1], r.height.worst_seam_faces[1]);
        assert_true(r.worst_seam_ratio > 2 * smooth);
        assert_true(r.worst_seam_ratio_local > 2);
        /* the field named is the one whose worst seam is worse */
        const bool albedo = r.albedo.worst_seam_ratio > r.height.worst_seam_ratio;
        assert_string_equal(r.worst_seam_field, albedo ? "albedo" : "height");
        assert_true(r.worst_seam_ratio ==
                    (albedo ? r.albedo.worst_seam_ratio : r.height.worst_seam_ratio));
        pg_planet_free(&p);
    }
}

static void test_smooth_field_has_no_seams(void **s) {
    (void)s;
    pg_planet p;
    pg_inspect_seams r;
    smooth_seams(&p, &r);
    print_message("smooth: face_seam_ratio h %.3f a %.3f, tile_edge_ratio %.3f\n",
                  r.height.face_seam_ratio, r.albedo.face_seam_ratio, r.tile_edge_ratio);
    assert_true(r.face_seam_ratio <= PG_INSPECT_FACE_SEAM_GATE);
    assert_true(r.face_seam_ratio >= 0.9);
    assert_true(fabs(r.tile_edge_ratio - 1) < 0.05);
    /* 12 seams of n texels, counted from both sides */
    assert_int_equal(r.height.face_seam_pairs, 12 * 2 * p.n);
    pg_planet_free(&p);
}

static void test_turned_face_fails(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 4, 32);
    turn_face(&p, PG_CUBE_FACE_PY);
    pg_inspect_seams r;
    pg_error err = {0};
    assert_int_equal(pg_inspect_seams_compute(&p, &r, &err), PG_OK);
    print_message("one face turned: face_seam_ratio h %.3f a %.3f, tile_edge_ratio %.3f\n",
                  r.height.face_seam_ratio, r.albedo.face_seam_ratio, r.tile_edge_ratio);
    assert_true(r.height.face_seam_ratio > 1.3 && r.albedo.face_seam_ratio > 1.3);
    assert_true(fabs(r.tile_edge_ratio - 1) < 0.05); /* nothing changed inside faces */
    pg_planet_free(&p);
}

static void test_offset_tiles_show_at_tile_edges(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 4, 32);
    int64_t n = p.n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                uint64_t tile = (uint64_t)(f * 16 + (y / 32) * 4 + x / 32);
                p.height[f][y * n + x] += (float)(400 * unit(9, tile, 0));
            }
    pg_inspect_seams r;
    pg_error err = {0};
    assert_int_equal(pg_inspect_seams_compute(&p, &r, &err), PG_OK);
    print_message("offset tiles: tile_edge_ratio h %.3f\n", r.height.tile_edge_ratio);
    assert_true(r.height.tile_edge_ratio > 1.5);
    assert_true(r.albedo.tile_edge_ratio < 1.05);
    pg_planet_free(&p);
}

/* Scale the detail of every field by a weight of the distance to the face's nearest
 * edge (the same on both sides of a seam, so the field stays seamless): w_edge up to a
 * tenth of the face in (wider than the local ratio's band), then a ramp to w_inside a
 * quarter of the face in. */
static void weight_by_edge(pg_planet *p, double w_edge, double w_inside) {
    int64_t n = p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                double u = (2.0 * x + 1) / n - 1, v = (2.0 * y + 1) / n - 1;
                double e = 1 - fmax(fabs(u), fabs(v)), t = fmin(fmax(e - 0.2, 0) / 0.3, 1.0);
                double w = w_edge + (w_inside - w_edge) * t;
                size_t i = (size_t)(y * n + x);
                p->height[f][i] *= (float)w;
                for (int c = 0; c < 3; c++)
                    p->albedo[f][3 * i + c] = (float)(0.5 + w * (p->albedo[f][3 * i + c] - 0.5));
            }
}

static void test_local_ratio_ignores_where_detail_is(void **s) {
    (void)s;
    const double w[2][2] = {{3.0, 0.5}, {0.5, 3.0}}; /* busy edges; calm edges */
    for (int k = 0; k < 2; k++) {
        pg_planet p;
        make_planet(&p, 4, 32);
        weight_by_edge(&p, w[k][0], w[k][1]);
        pg_inspect_seams r;
        pg_error err = {0};
        assert_int_equal(pg_inspect_seams_compute(&p, &r, &err), PG_OK);
        print_message("edges x%.1f, inside x%.1f: face_seam_ratio %.3f, local %.3f\n", w[k][0],
                      w[k][1], r.face_seam_ratio, r.face_seam_ratio_local);
        if (k == 0) assert_true(r.face_seam_ratio > 1.3); /* the pooled ratio is fooled */
        if (k == 1) assert_true(r.height.face_seam_ratio < 0.7);
        assert_true(fabs(r.height.face_seam_ratio_local - 1) < 0.1);
        assert_true(fabs(r.albedo.face_seam_ratio_local - 1) < 0.1);
        /* and a real seam still shows */
        turn_face(&p, PG_CUBE_FACE_PY);
        assert_int_equal(pg_inspect_seams_compute(&p, &r, &err), PG_OK);
        print_message("  one face turned: local %.3f\n", r.face_seam_ratio_local);
        assert_true(r.height.face_seam_ratio_local > 1.3 && r.albedo.face_seam_ratio_local > 1.3);
        pg_planet_free(&p);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_smooth_field_has_no_seams),
                                       cmocka_unit_test(test_turned_face_fails),
                                       cmocka_unit_test(test_offset_tiles_show_at_tile_edges),
                                       cmocka_unit_test(test_local_ratio_ignores_where_detail_is),
                                       cmocka_unit_test(test_worst_seam_named)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
