/* test_inspect_copy.c - copy detection and face seam coherence from the coordinate map
 * (pg_inspect_copy.h) on maps with known answers, and end to end on planets that
 * `planetgen generate` writes.
 *
 * Known answers, on a planet of 6 x 64^2 and an exemplar cube of the same size:
 *  - the identity map (Earth copied texel for texel): every source is its own texel,
 *    so near = 1, while the shuffled baseline only scores where a random longitude
 *    lands within 500 km (a few per cent); every adjacent pair is a pair of
 *    neighbouring exemplar texels, across the face seams too: coherence 1 and 1;
 *  - the same map turned by 180 degrees of longitude: sources are half a world away
 *    except within 2.25 degrees of the poles: fraction ~0;
 *  - hashed sources: two random texels are neighbours with chance 8 / (6 E^2): ~0;
 *  - the identity with face +Y's map turned a quarter about the face centre: inside
 *    faces adjacent texels still take adjacent sources (a rotation keeps adjacency),
 *    but the four seams of +Y now join texels whose sources lie on different edges:
 *    8 of 12 seams coherent, a ratio near 2/3. */
#include "pg_test.h"

#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_inspect_copy.h"
#include "planetgen/pg_synth.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N 64

static void make_planet(pg_planet *p, int n) {
    pg_error err = {0};
    assert_int_equal(pg_planet_alloc(p, PG_CUBE_EQUIANGULAR, 1, n, pg_ellipsoid_sphere(), &err),
                     PG_OK);
    p->seed = 11;
}

static void identity(pg_planet *p, int e) {
    pg_error err = {0};
    assert_int_equal(pg_planet_source_identity(p, e, PG_CUBE_EQUIANGULAR, &err), PG_OK);
}

static void copy_stat(const pg_planet *p, pg_inspect_copy_stat *c) {
    pg_error err = {0};
    assert_int_equal(pg_inspect_copy_fraction(p, c, &err), PG_OK);
}

static void coherence_stat(const pg_planet *p, pg_inspect_coherence_stat *c) {
    pg_error err = {0};
    assert_int_equal(pg_inspect_copy_coherence(p, c, &err), PG_OK);
}

/* Both measures of p, printed. */
static void measure(const pg_planet *p, const char *what, pg_inspect_copy_stat *c,
                    pg_inspect_coherence_stat *h) {
    copy_stat(p, c);
    coherence_stat(p, h);
    print_message("%-22s near %.4f shuffled %.4f fraction %.4f | coherence seam %.4f interior "
                  "%.4f ratio %.4f\n",
                  what, c->near_share, c->shuffled_share, c->earth_copy_fraction, h->seam_share,
                  h->interior_share, h->face_seam_coherence);
}

static void test_identity(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, N);
    identity(&p, N);
    pg_inspect_copy_stat c;
    pg_inspect_coherence_stat h;
    measure(&p, "identity", &c, &h);
    assert_true(c.texels == 6u * N * N);
    assert_float_equal(c.near_share, 1.0, 0);
    assert_true(c.shuffled_share > 0.005 && c.shuffled_share < 0.1);
    assert_true(c.earth_copy_fraction >= 0.5);
    assert_true(h.seam_pairs == 12u * N);
    assert_true(h.interior_pairs == 12u * N * (N - 1));
    assert_float_equal(h.interior_share, 1.0, 0);
    assert_float_equal(h.seam_share, 1.0, 0);
    assert_float_equal(h.face_seam_coherence, 1.0, 1e-12);
    pg_planet_free(&p);
}

/* Every texel takes the exemplar texel nearest its own direction turned by 180
 * degrees about the polar axis. */
/* A magnified copy: the identity map of an exemplar cube half as fine, so every 2 x 2
 * block of texels shares one source. Pairs inside a block say nothing and are left out;
 * counted as incoherent they once halved the interior share and doubled the ratio. */
static void test_magnified_identity(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, N);
    identity(&p, N / 2);
    pg_inspect_coherence_stat h;
    coherence_stat(&p, &h);
    print_message("magnified identity: seam %.3f inside %.3f ratio %.3f\n", h.seam_share,
                  h.interior_share, h.face_seam_coherence);
    assert_true(h.interior_pairs == 12u * N * (N / 2 - 1));
    assert_true(h.interior_share > 0.99 && h.seam_share > 0.99);
    assert_true(fabs(h.face_seam_coherence - 1) < 0.02);
    pg_planet_free(&p);
}

static void test_antipodal_longitude(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, N);
    identity(&p, N);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                double d[3], u, v;
                int ef;
                pg_cube_to_dir(p.projection, f, (2.0 * x + 1) / N - 1, (2.0 * y + 1) / N - 1, d);
                d[0] = -d[0], d[1] = -d[1];
                pg_cube_from_dir(p.source.projection, d, &ef, &u, &v);
                int eu = (int)((u + 1) * 0.5 * N), ev = (int)((v + 1) * 0.5 * N);
                eu = eu < 0 ? 0 : (eu >= N ? N - 1 : eu);
                ev = ev < 0 ? 0 : (ev >= N ? N - 1 : ev);
                p.source.coords[f][y * N + x] = pg_synth_pack(ef, eu, ev);
            }
    pg_inspect_copy_stat c;
    pg_inspect_coherence_stat h;
    measure(&p, "180 deg of longitude", &c, &h);
    assert_true(c.near_share < 0.01); /* only the polar caps */
    assert_true(fabs(c.earth_copy_fraction) < 0.05);
    /* a rigid rotation of the whole map keeps the patches whole */
    assert_true(h.interior_share > 0.99 && h.face_seam_coherence > 0.95);
    pg_planet_free(&p);
}

/* Both shares against a direct computation (haversine on the mean radius (2a + b)/3,
 * directions from pg_cube_to_dir, the baseline's longitude re-derived from the same
 * hash) on a map whose sources lie 5 degrees of longitude east of their texel: near at
 * low latitudes, near at high ones. Planet and exemplar projections differ, so both
 * of the measure's direction paths (tabulated and not) are read. */
static double haversine(double lat1, double lon1, double lat2, double lon2) {
    double s1 = sin((lat2 - lat1) / 2), s2 = sin((lon2 - lon1) / 2);
    return 2 * asin(sqrt(s1 * s1 + cos(lat1) * cos(lat2) * s2 * s2));
}

static void check_known_distances(pg_cube_projection planet_proj, pg_cube_projection ex_proj,
                                  int e) {
    pg_planet p;
    pg_error err = {0};
    assert_int_equal(pg_planet_alloc(&p, planet_proj, 1, N, pg_ellipsoid_wgs84(), &err), PG_OK);
    p.seed = 4;
    assert_int_equal(pg_planet_source_alloc(&p, e, ex_proj, &err), PG_OK);
    const double R = (2 * p.ellipsoid.a + p.ellipsoid.a * (1 - p.ellipsoid.f)) / 3;
    const double shift = 5 * M_PI / 180, r = 500e3 / R;
    long near = 0, shuffled = 0;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                double d[3], s[3], u, v;
                int ef;
                pg_cube_to_dir(planet_proj, f, (2.0 * x + 1) / N - 1, (2.0 * y + 1) / N - 1, d);
                double lat = asin(d[2]), lon = atan2(d[1], d[0]);
                double t[3] = {cos(lat) * cos(lon + shift), cos(lat) * sin(lon + shift), d[2]};
                pg_cube_from_dir(ex_proj, t, &ef, &u, &v);
                int eu = (int)((u + 1) * 0.5 * e), ev = (int)((v + 1) * 0.5 * e);
                eu = eu >= e ? e - 1 : eu, ev = ev >= e ? e - 1 : ev;
                p.source.coords[f][y * N + x] = pg_synth_pack(ef, eu, ev);
                pg_planet_source_dir(&p, f, x, y, s);
                double slat = asin(s[2] / sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]));
                near += haversine(lat, lon, slat, atan2(s[1], s[0])) <= r;
                double hl =
                    2 * M_PI * (pg_synth_hash(4, 0, f, x, y, 0x636f7079) / 4294967296.0) - M_PI;
                shuffled += haversine(lat, lon, slat, hl) <= r;
            }
    pg_inspect_copy_stat c;
    copy_stat(&p, &c);
    print_message("5 deg east (%s on %s): near %.4f (direct %.4f), shuffled %.4f (direct %.4f)\n",
                  pg_cube_projection_name(planet_proj), pg_cube_projection_name(ex_proj),
                  c.near_share, near / (6.0 * N * N), c.shuffled_share, shuffled / (6.0 * N * N));
    /* a texel sitting on the 500 km circle may fall either side of it by rounding */
    assert_float_equal(c.near_share, near / (6.0 * N * N), 2.0 / (6 * N * N));
    assert_float_equal(c.shuffled_share, shuffled / (6.0 * N * N), 2.0 / (6 * N * N));
    assert_true(c.near_share > 0.1 && c.near_share < 0.9); /* the radius cuts the map */
    pg_planet_free(&p);
}

static void test_known_distances(void **s) {
    (void)s;
    check_known_distances(PG_CUBE_EQUIANGULAR, PG_CUBE_EQUIANGULAR, 3 * N);
    check_known_distances(PG_CUBE_EQUALAREA, PG_CUBE_GNOMONIC, 2 * N);
}

static void hashed(pg_planet *p, int e) {
    identity(p, e);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < p->n * p->n; i++) {
            uint32_t h = pg_synth_hash(3, 0, f, (long)i, 0, 7);
            p->source.coords[f][i] = pg_synth_pack((int)(h % 6), (int)((h >> 3) % (uint32_t)e),
                                                   (int)((h >> 16) % (uint32_t)e));
        }
}

static void test_random_sources(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, N);
    hashed(&p, N);
    pg_inspect_copy_stat c;
    pg_inspect_coherence_stat h;
    measure(&p, "hashed sources", &c, &h);
    assert_true(h.interior_share < 0.005);
    assert_true(h.seam_share < 0.01);
    /* random places: near the baseline, not Earth in place */
    assert_true(fabs(c.earth_copy_fraction) < 0.05);
    pg_planet_free(&p);
}

/* Face +Y's texel (x, y) takes the source of the texel a quarter turn away about the
 * face centre, (n-1-y, x). */
static void test_face_turned(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, N);
    identity(&p, N);
    uint32_t *old = malloc(sizeof(uint32_t) * N * N), *c = p.source.coords[PG_CUBE_FACE_PY];
    assert_non_null(old);
    memcpy(old, c, sizeof(uint32_t) * N * N);
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++)
            c[y * N + x] = old[x * N + (N - 1 - y)];
    free(old);
    pg_inspect_copy_stat cs;
    pg_inspect_coherence_stat h;
    measure(&p, "face +Y turned 90 deg", &cs, &h);
    assert_float_equal(h.interior_share, 1.0, 0);
    assert_true(h.seam_share > 0.6 && h.seam_share < 0.72); /* 8 of 12 seams */
    assert_true(h.face_seam_coherence < 0.75);
    pg_planet_free(&p);
}

static void test_without_map(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, 16);
    pg_inspect_copy_stat c;
    pg_inspect_coherence_stat h;
    copy_stat(&p, &c);
    coherence_stat(&p, &h);
    assert_true(isnan(c.earth_copy_fraction) && isnan(c.near_share) && c.texels == 0);
    assert_true(isnan(h.face_seam_coherence) && isnan(h.seam_share) && h.seam_pairs == 0);
    /* a map pointing outside its exemplar cube is refused, not read */
    identity(&p, 16);
    p.source.coords[2][5] = pg_synth_pack(6, 0, 0);
    pg_error err = {0};
    assert_int_equal(pg_inspect_copy_fraction(&p, &c, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "coordinate map"));
    pg_planet_free(&p);
}

/* One and two threads give identical figures (integer counts). */
static void test_thread_count(void **s) {
    (void)s;
    pg_planet p;
    make_planet(&p, N);
    hashed(&p, 4 * N);
    for (int64_t i = 0; i < N * N / 2; i++) /* half of face +X copied in place */
        p.source.coords[0][i] = pg_synth_pack(0, (int)(4 * (i % N)), (int)(4 * (i / N)));
    pg_inspect_copy_stat c1, c2;
    pg_inspect_coherence_stat h1, h2;
    int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    copy_stat(&p, &c1);
    coherence_stat(&p, &h1);
    omp_set_num_threads(2);
    copy_stat(&p, &c2);
    coherence_stat(&p, &h2);
    omp_set_num_threads(threads);
    assert_memory_equal(&c1, &c2, sizeof c1);
    assert_memory_equal(&h1, &h2, sizeof h1);
    pg_planet_free(&p);
}

/* ---- end to end: planetgen generate writes the map ----
 * The map must exist, load, stay in range and tell the truth: a texel's albedo is
 * Blue Marble's at its source's direction (nearest pixel; a few hundredths off from
 * resampling), not at its own direction (a tenth or more off on a planet that is not
 * a copy). Layout earth copies Earth in place only where a planet texel is an exemplar
 * texel, N = E: a 6 x 128^2 planet is synthesized from the exemplar cube of 512 (the
 * smallest), at the exemplar's ground scale, so it is a quarter-size Earth whose
 * sources cannot sit at their own directions (earth_copy_fraction 0.01 measured).
 * The in-place check therefore runs at N = E = 512 (one pass, no pit removal, which
 * changes heights only, to keep it short); layout free is measured at 128. */

static void generate(const char *dir, const char *opts) {
    static char out[65536], err[65536];
    char args[2048];
    snprintf(args, sizeof args, "generate %s --no-glb --cache-dir %s/synth-cache -o %s", opts,
             getenv("PG_BUILD_DIR"), dir);
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("exit %d: %s", rc, err);
}

static void nearest_pixel(const pg_exemplar *ex, const double d[3], const float **rgb) {
    double lat = asin(d[2] / sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])) * 180 / M_PI;
    double lon = atan2(d[1], d[0]) * 180 / M_PI;
    int i = (int)((lon + 180) / 360 * ex->width), j = (int)((90 - lat) / 180 * ex->height);
    i = i >= ex->width ? ex->width - 1 : i, j = j >= ex->height ? ex->height - 1 : j;
    *rgb = ex->albedo + 3 * ((size_t)j * ex->width + i);
}

/* Mean |albedo - Blue Marble| at the sources' directions (out[0]) and at the texels'
 * own directions (out[1]). */
static void albedo_truth(const pg_planet *p, const pg_exemplar *ex, double out[2]) {
    const int64_t n = p->n;
    double sum[2] = {0, 0};
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                double d[3], s[3];
                const float *a = p->albedo[f] + 3 * (y * n + x), *bs, *bo;
                pg_cube_to_dir(p->projection, f, (2.0 * x + 1) / n - 1, (2.0 * y + 1) / n - 1, d);
                pg_planet_source_dir(p, f, x, y, s);
                nearest_pixel(ex, s, &bs);
                nearest_pixel(ex, d, &bo);
                for (int c = 0; c < 3; c++) {
                    sum[0] += fabs(a[c] - bs[c]);
                    sum[1] += fabs(a[c] - bo[c]);
                }
            }
    out[0] = sum[0] / (18.0 * n * n);
    out[1] = sum[1] / (18.0 * n * n);
}

/* Generate with opts, load, check the map; the planet's copy fraction. */
static double generated_fraction(const char *tag, const char *opts, const pg_exemplar *ex) {
    char dir[1024], path[1200];
    pg_test_scratch_dir(tag, dir, sizeof dir);
    strcat(dir, "/p");
    generate(dir, opts);
    snprintf(path, sizeof path, "%s/source.exr", dir);
    assert_true(pg_test_file_nonempty(path));
    pg_planet p;
    pg_error err = {0};
    if (pg_planet_load(dir, &p, &err) != PG_OK) fail_msg("%s", err.msg);
    assert_true(pg_planet_has_source(&p));
    assert_int_equal(p.source.face_size, 512); /* the exemplar cube of planets up to 512 */
    assert_int_equal(p.source.projection, PG_CUBE_DEFAULT_PROJECTION);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < p.n * p.n; i++) {
            uint32_t c = p.source.coords[f][i];
            assert_true(pg_synth_face(c) < 6 && pg_synth_u(c) < 512 && pg_synth_v(c) < 512);
            assert_int_equal(pg_synth_orient(c), 0);
        }
    double truth[2];
    albedo_truth(&p, ex, truth);
    pg_inspect_copy_stat c;
    pg_inspect_coherence_stat h;
    print_message("%s: |albedo - Earth| at the source %.4f, at the texel %.4f\n", opts, truth[0],
                  truth[1]);
    measure(&p, tag, &c, &h);
    assert_true(truth[0] < 0.03);
    pg_planet_free(&p);
    return c.earth_copy_fraction;
}

static void test_generate_writes_map(void **s) {
    (void)s;
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    pg_exemplar ex;
    pg_error err = {0};
    assert_int_equal(pg_exemplar_load(&o, &ex, &err), PG_OK);
    double free_layout = generated_fraction(
        "copy_e2e_free", "--tiles 1 --tile-size 128 --seed 3 --layout free", &ex);
    double earth = generated_fraction(
        "copy_e2e_earth", "--tiles 1 --tile-size 512 --seed 3 --layout earth --passes 1 --pits off",
        &ex);
    print_message("earth_copy_fraction: layout earth %.3f (N = 512), layout free %.3f (N = 128)\n",
                  earth, free_layout);
    assert_true(earth >= 0.5);
    pg_exemplar_free(&ex);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_identity),
        cmocka_unit_test(test_known_distances),
        cmocka_unit_test(test_antipodal_longitude),
        cmocka_unit_test(test_magnified_identity),
        cmocka_unit_test(test_random_sources),
        cmocka_unit_test(test_face_turned),
        cmocka_unit_test(test_without_map),
        cmocka_unit_test(test_thread_count),
        cmocka_unit_test(test_generate_writes_map),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
