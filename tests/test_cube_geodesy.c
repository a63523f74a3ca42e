/* test_cube_geodesy.c - the GeographicLib adapter: presets, parsing, direction <->
 * geodetic lat/lon round trips on a sphere and on WGS84 (where geodetic latitude of
 * the ray point differs from the geocentric angle by up to ~0.19 degrees), ECEF
 * heights along the normal, polygon areas against closed forms, and the cells of
 * latitude/longitude grids: their true areas and what a georeferencing says of them. */
#include "pg_test.h"

#include "planetgen/pg_geo.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PG_PI 3.14159265358979323846

static void test_presets_and_parse(void **state) {
    (void)state;
    pg_ellipsoid e;
    pg_error err = {0};
    assert_true(pg_ellipsoid_sphere().a == 6371008.8 && pg_ellipsoid_sphere().f == 0);
    assert_true(fabs(pg_ellipsoid_wgs84().a - 6378137) < 1e-9);
    assert_true(fabs(1 / pg_ellipsoid_wgs84().f - 298.257223563) < 1e-9);
    assert_int_equal(pg_ellipsoid_parse("wgs84", "--planet", &e, &err), PG_OK);
    assert_int_equal(pg_ellipsoid_parse("3389500,0.00589", "--planet", &e, &err), PG_OK);
    assert_true(e.a == 3389500 && e.f == 0.00589);
    const char *bad[] = {"1000,1", "1000,-0.1", "0,0.1", "-5,0", "mars", "1000,", "1000,0.1x"};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        pg_error_clear(&err);
        assert_int_equal(pg_ellipsoid_parse(bad[i], "--planet", &e, &err), PG_ERR_BADINPUT);
        assert_non_null(strstr(err.msg, "--planet"));
    }
}

static void test_round_trips(void **state) {
    (void)state;
    pg_ellipsoid es[2] = {pg_ellipsoid_sphere(), pg_ellipsoid_wgs84()};
    for (int k = 0; k < 2; k++) {
        double worst_geo_vs_centric = 0;
        for (double lat = -90; lat <= 90; lat += 7.5) {
            for (double lon = -180; lon < 180; lon += 11.25) {
                double d[3], la, lo;
                pg_geo_latlon_to_dir(&es[k], lat, lon, d);
                assert_true(fabs(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1) < 1e-15);
                pg_geo_dir_to_latlon(&es[k], d, &la, &lo);
                assert_true(fabs(la - lat) < 1e-9);
                if (fabs(lat) < 90) assert_true(fabs(remainder(lo - lon, 360)) < 1e-9);
                double centric = asin(d[2]) * 180 / PG_PI;
                worst_geo_vs_centric = fmax(worst_geo_vs_centric, fabs(centric - lat));
            }
        }
        if (k == 0)
            assert_true(worst_geo_vs_centric < 1e-9);
        else
            assert_true(worst_geo_vs_centric > 0.18 && worst_geo_vs_centric < 0.2);
    }
}

static void test_ecef(void **state) {
    (void)state;
    pg_ellipsoid w = pg_ellipsoid_wgs84();
    double p[3], q[3], d[3];
    pg_geo_ecef(&w, 0, 90, 100, p);
    assert_true(fabs(p[0]) < 1e-6 && fabs(p[1] - 6378237) < 1e-6 && fabs(p[2]) < 1e-6);
    pg_geo_ecef(&w, 90, 0, 0, p);
    assert_true(fabs(p[2] - 6378137 * (1 - w.f)) < 1e-6);
    /* h along the normal: the difference of two heights is h times the normal */
    pg_geo_latlon_to_dir(&w, 45, 10, d);
    pg_geo_dir_to_ecef(&w, d, 0, p);
    pg_geo_dir_to_ecef(&w, d, 1000, q);
    double nz = (q[2] - p[2]) / 1000;
    assert_true(fabs(nz - sin(45 * PG_PI / 180)) < 1e-12);
    assert_true(fabs(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 6367489.5) < 1.0);
}

static void test_areas(void **state) {
    (void)state;
    pg_ellipsoid s = pg_ellipsoid_sphere();
    double R = s.a;
    /* octant: three right angles, area 4 pi R^2 / 8 */
    double lat[3] = {0, 0, 90}, lon[3] = {0, 90, 0}, ang[3];
    double a = pg_geo_polygon_area(&s, 3, lat, lon, ang);
    assert_true(fabs(a / (PG_PI * R * R / 2) - 1) < 1e-12);
    for (int i = 0; i < 3; i++)
        assert_true(fabs(ang[i] - 90) < 1e-9);
    /* a lat/lon box: 2 pi R^2 (sin 10 - sin 0) * 20/360 */
    double bl[4] = {0, 0, 10, 10}, bo[4] = {0, 20, 20, 0};
    double box = pg_geo_polygon_area(&s, 4, bl, bo, NULL);
    double rhumb = 2 * PG_PI * R * R * sin(10 * PG_PI / 180) * 20 / 360;
    assert_true(box > rhumb && box < 1.02 * rhumb); /* the geodesic top edge bulges poleward */
    pg_ellipsoid w = pg_ellipsoid_wgs84();
    assert_true(fabs(pg_geo_total_area(&w) / 5.10065621724e14 - 1) < 1e-9);
}

/* Latitude/longitude cells: the sphere's closed form, a whole-globe WGS84 grid summing
 * to the ellipsoid's area, and a small cell against the geodesic quadrilateral. */
static void test_band_areas(void **state) {
    (void)state;
    pg_ellipsoid s = pg_ellipsoid_sphere(), w = pg_ellipsoid_wgs84();
    double lat[4] = {90, 60, 10, -35}, area[3];
    pg_geo_latlon_band_areas(&s, 3, lat, 2.5, area);
    for (int i = 0; i < 3; i++) {
        double exact = s.a * s.a * 2.5 * PG_PI / 180 *
                       (sin(lat[i] * PG_PI / 180) - sin(lat[i + 1] * PG_PI / 180));
        assert_true(fabs(area[i] / exact - 1) < 1e-12);
    }
    /* 1-degree rows of a whole-globe grid, 360 cells each */
    double edges[181], rows[180], sum = 0;
    for (int j = 0; j <= 180; j++)
        edges[j] = 90 - j;
    pg_geo_latlon_band_areas(&w, 180, edges, 1.0, rows);
    for (int j = 0; j < 180; j++)
        sum += 360 * rows[j];
    assert_true(fabs(sum / pg_geo_total_area(&w) - 1) < 1e-12);
    assert_true(rows[0] < rows[45] && rows[45] < rows[89] && fabs(rows[89] / rows[90] - 1) < 1e-12);
    /* a 0.01-degree cell: its geodesic edges differ from the parallels by < 1e-7 */
    double cl[2] = {45.01, 45.0}, cell;
    pg_geo_latlon_band_areas(&w, 1, cl, 0.01, &cell);
    double ql[4] = {45, 45, 45.01, 45.01}, qo[4] = {7, 7.01, 7.01, 7};
    assert_true(fabs(cell / pg_geo_polygon_area(&w, 4, ql, qo, NULL) - 1) < 1e-7);
}

/* Row areas from a georeferencing: geographic (true areas, whole-globe detection),
 * projected (the geotransform's determinant in metres), and none (refused). */
static void test_raster_cells(void **state) {
    (void)state;
    pg_error err = {0};
    pg_georef g = {0};
    pg_ellipsoid w = pg_ellipsoid_wgs84();
    assert_int_equal(pg_geo_raster_global(&w, 720, 360, &g, &err), PG_OK);
    assert_true(g.kind == PG_CRS_GEOGRAPHIC && fabs(g.a - w.a) < 1e-6 && fabs(g.f - w.f) < 1e-15);
    assert_non_null(strstr(g.crs_wkt, "4326"));
    assert_true(pg_geo_raster_is_global(&g, 720, 360));
    assert_false(pg_geo_raster_is_global(&g, 720, 359));
    double *rows = malloc(360 * sizeof *rows), sum = 0;
    assert_int_equal(pg_geo_raster_row_areas(&g, 720, 360, "t", rows, &err), PG_OK);
    for (int j = 0; j < 360; j++)
        sum += 720 * rows[j];
    assert_true(fabs(sum / pg_geo_total_area(&w) - 1) < 1e-12);
    /* a regional grid is not global; a projected one has constant cells */
    g.transform[0] = 0, g.transform[3] = 45;
    assert_false(pg_geo_raster_is_global(&g, 720, 360));
    g.kind = PG_CRS_PROJECTED;
    g.unit = 0.3048; /* feet */
    const double t[6] = {500000, 30, 0, 5200000, 0, -20};
    memcpy(g.transform, t, sizeof t);
    assert_int_equal(pg_geo_raster_row_areas(&g, 720, 360, "t", rows, &err), PG_OK);
    assert_true(fabs(rows[0] - 600 * 0.3048 * 0.3048) < 1e-9 && rows[359] == rows[0]);
    assert_false(pg_geo_raster_is_global(&g, 720, 360));
    g.kind = PG_CRS_NONE;
    assert_int_equal(pg_geo_raster_row_areas(&g, 720, 360, "in.tif", rows, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "in.tif"));
    free(rows);
    pg_georef_free(&g);
    /* another planet gets a CRS on its own sphere, not EPSG:4326 */
    pg_ellipsoid mars = {3389500, 0};
    assert_int_equal(pg_geo_raster_global(&mars, 64, 32, &g, &err), PG_OK);
    assert_null(strstr(g.crs_wkt, "4326"));
    assert_true(g.kind == PG_CRS_GEOGRAPHIC && g.a == 3389500 && g.f == 0);
    pg_georef_free(&g);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_presets_and_parse),
        cmocka_unit_test(test_round_trips),
        cmocka_unit_test(test_ecef),
        cmocka_unit_test(test_areas),
        cmocka_unit_test(test_band_areas),
        cmocka_unit_test(test_raster_cells),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
