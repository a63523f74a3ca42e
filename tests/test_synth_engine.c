/* test_synth_engine.c - properties of the synthesis engine on synthetic exemplars:
 * exact reproduction with jitter 0 on a toroidal exemplar, bit-identical results for
 * 1 and 2 threads and any tiling, the pass hook (for pit removal) editing V, the cache,
 * upsampling that does not depend on a coordinate's orientation, k-coherence candidates
 * that compose turns, and bad input (constant exemplar, bad size, bad jitter, a toroidal
 * exemplar for a planet). */
#include "pg_test.h"

#include "pg_synth_internal.h"
#include "planetgen/pg_planet_synth.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define TS 64 /* toroidal exemplar size */

/* A periodic procedural terrain: a few integer-frequency waves, so it tiles exactly.
 * Albedo follows height (water blue, land green to brown), plus an independent hue
 * wave, so that neighbourhoods are diverse. */
static void make_torus(float *rgb, float *h, int n) {
    const double tau = 6.283185307179586;
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            double u = (double)x / n, v = (double)y / n;
            double e = sin(tau * (2 * u + v)) + 0.6 * cos(tau * (3 * v - u)) +
                       0.3 * sin(tau * (7 * u + 5 * v)) + 0.15 * cos(tau * (11 * u - 13 * v));
            size_t i = (size_t)y * n + x;
            h[i] = (float)(1500.0 * e);
            double t = 0.5 + 0.25 * e;
            double w = 0.5 + 0.5 * sin(tau * (u - 2 * v));
            rgb[i * 3 + 0] = (float)(e < 0 ? 0.05 : 0.3 + 0.4 * t * w);
            rgb[i * 3 + 1] = (float)(e < 0 ? 0.15 + 0.1 * t : 0.5 - 0.2 * t);
            rgb[i * 3 + 2] = (float)(e < 0 ? 0.4 + 0.2 * t : 0.1 + 0.1 * w);
        }
}

static pg_synth_exemplar *torus_exemplar(int constant) {
    float *rgb = malloc(sizeof(float) * TS * TS * 3), *h = malloc(sizeof(float) * TS * TS);
    make_torus(rgb, h, TS);
    if (constant) {
        for (int i = 0; i < TS * TS * 3; i++)
            rgb[i] = 0.5f;
        for (int i = 0; i < TS * TS; i++)
            h[i] = 100.0f;
    }
    pg_synth_exemplar_params p;
    pg_synth_exemplar_params_default(&p);
    p.face_size = TS;
    p.levels = 3;
    p.min_separation = 0.1;
    pg_synth_exemplar *ex = NULL;
    pg_synth_prep_info info;
    pg_error err = {0};
    pg_status st = pg_synth_prepare_torus(rgb, h, TS, 0.0f, &p, "", &ex, &info, &err);
    free(rgb);
    free(h);
    if (constant) {
        assert_int_equal(st, PG_ERR_BADINPUT);
        assert_non_null(strstr(err.msg, "degenerate"));
        return NULL;
    }
    assert_int_equal(st, PG_OK);
    return ex;
}

/* Jitter 0 on a toroidal exemplar: upsampling alone reproduces the exemplar, and the
 * correction must keep it (every neighbourhood matches exactly). */
static void test_jitter0_reproduces_torus(void **state) {
    (void)state;
    pg_synth_exemplar *ex = torus_exemplar(0);
    pg_synth_params p;
    pg_synth_params_default(&p);
    p.jitter = 0;
    pg_synth_result r;
    pg_error err = {0};
    assert_int_equal(pg_synth_flat(ex, TS, &p, NULL, NULL, &r, &err), PG_OK);
    uint8_t *rgb = malloc(TS * TS * 3);
    float *h = malloc(sizeof(float) * TS * TS);
    pg_synth_render(ex, r.coords, r.offset, TS * TS, rgb, h);
    int wrong = 0;
    for (int y = 0; y < TS; y++)
        for (int x = 0; x < TS; x++) {
            size_t i = (size_t)y * TS + x;
            wrong += r.coords[i] != pg_synth_pack(0, x, y);
            wrong += memcmp(rgb + i * 3, ex->albedo + i * 3, 3) != 0;
            wrong += h[i] != ex->height[i];
        }
    assert_int_equal(wrong, 0);
    free(rgb);
    free(h);
    pg_synth_result_free(&r);
    pg_synth_exemplar_free(ex);
}

static void run(const pg_synth_exemplar *ex, int n, int threads, int tile, pg_synth_result *r) {
    pg_synth_params p;
    pg_synth_params_default(&p);
    p.seed = 42;
    p.tile_size = tile;
    omp_set_num_threads(threads);
    pg_error err = {0};
    assert_int_equal(pg_synth_flat(ex, n, &p, NULL, NULL, r, &err), PG_OK);
    omp_set_num_threads(2);
}

static int same(const pg_synth_result *a, const pg_synth_result *b, int n) {
    size_t c = (size_t)n * n;
    return memcmp(a->coords, b->coords, c * 4) == 0 && memcmp(a->offset, b->offset, c * 4) == 0;
}

static void test_threads_and_tilings_identical(void **state) {
    (void)state;
    pg_synth_exemplar *ex = torus_exemplar(0);
    const int n = 256;
    pg_synth_result ref, r;
    run(ex, n, 1, 0, &ref);
    /* the synthesis must have done something: not the identity, several sources */
    int moved = 0;
    for (int i = 0; i < n * n; i++)
        moved += ref.coords[i] != ref.coords[0];
    assert_true(moved > n * n / 2);
    const int tiles[] = {0, 16, 32, 64, 48};
    for (int t = 0; t < 5; t++)
        for (int th = 1; th <= 2; th++) {
            run(ex, n, th, tiles[t], &r);
            if (!same(&ref, &r, n)) fail_msg("tile %d threads %d differs", tiles[t], th);
            pg_synth_result_free(&r);
        }
    /* another seed gives another result */
    pg_synth_params p;
    pg_synth_params_default(&p);
    p.seed = 43;
    pg_error err = {0};
    assert_int_equal(pg_synth_flat(ex, n, &p, NULL, NULL, &r, &err), PG_OK);
    assert_false(same(&ref, &r, n));
    pg_synth_result_free(&r);
    pg_synth_result_free(&ref);
    pg_synth_exemplar_free(ex);
}

/* The pass hook sees every corrected level and pass, and its edits of V persist to the
 * output the way Gain-pit needs (R' - R added to V is what the next level starts from). */
typedef struct hook_log {
    int calls;
    int finest_calls;
} hook_log;

static void hook(void *user, const pg_synth_exemplar *ex, int scale, int pass, uint32_t *S,
                 float *V, int res, ptrdiff_t stride) {
    (void)ex, (void)pass, (void)S;
    hook_log *log = user;
    log->calls++;
    if (scale != 0) return;
    log->finest_calls++;
    for (int y = 0; y < res; y++)
        for (int x = 0; x < res; x++)
            V[(y + 1) * stride + x + 1] += 1000.0f;
}

static void test_pass_hook_edits_offsets(void **state) {
    (void)state;
    pg_synth_exemplar *ex = torus_exemplar(0);
    pg_synth_params p;
    pg_synth_params_default(&p);
    p.passes = 1; /* the hook runs after the last pass: its edit must survive */
    hook_log log = {0};
    pg_synth_result r, plain;
    pg_error err = {0};
    assert_int_equal(pg_synth_flat(ex, 128, &p, NULL, NULL, &plain, &err), PG_OK);
    assert_int_equal(pg_synth_flat(ex, 128, &p, hook, &log, &r, &err), PG_OK);
    assert_int_equal(log.calls, ex->levels * p.passes);
    assert_int_equal(log.finest_calls, 1);
    int bad = 0;
    for (int i = 0; i < 128 * 128; i++)
        bad += r.coords[i] != plain.coords[i] || r.offset[i] != plain.offset[i] + 1000.0f;
    assert_int_equal(bad, 0);
    pg_synth_result_free(&r);
    pg_synth_result_free(&plain);
    pg_synth_exemplar_free(ex);
}

static void test_constant_exemplar_is_degenerate(void **state) {
    (void)state;
    assert_null(torus_exemplar(1));
}

static void test_bad_parameters(void **state) {
    (void)state;
    pg_synth_exemplar *ex = torus_exemplar(0);
    pg_synth_params p;
    pg_synth_params_default(&p);
    pg_synth_result r;
    pg_error err = {0};
    assert_int_equal(pg_synth_flat(ex, 100, &p, NULL, NULL, &r, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "power of two"));
    pg_error_clear(&err);
    p.jitter = 1.5;
    assert_int_equal(pg_synth_flat(ex, 64, &p, NULL, NULL, &r, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "[0, 1]"));
    /* a planet needs a cube exemplar: the planet synthesis draws and reads faces 0..5,
     * which a toroidal tile (one face) does not have */
    pg_error_clear(&err);
    pg_planet_synth_params pp;
    pg_planet_synth_params_default(&pp);
    pp.tiles = 1;
    pp.tile_size = TS;
    pp.layout = PG_LAYOUT_FREE;
    pg_planet planet;
    assert_int_equal(pg_planet_synth_run(ex, &pp, &planet, NULL, NULL, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "cube"));
    pg_synth_exemplar_free(ex);
}

/* A second preparation with the same inputs loads the cache and gives the same data. */
static void test_cache_roundtrip(void **state) {
    (void)state;
    char dir[512];
    pg_test_scratch_dir("synth-cache-torus", dir, sizeof dir);
    float *rgb = malloc(sizeof(float) * TS * TS * 3), *h = malloc(sizeof(float) * TS * TS);
    make_torus(rgb, h, TS);
    pg_synth_exemplar_params p;
    pg_synth_exemplar_params_default(&p);
    p.face_size = TS;
    p.levels = 3;
    pg_synth_exemplar *a, *b;
    pg_synth_prep_info ia, ib;
    pg_error err = {0};
    assert_int_equal(pg_synth_prepare_torus(rgb, h, TS, 0, &p, dir, &a, &ia, &err), PG_OK);
    assert_false(ia.from_cache);
    assert_int_equal(pg_synth_prepare_torus(rgb, h, TS, 0, &p, dir, &b, &ib, &err), PG_OK);
    assert_true(ib.from_cache);
    size_t n = (size_t)TS * TS;
    for (int s = 0; s < p.levels; s++) {
        assert_memory_equal(a->app[s], b->app[s], n * PG_SYNTH_MAX_DIMS * 2);
        assert_memory_equal(a->kcoh[s], b->kcoh[s], n * 4);
    }
    assert_memory_equal(a->height, b->height, n * 4);
    assert_memory_equal(a->albedo, b->albedo, n * 3);
    assert_memory_equal(a->pca_basis, b->pca_basis, sizeof a->pca_basis);
    assert_memory_equal(a->pca_mean, b->pca_mean, sizeof a->pca_mean);
    assert_memory_equal(a->app_scale, b->app_scale, sizeof a->app_scale);
    /* the hit maps the file: its arrays are not copies */
    assert_null(a->map);
    assert_non_null(b->map);
    assert_true((const char *)b->app[0] >= (const char *)b->map &&
                (const char *)b->app[0] < (const char *)b->map + b->map_bytes);
    assert_int_equal((uintptr_t)b->app[0] % 64, 0);
    /* the index from a source fingerprint: a miss until remembered, then the same file */
    pg_synth_exemplar *d = NULL;
    pg_synth_prep_info id;
    assert_int_equal(pg_synth_lookup_exemplar(42, &p, dir, &d, &id, &err), PG_OK);
    assert_null(d);
    pg_synth_remember_sources(42, &p, dir, a);
    assert_int_equal(pg_synth_lookup_exemplar(41, &p, dir, &d, &id, &err), PG_OK);
    assert_null(d);
    assert_int_equal(pg_synth_lookup_exemplar(42, &p, dir, &d, &id, &err), PG_OK);
    assert_non_null(d);
    assert_true(id.from_cache);
    assert_int_equal(d->key, a->key);
    assert_memory_equal(a->kcoh[1], d->kcoh[1], n * 4);
    pg_synth_exemplar_free(d);
    /* a truncated cache file is a miss, never a crash */
    assert_int_equal(truncate(ib.cache_path, 4096), 0);
    assert_int_equal(pg_synth_lookup_exemplar(42, &p, dir, &d, &id, &err), PG_OK);
    assert_null(d);
    /* a changed input misses the cache */
    h[5] += 1;
    pg_synth_exemplar *c;
    pg_synth_prep_info ic;
    assert_int_equal(pg_synth_prepare_torus(rgb, h, TS, 0, &p, dir, &c, &ic, &err), PG_OK);
    assert_false(ic.from_cache);
    pg_synth_exemplar_free(a);
    pg_synth_exemplar_free(b);
    pg_synth_exemplar_free(c);
    free(rgb);
    free(h);
}

/* k-coherence entries are far from their texel and closer in appearance than average. */
static void test_kcoherence_entries(void **state) {
    (void)state;
    pg_synth_exemplar *ex = torus_exemplar(0);
    const int sep = (int)(0.1 * TS + 0.999);
    double d_k = 0, d_rand = 0;
    for (int t = 0; t < TS * TS; t++) {
        uint32_t q = ex->kcoh[0][t];
        int du = abs(pg_synth_u(q) - t % TS), dv = abs(pg_synth_v(q) - t / TS);
        if (du > TS / 2) du = TS - du;
        if (dv > TS / 2) dv = TS - dv;
        assert_true(du * du + dv * dv >= sep * sep);
        size_t r = (size_t)(t * 7919 + 13) % (TS * TS);
        for (int i = 0; i < PG_SYNTH_MAX_DIMS; i++) {
            double a = ex->app[0][t * 8 + i], b = ex->app[0][pg_synth_texel(ex, q) * 8 + i];
            double c = ex->app[0][r * 8 + i];
            d_k += (a - b) * (a - b);
            d_rand += (a - c) * (a - c);
        }
    }
    assert_true(d_k < 0.2 * d_rand);
    pg_synth_exemplar_free(ex);
}

static void test_orientation(void **state) {
    (void)state;
    for (int o = 0; o < 8; o++) {
        int x = 3, y = 1;
        pg_synth_orient_apply(o, &x, &y);
        assert_int_equal(x * x + y * y, 10); /* an isometry */
    }
    int x = 3, y = 1;
    pg_synth_orient_apply(1, &x, &y); /* a quarter turn counter-clockwise */
    assert_int_equal(x, -1);
    assert_int_equal(y, 3);
}

/* Upsampling a parent of any orientation gives the same 2 x 2 exemplar texels (at the
 * finest scale u + {-1, 0}^2: the half-texel is rounded in the exemplar's frame), each
 * child keeps the orientation, and the children continue one another in the output frame.
 * Rounded in the output frame and then turned, the block moved with the orientation, and
 * coherent parents across a turned cube seam had children a texel apart. */
static void test_upsample_orientation(void **state) {
    (void)state;
    pg_synth_exemplar *ex = torus_exemplar(0);
    for (int s = 0; s < 3; s++) {
        const int h = 1 << s;
        int base[4][2];
        for (int o = 0; o < 4; o++) {
            uint32_t S0 = pg_synth_with_orient(pg_synth_pack(0, 20, 30), o), S1[4];
            float V0 = 0, V1[4];
            pg_synth_view parent = {&S0, &V0, NULL, 1, 1, 1, 0, 0, 0, 0};
            pg_synth_view child = {S1, V1, NULL, 2, 2, 2, 0, 0, 0, 0};
            pg_synth_upsample(ex, s, &parent, &child);
            int set[4][2];
            for (int d = 0; d < 4; d++) {
                assert_int_equal(pg_synth_orient(S1[d]), o);
                assert_int_equal(pg_synth_offset(ex, S1[0], h * (d & 1), h * (d >> 1)), S1[d]);
                set[d][0] = pg_synth_u(S1[d]) - 20, set[d][1] = pg_synth_v(S1[d]) - 30;
            }
            if (o == 0) memcpy(base, set, sizeof set);
            for (int d = 0; d < 4; d++) { /* the same texels, in any order */
                int found = 0;
                for (int e = 0; e < 4; e++)
                    found |= set[e][0] == base[d][0] && set[e][1] == base[d][1];
                assert_true(found);
            }
            if (s == 0)
                for (int d = 0; d < 4; d++)
                    assert_true(set[d][0] >= -1 && set[d][0] <= 0 && set[d][1] >= -1 &&
                                set[d][1] <= 0);
        }
    }
    pg_synth_exemplar_free(ex);
}

/* A k-coherence candidate is seen through the coordinate's turn and then the entry's: its
 * orientation turns any move as the two turns one after the other do. OR-ing the two
 * orientations, as the synthesis did, gave 1 | 1 = 1 for two quarter turns. */
static void test_kcoherence_candidate_turns(void **state) {
    (void)state;
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++) {
            uint32_t q = pg_synth_with_orient(pg_synth_pack(1, 5, 6), a);
            uint32_t e = pg_synth_with_orient(pg_synth_pack(2, 7, 8), b);
            uint32_t c = pg_kcoherence_candidate(q, e);
            assert_int_equal(c & ~PG_SYNTH_ORIENT_MASK, e & ~PG_SYNTH_ORIENT_MASK);
            int x = 3, y = 1, x2 = 3, y2 = 1;
            pg_synth_orient_apply(pg_synth_orient(c), &x, &y);
            pg_synth_orient_apply(a, &x2, &y2);
            pg_synth_orient_apply(b, &x2, &y2);
            assert_int_equal(x, x2);
            assert_int_equal(y, y2);
        }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jitter0_reproduces_torus),
        cmocka_unit_test(test_threads_and_tilings_identical),
        cmocka_unit_test(test_pass_hook_edits_offsets),
        cmocka_unit_test(test_constant_exemplar_is_degenerate),
        cmocka_unit_test(test_bad_parameters),
        cmocka_unit_test(test_cache_roundtrip),
        cmocka_unit_test(test_kcoherence_entries),
        cmocka_unit_test(test_orientation),
        cmocka_unit_test(test_upsample_orientation),
        cmocka_unit_test(test_kcoherence_candidate_turns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
