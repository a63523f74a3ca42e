/* test_earthlike.c - the Earth-likeness statistics (pg_earthlike.h) on constructed
 * planets with known answers: texel areas sum to the ellipsoid's area, geodetic
 * latitudes agree with GeographicLib, a spherical cap has the cap's area share and
 * is one landmass (also across a face seam and over a cube corner), landmass counts
 * and shares at the 1e4 / 1e6 km^2 thresholds, the rank-size slope of three caps,
 * hypsometry (Archimedes: z is uniform by area on a sphere, so h = c z has known
 * quantiles, moments and W1), zonal ice and desert figures, the zonal correlation,
 * thread-count independence, bad input, shelf widths round a continent with a narrow
 * and a wide shelf; and novelty against the real exemplar: Earth
 * itself agrees with Earth, Earth turned 180 degrees in longitude agrees by chance.
 * Over 600 lines because one file holds every case of the module, each independent. */
#include "pg_test.h"

#include "pg_earthlike_internal.h"
#include "planetgen/pg_earthlike.h"
#include "planetgen/pg_pits.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEG (M_PI / 180)

/* ---- constructing planets ---- */

typedef void (*texel_fn)(const double d[3], const void *ctx, float *h, float rgb[3]);

static void make_planet(pg_planet *p, int n, pg_ellipsoid ell, pg_cube_projection proj) {
    pg_error err = {0};
    assert_int_equal(pg_planet_alloc(p, proj, 1, n, ell, &err), PG_OK);
    p->sea_level = 0;
}

/* Set every texel from its centre direction. */
static void paint(pg_planet *p, texel_fn fn, const void *ctx) {
    int64_t n = p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                double d[3], u = (2.0 * x + 1) / n - 1, v = (2.0 * y + 1) / n - 1;
                pg_cube_to_dir(p->projection, f, u, v, d);
                size_t i = (size_t)(y * n + x);
                fn(d, ctx, &p->height[f][i], &p->albedo[f][3 * i]);
            }
}

static void unit(double d[3]) {
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    d[0] /= l, d[1] /= l, d[2] /= l;
}

static double dot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Land caps: centre (unit), angular radius; land 500 m, ocean -3000 m. */
typedef struct caps {
    int count;
    double c[4][3], radius_deg[4];
} caps;

static void cap_texel(const double d[3], const void *ctx, float *h, float rgb[3]) {
    const caps *k = ctx;
    *h = -3000;
    for (int i = 0; i < k->count; i++)
        if (dot(d, k->c[i]) >= cos(k->radius_deg[i] * DEG)) *h = 500;
    rgb[0] = 0.3f, rgb[1] = 0.35f, rgb[2] = 0.2f;
}

static void add_cap(caps *k, double x, double y, double z, double radius_deg) {
    double *c = k->c[k->count];
    c[0] = x, c[1] = y, c[2] = z;
    unit(c);
    k->radius_deg[k->count++] = radius_deg;
}

/* Angular radius (degrees) of a cap of `km2` on a sphere of radius R. */
static double cap_radius_for_area(double km2) {
    double R = PG_ELLIPSOID_SPHERE_RADIUS_M;
    return acos(1 - km2 * 1e6 / (2 * M_PI * R * R)) / DEG;
}

static double cap_km2(double radius_deg) {
    double R = PG_ELLIPSOID_SPHERE_RADIUS_M;
    return 2 * M_PI * R * R * (1 - cos(radius_deg * DEG)) / 1e6;
}

static void compute(const pg_planet *p, pg_earthlike *e) {
    pg_error err = {0};
    pg_status st = pg_earthlike_compute(p, e, &err);
    if (st) fprintf(stderr, "%s\n", err.msg);
    assert_int_equal(st, PG_OK);
}

static pg_earthlike *compute_new(const pg_planet *p) {
    pg_earthlike *e = malloc(sizeof *e);
    assert_non_null(e);
    compute(p, e);
    return e;
}

/* ---- geometry ---- */

/* The texel areas tile the ellipsoid: their sum is its area (GeographicLib), on a
 * sphere, on WGS84 and on a very flat ellipsoid (f = 0.1, where the midpoint rule's
 * O(f / N^2) error is 7e-7 at N = 32). A Jacobian-free sum (the sphere of radius a)
 * would be 0.22% too large on WGS84. */
static void test_areas_sum_to_the_ellipsoid(void **s) {
    (void)s;
    const pg_cube_projection projs[3] = {PG_CUBE_GNOMONIC, PG_CUBE_EQUIANGULAR, PG_CUBE_EQUALAREA};
    const pg_ellipsoid ells[3] = {pg_ellipsoid_wgs84(), pg_ellipsoid_sphere(), {6.0e6, 0.1}};
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            pg_planet p;
            make_planet(&p, 32, ells[j], projs[i]);
            pg_earthlike *e = compute_new(&p);
            double want = pg_geo_total_area(&ells[j]);
            double tol = j < 2 ? 1e-8 : 2e-6; /* midpoint rule: O(f / N^2) */
            assert_float_equal(e->total_area_m2 / want, 1, tol);
            /* heights are all 0 = sea level: all ocean */
            assert_true(e->land_fraction == 0);
            assert_int_equal(e->landmasses, 0);
            assert_true(isnan(e->largest_landmass_share));
            assert_true(isnan(e->land_quantiles[0]) && isnan(e->land_std_m));
            double bands = 0;
            for (int b = 0; b < PG_EARTHLIKE_BANDS; b++)
                bands += e->band_area_m2[b];
            assert_float_equal(bands / want, 1, tol);
            free(e);
            pg_planet_free(&p);
        }
}

/* The closed-form geodetic latitude equals GeographicLib's. */
static void test_geodetic_latitude(void **s) {
    (void)s;
    pg_ellipsoid e[2] = {pg_ellipsoid_wgs84(), {6.0e6, 0.1}};
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 200; i++) {
            double d[3] = {sin(i * 1.7), cos(i * 2.3), sin(i * 0.37) * 2}, lat, lon;
            pg_geo_dir_to_latlon(&e[k], d, &lat, &lon);
            assert_float_equal(pg_earthlike_geodetic_lat(&e[k], d), lat, 1e-9);
        }
}

/* ---- landmasses ---- */

/* One round continent: land share = the cap's area share, one landmass, all of it. */
static void test_one_cap(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 128, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    caps k = {0};
    add_cap(&k, 0.3, 0.5, 0.8, 25);
    paint(&p, cap_texel, &k);
    pg_earthlike *e = compute_new(&p);
    double share = (1 - cos(25 * DEG)) / 2; /* 0.0468 */
    assert_float_equal(e->land_fraction, share, 0.01 * share);
    assert_float_equal(e->land_area_m2 / 1e6, cap_km2(25), 0.01 * cap_km2(25));
    assert_int_equal(e->landmasses, 1);
    assert_int_equal(e->landmasses_1e4, 1);
    assert_int_equal(e->landmasses_1e6, 1); /* 2.4e7 km^2 */
    assert_true(e->largest_landmass_share == 1);
    assert_float_equal(e->largest_landmass_km2 * 1e6, e->land_area_m2, 1e-6 * e->land_area_m2);
    assert_true(isnan(e->rank_size_slope));
    free(e);
    pg_planet_free(&p);
}

static int faces_with_land(const pg_planet *p) {
    int count = 0;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        int any = 0;
        for (int64_t i = 0; i < p->n * p->n; i++)
            any |= p->height[f][i] > p->sea_level;
        count += any;
    }
    return count;
}

/* A continent across the +X/+Y seam and one over the (+X, +Y, +Z) cube corner are
 * one landmass each; two caps 4 degrees apart stay two. */
static void test_seam_and_corner(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 64, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    caps seam = {0}, corner = {0}, two = {0};
    add_cap(&seam, 1, 1, 0.1, 12);
    add_cap(&corner, 1, 1, 1, 12);
    add_cap(&two, -1, 0.08, 0, 2);
    add_cap(&two, -1, -0.08, 0, 2); /* centres 9.1 degrees apart: a 5-degree strait */
    const caps *cases[3] = {&seam, &corner, &two};
    const int want_faces[3] = {2, 3, 1}, want_masses[3] = {1, 1, 2};
    for (int c = 0; c < 3; c++) {
        paint(&p, cap_texel, cases[c]);
        assert_int_equal(faces_with_land(&p), want_faces[c]);
        pg_earthlike *e = compute_new(&p);
        assert_int_equal(e->landmasses, want_masses[c]);
        if (c < 2) assert_true(e->largest_landmass_share == 1);
        free(e);
    }
    pg_planet_free(&p);
}

/* A 4e6 km^2 continent, a 3e5 km^2 island and a one-texel islet (~6100 km^2): three
 * landmasses, two of at least 1e4 km^2, one of at least 1e6 km^2. */
static void test_thresholds_and_share(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 128, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    caps k = {0};
    double rb = cap_radius_for_area(4e6), ra = cap_radius_for_area(3e5);
    add_cap(&k, 1, 0.2, 0.3, rb);
    add_cap(&k, -0.5, 1, -0.4, ra);
    paint(&p, cap_texel, &k);
    /* the islet: one texel in the middle of the -Z face, in open ocean */
    int64_t n = p.n, c = (n / 2) * n + n / 2;
    assert_true(p.height[PG_CUBE_FACE_NZ][c] < 0);
    pg_planet only; /* the islet alone: its area */
    make_planet(&only, 128, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    only.height[PG_CUBE_FACE_NZ][c] = p.height[PG_CUBE_FACE_NZ][c] = 10;
    pg_earthlike *e1 = compute_new(&only);
    double islet = e1->largest_landmass_km2;
    assert_true(islet > 1000 && islet < 1e4);
    assert_float_equal(e1->land_area_m2 / 1e6, islet, 1e-9 * islet);
    free(e1);
    pg_planet_free(&only);
    pg_earthlike *e = compute_new(&p);
    assert_int_equal(e->landmasses, 3);
    assert_int_equal(e->landmasses_1e4, 2);
    assert_int_equal(e->landmasses_1e6, 1);
    assert_float_equal(e->largest_landmass_km2, 4e6, 0.02 * 4e6);
    assert_float_equal(e->largest_landmass_share, 4e6 / (4e6 + 3e5 + islet), 0.005);
    assert_true(isnan(e->rank_size_slope)); /* only 2 landmasses >= 1e4 km^2 */
    free(e);
    pg_planet_free(&p);
}

/* Three caps of 4e6, 1e6 and 2.5e5 km^2 (and a sub-threshold islet, left out): the
 * measured slope is the least-squares slope of ln(exact cap area) on ln(rank 1, 2, 3):
 * -2.47 (areas fall by 4 per rank; at ranks 1, 2, 4 it would be exactly -2). */
static void test_rank_size_slope(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 128, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    caps k = {0};
    double area[3] = {4e6, 1e6, 2.5e5};
    add_cap(&k, 1, 0.1, 0.2, cap_radius_for_area(area[0]));
    add_cap(&k, -1, 0.3, -0.2, cap_radius_for_area(area[1]));
    add_cap(&k, 0.1, 0.2, -1, cap_radius_for_area(area[2]));
    paint(&p, cap_texel, &k);
    p.height[PG_CUBE_FACE_PZ][(p.n / 2) * p.n + p.n / 2] = 10;
    pg_earthlike *e = compute_new(&p);
    assert_int_equal(e->landmasses, 4);
    assert_int_equal(e->landmasses_1e4, 3);
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (int i = 0; i < 3; i++) {
        double x = log(i + 1.0), y = log(area[i]);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    double want = (sxy - sx * sy / 3) / (sxx - sx * sx / 3); /* -2.47 */
    assert_float_equal(e->rank_size_slope, want, 0.03);
    free(e);
    pg_planet_free(&p);
}

/* ---- hypsometry ---- */

/* Land north of the equator at h = scale * z^pow, ocean south of it at 4000 z. On a
 * sphere z is uniform by area (Archimedes), so land heights are uniform on
 * [0, scale] for pow = 1 (quantile scale q) and have quantile scale q^2 for pow = 2;
 * the ocean is uniform on [-4000, 0]. */
typedef struct hyps {
    double scale, shift;
    int pow;
    double sea; /* added to every height (with the sea level moved along) */
} hyps;

static void hyps_texel(const double d[3], const void *ctx, float *h, float rgb[3]) {
    const hyps *k = ctx;
    double z = d[2];
    *h = (float)((z > 0 ? k->scale * (k->pow == 2 ? z * z : z) + k->shift : 4000 * z) + k->sea);
    rgb[0] = 0.3f, rgb[1] = 0.35f, rgb[2] = 0.2f;
}

static void test_hypsometry(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 64, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    hyps lin = {2000, 0, 1, 0}, shifted = {2000, 100, 1, 0}, sq = {2000, 0, 2, 0};
    hyps raised = {2000, 0, 1, 250}; /* the same world 250 m up, sea level too */
    paint(&p, hyps_texel, &lin);
    pg_earthlike *a = compute_new(&p);
    paint(&p, hyps_texel, &shifted);
    pg_earthlike *b = compute_new(&p);
    paint(&p, hyps_texel, &sq);
    pg_earthlike *c = compute_new(&p);
    paint(&p, hyps_texel, &raised);
    p.sea_level = 250;
    pg_earthlike *d = compute_new(&p);
    /* the quantile functions, moments */
    for (int k = 0; k < PG_EARTHLIKE_QUANTILES; k++) {
        double q = (k + 0.5) / PG_EARTHLIKE_QUANTILES;
        assert_float_equal(a->land_quantiles[k], 2000 * q, 20);
        assert_float_equal(a->ocean_quantiles[k], -4000 + 4000 * q, 40);
        assert_float_equal(c->land_quantiles[k], 2000 * q * q, 20);
    }
    assert_float_equal(a->land_mean_m, 1000, 5);
    assert_float_equal(a->land_std_m, 2000 / sqrt(12), 3);
    assert_float_equal(a->ocean_mean_m, -2000, 10);
    assert_float_equal(a->ocean_std_m, 4000 / sqrt(12), 6);
    assert_float_equal(b->land_std_m, a->land_std_m, 1e-3);
    /* W1 */
    double wl, wo;
    pg_earthlike_w1(a, a, &wl, &wo);
    assert_true(wl == 0 && wo == 0);
    pg_earthlike_w1(a, d, &wl, &wo); /* heights count from sea level */
    assert_true(wl < 0.01 && wo < 0.01);
    assert_float_equal(d->land_mean_m, a->land_mean_m, 0.01);
    pg_earthlike_w1(a, b, &wl, &wo);
    assert_float_equal(wl, 100, 0.01);
    assert_true(wo == 0);
    pg_earthlike_w1(b, a, &wl, NULL);
    assert_float_equal(wl, 100, 0.01);
    pg_earthlike_w1(a, c, &wl, NULL); /* integral of 2000 (q - q^2) = 333.3 */
    assert_float_equal(wl, 2000.0 / 6, 5);
    free(a), free(b), free(c), free(d);
    pg_planet_free(&p);
}

static int cmp_hw(const void *a, const void *b) {
    const double *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

static uint32_t hash32(uint32_t a, uint32_t b);

/* Random heights: the quantiles match a brute-force area-weighted sort of the texels
 * to within two histogram bins, and the moments match exactly. The sort takes the
 * texel areas from pg_pits_cube_face_areas (on a sphere the ellipsoid factor is R^2)
 * and F^-1(t) = the smallest height whose cumulative area reaches t. */
static void test_quantiles_brute_force(void **s) {
    (void)s;
    pg_planet p;
    pg_error err = {0};
    int n = 64;
    make_planet(&p, n, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    double *area = malloc(sizeof *area * n * n), *hw = malloc(sizeof *hw * 2 * 6 * n * n);
    assert_int_equal(
        pg_pits_cube_face_areas(p.projection, n, PG_ELLIPSOID_SPHERE_RADIUS_M, area, &err), PG_OK);
    size_t m = 0;
    double sw = 0, swh = 0, swh2 = 0, lo = INFINITY, hi = -INFINITY;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int i = 0; i < n * n; i++) {
            uint32_t r = hash32(77u + f, (uint32_t)i);
            float h = r % 2 ? (float)(r % 100000) * 0.03f + 1 : -100;
            p.height[f][i] = h;
            if (h <= 0) continue;
            hw[2 * m] = h, hw[2 * m + 1] = area[i], m++;
            sw += area[i], swh += area[i] * h, swh2 += area[i] * h * h;
            lo = fmin(lo, h), hi = fmax(hi, h);
        }
    qsort(hw, m, 2 * sizeof *hw, cmp_hw);
    pg_earthlike *e = compute_new(&p);
    double cum = 0, width = (hi - lo) / 65536;
    size_t j = 0;
    for (int k = 0; k < PG_EARTHLIKE_QUANTILES; k++) {
        double t = (k + 0.5) / PG_EARTHLIKE_QUANTILES * sw;
        while (cum + hw[2 * j + 1] < t)
            cum += hw[2 * j + 1], j++;
        assert_float_equal(e->land_quantiles[k], hw[2 * j], 2 * width);
    }
    double mean = swh / sw;
    assert_float_equal(e->land_mean_m, mean, 1e-9 * mean);
    assert_float_equal(e->land_std_m, sqrt(swh2 / sw - mean * mean), 1e-6);
    assert_true(e->ocean_quantiles[0] == -100 && e->ocean_quantiles[1023] == -100);
    assert_true(e->ocean_std_m == 0);
    free(e), free(area), free(hw);
    pg_planet_free(&p);
}

/* ---- zonal climate ---- */

/* Land everywhere (100 m) but ocean south of -60;
 * desert in 15..35 north, in 15..35 south only east of the 90W-90E meridian plane
 * (x > 0, half the band by symmetry), and within `desert_eq` of the equator; forest
 * in 50..60 north if `forest`; grass elsewhere. Ice: with `tropical` unset, white
 * land poleward of `ice_lat` north and white sea ice south of -70; with it set, the tropics (|lat|
 * < 20) are white land ice for x > 0 and open (dark) ocean for x < 0. */
typedef struct zonal_world {
    double ice_lat, desert_eq;
    int forest, tropical;
} zonal_world;

static void set_rgb(float rgb[3], float r, float g, float b) {
    rgb[0] = r, rgb[1] = g, rgb[2] = b;
}

static void zonal_texel(const double d[3], const void *ctx, float *h, float rgb[3]) {
    const zonal_world *w = ctx;
    double lat = asin(d[2]) / DEG, a = fabs(lat); /* a sphere: geodetic = geocentric */
    int tropics = w->tropical && a < 20;
    *h = lat < -60 || (tropics && d[0] < 0) ? -100 : 100;
    set_rgb(rgb, 0.35f, 0.35f, 0.2f); /* grass */
    if ((a >= 15 && a < 35 && (lat > 0 || d[0] > 0)) || a < w->desert_eq)
        set_rgb(rgb, 0.8f, 0.7f, 0.5f);
    if (w->forest && lat >= 50 && lat < 60) set_rgb(rgb, 0.1f, 0.2f, 0.1f);
    if (tropics) set_rgb(rgb, 0.1f, 0.1f, 0.3f); /* dark blue: the open-ocean half */
    if ((!w->tropical && (lat >= w->ice_lat || lat < -70)) || (tropics && d[0] > 0))
        set_rgb(rgb, 0.95f, 0.95f, 0.95f);
}

static void test_zonal(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 128, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    zonal_world polar = {70, 2, 1, 0}, tropical = {0, 2, 0, 1}, no_eq_desert = {70, 0, 1, 0};
    paint(&p, zonal_texel, &polar);
    pg_earthlike *a = compute_new(&p);
    paint(&p, zonal_texel, &tropical);
    pg_earthlike *b = compute_new(&p);
    paint(&p, zonal_texel, &no_eq_desert);
    pg_earthlike *c = compute_new(&p);
    /* land ice share poleward of 66: north only (the south is sea ice, not land) */
    double want_polar = (1 - sin(70 * DEG)) / (1 - sin(66 * DEG)); /* 0.698 */
    assert_float_equal(a->ice_polar_fraction, want_polar, 0.01);
    assert_true(a->ice_equator_fraction == 0);
    /* desert share of land: 3/4 in 15..35 (all north, half south), sin 2 / sin 10
     * within 10 degrees */
    assert_float_equal(a->desert_band_ratio, 0.75 * sin(10 * DEG) / sin(2 * DEG), 0.08); /* 3.73 */
    assert_true(isinf(c->desert_band_ratio) && c->desert_band_ratio > 0);
    /* the table: bands 70..80 and 80..90 all ice, 60..70 grass, the southern cap ice
     * (sea ice is classified ice), -70..-60 open ocean, 20..30 north all desert,
     * 50..60 forest; each band sums to 1 */
    assert_true(a->zonal[17][PG_TYPE_ICE] > 0.999 && a->zonal[16][PG_TYPE_ICE] > 0.999);
    assert_true(a->zonal[15][PG_TYPE_ICE] == 0 && a->zonal[15][PG_TYPE_GRASS] > 0.999);
    assert_true(a->zonal[0][PG_TYPE_ICE] > 0.999 && a->zonal[2][PG_TYPE_OCEAN] > 0.999);
    assert_true(a->zonal[11][PG_TYPE_DESERT] > 0.999 && a->zonal[14][PG_TYPE_FOREST] > 0.999);
    assert_float_equal(a->zonal[6][PG_TYPE_DESERT], 0.5, 1e-6);
    for (int bnd = 0; bnd < PG_EARTHLIKE_BANDS; bnd++) {
        double sum = 0;
        for (int t = 0; t < PG_TYPE_COUNT; t++)
            sum += a->zonal[bnd][t];
        assert_float_equal(sum, 1, 1e-9);
    }
    /* ice on half the tropics, open ocean on the other half: ice is half of ALL the
     * area within 20 degrees (though all of its land) */
    assert_float_equal(b->ice_equator_fraction, 0.5, 1e-6);
    assert_true(b->ice_polar_fraction == 0);
    /* correlation: itself 1; ice moved from the poles to the tropics scores lower,
     * ice's own profile anti-correlates; forest (only in a) counts 0, mountain (in
     * neither) is left out */
    double per[PG_TYPE_COUNT];
    assert_float_equal(pg_earthlike_zonal_correlation(a, a, NULL), 1, 1e-12);
    double r = pg_earthlike_zonal_correlation(a, b, per);
    assert_true(per[PG_TYPE_ICE] < 0);
    assert_true(per[PG_TYPE_FOREST] == 0 && isnan(per[PG_TYPE_MOUNTAIN]));
    double mean = 0;
    for (int t = 0; t < PG_TYPE_MOUNTAIN; t++)
        mean += per[t] / PG_TYPE_MOUNTAIN;
    assert_float_equal(r, mean, 1e-12);
    assert_true(r < 0.7);
    free(a), free(b), free(c);
    pg_planet_free(&p);
}

/* Albedo is rounded to 8 bits before classifying: grey 158.6/255 becomes 159, whose
 * luma 0.6235 passes the ice rule (L >= 0.62); truncated to 158 (0.6196) it would
 * be desert. */
static void grey_texel(const double d[3], const void *ctx, float *h, float rgb[3]) {
    (void)d, (void)ctx;
    *h = 100;
    set_rgb(rgb, 158.6f / 255, 158.6f / 255, 158.6f / 255);
}

static void test_albedo_rounding(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 16, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    paint(&p, grey_texel, NULL);
    pg_earthlike *e = compute_new(&p);
    assert_true(e->land_fraction == 1 && e->landmasses == 1);
    for (int b = 0; b < PG_EARTHLIKE_BANDS; b++)
        assert_true(e->zonal[b][PG_TYPE_ICE] == 1);
    assert_true(e->ice_polar_fraction == 1 && e->ice_equator_fraction == 1);
    assert_true(isnan(e->desert_band_ratio)); /* land, but no desert anywhere */
    free(e);
    pg_planet_free(&p);
}

/* ---- determinism and bad input ---- */

static uint32_t hash32(uint32_t a, uint32_t b) {
    uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u;
    h ^= h >> 15;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12;
    return h ^ (h >> 15);
}

static void test_thread_count_independent(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 64, pg_ellipsoid_wgs84(), PG_CUBE_EQUIANGULAR);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (uint32_t i = 0; i < 64 * 64; i++) {
            uint32_t r = hash32((uint32_t)f, i);
            p.height[f][i] = (float)((r % 9000) - 5000.0);
            for (int c = 0; c < 3; c++)
                p.albedo[f][3 * i + c] = (float)(hash32(r, (uint32_t)c) % 256) / 255;
        }
    int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    pg_earthlike *a = compute_new(&p);
    omp_set_num_threads(2);
    pg_earthlike *b = compute_new(&p);
    omp_set_num_threads(saved);
    assert_memory_equal(a, b, sizeof *a);
    assert_true(a->landmasses > 10);
    free(a), free(b);
    pg_planet_free(&p);
}

static void test_bad_input(void **s) {
    (void)s;
    pg_planet p;
    pg_earthlike e;
    pg_error err = {0};
    make_planet(&p, 8, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    p.height[3][5] = NAN;
    assert_int_equal(pg_earthlike_compute(&p, &e, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "not finite"));
    pg_planet_free(&p);
    pg_planet empty = {0};
    pg_error_clear(&err);
    assert_int_equal(pg_earthlike_compute(&empty, &e, &err), PG_ERR_BADINPUT);
}

/* ---- novelty against the real exemplar ---- */

/* Earth turned 180 degrees about the polar axis: +X <-> -X and +Y <-> -Y texel for
 * texel (their frames map onto each other), +Z and -Z turned in place. */
static void rotate_180(const pg_planet *src, pg_planet *dst) {
    static const int to[PG_CUBE_NFACES] = {1, 0, 3, 2, 4, 5};
    int64_t n = src->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < n * n; i++) {
            int64_t j = f < PG_CUBE_FACE_PZ ? i : n * n - 1 - i; /* (n-1-x, n-1-y) */
            dst->height[to[f]][j] = src->height[f][i];
            memcpy(dst->albedo[to[f]] + 3 * j, src->albedo[f] + 3 * i, 3 * sizeof(float));
        }
    dst->sea_level = src->sea_level;
}

static void test_novelty_real_exemplar(void **s) {
    (void)s;
    pg_error err = {0};
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    pg_exemplar ex;
    assert_int_equal(pg_exemplar_load(&o, &ex, &err), PG_OK);
    pg_planet earth, turned;
    make_planet(&earth, 64, pg_ellipsoid_wgs84(), PG_CUBE_EQUIANGULAR);
    make_planet(&turned, 64, pg_ellipsoid_wgs84(), PG_CUBE_EQUIANGULAR);
    assert_int_equal(pg_planet_from_exemplar(&earth, &ex, 2, &err), PG_OK);
    rotate_180(&earth, &turned);
    pg_earthlike_novelty a, b, a1;
    int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    assert_int_equal(pg_earthlike_novelty_compute(&earth, &ex, &a1, &err), PG_OK);
    omp_set_num_threads(2);
    assert_int_equal(pg_earthlike_novelty_compute(&earth, &ex, &a, &err), PG_OK);
    omp_set_num_threads(saved);
    assert_memory_equal(&a, &a1, sizeof a); /* thread-count independent */
    assert_int_equal(pg_earthlike_novelty_compute(&turned, &ex, &b, &err), PG_OK);
    assert_true(a.agreement >= 0.95);
    assert_true(a.kappa >= 0.9 && a.novelty <= 0.1);
    assert_float_equal(a.earth_land_fraction, 0.29, 0.02);
    assert_float_equal(a.planet_land_fraction, a.earth_land_fraction, 0.01);
    assert_float_equal(b.planet_land_fraction, a.planet_land_fraction, 1e-12);
    assert_float_equal(b.chance, 0.588, 0.02);
    /* Turned Earth keeps its latitude profile (Antarctica, the Southern Ocean), so it
     * agrees by somewhat more than chance, and by chance given latitude */
    assert_true(b.agreement > b.chance && b.agreement < b.chance + 0.12);
    assert_true(b.kappa < 0.25);
    assert_float_equal(b.agreement, b.chance_zonal, 0.03);
    assert_true(fabs(b.kappa_zonal) < 0.1);
    assert_true(a.kappa_zonal > 0.9);
    /* pg_earthlike_compute measures the same land share with the same areas */
    pg_earthlike *e = compute_new(&earth);
    assert_float_equal(e->land_fraction, a.planet_land_fraction, 1e-9);
    pg_planet_free(&earth);
    pg_planet_free(&turned);
    pg_exemplar_free(&ex);
    free(e);
}

/* A round continent (radius 20 degrees, over the (+X, +Y, +Z) cube corner) whose shelf
 * (-100 m) is 8 degrees wide on one side of it and 2 on the other, then deep ocean; a
 * lake (-50 m) inside it never reaches deep water. The widths come out as the two
 * shelves (the 8-neighbour hop count reads a radial path between 1/sqrt(2) and 1 of its
 * length), and the lake's shore is counted apart, not as shelf. */
typedef struct shelf_world {
    double c[3], side[3];
} shelf_world;

static void shelf_texel(const double d[3], const void *ctx, float *h, float rgb[3]) {
    const shelf_world *w = ctx;
    double r = acos(fmin(1, dot(d, w->c))) / DEG, width = dot(d, w->side) > 0 ? 8 : 2;
    *h = r < 2 ? -50 : r < 20 ? 300 : r < 20 + width ? -100 : -3000;
    rgb[0] = 0.3f, rgb[1] = 0.35f, rgb[2] = 0.2f;
}

static void test_shelf_width(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 256, pg_ellipsoid_sphere(), PG_CUBE_EQUIANGULAR);
    shelf_world w = {{1, 1, 1}, {1, -1, 0}};
    unit(w.c);
    paint(&p, shelf_texel, &w);
    pg_earthlike *e = compute_new(&p);
    const double km_per_deg = PG_ELLIPSOID_SPHERE_RADIUS_M * DEG / 1000;
    double narrow = 2 * km_per_deg, wide = 8 * km_per_deg;
    assert_true(e->shelf_closed_texels > 0);
    assert_true(e->shelf_coast_texels > 4 * e->shelf_closed_texels);
    printf("shelf widths p10 %.0f, p50 %.0f, p90 %.0f km (shelves %.0f and %.0f km)\n",
           e->shelf_width_p10_km, e->shelf_width_p50_km, e->shelf_width_p90_km, narrow, wide);
    assert_true(e->shelf_width_p10_km > 0.65 * narrow && e->shelf_width_p10_km < 1.15 * narrow);
    assert_true(e->shelf_width_p90_km > 0.65 * wide && e->shelf_width_p90_km < 1.15 * wide);
    /* no shelf at all: every coast texel is one texel (about 36 km here) from deep water */
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < p.n * p.n; i++)
            if (p.height[f][i] == -100) p.height[f][i] = -3000;
    free(e);
    e = compute_new(&p);
    /* the mean texel width: the sphere's area over the texel count, square-rooted */
    double texel = PG_ELLIPSOID_SPHERE_RADIUS_M / 1000 * sqrt(4 * M_PI / 6) / 256;
    printf("without the shelf: p10 %.1f, p90 %.1f km (texel %.1f km)\n", e->shelf_width_p10_km,
           e->shelf_width_p90_km, texel);
    assert_true(e->shelf_width_p10_km > 0.75 * texel && e->shelf_width_p90_km < 1.25 * texel);
    free(e);
    pg_planet_free(&p);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_areas_sum_to_the_ellipsoid),
        cmocka_unit_test(test_geodetic_latitude),
        cmocka_unit_test(test_one_cap),
        cmocka_unit_test(test_seam_and_corner),
        cmocka_unit_test(test_thresholds_and_share),
        cmocka_unit_test(test_rank_size_slope),
        cmocka_unit_test(test_hypsometry),
        cmocka_unit_test(test_quantiles_brute_force),
        cmocka_unit_test(test_zonal),
        cmocka_unit_test(test_albedo_rounding),
        cmocka_unit_test(test_thread_count_independent),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_shelf_width),
        cmocka_unit_test(test_novelty_real_exemplar),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
