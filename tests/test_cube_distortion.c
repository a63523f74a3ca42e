/* test_cube_distortion.c - texel area distortion for T = 8, S = 256 (N = 2048)
 * matches theory: gnomonic max/min area ~ 3^1.5 = 5.196, equi-angular ~ sqrt 2
 * (+-0.02), equal-area 1.00 (+-0.01); texel areas add up to the ellipsoid's area
 * (so the symmetry shortcut counts every texel once); the result does not depend
 * on the thread count. */
#include "pg_test.h"

#include "planetgen/pg_cube.h"

#include <math.h>
#include <omp.h>

#define PG_PI 3.14159265358979323846

static void run(pg_cube_projection p, const pg_ellipsoid *e, int64_t n, pg_cube_distortion *d) {
    pg_error err = {0};
    assert_int_equal(pg_cube_distortion_compute(p, n, e, d, &err), PG_OK);
    print_message("%-13s N=%lld f=%.6f: area ratio %.4f, min %.4g m2, max %.4g m2, "
                  "angle dev %.3f deg, mean texel %.4f km\n",
                  pg_cube_projection_name(p), (long long)n, e->f, d->area_ratio, d->area_min_m2,
                  d->area_max_m2, d->max_angle_dev_deg, d->mean_texel_km);
    double total = pg_geo_total_area(e);
    assert_true(fabs(d->total_area_m2 / total - 1) < 1e-9);
}

static void test_sphere_table(void **state) {
    (void)state;
    pg_ellipsoid s = pg_ellipsoid_sphere();
    pg_cube_distortion d;
    run(PG_CUBE_GNOMONIC, &s, 2048, &d);
    assert_true(fabs(d.area_ratio - 5.2) < 0.05);
    assert_true(d.max_angle_dev_deg > 29.9 && d.max_angle_dev_deg < 30.1); /* 120-degree vertex */
    run(PG_CUBE_EQUIANGULAR, &s, 2048, &d);
    assert_true(fabs(d.area_ratio - 1.41) <= 0.02);
    run(PG_CUBE_EQUALAREA, &s, 2048, &d);
    assert_true(fabs(d.area_ratio - 1.00) <= 0.01);
    assert_true(fabs(d.mean_texel_km - s.a / 1000 * sqrt(4 * PG_PI / 6) / 2048) < 1e-9);
}

static void test_wgs84(void **state) {
    (void)state;
    pg_ellipsoid w = pg_ellipsoid_wgs84();
    pg_cube_distortion d;
    run(PG_CUBE_EQUIANGULAR, &w, 512, &d);
    assert_true(fabs(d.area_ratio - 1.41) <= 0.03);
    run(PG_CUBE_EQUALAREA, &w, 512, &d);
    assert_true(d.area_ratio < 1.02); /* equal-area on the sphere, not the ellipsoid */
}

static void test_thread_independent(void **state) {
    (void)state;
    pg_ellipsoid w = pg_ellipsoid_wgs84();
    pg_cube_distortion a, b;
    omp_set_num_threads(1);
    run(PG_CUBE_EQUIANGULAR, &w, 96, &a);
    omp_set_num_threads(2);
    run(PG_CUBE_EQUIANGULAR, &w, 96, &b);
    assert_true(a.total_area_m2 == b.total_area_m2 && a.area_min_m2 == b.area_min_m2 &&
                a.max_angle_dev_deg == b.max_angle_dev_deg);
    /* odd N: centre rows and columns have smaller symmetry orbits */
    run(PG_CUBE_GNOMONIC, &w, 33, &a);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_table),
        cmocka_unit_test(test_wgs84),
        cmocka_unit_test(test_thread_independent),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
