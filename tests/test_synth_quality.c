/* test_synth_quality.c - quality of flat synthesis from the real default exemplar
 * (Blue Marble + Marble relief on the exemplar cube), with numbers:
 *
 *  - neighbourhood fidelity: appearance vectors are recomputed from the *output images*
 *    (Lab albedo + weighted height, 5x5 Gaussian-weighted, the exemplar's own PCA basis)
 *    and compared with their nearest exemplar vector (computed the same way from the
 *    exemplar images). The mean distance must be <= 1.5 x the exemplar's leave-one-out
 *    figure (nearest vector excluding texels within 2 of the query) and <= 0.5 x the
 *    figure for an output of uniformly random coordinates;
 *  - histograms: Wasserstein-1 distance of height and of albedo to the exemplar's;
 *  - coherence: 4-connected patches where S[p + d] = S[p] + d; mean size floor and no
 *    patch over 25% of the output.
 * The prepared exemplar is cached in $PG_BUILD_DIR/synth-cache (shared with
 * test_synth_cli), so only the first run pays the preparation. */
#include "pg_test.h"

#include "pg_synth_internal.h"
#include "planetgen/pg_exemplar.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N 512
#define DBSTEP 4 /* exemplar database: every 4th texel in x and y */
#define NQUERY 500

static pg_synth_exemplar *ex;
static pg_synth_result res;
static pg_exemplar src; /* kept for the small-cube preparation test */

static int setup(void **state) {
    (void)state;
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo);
    pg_error err = {0};
    if (pg_exemplar_load(&eo, &src, &err) != PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    char dir[512];
    const char *build = getenv("PG_BUILD_DIR");
    if (!build) {
        fprintf(stderr, "PG_BUILD_DIR is not set (run under ctest)\n");
        return -1;
    }
    snprintf(dir, sizeof dir, "%s/synth-cache", build);
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    pg_synth_prep_info info;
    pg_status st = pg_synth_prepare_exemplar(src.albedo, src.elevation, src.width, src.height,
                                             src.sea_level, &ep, dir, &ex, &info, &err);
    if (st != PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    pg_synth_params p;
    pg_synth_params_default(&p);
    return pg_synth_flat(ex, N, &p, NULL, NULL, &res, &err) == PG_OK ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    pg_synth_result_free(&res);
    pg_synth_exemplar_free(ex);
    pg_exemplar_free(&src);
    return 0;
}

/* On the real cube exemplar (coordinates wrapping across exemplar seams), 1 thread
 * whole-level and 2 threads in 64-texel tiles give the same bytes. */
static void test_cube_threads_and_tiles(void **state) {
    (void)state;
    pg_synth_params p;
    pg_synth_params_default(&p);
    p.seed = 5;
    pg_synth_result a, b;
    pg_error err = {0};
    omp_set_num_threads(1);
    assert_int_equal(pg_synth_flat(ex, 256, &p, NULL, NULL, &a, &err), PG_OK);
    omp_set_num_threads(2);
    p.tile_size = 64;
    assert_int_equal(pg_synth_flat(ex, 256, &p, NULL, NULL, &b, &err), PG_OK);
    assert_memory_equal(a.coords, b.coords, 256 * 256 * 4);
    assert_memory_equal(a.offset, b.offset, 256 * 256 * 4);
    pg_synth_result_free(&a);
    pg_synth_result_free(&b);
}

/* Preparation (PCA sums, per-face PatchMatch) is thread-count independent: a small
 * cube (E = 64) prepared with 1 and with 2 threads has identical tables. */
static void test_prepare_threads(void **state) {
    (void)state;
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    ep.face_size = 64;
    ep.levels = 3;
    pg_synth_exemplar *e[2];
    pg_synth_prep_info info;
    pg_error err = {0};
    for (int t = 0; t < 2; t++) {
        omp_set_num_threads(t + 1);
        assert_int_equal(pg_synth_prepare_exemplar(src.albedo, src.elevation, src.width, src.height,
                                                   src.sea_level, &ep, "", &e[t], &info, &err),
                         PG_OK);
    }
    size_t n = (size_t)6 * 64 * 64;
    for (int s = 0; s < ep.levels; s++) {
        assert_memory_equal(e[0]->app[s], e[1]->app[s], n * PG_SYNTH_MAX_DIMS * 2);
        assert_memory_equal(e[0]->kcoh[s], e[1]->kcoh[s], n * 4);
    }
    pg_synth_exemplar_free(e[0]);
    pg_synth_exemplar_free(e[1]);
}

/* Fewer appearance components than stored: the rest of every vector is 0, whatever the
 * scratch the caller hands in holds (the preparation reuses one for every level's float
 * vectors and for the k-coherence distances). Filled with large values here, they would
 * also set the quantization scale if the unused components were read. */
static void test_pca_few_dims(void **state) {
    (void)state;
    enum { SIZE = 32, NF = 2, DIMS = 4 };
    pg_synth_faces f = {NF, SIZE, 8, SIZE + 16, false, NULL};
    size_t nf = (size_t)NF * f.ext * f.ext * PG_SYNTH_CH, n = (size_t)NF * SIZE * SIZE;
    f.px = malloc(nf * sizeof(float));
    float *vals = malloc(n * PG_SYNTH_MAX_DIMS * sizeof(float));
    pg_synth_exemplar *e = pg_synth_exemplar_alloc(NF, SIZE, 2, DIMS, 2);
    assert_true(f.px && vals && e);
    for (size_t i = 0; i < nf; i++)
        f.px[i] = (float)((i * 7919 + 13) % 2001) / 10.0f - 100.0f;
    e->lab_height_scale = 1;
    pg_error err = {0};
    for (int s = 0; s < 2; s++) {
        for (size_t i = 0; i < n * PG_SYNTH_MAX_DIMS; i++)
            vals[i] = 1e6f * (float)(i % 7);
        assert_int_equal(pg_appearance_pca_level(&f, s, e, vals, &err), PG_OK);
        int16_t big = 0;
        for (size_t t = 0; t < n; t++)
            for (int c = 0; c < PG_SYNTH_MAX_DIMS; c++) {
                int16_t v = e->app[s][t * PG_SYNTH_MAX_DIMS + c];
                if (c >= DIMS && v != 0)
                    fail_msg("level %d, texel %zu, component %d: %d, not 0", s, t, c, v);
                if (c < DIMS && abs(v) > big) big = (int16_t)abs(v);
            }
        assert_int_equal(big, 32000); /* the largest used component sets the scale */
    }
    pg_synth_exemplar_free(e);
    free(vals);
    free(f.px);
}

/* ---- appearance vectors from images ---- */

/* Faces struct (no gutter, clamped reads) holding Lab + weighted height of `count`
 * rendered texels laid out as nfaces images of size x size. */
static pg_synth_faces image_faces(const uint8_t *rgb, const float *h, int nfaces, int size) {
    pg_synth_faces f = {nfaces, size, 0, size, false, NULL};
    size_t n = (size_t)nfaces * size * size;
    f.px = malloc(n * PG_SYNTH_CH * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        float c[3] = {rgb[i * 3] / 255.0f, rgb[i * 3 + 1] / 255.0f, rgb[i * 3 + 2] / 255.0f};
        pg_synth_srgb_to_lab(c, f.px + i * PG_SYNTH_CH);
        f.px[i * PG_SYNTH_CH + 3] = h[i] * ex->lab_height_scale;
    }
    return f;
}

static void vec_at(const pg_synth_faces *f, int face, int x, int y, float *v) {
    float raw[PG_SYNTH_RAW];
    pg_appearance_gather(f, face, x, y, 1, raw);
    pg_appearance_project(ex, 0, raw, v);
}

typedef struct db {
    float *v;
    int *face, *x, *y;
    int n;
} db;

/* Nearest database distance; texels within `excl` of (face, x, y) are skipped. */
static double nearest(const db *d, const float *q, int face, int x, int y, int excl) {
    double best = 1e300;
    for (int i = 0; i < d->n; i++) {
        if (excl && d->face[i] == face && abs(d->x[i] - x) <= excl && abs(d->y[i] - y) <= excl)
            continue;
        const float *v = d->v + (size_t)i * ex->dims;
        double s = 0;
        for (int k = 0; k < ex->dims; k++)
            s += (q[k] - v[k]) * (q[k] - v[k]);
        if (s < best) best = s;
    }
    return sqrt(best);
}

static double output_fidelity(const db *d, const uint32_t *coords, const float *offset) {
    uint8_t *rgb = malloc((size_t)N * N * 3);
    float *h = malloc(sizeof(float) * N * N);
    pg_synth_render(ex, coords, offset, (size_t)N * N, rgb, h);
    pg_synth_faces f = image_faces(rgb, h, 1, N);
    double sum = 0;
    for (int i = 0; i < NQUERY; i++) {
        uint32_t r = pg_synth_hash(9, 0, 0, i, 0, 0);
        int x = 2 + (int)(r % (N - 4)), y = 2 + (int)((r >> 16) % (N - 4));
        float q[PG_SYNTH_MAX_DIMS];
        vec_at(&f, 0, x, y, q);
        sum += nearest(d, q, -1, 0, 0, 0);
    }
    pg_synth_faces_free(&f);
    free(rgb);
    free(h);
    return sum / NQUERY;
}

static void test_neighbourhood_fidelity(void **state) {
    (void)state;
    const int E = ex->face_size, nf = ex->nfaces;
    pg_synth_faces f = image_faces(ex->albedo, ex->height, nf, E);
    db d = {0};
    int cap = nf * (E / DBSTEP) * (E / DBSTEP);
    d.v = malloc(sizeof(float) * cap * ex->dims);
    d.face = malloc(sizeof(int) * cap * 3);
    d.x = d.face + cap;
    d.y = d.x + cap;
    for (int face = 0; face < nf; face++)
        for (int y = 2; y < E - 2; y += DBSTEP)
            for (int x = 2; x < E - 2; x += DBSTEP) {
                float v[PG_SYNTH_MAX_DIMS];
                vec_at(&f, face, x, y, v);
                memcpy(d.v + (size_t)d.n * ex->dims, v, sizeof(float) * ex->dims);
                d.face[d.n] = face, d.x[d.n] = x, d.y[d.n] = y;
                d.n++;
            }
    /* leave-one-out: exemplar queries on the database lattice, own 5x5 excluded */
    double loo = 0;
    for (int i = 0; i < NQUERY; i++) {
        int j = (int)(pg_synth_hash(5, 0, 0, i, 0, 0) % (uint32_t)d.n);
        loo += nearest(&d, d.v + (size_t)j * ex->dims, d.face[j], d.x[j], d.y[j], 2);
    }
    loo /= NQUERY;
    double out = output_fidelity(&d, res.coords, res.offset);
    uint32_t *rnd = malloc(sizeof(uint32_t) * N * N);
    for (int i = 0; i < N * N; i++) {
        uint32_t a = pg_synth_hash(77, 0, 0, i, 0, 0), b = pg_synth_hash(77, 0, 0, i, 0, 1);
        rnd[i] = pg_synth_pack((int)(a % 6), (int)((a >> 4) % E), (int)(b % E));
    }
    double random = output_fidelity(&d, rnd, NULL);
    print_message("neighbourhood distance: output %.3f, leave-one-out %.3f (ratio %.2f), random "
                  "coordinates %.3f (ratio %.2f)\n",
                  out, loo, out / loo, random, out / random);
    assert_true(out <= 1.5 * loo);
    assert_true(out <= 0.5 * random);
    free(rnd);
    free(d.v);
    free(d.face);
    pg_synth_faces_free(&f);
}

/* ---- histograms ---- */

static int cmp_float(const void *a, const void *b) {
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* W1 between two samples: the mean |quantile difference| over 1000 quantiles. */
static double wasserstein1(float *a, size_t na, float *b, size_t nb) {
    qsort(a, na, sizeof(float), cmp_float);
    qsort(b, nb, sizeof(float), cmp_float);
    double s = 0;
    for (int k = 0; k < 1000; k++) {
        double q = (k + 0.5) / 1000;
        s += fabs(a[(size_t)(q * na)] - b[(size_t)(q * nb)]);
    }
    return s / 1000;
}

static void test_histograms(void **state) {
    (void)state;
    size_t ne = (size_t)ex->nfaces * ex->face_size * ex->face_size, no = (size_t)N * N;
    float *eh = malloc(sizeof(float) * ne), *oh = malloc(sizeof(float) * no);
    float *rh = malloc(sizeof(float) * no);
    uint8_t *orgb = malloc(no * 3);
    pg_synth_render(ex, res.coords, res.offset, no, orgb, oh);
    memcpy(eh, ex->height, sizeof(float) * ne);
    for (size_t i = 0; i < no; i++) /* baseline: uniform noise over the exemplar's range */
        rh[i] = ex->height_min + (ex->height_max - ex->height_min) *
                                     (pg_synth_hash(3, 0, 0, (long)i, 0, 0) / 4294967296.0f);
    float *tmp = malloc(sizeof(float) * no);
    memcpy(tmp, oh, sizeof(float) * no);
    double w_h = wasserstein1(tmp, no, eh, ne);
    double w_hr = wasserstein1(rh, no, eh, ne);
    double w_a = 0, w_ar = 0;
    float *ea = malloc(sizeof(float) * ne), *oa = malloc(sizeof(float) * no);
    for (int c = 0; c < 3; c++) {
        for (size_t i = 0; i < ne; i++)
            ea[i] = ex->albedo[i * 3 + c];
        for (size_t i = 0; i < no; i++)
            oa[i] = orgb[i * 3 + c];
        w_a += wasserstein1(oa, no, ea, ne) / 3;
        for (size_t i = 0; i < no; i++)
            oa[i] = (float)(pg_synth_hash(4, c, 0, (long)i, 0, 0) % 256);
        w_ar += wasserstein1(oa, no, ea, ne) / 3;
    }
    print_message("W1 height: output %.0f m, uniform-noise baseline %.0f m; W1 albedo: output "
                  "%.1f, baseline %.1f (of 255)\n",
                  w_h, w_hr, w_a, w_ar);
    assert_true(w_h <= 600.0 && w_h <= 0.25 * w_hr);
    assert_true(w_a <= 15.0 && w_a <= 0.25 * w_ar);
    free(eh), free(oh), free(rh), free(orgb), free(tmp), free(ea), free(oa);
}

/* ---- coherence ---- */

static int find(int *p, int i) {
    while (p[i] != i)
        i = p[i] = p[p[i]];
    return i;
}

static void test_coherent_patches(void **state) {
    (void)state;
    int *par = malloc(sizeof(int) * N * N), *size = calloc(N * N, sizeof(int));
    for (int i = 0; i < N * N; i++)
        par[i] = i;
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            /* coherent: the neighbour holds this texel's coordinate moved by one step
             * (in its orientation, continuing across exemplar seams: pg_synth_offset) */
            uint32_t c = res.coords[y * N + x];
            if (x + 1 < N && res.coords[y * N + x + 1] == pg_synth_offset(ex, c, 1, 0))
                par[find(par, y * N + x)] = find(par, y * N + x + 1);
            if (y + 1 < N && res.coords[(y + 1) * N + x] == pg_synth_offset(ex, c, 0, 1))
                par[find(par, y * N + x)] = find(par, (y + 1) * N + x);
        }
    int patches = 0, biggest = 0;
    for (int i = 0; i < N * N; i++)
        size[find(par, i)]++;
    for (int i = 0; i < N * N; i++)
        if (size[i]) {
            patches++;
            if (size[i] > biggest) biggest = size[i];
        }
    double mean = (double)N * N / patches;
    print_message("coherent patches: %d, mean size %.1f texels, largest %d (%.1f%% of output)\n",
                  patches, mean, biggest, 100.0 * biggest / (N * N));
    assert_true(mean >= 15.0);
    assert_true(biggest <= N * N / 4);
    free(par);
    free(size);
}

/* The preparation projects texels in batches (one per vector lane): on the real basis of every
 * level, 37 raw vectors (two batches of 16 and a tail) give the same bits as one at a time. */
static void test_project_batches(void **state) {
    (void)state;
    enum { NV = 37 };
    static float raw[NV][PG_SYNTH_RAW], batch[NV * PG_SYNTH_MAX_DIMS], one[PG_SYNTH_MAX_DIMS];
    for (int s = 0; s < ex->levels; s++) {
        for (int t = 0; t < NV; t++)
            for (int i = 0; i < PG_SYNTH_RAW; i++) /* Lab-like values, both signs, 1/3 steps */
                raw[t][i] = (float)((t * 7919 + i * 104729 + s * 31) % 301 - 100) / 3.0f;
        memset(batch, 0, sizeof batch);
        pg_appearance_project_n(ex, s, (const float(*)[PG_SYNTH_RAW])raw, NV, batch);
        for (int t = 0; t < NV; t++) {
            pg_appearance_project(ex, s, raw[t], one);
            for (int k = 0; k < ex->dims; k++)
                if (memcmp(&one[k], &batch[(size_t)t * PG_SYNTH_MAX_DIMS + k], sizeof(float)))
                    fail_msg("level %d, vector %d, component %d: batch %a, alone %a", s, t, k,
                             batch[(size_t)t * PG_SYNTH_MAX_DIMS + k], one[k]);
        }
    }
}

/* The preparation gathers and projects whole rows straight from the faces where no read
 * clamps: at every level, a face's first row, a run of two batches and a tail in the
 * middle, and a batch that ends a face's last row give the same bits as gathering and
 * projecting each texel alone. With the preparation's gutter; with one of 4 texels, whose
 * level 1 reads reach exactly the stored edge on every side (the rows path's bounds) and
 * whose coarser levels clamp (the texel-by-texel path); and with one of 3, whose level 1
 * reads would pass the edge by one texel (so must clamp). */
static void test_project_span(void **state) {
    (void)state;
    enum { SIZE = 64, NF = 2 };
    const int gutters[3] = {4 << (ex->levels - 1), 4, 3};
    /* face, y, first x, count */
    static const int rows[][4] = {{0, 0, 0, SIZE}, {1, 17, 5, 37}, {1, SIZE - 1, SIZE - 16, 16}};
    float span[SIZE * PG_SYNTH_MAX_DIMS], one[PG_SYNTH_MAX_DIMS], raw[PG_SYNTH_RAW];
    for (int gi = 0; gi < 3; gi++) {
        const int gutter = gutters[gi];
        pg_synth_faces f = {NF, SIZE, gutter, SIZE + 2 * gutter, false, NULL};
        size_t nf = (size_t)NF * f.ext * f.ext * PG_SYNTH_CH;
        f.px = malloc(nf * sizeof(float));
        assert_non_null(f.px);
        for (size_t i = 0; i < nf; i++) /* Lab-like values, both signs */
            f.px[i] = (float)((i * 7919 + 13) % 2001) / 10.0f - 100.0f;
        for (int s = 0; s < ex->levels; s++)
            for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
                const int face = rows[r][0], y = rows[r][1], x = rows[r][2], n = rows[r][3];
                memset(span, 0, sizeof span);
                pg_appearance_project_span(&f, ex, s, face, x, y, n, span);
                for (int t = 0; t < n; t++) {
                    pg_appearance_gather(&f, face, x + t, y, 1 << s, raw);
                    pg_appearance_project(ex, s, raw, one);
                    for (int k = 0; k < ex->dims; k++)
                        if (memcmp(&one[k], &span[(size_t)t * PG_SYNTH_MAX_DIMS + k],
                                   sizeof(float)))
                            fail_msg("gutter %d, level %d, face %d, texel (%d, %d), component "
                                     "%d: row %a, alone %a",
                                     gutter, s, face, x + t, y, k,
                                     span[(size_t)t * PG_SYNTH_MAX_DIMS + k], one[k]);
                }
            }
        free(f.px);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_neighbourhood_fidelity),
        cmocka_unit_test(test_histograms),
        cmocka_unit_test(test_coherent_patches),
        cmocka_unit_test(test_cube_threads_and_tiles),
        cmocka_unit_test(test_prepare_threads),
        cmocka_unit_test(test_project_batches),
        cmocka_unit_test(test_project_span),
        cmocka_unit_test(test_pca_few_dims),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
