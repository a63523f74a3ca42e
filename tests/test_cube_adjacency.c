/* test_cube_adjacency.c - the adjacency map: counts (6 T^2 tiles, 12 face seams, 8
 * cube vertices), symmetry (A's neighbour across an edge is B, B's neighbour across
 * the matching edge is A, and the two transforms compose to the identity), exact
 * mirror geometry across every seam, and nearest-texel geometry: every seam texel's
 * neighbour across the seam is its nearest texel on the other faces, exhaustively
 * for small S and sampled for large S. */
#include "pg_test.h"

#include "planetgen/pg_cube.h"

#include <math.h>
#include <stdlib.h>

static const pg_cube_projection PROJS[3] = {PG_CUBE_GNOMONIC, PG_CUBE_EQUIANGULAR,
                                            PG_CUBE_EQUALAREA};

static double dist3(const double a[3], const double b[3]) {
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

static void check_symmetry(int T, int S) {
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, PG_CUBE_EQUIANGULAR, T, S, NULL), PG_OK);
    assert_int_equal(g.ntiles, 6 * T * T);
    int missing = 0;
    for (int64_t a = 0; a < g.ntiles; a++) {
        pg_cube_neighbor na[8];
        pg_cube_tile_neighbors(&g, a, na);
        for (int d = 0; d < 8; d++) {
            if (na[d].tile < 0) {
                assert_true(d >= 4); /* only corners can be missing */
                missing++;
                continue;
            }
            assert_true(na[d].tile >= 0 && na[d].tile < g.ntiles && na[d].tile != a);
            pg_cube_neighbor nb[8];
            pg_cube_tile_neighbors(&g, na[d].tile, nb);
            int back = 0;
            for (int e = 0; e < 8; e++) {
                if (nb[e].tile != a || (e < 4) != (d < 4)) continue;
                /* the matching edge: B's transform maps A into B, ours maps B into A */
                pg_cube_xform id = pg_cube_xform_compose(na[d].xf, nb[e].xf);
                if (id.rot == 0 && id.ox == 0 && id.oy == 0) back++;
            }
            assert_int_equal(back, 1);
            /* the neighbour tile lands exactly on the S x S block in direction d */
            int dx, dy;
            pg_cube_dir_offset((pg_cube_dir)d, &dx, &dy);
            int64_t x0, y0, x1, y1;
            pg_cube_xform_apply(na[d].xf, 0, 0, &x0, &y0);
            pg_cube_xform_apply(na[d].xf, S - 1, S - 1, &x1, &y1);
            assert_int_equal(llabs(x1 - x0), S - 1);
            assert_int_equal((x0 < x1 ? x0 : x1), dx * S);
            assert_int_equal((y0 < y1 ? y0 : y1), dy * S);
        }
    }
    assert_int_equal(missing, 24); /* 8 vertices x 3 faces */
}

static void test_symmetry_and_counts(void **state) {
    (void)state;
    check_symmetry(1, 16);
    check_symmetry(2, 4);
    check_symmetry(3, 8);
    check_symmetry(8, 1);
}

static void test_seams_and_vertices(void **state) {
    (void)state;
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, PG_CUBE_GNOMONIC, 1, 16, NULL), PG_OK);
    int pair[6][6] = {{0}}, seams = 0;
    for (int f = 0; f < 6; f++) {
        for (int e = 0; e < 4; e++) {
            int h = g.nbr_face[f][e];
            assert_true(h != f && h / 2 != f / 2); /* never itself nor its opposite */
            pair[f][h]++;
        }
    }
    for (int f = 0; f < 6; f++)
        for (int h = f + 1; h < 6; h++) {
            assert_int_equal(pair[f][h], pair[h][f]);
            seams += pair[f][h];
        }
    assert_int_equal(seams, 12);
    /* cube vertices: distinct face-corner directions, each shared by 3 faces */
    double v[24][3];
    int nv = 0, mult[24] = {0};
    for (int f = 0; f < 6; f++) {
        for (int c = 0; c < 4; c++) {
            double d[3];
            pg_cube_corner_dir(&g, f, (c & 1) * g.n, (c >> 1) * g.n, d);
            int k = 0;
            while (k < nv && dist3(v[k], d) > 1e-12)
                k++;
            if (k == nv) v[nv][0] = d[0], v[nv][1] = d[1], v[nv][2] = d[2], nv++;
            mult[k]++;
        }
    }
    assert_int_equal(nv, 8);
    for (int k = 0; k < 8; k++)
        assert_int_equal(mult[k], 3);
}

/* Texel k rows past an edge is the mirror image of texel k-1 rows inside it,
 * reflected in the seam plane (normal n_f - n_g): exact for every projection. */
static void test_mirror_geometry(void **state) {
    (void)state;
    for (int pi = 0; pi < 3; pi++) {
        pg_cube_grid g;
        assert_int_equal(pg_cube_grid_init(&g, PROJS[pi], 2, 8, NULL), PG_OK);
        int64_t N = g.n;
        for (int f = 0; f < 6; f++) {
            for (int e = 0; e < 4; e++) {
                int dx, dy, nf[3], nu[3], nv[3], ng[3];
                pg_cube_dir_offset((pg_cube_dir)e, &dx, &dy);
                pg_cube_face_frame(f, nf, nu, nv);
                pg_cube_face_frame(g.nbr_face[f][e], ng, nu, nv);
                double m[3] = {(nf[0] - ng[0]) / sqrt(2.0), (nf[1] - ng[1]) / sqrt(2.0),
                               (nf[2] - ng[2]) / sqrt(2.0)};
                for (int64_t k = 0; k < N; k++) {
                    for (int64_t s = 0; s < N; s++) {
                        int64_t xi = dx ? (dx > 0 ? N - 1 - k : k) : s;
                        int64_t yi = dy ? (dy > 0 ? N - 1 - k : k) : s;
                        int64_t xo = dx ? (dx > 0 ? N + k : -1 - k) : s;
                        int64_t yo = dy ? (dy > 0 ? N + k : -1 - k) : s;
                        int rot;
                        int64_t id = pg_cube_wrap(&g, f, xo, yo, &rot);
                        assert_int_equal(id / (N * N), g.nbr_face[f][e]);
                        double a[3], b[3];
                        pg_cube_texel_dir(&g, (f * N + yi) * N + xi, a);
                        pg_cube_texel_dir(&g, id, b);
                        double dm = a[0] * m[0] + a[1] * m[1] + a[2] * m[2];
                        for (int i = 0; i < 3; i++)
                            assert_true(fabs(a[i] - 2 * dm * m[i] - b[i]) < 1e-13);
                    }
                }
            }
        }
    }
}

/* Nearest texel on the other faces to texel p of face f; candidates either all
 * texels (exhaustive) or a window around (x, y) reached through pg_cube_wrap. */
static double nearest_other(const pg_cube_grid *g, const double *dirs, int f, const double p[3],
                            int64_t x, int64_t y, int window) {
    int64_t N = g->n;
    double best = INFINITY;
    if (!window) {
        for (int64_t id = 0; id < 6 * N * N; id++)
            if (id / (N * N) != f) best = fmin(best, dist3(p, dirs + 3 * id));
        return best;
    }
    for (int j = -window; j <= window; j++) {
        for (int i = -window; i <= window; i++) {
            int64_t id = pg_cube_wrap(g, f, x + i, y + j, NULL);
            if (id / (N * N) == f) continue;
            double q[3];
            pg_cube_texel_dir(g, id, q);
            best = fmin(best, dist3(p, q));
        }
    }
    return best;
}

static void check_seam_nearest(pg_cube_projection proj, int T, int S, int samples) {
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, proj, T, S, NULL), PG_OK);
    int64_t N = g.n;
    double *dirs = NULL;
    if (!samples) {
        dirs = malloc(6 * N * N * 3 * sizeof *dirs);
        for (int64_t id = 0; id < 6 * N * N; id++)
            pg_cube_texel_dir(&g, id, dirs + 3 * id);
    }
    uint64_t rng = 99;
    int64_t count = samples ? samples : 6 * 4 * N;
    for (int64_t k = 0; k < count; k++) {
        int64_t f, e, s;
        if (samples) {
            rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
            f = (int64_t)(rng >> 33) % 6, e = (int64_t)(rng >> 40) % 4;
            s = (int64_t)((rng >> 13) % (uint64_t)N);
            if (k < 48) s = (k % 2) ? N - 1 - k / 2 % 3 : k / 2 % 3; /* ends of seams */
        } else {
            f = k / (4 * N), e = k / N % 4, s = k % N;
        }
        int dx, dy;
        pg_cube_dir_offset((pg_cube_dir)e, &dx, &dy);
        int64_t x = dx ? (dx > 0 ? N - 1 : 0) : s, y = dy ? (dy > 0 ? N - 1 : 0) : s;
        double p[3], q[3];
        pg_cube_texel_dir(&g, (f * N + y) * N + x, p);
        int64_t nb = pg_cube_wrap(&g, (int)f, x + dx, y + dy, NULL);
        pg_cube_texel_dir(&g, nb, q);
        double dn = dist3(p, q);
        double best = nearest_other(&g, dirs, (int)f, p, x, y, samples ? 4 : 0);
        assert_true(dn <= best * (1 + 1e-12));
    }
    free(dirs);
}

static void test_seam_nearest_exhaustive(void **state) {
    (void)state;
    for (int pi = 0; pi < 3; pi++) {
        check_seam_nearest(PROJS[pi], 1, 16, 0);
        check_seam_nearest(PROJS[pi], 2, 16, 0);
        check_seam_nearest(PROJS[pi], 3, 8, 0);
    }
}

static void test_seam_nearest_sampled(void **state) {
    (void)state;
    for (int pi = 0; pi < 3; pi++) {
        check_seam_nearest(PROJS[pi], 8, 256, 20000);
        check_seam_nearest(PROJS[pi], 1, 8192, 20000);
    }
}

static void test_xform_algebra(void **state) {
    (void)state;
    for (int r = 0; r < 4; r++) {
        pg_cube_xform t = {r, 5, -3}, inv = pg_cube_xform_inverse(t);
        int64_t x, y, x2, y2;
        pg_cube_xform_apply(t, 7, 11, &x, &y);
        pg_cube_xform_apply(inv, x, y, &x2, &y2);
        assert_true(x2 == 7 && y2 == 11);
        pg_cube_xform c = pg_cube_xform_compose(t, inv);
        assert_true(c.rot == 0 && c.ox == 0 && c.oy == 0);
    }
    pg_error err = {0};
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, PG_CUBE_GNOMONIC, 0, 16, &err), PG_ERR_BADINPUT);
    pg_error_clear(&err);
    assert_int_equal(pg_cube_grid_init(&g, PG_CUBE_GNOMONIC, 2, 24, &err), PG_ERR_BADINPUT);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_xform_algebra),           cmocka_unit_test(test_symmetry_and_counts),
        cmocka_unit_test(test_seams_and_vertices),      cmocka_unit_test(test_mirror_geometry),
        cmocka_unit_test(test_seam_nearest_exhaustive), cmocka_unit_test(test_seam_nearest_sampled),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
