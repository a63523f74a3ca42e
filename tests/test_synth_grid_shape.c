/* test_synth_grid_shape.c - the grid-shape term of the correction near the cube's corners
 * (pg_synth_grid_shape.h; docs/synthesis.md, "Grid shape at the cube's corners"): its Gram
 * matrices against the equi-angular projection's own directions, its turn rule against
 * the rotations the synthesis applies, where it acts (symmetric about a face's centre
 * lines at every level size, off on the edges), which candidates it favours at a corner,
 * and on the real exemplar, that planets synthesized with it copy their corners more
 * faithfully than without it (pg_inspect_distortion). */
#include "pg_test.h"

#include "pg_synth_grid_shape.h"
#include "pg_synth_internal.h"
#include "planetgen/pg_cube.h"
#include "planetgen/pg_inspect_distortion.h"
#include "planetgen/pg_planet_synth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static const double PI = 3.14159265358979323846;

/* The Gram matrix of the grid steps of face f at (u, v) in [-1, 1]^2 by central
 * differences of pg_cube_to_dir, over the step at a face centre (pi / 4 per unit). */
static void numeric_gram(int f, double u, double v, double g[3]) {
    const double h = 1e-5;
    double a[3], b[3], c[3], d[3], du[3], dv[3];
    pg_cube_to_dir(PG_CUBE_EQUIANGULAR, f, u + h, v, a);
    pg_cube_to_dir(PG_CUBE_EQUIANGULAR, f, u - h, v, b);
    pg_cube_to_dir(PG_CUBE_EQUIANGULAR, f, u, v + h, c);
    pg_cube_to_dir(PG_CUBE_EQUIANGULAR, f, u, v - h, d);
    const double s = 2 * h * (PI / 4);
    for (int i = 0; i < 3; i++)
        du[i] = (a[i] - b[i]) / s, dv[i] = (c[i] - d[i]) / s;
    g[0] = du[0] * du[0] + du[1] * du[1] + du[2] * du[2];
    g[1] = dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2];
    g[2] = du[0] * dv[0] + du[1] * dv[1] + du[2] * dv[2];
}

static void formula_gram(double u, double v, float g[3]) {
    pg_synth_grid_gram((float)tan(u * PI / 4), (float)tan(v * PI / 4), g);
}

/* The closed form is the projection's metric on every face, in the face's own frame. */
static void test_gram_is_the_projection_metric(void **state) {
    (void)state;
    double worst = 0;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int i = 0; i <= 20; i++)
            for (int j = 0; j <= 20; j++) {
                const double u = -0.98 + 0.098 * i, v = -0.98 + 0.098 * j;
                double n[3];
                float g[3];
                numeric_gram(f, u, v, n);
                formula_gram(u, v, g);
                for (int k = 0; k < 3; k++)
                    if (fabs(n[k] - g[k]) > worst) worst = fabs(n[k] - g[k]);
            }
    printf("largest difference from the projection's metric: %.2e\n", worst);
    assert_true(worst < 1e-5);
    /* the shapes docs/inspect.md names: square at a centre, 1 : 0.71 at an edge's
     * midpoint, a rhombus of 120 degrees at a corner */
    float g[3];
    formula_gram(0, 0, g);
    assert_float_equal(g[0], 1, 1e-6), assert_float_equal(g[1], 1, 1e-6);
    assert_float_equal(g[2], 0, 1e-6);
    formula_gram(1, 0, g);
    assert_float_equal(sqrt(g[1] / g[0]), sqrt(0.5), 1e-6);
    formula_gram(1, 1, g);
    assert_float_equal(g[2] / sqrt(g[0] * g[1]), -0.5, 1e-6);
}

/* The turn rule is M^T G M, M the rotation pg_synth_orient_apply takes view offsets
 * through into the texel's frame. */
static void test_turned_gram(void **state) {
    (void)state;
    const float g[3] = {0.9f, 0.6f, -0.3f};
    for (int o = 0; o < 4; o++) {
        int ax = 1, ay = 0, bx = 0, by = 1; /* M e_x, M e_y */
        pg_synth_orient_apply(o, &ax, &ay);
        pg_synth_orient_apply(o, &bx, &by);
        const float xx = ax * (g[0] * ax + g[2] * ay) + ay * (g[2] * ax + g[1] * ay);
        const float yy = bx * (g[0] * bx + g[2] * by) + by * (g[2] * bx + g[1] * by);
        const float xy = ax * (g[0] * bx + g[2] * by) + ay * (g[2] * bx + g[1] * by);
        float t[3];
        pg_synth_grid_gram_turned(g, o, t);
        assert_float_equal(t[0], xx, 1e-7);
        assert_float_equal(t[1], yy, 1e-7);
        assert_float_equal(t[2], xy, 1e-7);
    }
}

/* The nearness s: 0 on the face's edges and in the middle band, at every level size;
 * mirrored texels get the same s, and G mirrored in one axis negates gxy, at the sizes
 * where each texel's bin is the bin of its centre (pg_synth_shape_bin: multiples of
 * 2 PG_SYNTH_SHAPE_Q); largest at a corner, smaller in the fade. */
static void test_where_it_acts(void **state) {
    (void)state;
    float tanq[PG_SYNTH_SHAPE_Q];
    pg_synth_shape_table(tanq);
    const int64_t sizes[] = {8, 16, 32, 64, 128, 512, 1024, 3000, 4096};
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        const int64_t r = sizes[k];
        const int centred = r % (2 * PG_SYNTH_SHAPE_Q) == 0;
        for (int64_t y = 0; y<r; y += r> 64 ? 7 : 1)
            for (int64_t x = 0; x<r; x += r> 64 ? 5 : 1) {
                pg_synth_shape_texel a, m;
                const int on = pg_synth_shape_texel_at(tanq, r, x, y, &a);
                const int mon = pg_synth_shape_texel_at(tanq, r, r - 1 - x, y, &m);
                if (centred) {
                    assert_int_equal(on, mon);
                    assert_float_equal(a.s, m.s, 0);
                    if (on) {
                        assert_float_equal(a.g[0], m.g[0], 1e-6);
                        assert_float_equal(a.g[2], -m.g[2], 1e-6);
                    }
                }
                if (x == 0 || y == 0 || x == r - 1 || y == r - 1) assert_false(on);
                if (4 * x >= r && 4 * (x + 1) <= 3 * r) /* x's texel within 0.5 of the centre */
                    assert_false(on);
            }
    }
    pg_synth_shape_texel c, e;
    assert_true(pg_synth_shape_texel_at(tanq, 1024, 6, 6, &c)); /* past the fade */
    assert_true(c.s > 0.95f);
    assert_true(pg_synth_shape_texel_at(tanq, 1024, 2, 60, &e)); /* in the fade */
    assert_true(e.s < 0.5f * c.s);
}

/* At an output corner, the exemplar texel at the same corner, unturned, costs nothing
 * extra; so does the texel at the corner of the other diagonal turned by a quarter turn
 * (its rhombus has the same shape in the output's frame); the exemplar's centre and the
 * other diagonal's corner unturned cost more. */
static void test_which_candidates_it_favours(void **state) {
    (void)state;
    float tanq[PG_SYNTH_SHAPE_Q];
    pg_synth_shape_table(tanq);
    const int E = 1024;
    pg_synth_shape_texel t;
    assert_true(pg_synth_shape_texel_at(tanq, 1024, 6, 6, &t));
    const float ws = 25 * t.s;
    const uint32_t same = pg_synth_pack(2, 6, 6), centre = pg_synth_pack(2, 512, 512),
                   other = pg_synth_pack(2, E - 7, 6);
    const float f_same = pg_synth_shape_factor(tanq, &t, ws, E, same),
                f_centre = pg_synth_shape_factor(tanq, &t, ws, E, centre),
                f_other = pg_synth_shape_factor(tanq, &t, ws, E, other),
                f_turned = pg_synth_shape_factor(tanq, &t, ws, E, pg_synth_with_orient(other, 1)),
                f_same2 = pg_synth_shape_factor(tanq, &t, ws, E, pg_synth_with_orient(same, 2));
    printf("factors: same corner %.3f, turned twice %.3f, other diagonal turned %.3f, "
           "unturned %.3f, centre %.3f\n",
           f_same, f_same2, f_turned, f_other, f_centre);
    assert_float_equal(f_same, 1, 1e-6);
    assert_float_equal(f_same2, 1, 1e-6);
    assert_float_equal(f_turned, 1, 1e-6);
    assert_true(f_other > 10 && f_centre > 10);
}

/* ---- on the real exemplar ---- */

static pg_synth_exemplar *ex;

static int setup(void **state) {
    (void)state;
    ex = pg_test_default_exemplar();
    return ex ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    pg_synth_exemplar_free(ex);
    return 0;
}

/* A layout-free planet of 6 x 256^2 with the term at weight w, with its coordinate map. */
static void planet_of(uint64_t seed, double w, pg_planet *planet) {
    pg_planet_synth_params p;
    pg_planet_synth_params_default(&p);
    p.tiles = 1;
    p.tile_size = 256;
    p.layout = PG_LAYOUT_FREE;
    p.synth.seed = seed;
    p.synth.grid_shape = w;
    uint32_t *coords = NULL;
    pg_error err = {0};
    assert_int_equal(pg_planet_synth_run(ex, &p, planet, &coords, NULL, &err), PG_OK);
    assert_int_equal(
        pg_planet_source_alloc(planet, ex->face_size, PG_CUBE_DEFAULT_PROJECTION, &err), PG_OK);
    const size_t nn = (size_t)planet->n * planet->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (size_t i = 0; i < nn; i++)
            planet->source.coords[f][i] = pg_synth_with_orient(coords[f * nn + i], 0);
    free(coords);
}

/* The mean figure (docs/inspect.md, "Distortion") over the coherent texels of two zones of
 * every face: near the corners (both face coordinates beyond 0.8, where the term acts at
 * more than 0.6 of its weight) and around the centre (both within 0.3). */
static void zone_figures(const pg_planet *p, double *corner, double *centre) {
    double sc = 0, sm = 0;
    long nc = 0, nm = 0;
    const int64_t n = p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t y = 2; y < n - 2; y++)
            for (int64_t x = 2; x < n - 2; x++) {
                const double a = fabs((2.0 * x + 1) / n - 1), b = fabs((2.0 * y + 1) / n - 1);
                const int in_corner = a > 0.8 && b > 0.8, in_centre = a < 0.3 && b < 0.3;
                if (!in_corner && !in_centre) continue;
                pg_inspect_distortion_texel t;
                pg_inspect_distortion_texel_at(p, 1, f, x, y, &t);
                if (!t.coherent) continue;
                if (in_corner)
                    sc += t.figure, nc++;
                else
                    sm += t.figure, nm++;
            }
    assert_true(nc > 1000 && nm > 1000);
    *corner = sc / nc, *centre = sm / nm;
}

/* With the term the corners' copies are closer to isometric, measured against the same
 * planet's face centres: over three seeds, the corner zones' mean figure over the centre
 * zones' falls (3.23 -> 3.05 when written; every seed falls). The realism gate's
 * worst-view ratio is printed but not asserted: on planets this small a view holds a
 * few hundred texels. */
static void test_corners_copy_more_faithfully(void **state) {
    (void)state;
    double off = 0, on = 0;
    for (uint64_t seed = 1; seed <= 3; seed++) {
        double r[2];
        for (int k = 0; k < 2; k++) {
            pg_planet planet;
            planet_of(seed, k ? PG_PLANET_GRID_SHAPE : 0, &planet);
            double corner, centre;
            zone_figures(&planet, &corner, &centre);
            pg_inspect_distortion d;
            pg_error err = {0};
            assert_int_equal(pg_inspect_distortion_compute(&planet, &d, &err), PG_OK);
            printf("seed %d, weight %g: corners %.3f, centres %.3f; gate ratio %.3f\n", (int)seed,
                   k ? PG_PLANET_GRID_SHAPE : 0.0, corner, centre, d.ratio);
            r[k] = corner / centre;
            pg_planet_free(&planet);
        }
        off += r[0], on += r[1];
    }
    printf("sum of corners / centres: %.3f -> %.3f\n", off, on);
    assert_true(on < off - 0.1);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gram_is_the_projection_metric),
        cmocka_unit_test(test_turned_gram),
        cmocka_unit_test(test_where_it_acts),
        cmocka_unit_test(test_which_candidates_it_favours),
        cmocka_unit_test_setup_teardown(test_corners_copy_more_faithfully, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
