/* test_cube_projection.c - face frames and the three projections: frames are
 * right-handed with +Z north, forward/inverse round trips stay below 1e-12 both
 * ways on dense grids including edges and corners, the equal-area map really is
 * equal-area (finite-difference Jacobian), and the texel finder places every direction
 * in the texel pg_cube_from_dir's coordinates give, on and next to the cell edges too. */
#include "pg_test.h"

#include "planetgen/pg_cube.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PG_PI 3.14159265358979323846

static const pg_cube_projection PROJS[3] = {PG_CUBE_GNOMONIC, PG_CUBE_EQUIANGULAR,
                                            PG_CUBE_EQUALAREA};

static void test_frames(void **state) {
    (void)state;
    int seen[3][2] = {{0}};
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        int n[3], u[3], v[3];
        pg_cube_face_frame(f, n, u, v);
        int c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0]};
        for (int i = 0; i < 3; i++)
            assert_int_equal(c[i], n[i]); /* e_u x e_v = n */
        for (int i = 0; i < 3; i++)
            if (n[i]) seen[i][n[i] > 0]++;
        if (f < 4) assert_int_equal(v[2], 1); /* equatorial faces: v points north */
    }
    for (int i = 0; i < 3; i++)
        assert_true(seen[i][0] == 1 && seen[i][1] == 1);
    int n[3], u[3], v[3];
    pg_cube_face_frame(PG_CUBE_FACE_PZ, n, u, v);
    assert_int_equal(n[2], 1); /* +Z is the north pole */
    assert_string_equal(pg_cube_face_name(PG_CUBE_FACE_NY), "-Y");
    double d[3];
    pg_cube_to_dir(PG_CUBE_EQUIANGULAR, PG_CUBE_FACE_PZ, 0, 0, d);
    assert_true(fabs(d[2] - 1) < 1e-15);
}

static void test_round_trips(void **state) {
    (void)state;
    const int K = 201;
    for (int pi = 0; pi < 3; pi++) {
        double worst_uv = 0, worst_dir = 0;
        for (int f = 0; f < PG_CUBE_NFACES; f++) {
            for (int j = 0; j < K; j++) {
                for (int i = 0; i < K; i++) {
                    /* include exact edges, corners and the centre, plus tiny offsets */
                    double u = -1 + 2.0 * i / (K - 1), v = -1 + 2.0 * j / (K - 1);
                    if (i == 1) u = -1 + 1e-9;
                    if (j == 2) v = 1e-13;
                    double d[3], d2[3], u2, v2;
                    int f2;
                    pg_cube_to_dir(PROJS[pi], f, u, v, d);
                    assert_true(fabs(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1) < 1e-14);
                    pg_cube_from_dir(PROJS[pi], d, &f2, &u2, &v2);
                    /* on an edge the face may legitimately change: compare directions */
                    pg_cube_to_dir(PROJS[pi], f2, u2, v2, d2);
                    double e =
                        fmax(fabs(d[0] - d2[0]), fmax(fabs(d[1] - d2[1]), fabs(d[2] - d2[2])));
                    worst_dir = fmax(worst_dir, e);
                    if (f2 == f)
                        worst_uv = fmax(worst_uv, fmax(fabs(u - u2), fabs(v - v2)));
                    else
                        assert_true(fabs(u) == 1 || fabs(v) == 1);
                }
            }
        }
        print_message("%-13s max |uv - uv'| %.3g, max |d - d'| %.3g\n",
                      pg_cube_projection_name(PROJS[pi]), worst_uv, worst_dir);
        assert_true(worst_uv < 1e-12);
        assert_true(worst_dir < 1e-12);
    }
}

/* Direction -> (u, v) -> direction over random directions. */
static void test_inverse_round_trip(void **state) {
    (void)state;
    uint64_t s = 12345;
    for (int pi = 0; pi < 3; pi++) {
        double worst = 0;
        for (int k = 0; k < 200000; k++) {
            double d[3], r = 0;
            for (int i = 0; i < 3; i++) {
                s = s * 6364136223846793005ULL + 1442695040888963407ULL;
                d[i] = (double)(s >> 11) / 9007199254740992.0 * 2 - 1;
                r += d[i] * d[i];
            }
            if (r < 1e-6 || r > 1) continue;
            for (int i = 0; i < 3; i++)
                d[i] /= sqrt(r);
            int f;
            double u, v, d2[3];
            pg_cube_from_dir(PROJS[pi], d, &f, &u, &v);
            assert_true(fabs(u) <= 1 && fabs(v) <= 1);
            pg_cube_to_dir(PROJS[pi], f, u, v, d2);
            for (int i = 0; i < 3; i++)
                worst = fmax(worst, fabs(d[i] - d2[i]));
        }
        assert_true(worst < 1e-12);
    }
}

/* Equal area: the Jacobian |dd/du x dd/dv| is constant = (4 pi / 6) / 4. */
static void test_equal_area_jacobian(void **state) {
    (void)state;
    const double h = 1e-6, want = 4 * PG_PI / 6 / 4;
    double lo = 1e9, hi = 0;
    for (int j = -9; j <= 9; j++) {
        for (int i = -9; i <= 9; i++) {
            double u = 0.105 * i + 0.0011, v = 0.105 * j + 0.0007, a[3], b[3], c[3], e[3];
            pg_cube_to_dir(PG_CUBE_EQUALAREA, 2, u + h, v, a);
            pg_cube_to_dir(PG_CUBE_EQUALAREA, 2, u - h, v, b);
            pg_cube_to_dir(PG_CUBE_EQUALAREA, 2, u, v + h, c);
            pg_cube_to_dir(PG_CUBE_EQUALAREA, 2, u, v - h, e);
            double du[3], dv[3];
            for (int k = 0; k < 3; k++)
                du[k] = (a[k] - b[k]) / (2 * h), dv[k] = (c[k] - e[k]) / (2 * h);
            double x = du[1] * dv[2] - du[2] * dv[1], y = du[2] * dv[0] - du[0] * dv[2],
                   z = du[0] * dv[1] - du[1] * dv[0];
            double J = sqrt(x * x + y * y + z * z);
            lo = fmin(lo, J), hi = fmax(hi, J);
        }
    }
    assert_true(fabs(lo / want - 1) < 1e-6);
    assert_true(fabs(hi / want - 1) < 1e-6);
}

static void test_projection_names(void **state) {
    (void)state;
    pg_cube_projection p;
    pg_error err = {0};
    assert_int_equal(pg_cube_projection_parse("equal-area", "--projection", &p, &err), PG_OK);
    assert_int_equal(p, PG_CUBE_EQUALAREA);
    assert_int_equal(pg_cube_projection_parse("mercator", "--projection", &p, &err),
                     PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "--projection"));
}

/* The texel of pg_cube_from_dir's (u, v), as the finder documents it. */
static int64_t texel_of(pg_cube_projection p, int64_t n, const double d[3]) {
    int face;
    double u, v;
    pg_cube_from_dir(p, d, &face, &u, &v);
    int64_t x = (int64_t)floor((u + 1) * 0.5 * (double)n), y = (int64_t)floor((v + 1) * 0.5 * n);
    x = x < 0 ? 0 : (x >= n ? n - 1 : x);
    y = y < 0 ? 0 : (y >= n ? n - 1 : y);
    return ((int64_t)face * n + y) * n + x;
}

/* Random directions, every texel corner (cell edges meet there; seams and cube
 * vertices among them), and each corner nudged by a few ulps in every component. */
static void test_texel_finder(void **state) {
    (void)state;
    const pg_cube_projection projs[3] = {PG_CUBE_GNOMONIC, PG_CUBE_EQUIANGULAR, PG_CUBE_EQUALAREA};
    const int64_t sizes[3] = {1, 7, 128};
    uint64_t rng = 12345, checked = 0;
    for (int pi = 0; pi < 3; pi++)
        for (int si = 0; si < 3; si++) {
            const int64_t n = sizes[si];
            pg_cube_texel_finder f;
            pg_error err = {0};
            assert_int_equal(pg_cube_texel_finder_init(&f, projs[pi], n, &err), PG_OK);
            assert_true((f.edge == NULL) == (projs[pi] == PG_CUBE_EQUALAREA));
            for (int i = 0; i < 200000; i++, checked++) {
                double d[3];
                for (int k = 0; k < 3; k++) {
                    rng = rng * 6364136223846793005ULL + 1442695040888963407ULL;
                    d[k] = (double)(rng >> 11) / 9007199254740992.0 * 2 - 1;
                }
                assert_int_equal(pg_cube_texel_find(&f, d), texel_of(projs[pi], n, d));
            }
            for (int face = 0; face < 6; face++)
                for (int64_t cy = 0; cy <= n; cy++)
                    for (int64_t cx = 0; cx <= n; cx++) {
                        double c[3];
                        pg_cube_to_dir(projs[pi], face, 2.0 * cx / n - 1, 2.0 * cy / n - 1, c);
                        for (int k = 0; k < 27; k++, checked++) {
                            double d[3] = {c[0], c[1], c[2]};
                            for (int a = 0, m = k; a < 3; a++, m /= 3)
                                for (int step = 0; step < 2 && m % 3; step++)
                                    d[a] = nextafter(d[a], m % 3 == 1 ? 2.0 : -2.0);
                            assert_int_equal(pg_cube_texel_find(&f, d), texel_of(projs[pi], n, d));
                        }
                    }
            pg_cube_texel_finder_free(&f);
        }
    printf("texel finder: %llu directions as pg_cube_from_dir\n", (unsigned long long)checked);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frames),
        cmocka_unit_test(test_round_trips),
        cmocka_unit_test(test_inverse_round_trip),
        cmocka_unit_test(test_equal_area_jacobian),
        cmocka_unit_test(test_projection_names),
        cmocka_unit_test(test_texel_finder),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
