/* test_plates.c - the plate model (pg_plates.h): the same seed gives byte-identical
 * worlds with 1 and 2 threads and another seed another world; plates are non-empty,
 * tile the sphere and none covers half of it; all three boundary kinds occur, and two
 * hemispheres with known Euler poles are classified as theory says; sea level yields
 * the requested land share; over seeds 1..8 the macro structure is Earth-like
 * (landmasses, mountain belts on convergent boundaries, ocean and land mean heights).
 * The warped detail (pg_plates_detail) moves directions by about a source texel, no
 * more than three, the same way for any thread count and seamlessly across faces.
 * Every direction lies within the grid's texel reach of the centre of the texel found
 * for it, which the gather's plate caps rely on to skip lookups; with the caps off, the
 * same worlds come out byte for byte.
 * Renders the preview maps into the scratch directory and prints the timing. */
#include "pg_test.h"

#include "pg_plates_internal.h"
#include "planetgen/pg_plates.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PG_PI 3.14159265358979323846

static void gen(const pg_plates_params *p, pg_plates_world *w) {
    pg_error err = {0};
    pg_plates_world_init(w);
    pg_status st = pg_plates_generate(p, w, &err);
    if (st != PG_OK) print_message("%s\n", err.msg);
    assert_int_equal(st, PG_OK);
}

static int64_t count(const pg_plates_world *w) {
    return 6 * w->n * w->n;
}

static int same_world(const pg_plates_world *a, const pg_plates_world *b) {
    size_t c = (size_t)count(a);
    return a->n == b->n && !memcmp(a->elevation_m, b->elevation_m, c * sizeof(float)) &&
           !memcmp(a->crust, b->crust, c) && !memcmp(a->age_myr, b->age_myr, c * sizeof(float)) &&
           !memcmp(a->plate, b->plate, c) && !memcmp(a->boundary, b->boundary, c) &&
           !memcmp(a->convergent_km, b->convergent_km, c * sizeof(float));
}

static void test_determinism(void **state) {
    (void)state;
    pg_plates_params p;
    pg_plates_params_default(&p);
    p.seed = 7;
    pg_plates_world a, b, c;
    omp_set_num_threads(1);
    double t0 = omp_get_wtime();
    gen(&p, &a);
    double t1 = omp_get_wtime();
    omp_set_num_threads(2);
    gen(&p, &b);
    double t2 = omp_get_wtime();
    print_message("default world (n = 64, 14 plates, %d steps): %.2f s on 1 thread, %.2f s on 2\n",
                  p.steps, t1 - t0, t2 - t1);
    assert_true(same_world(&a, &b));
    p.seed = 8;
    gen(&p, &c);
    assert_false(same_world(&a, &c));
    size_t differ = 0;
    for (int64_t t = 0; t < count(&a); t++)
        differ += a.elevation_m[t] != c.elevation_m[t];
    assert_true(differ > (size_t)count(&a) / 2);
    pg_plates_world_free(&a);
    pg_plates_world_free(&b);
    pg_plates_world_free(&c);
}

static void test_plate_areas(void **state) {
    (void)state;
    pg_plates_params p;
    pg_plates_params_default(&p);
    for (uint64_t seed = 1; seed <= 3; seed++) {
        p.seed = seed;
        pg_plates_world w;
        gen(&p, &w);
        double sum = 0, largest = 0, sphere = 4 * PG_PI * p.radius_km * p.radius_km;
        for (int k = 0; k < w.nplates; k++) {
            assert_true(w.plates[k].area_km2 > 0);
            sum += w.plates[k].area_km2;
            largest = fmax(largest, w.plates[k].area_km2);
        }
        print_message("seed %llu: plate areas sum / sphere - 1 = %.2e, largest plate %.3f\n",
                      (unsigned long long)seed, sum / sphere - 1, largest / sphere);
        assert_true(fabs(sum / sphere - 1) < 1e-6);
        assert_true(largest / sphere <= 0.5);
        pg_plates_world_free(&w);
    }
}

/* Two hemispheres, x > 0 (plate 0) and x < 0 (plate 1), spun about `axis` in opposite
 * senses; `expect` gives the kind theory predicts at a boundary texel's centre. */
static double two_plate_score(const double axis[3], int (*expect)(const double p[3])) {
    const int64_t n = 48;
    const pg_cube_projection proj = PG_CUBE_DEFAULT_PROJECTION;
    static uint8_t plate[6 * 48 * 48], kind[6 * 48 * 48];
    pg_cube_grid g;
    pg_error err = {0};
    assert_int_equal(pg_cube_grid_init(&g, proj, 3, 16, &err), PG_OK);
    for (int64_t t = 0; t < 6 * n * n; t++) {
        double d[3];
        pg_cube_texel_dir(&g, t, d);
        plate[t] = d[0] < 0;
    }
    double omega[2][3];
    for (int i = 0; i < 3; i++) {
        omega[0][i] = axis[i];
        omega[1][i] = -axis[i];
    }
    assert_int_equal(pg_plates_classify(n, proj, plate, 2, (const double(*)[3])omega, kind, &err),
                     PG_OK);
    int64_t total = 0, right = 0;
    for (int64_t t = 0; t < 6 * n * n; t++) {
        if (kind[t] == PG_PLATES_INTERIOR) continue;
        double d[3];
        pg_cube_texel_dir(&g, t, d);
        total++;
        right += kind[t] == expect(d);
    }
    assert_true(total > 4 * n);
    return (double)right / (double)total;
}

/* Spin about +z: plate 0 (x > 0) moves towards -x where y > 0, plate 1 towards +x:
 * they meet (convergent) at y > 0 and part (divergent) at y < 0. */
static int expect_z(const double p[3]) {
    return p[1] > 0 ? PG_PLATES_CONVERGENT : PG_PLATES_DIVERGENT;
}

/* Spin about +x, the boundary circle's own axis: motion along the boundary. */
static int expect_x(const double p[3]) {
    (void)p;
    return PG_PLATES_TRANSFORM;
}

static void test_boundary_kinds(void **state) {
    (void)state;
    double z[3] = {0, 0, 1}, x[3] = {1, 0, 0};
    double sz = two_plate_score(z, expect_z), sx = two_plate_score(x, expect_x);
    print_message("two hemispheres: %.3f right spinning apart about z, %.3f about x\n", sz, sx);
    assert_true(sz >= 0.9);
    assert_true(sx >= 0.9);
    pg_plates_params p;
    pg_plates_params_default(&p);
    pg_plates_world w;
    gen(&p, &w);
    int64_t kinds[4] = {0};
    for (int64_t t = 0; t < count(&w); t++)
        kinds[w.boundary[t] & 3]++;
    print_message("default seed 1: boundary texels convergent %lld, divergent %lld, "
                  "transform %lld\n",
                  (long long)kinds[1], (long long)kinds[2], (long long)kinds[3]);
    assert_true(kinds[1] > 0 && kinds[2] > 0 && kinds[3] > 0);
    pg_plates_world_free(&w);
}

static void test_land_fraction(void **state) {
    (void)state;
    const double want[3] = {0.15, 0.29, 0.5};
    for (int i = 0; i < 3; i++) {
        pg_plates_params p;
        pg_plates_params_default(&p);
        p.land_fraction = want[i];
        pg_plates_world w;
        gen(&p, &w);
        pg_plates_stats s;
        pg_error err = {0};
        assert_int_equal(pg_plates_stats_compute(&w, &s, &err), PG_OK);
        print_message("land_fraction %.2f -> %.4f\n", want[i], s.land_fraction);
        assert_true(fabs(s.land_fraction - want[i]) <= 0.01);
        pg_plates_world_free(&w);
    }
}

/* Area-weighted share of the world's land (ocean) at or below z. */
static double share_below(const pg_plates_world *w, int land, double z) {
    double below = 0, total = 0;
    for (int64_t t = 0; t < count(w); t++)
        if ((w->elevation_m[t] > 0) == land) {
            total += w->area_km2[t];
            if (w->elevation_m[t] <= z) below += w->area_km2[t];
        }
    return below / total;
}

/* The hypsometry match keeps every coast and every texel's rank and gives the target's
 * distribution: a target whose land heights are uniform on 1..5001 m and ocean depths on
 * -8000..-1 m has its quartiles at 1251, 2501, 3751 m (-6000, -4000, -2000 m) after the
 * match, to a texel's area; tables that are too short or not ascending are refused. */
static void test_hypsometry(void **state) {
    (void)state;
    pg_plates_params p;
    pg_plates_params_default(&p);
    pg_plates_world w;
    gen(&p, &w);
    const int64_t c = count(&w);
    float *before = malloc((size_t)c * sizeof *before);
    assert_non_null(before);
    memcpy(before, w.elevation_m, (size_t)c * sizeof *before);
    enum { NQ = 101 };
    float land[NQ], ocean[NQ];
    for (int i = 0; i < NQ; i++) {
        land[i] = 1.0f + 5000.0f * i / (NQ - 1);
        ocean[i] = -8000.0f + 7999.0f * i / (NQ - 1);
    }
    pg_plates_hypsometry h = {NQ, land, ocean, NULL};
    pg_error err = {0};
    assert_int_equal(pg_plates_match_hypsometry(&w, &h, &err), PG_OK);
    int64_t coast = 0, order = 0, pairs = 0;
    for (int64_t t = 0; t < c; t++) {
        coast += (before[t] > 0) != (w.elevation_m[t] > 0);
        int64_t u = (t * 7919 + 13) % c; /* a pseudo-random partner of the same kind */
        if ((before[t] > 0) == (before[u] > 0) && before[t] < before[u]) {
            pairs++;
            order += w.elevation_m[t] > w.elevation_m[u];
        }
    }
    assert_int_equal(coast, 0);
    assert_true(pairs > 1000);
    assert_int_equal(order, 0);
    for (int k = 1; k <= 3; k++) {
        double lq = share_below(&w, 1, 1.0 + 5000.0 * k / 4),
               oq = share_below(&w, 0, -8000.0 + 7999.0 * k / 4);
        print_message("quartile %d: land share below %.3f, ocean %.3f\n", k, lq, oq);
        assert_true(fabs(lq - k / 4.0) < 0.01);
        assert_true(fabs(oq - k / 4.0) < 0.01);
    }
    /* a rank offset lifts its texels above all others: the 5% lowest land (an ice sheet
     * on lowland) with 10 km added ends up at the top of the land */
    float *off = calloc((size_t)c, sizeof *off);
    assert_non_null(off);
    int64_t lifted = 0;
    for (int64_t t = 0; t < c; t++)
        if (w.elevation_m[t] > 0 && w.elevation_m[t] < 1.0 + 5000.0 * 0.05)
            off[t] = 10000, lifted++;
    assert_true(lifted > 100);
    pg_plates_hypsometry ho = {NQ, land, ocean, off};
    assert_int_equal(pg_plates_match_hypsometry(&w, &ho, &err), PG_OK);
    for (int64_t t = 0; t < c; t++)
        if (off[t] > 0) assert_true(w.elevation_m[t] > 1.0 + 5000.0 * 0.94);
    free(off);
    float bad[NQ];
    memcpy(bad, land, sizeof bad);
    bad[50] = 0; /* not ascending */
    pg_plates_hypsometry hb = {NQ, bad, ocean, NULL};
    assert_int_equal(pg_plates_match_hypsometry(&w, &hb, &err), PG_ERR_BADINPUT);
    pg_plates_hypsometry hs = {1, land, ocean, NULL};
    assert_int_equal(pg_plates_match_hypsometry(&w, &hs, &err), PG_ERR_BADINPUT);
    free(before);
    pg_plates_world_free(&w);
}

static void test_macro_structure(void **state) {
    (void)state;
    int shaped = 0, belts = 0, ocean = 0, land = 0;
    for (uint64_t seed = 1; seed <= 8; seed++) {
        pg_plates_params p;
        pg_plates_params_default(&p);
        p.seed = seed;
        pg_plates_world w;
        gen(&p, &w);
        pg_plates_stats s;
        pg_error err = {0};
        assert_int_equal(pg_plates_stats_compute(&w, &s, &err), PG_OK);
        print_message("seed %llu: largest landmass %.3f of land, %d landmasses >= 1e6 km2, "
                      "mountain belt %.3f (high land %.3f of land), ocean depth %.0f m, "
                      "land mean %.0f m, largest plate %.3f\n",
                      (unsigned long long)seed, s.largest_land_share, s.landmasses_1e6km2,
                      s.mountain_belt_share, s.high_land_fraction, s.ocean_mean_depth_m,
                      s.land_mean_m, s.largest_plate_share);
        shaped += s.largest_land_share >= 0.25 && s.landmasses_1e6km2 >= 3;
        belts += s.mountain_belt_share >= 0.7;
        ocean += s.ocean_mean_depth_m >= 3000 && s.ocean_mean_depth_m <= 4500;
        land += s.land_mean_m >= 300 && s.land_mean_m <= 1500;
        pg_plates_world_free(&w);
    }
    print_message("of 8 seeds: %d continental shape, %d mountain belts, %d ocean depth, "
                  "%d land height\n",
                  shaped, belts, ocean, land);
    assert_true(shaped >= 7);
    assert_true(belts == 8);
    assert_true(ocean == 8);
    assert_true(land == 8);
}

static void test_render(void **state) {
    (void)state;
    pg_plates_params p;
    pg_plates_params_default(&p);
    const char *env = getenv("PG_PLATES_SEED");
    if (env) p.seed = strtoull(env, NULL, 10);
    pg_plates_world w;
    gen(&p, &w);
    char dir[1024], path[1200];
    pg_test_scratch_dir("plates", dir, sizeof dir);
    pg_image img = {0};
    pg_error err = {0};
    assert_int_equal(pg_plates_render_plates(&w, 1024, &img, &err), PG_OK);
    snprintf(path, sizeof path, "%s/plates.png", dir);
    assert_int_equal(pg_image_write_png(path, &img, 8, &err), PG_OK);
    assert_true(pg_test_file_nonempty(path));
    pg_image_free(&img);
    assert_int_equal(pg_plates_render_relief(&w, 1024, &img, &err), PG_OK);
    snprintf(path, sizeof path, "%s/relief.png", dir);
    assert_int_equal(pg_image_write_png(path, &img, 8, &err), PG_OK);
    assert_true(pg_test_file_nonempty(path));
    print_message("previews in %s\n", dir);
    pg_image_free(&img);
    pg_plates_world_free(&w);
}

static void test_bad_input(void **state) {
    (void)state;
    pg_plates_params p;
    pg_plates_world w;
    pg_error err = {0};
    pg_plates_world_init(&w);
    pg_plates_params_default(&p);
    p.plates = 1;
    assert_int_equal(pg_plates_generate(&p, &w, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "plates"));
    pg_plates_params_default(&p);
    p.plates = 65;
    pg_error_clear(&err);
    assert_int_equal(pg_plates_generate(&p, &w, &err), PG_ERR_BADINPUT);
    pg_plates_params_default(&p);
    p.land_fraction = 1;
    pg_error_clear(&err);
    assert_int_equal(pg_plates_generate(&p, &w, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "land_fraction"));
    assert_null(w.elevation_m);
}

/* pg_plates_detail on a field whose channels are the texel's own direction: each output
 * texel then holds (nearly) the direction it was moved to, so the warp can be read off. */
static void test_detail_warp(void **state) {
    (void)state;
    const int64_t n = 16, m = 64;
    pg_error err = {0};
    pg_cube_grid src, dst;
    assert_int_equal(pg_cube_grid_init(&src, PG_CUBE_DEFAULT_PROJECTION, 1, (int)n, &err), PG_OK);
    assert_int_equal(pg_cube_grid_init(&dst, PG_CUBE_DEFAULT_PROJECTION, 1, (int)m, &err), PG_OK);
    float *in = malloc((size_t)6 * n * n * 3 * sizeof *in);
    float *a = malloc((size_t)6 * m * m * 3 * sizeof *a),
          *b = malloc((size_t)6 * m * m * 3 * sizeof *b);
    assert_non_null(in);
    assert_non_null(a);
    assert_non_null(b);
    for (int64_t i = 0; i < 6 * n * n; i++) {
        double d[3];
        pg_cube_texel_dir(&src, i, d);
        for (int c = 0; c < 3; c++)
            in[3 * i + c] = (float)d[c];
    }
    omp_set_num_threads(1);
    assert_int_equal(pg_plates_detail(5, PG_CUBE_DEFAULT_PROJECTION, n, in, 3, m, a, &err), PG_OK);
    omp_set_num_threads(2);
    assert_int_equal(pg_plates_detail(5, PG_CUBE_DEFAULT_PROJECTION, n, in, 3, m, b, &err), PG_OK);
    assert_memory_equal(a, b, (size_t)6 * m * m * 3 * sizeof *a);
    const double texel = 3.14159265358979 / 2 / (double)n;
    double sum = 0, worst = 0;
    for (int64_t i = 0; i < 6 * m * m; i++) {
        double p[3], dot = 0, len = 0;
        pg_cube_texel_dir(&dst, i, p);
        for (int c = 0; c < 3; c++) {
            dot += p[c] * a[3 * i + c];
            len += (double)a[3 * i + c] * a[3 * i + c];
        }
        double ang = acos(fmin(1.0, dot / sqrt(len))) / texel;
        sum += ang;
        worst = fmax(worst, ang);
    }
    print_message("detail: mean displacement %.2f source texels, largest %.2f\n",
                  sum / (6.0 * m * m), worst);
    assert_true(sum / (6.0 * m * m) > 0.3); /* it warps */
    assert_true(worst < 3.0);               /* by about a texel, not across the map */
    /* another seed, another warp; bad sizes refused */
    assert_int_equal(pg_plates_detail(6, PG_CUBE_DEFAULT_PROJECTION, n, in, 3, m, b, &err), PG_OK);
    assert_true(memcmp(a, b, (size_t)6 * m * m * 3 * sizeof *a) != 0);
    assert_int_equal(pg_plates_detail(5, PG_CUBE_DEFAULT_PROJECTION, n, in, 3, n - 1, b, &err),
                     PG_ERR_BADINPUT);
    free(in), free(a), free(b);
}

/* The gather's plate caps skip lookups, never results: with them off the same worlds come
 * out byte for byte (and the same plate records: the collisions' slow-downs included). */
static void test_caps_exact(void **state) {
    (void)state;
    pg_plates_params p;
    pg_plates_params_default(&p);
    for (int k = 0; k < 10; k++) {
        p.seed = (uint64_t)(k + 1);
        p.plates = k < 8 ? 14 : (k == 8 ? 4 : 40);
        p.n = k % 2 ? 64 : 48;
        pg_plates_world a, b;
        gen(&p, &a);
        pg_error err = {0};
        pg_plates_world_init(&b);
        assert_int_equal(pg_plates_generate_uncapped(&p, &b, &err), PG_OK);
        assert_true(same_world(&a, &b));
        assert_memory_equal(a.plates, b.plates, sizeof *a.plates * (size_t)a.nplates);
        pg_plates_world_free(&a);
        pg_plates_world_free(&b);
    }
}

/* pg_plates_grid's texel_reach bounds the angle from a direction to the centre of the
 * texel pg_plates_grid_nearest gives for it, in every projection: the gather's plate caps
 * (pg_plates_cortial2019.c) skip a plate only when no alive texel can be that near. The
 * directions are a dense Fibonacci sphere plus points next to every texel corner, where
 * the reach is attained. */
static void test_texel_reach(void **state) {
    (void)state;
    const pg_cube_projection projs[3] = {PG_CUBE_GNOMONIC, PG_CUBE_EQUIANGULAR, PG_CUBE_EQUALAREA};
    for (int pi = 0; pi < 3; pi++)
        for (int64_t n = 16; n <= 64; n *= 4) {
            pg_plates_grid g;
            pg_error err = {0};
            assert_int_equal(pg_plates_grid_init(&g, n, projs[pi], 6371, &err), PG_OK);
            const double texel = PG_PI / 2 / (double)n;
            assert_true(g.texel_reach > 0.5 * texel && g.texel_reach < 3 * texel);
            double worst = 0;
            const int64_t m = 400000;
            for (int64_t i = 0; i < m + 4 * g.count; i++) {
                double d[3];
                if (i < m) { /* Fibonacci sphere */
                    double z = 1 - (2 * (double)i + 1) / (double)m, r = sqrt(1 - z * z);
                    double a = (double)i * PG_PI * (3 - sqrt(5.0));
                    d[0] = r * cos(a), d[1] = r * sin(a), d[2] = z;
                } else { /* 1e-6 of the way from corner k of texel t to its centre */
                    int64_t t = (i - m) / 4;
                    int k = (int)((i - m) % 4), f = (int)(t / (n * n));
                    double u = 2.0 * (double)(t % n + (k & 1)) / (double)n - 1,
                           v = 2.0 * (double)(t / n % n + (k >> 1)) / (double)n - 1, c[3];
                    pg_cube_to_dir(projs[pi], f, u, v, c);
                    double len = 0;
                    for (int j = 0; j < 3; j++)
                        d[j] = c[j] + 1e-6 * (g.dir[3 * t + j] - c[j]), len += d[j] * d[j];
                    for (int j = 0; j < 3; j++)
                        d[j] /= sqrt(len);
                }
                int64_t t = pg_plates_grid_nearest(&g, d);
                worst = fmax(worst, pg_plates_angle(d, g.dir + 3 * t));
            }
            print_message("projection %d, n = %lld: texel reach %.3f texels, farthest direction "
                          "found %.3f\n",
                          pi, (long long)n, g.texel_reach / texel, worst / texel);
            assert_true(worst <= g.texel_reach * (1 + 1e-9));
            assert_true(worst > 0.9 * g.texel_reach); /* the corners come close to it */
            pg_plates_grid_free(&g);
        }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_input),       cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_plate_areas),     cmocka_unit_test(test_boundary_kinds),
        cmocka_unit_test(test_land_fraction),   cmocka_unit_test(test_render),
        cmocka_unit_test(test_macro_structure), cmocka_unit_test(test_hypsometry),
        cmocka_unit_test(test_detail_warp),     cmocka_unit_test(test_texel_reach),
        cmocka_unit_test(test_caps_exact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
