/* test_lpips.c - the LPIPS-style distance on real texture: crops of NASA Blue Marble.
 *
 * Properties (docs/inspect.md): identical images score 0; the distance is symmetric; it rises
 * monotonically with blur strength and with stretch factor; a slightly shifted crop
 * of a texture scores much lower than a different texture. */
#include "pg_marble.h"
#include "pg_test.h"

#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_lpips.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CROP 256

typedef struct fixture {
    pg_image bm; /* Blue Marble, values 0..1 */
} fixture;

static int setup(void **state) {
    fixture *fx = calloc(1, sizeof *fx);
    pg_error err = {0};
    if (pg_image_read(PG_MARBLE_ALBEDO, 0, &fx->bm, &err) != PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    for (size_t i = 0; i < (size_t)fx->bm.width * fx->bm.height * fx->bm.channels; i++)
        fx->bm.data[i] *= fx->bm.unit_scale;
    *state = fx;
    return 0;
}

static int teardown(void **state) {
    fixture *fx = *state;
    pg_image_free(&fx->bm);
    free(fx);
    return 0;
}

/* Bilinear sample of the image (clamped) at pixel coordinates (x, y). */
static void sample(const pg_image *im, double x, double y, float *out) {
    x = fmin(fmax(x - 0.5, 0), im->width - 1.001);
    y = fmin(fmax(y - 0.5, 0), im->height - 1.001);
    int x0 = (int)x, y0 = (int)y;
    double tx = x - x0, ty = y - y0;
    for (int c = 0; c < 3; c++) {
        const float *p = im->data + ((size_t)y0 * im->width + x0) * im->channels + c;
        size_t dx = (size_t)im->channels, dy = (size_t)im->width * im->channels;
        out[c] = (float)((1 - ty) * ((1 - tx) * p[0] + tx * p[dx]) +
                         ty * ((1 - tx) * p[dy] + tx * p[dy + dx]));
    }
}

/* A CROP x CROP crop centred on pixel corner (cx, cy), magnified by sx horizontally. */
static float *crop(const pg_image *im, double cx, double cy, double sx) {
    float *o = malloc((size_t)CROP * CROP * 3 * sizeof *o);
    for (int j = 0; j < CROP; j++)
        for (int i = 0; i < CROP; i++)
            sample(im, cx + (i + 0.5 - CROP / 2) / sx, cy + (j + 0.5 - CROP / 2),
                   o + ((size_t)j * CROP + i) * 3);
    return o;
}

/* Separable Gaussian blur of a CROP x CROP RGB image (clamped borders). */
static float *blur(const float *src, double sigma) {
    int r = (int)ceil(3 * sigma);
    double *k = malloc((2 * r + 1) * sizeof *k), s = 0;
    for (int t = -r; t <= r; t++)
        s += k[t + r] = exp(-0.5 * t * t / (sigma * sigma));
    float *tmp = malloc((size_t)CROP * CROP * 3 * sizeof *tmp),
          *o = malloc((size_t)CROP * CROP * 3 * sizeof *o);
    for (int pass = 0; pass < 2; pass++) {
        const float *in = pass ? tmp : src;
        float *out = pass ? o : tmp;
        for (int j = 0; j < CROP; j++)
            for (int i = 0; i < CROP; i++)
                for (int c = 0; c < 3; c++) {
                    double acc = 0;
                    for (int t = -r; t <= r; t++) {
                        int ii = pass ? i : i + t, jj = pass ? j + t : j;
                        ii = ii < 0 ? 0 : ii >= CROP ? CROP - 1 : ii;
                        jj = jj < 0 ? 0 : jj >= CROP ? CROP - 1 : jj;
                        acc += k[t + r] * in[((size_t)jj * CROP + ii) * 3 + c];
                    }
                    out[((size_t)j * CROP + i) * 3 + c] = (float)(acc / s);
                }
    }
    free(k), free(tmp);
    return o;
}

static double dist(const float *a, const float *b) {
    pg_lpips_params p;
    pg_lpips_params_default(&p);
    pg_lpips_image A = {CROP, CROP, a, NULL}, B = {CROP, CROP, b, NULL};
    pg_lpips_result r;
    pg_error err = {0};
    assert_int_equal(pg_lpips_distance(&A, &B, &p, &r, &err), PG_OK);
    assert_int_equal(r.layers, PG_LPIPS_OCTAVES);
    assert_true(r.distance >= 0 && r.distance <= 1);
    return r.distance;
}

/* Texture centres (pixel corners of the 2700 x 1350 map, 7.5 px per degree). */
#define ARABIA_X 1688.0 /* 45 E */
#define ARABIA_Y 488.0  /* 25 N */
#define AMAZON_X 900.0  /* 60 W */
#define AMAZON_Y 750.0  /* 10 S */
#define TIBET_X 2010.0  /* 88 E */
#define TIBET_Y 435.0   /* 32 N */

static void test_identity_and_symmetry(void **state) {
    fixture *fx = *state;
    float *a = crop(&fx->bm, ARABIA_X, ARABIA_Y, 1), *b = crop(&fx->bm, AMAZON_X, AMAZON_Y, 1);
    assert_float_equal(dist(a, a), 0, 1e-12);
    double ab = dist(a, b), ba = dist(b, a);
    printf("d(Arabia, Amazon) = %.4f, d(Amazon, Arabia) = %.4f\n", ab, ba);
    assert_true(ab > 0.05);
    assert_float_equal(ab, ba, 1e-9);
    free(a), free(b);
}

/* Degrade the Tibet crop with strength x: 0 = blur, 1 = stretch. */
static float *degrade(const fixture *fx, const float *a, int kind, double x) {
    return kind == 0 ? blur(a, x) : crop(&fx->bm, TIBET_X, TIBET_Y, x);
}

/* d(original, degraded) must rise strictly along the strengths. */
static void check_monotone(const fixture *fx, int kind, const double *x, int n) {
    float *a = crop(&fx->bm, TIBET_X, TIBET_Y, 1);
    double prev = 0;
    for (int i = 0; i < n; i++) {
        float *b = degrade(fx, a, kind, x[i]);
        double d = dist(a, b);
        printf("%s %.2f: d = %.4f\n", kind ? "stretch factor" : "blur sigma (px)", x[i], d);
        assert_true(d > prev);
        prev = d;
        free(b);
    }
    free(a);
}

static void test_monotone_in_blur(void **state) {
    const double sigmas[] = {0.5, 1, 2, 4, 8};
    check_monotone(*state, 0, sigmas, 5);
}

static void test_monotone_in_stretch(void **state) {
    const double factors[] = {1.05, 1.1, 1.25, 1.5, 2, 3};
    check_monotone(*state, 1, factors, 6);
}

static void test_shift_vs_different_texture(void **state) {
    fixture *fx = *state;
    const double centres[3][2] = {{ARABIA_X, ARABIA_Y}, {AMAZON_X, AMAZON_Y}, {TIBET_X, TIBET_Y}};
    for (int t = 0; t < 3; t++) {
        float *a = crop(&fx->bm, centres[t][0], centres[t][1], 1);
        float *s = crop(&fx->bm, centres[t][0] + 3, centres[t][1] + 2, 1);
        double dshift = dist(a, s), dmin = 1;
        for (int u = 0; u < 3; u++) {
            if (u == t) continue;
            float *b = crop(&fx->bm, centres[u][0], centres[u][1], 1);
            dmin = fmin(dmin, dist(a, b));
            free(b);
        }
        printf("texture %d: shifted by (3, 2) px d = %.4f, nearest other texture d = %.4f\n", t,
               dshift, dmin);
        assert_true(dshift < 0.5 * dmin);
        free(a), free(s);
    }
}

static void test_bad_input(void **state) {
    fixture *fx = *state;
    float *a = crop(&fx->bm, ARABIA_X, ARABIA_Y, 1);
    pg_lpips_params p;
    pg_lpips_params_default(&p);
    pg_lpips_image small = {128, 128, a, NULL}, big = {CROP, CROP, a, NULL};
    pg_lpips_result r;
    pg_error err = {0};
    /* 5 octaves need 16 px at the coarsest level: 256 px */
    assert_int_equal(pg_lpips_distance(&small, &big, &p, &r, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "too small"));
    p.octaves = 4; /* 128 px is enough for 4, but the geometries differ */
    pg_error_clear(&err);
    assert_int_equal(pg_lpips_distance(&small, &big, &p, &r, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "cannot compare"));
    free(a);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_identity_and_symmetry), cmocka_unit_test(test_monotone_in_blur),
        cmocka_unit_test(test_monotone_in_stretch),
        cmocka_unit_test(test_shift_vs_different_texture), cmocka_unit_test(test_bad_input)};
    return cmocka_run_group_tests(tests, setup, teardown);
}
