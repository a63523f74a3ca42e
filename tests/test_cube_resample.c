/* test_cube_resample.c - equirectangular <-> cube resampling: a smooth synthetic
 * field survives the round trip within a stated bound, a checker keeps its edges
 * sharp, the poles are single-valued, latitudes are geodetic on an ellipsoid,
 * results do not depend on the thread count, and Blue Marble reprojected to six
 * faces and back looks right (previews written to the scratch directory). */
#include "pg_test.h"

#include "planetgen/pg_cube.h"
#include "planetgen/pg_image.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PG_PI 3.14159265358979323846

static const double DEG = PG_PI / 180;

/* A smooth function of direction. */
static double smooth(const double d[3]) {
    return 0.5 + 0.25 * d[0] + 0.15 * d[1] * d[2] + 0.1 * sin(3 * d[1]);
}

static float *equirect_of(int w, int h, int kind) {
    float *img = malloc((size_t)w * h * sizeof *img);
    for (int j = 0; j < h; j++) {
        for (int i = 0; i < w; i++) {
            double lat = 90 - (j + 0.5) * 180 / h, lon = -180 + (i + 0.5) * 360 / w;
            double d[3] = {cos(lat * DEG) * cos(lon * DEG), cos(lat * DEG) * sin(lon * DEG),
                           sin(lat * DEG)};
            double v = smooth(d);
            if (kind == 1) v = ((int)floor((lon + 180) / 30) + (int)floor((lat + 90) / 30)) % 2;
            if (kind == 2) v = lat;
            img[(size_t)j * w + i] = (float)v;
        }
    }
    return img;
}

/* Smooth field (range ~0.1..0.9): every cube texel matches f(direction) within
 * 2e-4, and the round trip back to the equirect grid stays within 1e-3. The round
 * trip is dominated by the half-texel bands along seams: bilinear taps across a
 * seam sit where the neighbour face puts them, up to half a texel off the straight
 * grid extension because texel rows bend at seams (see test_cube_halo), which makes
 * the error first-order there (~5e-4 here) instead of second-order (~1e-5). */
static void test_smooth_round_trip(void **state) {
    (void)state;
    const int W = 720, H = 360;
    const int64_t n = 192;
    pg_cube_projection projs[3] = {PG_CUBE_GNOMONIC, PG_CUBE_EQUIANGULAR, PG_CUBE_EQUALAREA};
    float *img = equirect_of(W, H, 0), *back = malloc((size_t)W * H * sizeof *back);
    float *cube = malloc(6 * n * n * sizeof *cube);
    for (int p = 0; p < 3; p++) {
        pg_error err = {0};
        assert_int_equal(pg_cube_from_equirect(projs[p], n, NULL, img, W, H, 1, 1, cube, &err),
                         PG_OK);
        pg_cube_grid g;
        assert_int_equal(pg_cube_grid_init(&g, projs[p], 3, 64, NULL), PG_OK); /* N = 192 */
        double fwd = 0;
        for (int64_t id = 0; id < 6 * n * n; id++) {
            double d[3];
            pg_cube_texel_dir(&g, id, d);
            fwd = fmax(fwd, fabs(cube[id] - smooth(d)));
        }
        assert_int_equal(pg_cube_to_equirect(projs[p], n, NULL, cube, 1, back, W, H, &err), PG_OK);
        double rt = 0;
        for (size_t i = 0; i < (size_t)W * H; i++)
            rt = fmax(rt, fabs(back[i] - img[i]));
        print_message("%-13s smooth field: equirect->cube max error %.2e, round trip %.2e\n",
                      pg_cube_projection_name(projs[p]), fwd, rt);
        assert_true(fwd < 2e-4);
        assert_true(rt < 1e-3);
    }
    free(img), free(back), free(cube);
}

/* Checker of 30-degree cells: after the round trip, large errors only sit within
 * two pixels of a cell edge (away from the poles, where pixels shrink below the
 * texel size in longitude), and the mean error is small. */
static void test_checker_round_trip(void **state) {
    (void)state;
    const int W = 720, H = 360;
    const int64_t n = 256;
    float *img = equirect_of(W, H, 1), *back = malloc((size_t)W * H * sizeof *back);
    float *cube = malloc(6 * n * n * sizeof *cube);
    pg_error err = {0};
    assert_int_equal(
        pg_cube_from_equirect(PG_CUBE_EQUIANGULAR, n, NULL, img, W, H, 1, 2, cube, &err), PG_OK);
    assert_int_equal(pg_cube_to_equirect(PG_CUBE_EQUIANGULAR, n, NULL, cube, 1, back, W, H, &err),
                     PG_OK);
    double sum = 0;
    int bad = 0;
    for (int j = 0; j < H; j++) {
        for (int i = 0; i < W; i++) {
            double e = fabs(back[(size_t)j * W + i] - img[(size_t)j * W + i]);
            sum += e;
            if (e <= 0.25 || j < H / 6 || j >= H - H / 6) continue;
            int di = (i + 1) % 60, dj = (j + 1) % 60; /* 60 px per cell; edges at 0, 60, ... */
            int dist = (int)fmin(fmin(di, 60 - di), fmin(dj, 60 - dj));
            if (dist > 2) bad++;
        }
    }
    print_message("checker: mean round-trip error %.4f, far-from-edge errors > 0.25: %d\n",
                  sum / (W * H), bad);
    assert_int_equal(bad, 0);
    assert_true(sum / (W * H) < 0.025);
    free(img), free(back), free(cube);
}

/* Poles: the image cos(lon) has no single value at a pole. Within the last half
 * pixel the field must go linearly to the polar mean (0): |value| <= 0.71 * colat /
 * 0.25 degrees (0.25 = half a pixel), i.e. continuous at the pole, where clamping
 * to the first row would give +-0.71 at any distance. */
static void test_poles(void **state) {
    (void)state;
    const int W = 720, H = 360;
    float *img = malloc((size_t)W * H * sizeof *img);
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++)
            img[(size_t)j * W + i] = (float)cos((-180 + (i + 0.5) / 2) * DEG);
    for (int64_t n = 256; n <= 1024; n *= 4) {
        float *cube = malloc(6 * n * n * sizeof *cube);
        assert_int_equal(
            pg_cube_from_equirect(PG_CUBE_EQUIANGULAR, n, NULL, img, W, H, 1, 1, cube, NULL),
            PG_OK);
        pg_cube_grid g;
        assert_int_equal(pg_cube_grid_init(&g, PG_CUBE_EQUIANGULAR, 1, (int)n, NULL), PG_OK);
        for (int f = 4; f < 6; f++) {
            for (int k = 0; k < 4; k++) {
                int64_t x = n / 2 - 1 + (k & 1), y = n / 2 - 1 + (k >> 1), id = (f * n + y) * n + x;
                double d[3];
                pg_cube_texel_dir(&g, id, d);
                double colat = acos(fabs(d[2])) / DEG;
                assert_true(fabs(cube[id]) <= 0.71 * fmin(1, colat / 0.25) + 1e-3);
                if (n == 1024) assert_true(fabs(cube[id]) < 0.2);
            }
        }
        free(cube);
    }
    free(img);
}

/* On WGS84 the image's latitudes are geodetic: the cube texel's value must be the
 * geodetic latitude of its ray point, not its geocentric angle (0.19 degrees apart
 * at 45 degrees). */
static void test_geodetic_latitude(void **state) {
    (void)state;
    const int W = 1440, H = 720;
    const int64_t n = 64;
    float *img = equirect_of(W, H, 2), *cube = malloc(6 * n * n * sizeof *cube);
    pg_ellipsoid e = pg_ellipsoid_wgs84();
    assert_int_equal(pg_cube_from_equirect(PG_CUBE_EQUIANGULAR, n, &e, img, W, H, 1, 1, cube, NULL),
                     PG_OK);
    pg_cube_grid g;
    pg_cube_grid_init(&g, PG_CUBE_EQUIANGULAR, 1, (int)n, NULL);
    double worst = 0, sep = 0;
    for (int64_t id = 0; id < 4 * n * n; id++) { /* equatorial faces: no pole blending */
        double d[3], lat, lon;
        pg_cube_texel_dir(&g, id, d);
        pg_geo_dir_to_latlon(&e, d, &lat, &lon);
        worst = fmax(worst, fabs(cube[id] - lat));
        sep = fmax(sep, fabs(lat - asin(d[2]) / DEG));
    }
    assert_true(worst < 1e-3);
    assert_true(sep > 0.15);
    free(img), free(cube);
}

static void test_threads_and_bad_input(void **state) {
    (void)state;
    const int W = 360, H = 180;
    const int64_t n = 64;
    float *img = equirect_of(W, H, 0), *a = malloc(6 * n * n * sizeof *a),
          *b = malloc(6 * n * n * sizeof *b);
    omp_set_num_threads(1);
    pg_cube_from_equirect(PG_CUBE_EQUALAREA, n, NULL, img, W, H, 1, 3, a, NULL);
    omp_set_num_threads(2);
    pg_cube_from_equirect(PG_CUBE_EQUALAREA, n, NULL, img, W, H, 1, 3, b, NULL);
    assert_memory_equal(a, b, 6 * n * n * sizeof *a);
    pg_error err = {0};
    assert_int_equal(pg_cube_from_equirect(PG_CUBE_EQUALAREA, n, NULL, img, 1, H, 1, 1, a, &err),
                     PG_ERR_BADINPUT);
    free(img), free(a), free(b);
}

/* The six faces as a cross: -Y +X +Y -X along the equator, +Z above +X, -Z below,
 * each cell read through pg_cube_wrap from +X's (or +Y's) unfolded frame. */
static void write_cross(const float *cube, int64_t n, const char *path) {
    pg_cube_grid g;
    pg_cube_grid_init(&g, PG_CUBE_EQUIANGULAR, 1, (int)n, NULL);
    pg_image im;
    assert_int_equal(pg_image_alloc(&im, (int)(4 * n), (int)(3 * n), 3, NULL), PG_OK);
    for (int64_t py = 0; py < 3 * n; py++) {
        for (int64_t px = 0; px < 4 * n; px++) {
            int64_t cx = px / n, cy = py / n, X = px - n, Y = 2 * n - 1 - py;
            if (cy != 1 && cx != 1) continue;
            int face = PG_CUBE_FACE_PX;
            if (cx == 3) face = PG_CUBE_FACE_PY, X -= n;
            int64_t id = pg_cube_wrap(&g, face, X, Y, NULL);
            memcpy(im.data + (py * 4 * n + px) * 3, cube + id * 3, 3 * sizeof(float));
        }
    }
    assert_int_equal(pg_image_write_png(path, &im, 8, NULL), PG_OK);
    pg_image_free(&im);
}

static void test_blue_marble(void **state) {
    (void)state;
    const char *bm = "/usr/share/marble/data/maps/earth/bluemarble/bluemarble.jpg";
    pg_image src;
    pg_error err = {0};
    assert_int_equal(pg_image_read(bm, 0, &src, &err), PG_OK);
    size_t np = (size_t)src.width * src.height * src.channels;
    for (size_t i = 0; i < np; i++)
        src.data[i] *= src.unit_scale;
    const int64_t n = 512;
    float *cube = malloc(6 * n * n * 3 * sizeof *cube);
    pg_image back;
    assert_int_equal(pg_image_alloc(&back, src.width, src.height, 3, NULL), PG_OK);
    assert_int_equal(pg_cube_from_equirect(PG_CUBE_EQUIANGULAR, n, NULL, src.data, src.width,
                                           src.height, 3, 2, cube, &err),
                     PG_OK);
    assert_int_equal(pg_cube_to_equirect(PG_CUBE_EQUIANGULAR, n, NULL, cube, 3, back.data,
                                         back.width, back.height, &err),
                     PG_OK);
    /* error statistics, weighted by pixel area (cos lat) */
    double sum = 0, wsum = 0;
    for (int j = 0; j < src.height; j++) {
        double w = cos((90 - (j + 0.5) * 180.0 / src.height) * DEG);
        for (int i = 0; i < src.width * 3; i++) {
            size_t k = (size_t)j * src.width * 3 + i;
            sum += w * fabs(back.data[k] - src.data[k]);
            wsum += w;
        }
    }
    char dir[1024], path[1200];
    pg_test_scratch_dir("cube_resample", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/bluemarble_cube_cross.png", dir);
    write_cross(cube, n, path);
    snprintf(path, sizeof path, "%s/bluemarble_roundtrip.png", dir);
    assert_int_equal(pg_image_write_png(path, &back, 8, NULL), PG_OK);
    print_message("Blue Marble %dx%d -> 6x%lldx%lld -> back: mean |error| %.4f (0..1), "
                  "previews in %s\n",
                  src.width, src.height, (long long)n, (long long)n, sum / wsum, dir);
    /* 2700 px round the equator vs 4*512 texels: some blur, no misplacement */
    assert_true(sum / wsum < 0.03);
    /* geography in the right place: Sahara (23N 10E) bright, Pacific (0, 150W) dark */
    double d[3];
    float v[3];
    pg_geo_latlon_to_dir(&(pg_ellipsoid){PG_ELLIPSOID_SPHERE_RADIUS_M, 0}, 23, 10, d);
    pg_cube_sample(PG_CUBE_EQUIANGULAR, n, cube, 3, d, v);
    assert_true(v[0] > 0.5);
    pg_geo_latlon_to_dir(&(pg_ellipsoid){PG_ELLIPSOID_SPHERE_RADIUS_M, 0}, 0, -150, d);
    pg_cube_sample(PG_CUBE_EQUIANGULAR, n, cube, 3, d, v);
    assert_true(v[0] < 0.15 && v[2] > v[0]);
    free(cube);
    pg_image_free(&back);
    pg_image_free(&src);
}

/* pg_cube_sample_grid with a grid built once gives pg_cube_sample's values at
 * directions all over the sphere (cube vertices and seams included), for a face size
 * that is not a power of two, as the previews use. */
static void test_sample_with_grid(void **state) {
    (void)state;
    const int64_t n = 96;
    float *cube = malloc((size_t)6 * n * n * 2 * sizeof *cube);
    for (size_t i = 0; i < (size_t)6 * n * n * 2; i++)
        cube[i] = (float)((i * 2654435761u) % 1000) / 1000.0f;
    pg_cube_grid g;
    pg_error err = {0};
    assert_int_equal(pg_cube_grid_init(&g, PG_CUBE_EQUIANGULAR, (int)n, 1, &err), PG_OK);
    int differ = 0;
    for (int k = 0; k < 20000; k++) {
        double d[3] = {sin(k * 0.7) * cos(k * 1.3), sin(k * 0.7) * sin(k * 1.3), cos(k * 0.7)};
        if (k < 8) d[0] = k & 1 ? 1 : -1, d[1] = k & 2 ? 1 : -1, d[2] = k & 4 ? 1 : -1;
        float a[2], b[2];
        pg_cube_sample(PG_CUBE_EQUIANGULAR, n, cube, 2, d, a);
        pg_cube_sample_grid(&g, cube, 2, d, b);
        differ += memcmp(a, b, sizeof a) != 0;
    }
    assert_int_equal(differ, 0);
    free(cube);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_smooth_round_trip),
        cmocka_unit_test(test_checker_round_trip),
        cmocka_unit_test(test_poles),
        cmocka_unit_test(test_geodetic_latitude),
        cmocka_unit_test(test_threads_and_bad_input),
        cmocka_unit_test(test_blue_marble),
        cmocka_unit_test(test_sample_with_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
