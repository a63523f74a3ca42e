/* test_planet.c - the planet directory format: a planet reprojected from the real
 * exemplar survives save and load, and damaged directories are refused by name. */
#include "pg_test.h"

#include "planetgen/pg_planet.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void test_roundtrip_real_exemplar(void **s) {
    (void)s;
    pg_error err = {0};
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    pg_exemplar ex;
    assert_int_equal(pg_exemplar_load(&o, &ex, &err), PG_OK);
    pg_planet p, q;
    assert_int_equal(pg_planet_alloc(&p, PG_CUBE_EQUIANGULAR, 2, 64, pg_ellipsoid_sphere(), &err),
                     PG_OK);
    p.seed = 12345678901234567ULL;
    assert_int_equal(pg_planet_from_exemplar(&p, &ex, 2, &err), PG_OK);
    /* +Z is north: the north face centre is Arctic ocean (below sea level), the south
     * face centre is the Antarctic ice sheet (kilometres up) */
    int64_t c = (p.n / 2) * p.n + p.n / 2;
    assert_true(p.height[PG_CUBE_FACE_PZ][c] < 0);
    assert_true(p.height[PG_CUBE_FACE_NZ][c] > 2000);
    char dir[1024];
    pg_test_scratch_dir("planet_rt", dir, sizeof dir);
    assert_int_equal(pg_planet_save_dir(&p, dir, &err), PG_OK);
    assert_int_equal(pg_test_count_files(dir), 8);
    assert_int_equal(pg_planet_load(dir, &q, &err), PG_OK);
    assert_int_equal(q.n, p.n);
    assert_int_equal(q.tiles, 2);
    assert_int_equal(q.projection, PG_CUBE_EQUIANGULAR);
    assert_true(q.seed == p.seed);
    assert_float_equal(q.ellipsoid.a, p.ellipsoid.a, 0);
    size_t nn = (size_t)p.n * p.n;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        assert_memory_equal(q.height[f], p.height[f], nn * sizeof(float)); /* float exact */
        for (size_t i = 0; i < nn * 3; i++)
            assert_float_equal(q.albedo[f][i], p.albedo[f][i], 0.5 / 255 + 1e-6); /* 8-bit */
    }
    pg_planet_free(&q);
    /* a missing face file is named */
    char path[1300];
    snprintf(path, sizeof path, "%s/albedo_-Y.png", dir);
    remove(path);
    pg_error_clear(&err);
    assert_int_equal(pg_planet_load(dir, &q, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "missing albedo_-Y.png"));
    /* a directory without planet.json is not a planet */
    snprintf(path, sizeof path, "%s/planet.json", dir);
    remove(path);
    pg_error_clear(&err);
    assert_int_equal(pg_planet_load(dir, &q, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "not a planet output"));
    pg_planet_free(&p);
    pg_exemplar_free(&ex);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_roundtrip_real_exemplar)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
