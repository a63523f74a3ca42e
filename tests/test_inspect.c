/* test_inspect.c - the texture comparison (the former pole check) on the real exemplar,
 * its negative control, the seam statistic, neighbourhood fidelity, Earth's side and its
 * caches, and `planetgen inspect` as a user runs it (docs/inspect.md).
 *
 * Positive case: the default-size planet (6 x 4x4 x 256^2, equi-angular) made by
 * reprojecting the Earth exemplar onto the cube (pg_planet_from_exemplar), the
 * undistorted planet until `planetgen generate` exists. Its pole distances must stay
 * within PG_INSPECT_POLE_GATE of the equator mean.
 *
 * Negative control (test code only): the same content laid out the way a synthesis in
 * equirectangular latitude-longitude space lays it out. Such a synthesis treats the
 * W x H lat-lon grid as a flat, isotropic image: a patch of P x P pixels holds P x P
 * pixels' worth of exemplar texture at the equator's scale wherever it is placed. We
 * emulate it with overlapping patches (raised-cosine windows, period PATCH px): each
 * patch is filled with the exemplar as seen in the tangent plane at the patch's centre,
 * one equatorial pixel per pixel. At the equator that is the identity; at latitude phi
 * the texture is squeezed east-west by cos(phi) and neighbouring patches disagree, so
 * towards the poles it pinches and smears - the classic lat-lon failure. The check
 * must fail visibly on it.
 *
 * Neighbourhood fidelity (pg_inspect_fidelity_compute) on the same Earth planet, with
 * its identity coordinate map: with its own sources excluded it scores about the
 * leave-one-out baseline (gate <= FID_GATE_GOOD); negative controls made from it -
 * every texel from a hashed texel (shuffled), heavy texel noise - must score >=
 * FID_GATE_BAD, and a copy blurred by 2 texels must fail the completeness gate. The
 * synthesized planets are checked through `planetgen inspect` in test_realism_e2e.c.
 * Over 600 lines because the cases share one loaded exemplar and its caches. */
#include "pg_test.h"

#include "planetgen/pg_equirect.h"
#include "planetgen/pg_inspect.h"
#include "planetgen/pg_realism.h"
#include "planetgen/pg_synth.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PATCH 48 /* lat-lon emulation: patch period in pixels of the exemplar grid */
/* Fidelity gates (docs/inspect.md: the Earth copy 1.005x, blurred 1.68x completeness,
 * noise 3.8x, shuffled 8.1x leave-one-out). */
#define FID_GATE_GOOD PG_INSPECT_FIDELITY_GATE /* a copy of the exemplar passes */
#define FID_GATE_BAD 2.0                       /* noisy and shuffled controls: at least this */
#define FID_NOISE_ALBEDO 0.2   /* uniform +-0.2 sRGB per channel (+-51 grey levels) */
#define FID_NOISE_HEIGHT_M 500 /* uniform +-500 m */
#define FID_BLUR_SIGMA 2.0     /* planet texels (1 analysis texel) */
static const double PI = 3.14159265358979323846;

typedef struct fixture {
    pg_exemplar ex;
    pg_planet earth;
    char dir[1024]; /* the Earth planet saved as a planet directory */
    bool have_fid;
    pg_inspect_fidelity earth_fid; /* the Earth planet's fidelity, computed on first use */
} fixture;

static int setup(void **state) {
    fixture *fx = calloc(1, sizeof *fx);
    pg_error err = {0};
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    if (pg_exemplar_load(&o, &fx->ex, &err) != PG_OK ||
        pg_planet_alloc(&fx->earth, PG_CUBE_DEFAULT_PROJECTION, 4, 256, pg_ellipsoid_sphere(),
                        &err) != PG_OK ||
        pg_planet_from_exemplar(&fx->earth, &fx->ex, 2, &err) != PG_OK ||
        pg_planet_source_identity(&fx->earth, (int)fx->earth.n, fx->earth.projection, &err) !=
            PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    pg_test_scratch_dir("inspect_earth", fx->dir, sizeof fx->dir);
    if (pg_planet_save_dir(&fx->earth, fx->dir, &err) != PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    *state = fx;
    return 0;
}

static int teardown(void **state) {
    fixture *fx = *state;
    pg_planet_free(&fx->earth);
    pg_exemplar_free(&fx->ex);
    free(fx);
    return 0;
}

/* ---- the lat-lon emulation ---- */

static void latlon_dir(double lat, double lon, double d[3]) {
    d[0] = cos(lat) * cos(lon), d[1] = cos(lat) * sin(lon), d[2] = sin(lat);
}

/* Exemplar RGB + height at a direction. */
static void ex_at(const pg_exemplar *ex, const double d[3], float out[4]) {
    double lat = atan2(d[2], hypot(d[0], d[1])) * 180 / PI, lon = atan2(d[1], d[0]) * 180 / PI;
    pg_equirect_sample(ex->albedo, ex->width, ex->height, 3, lat, lon, out);
    pg_equirect_sample(ex->elevation, ex->width, ex->height, 1, lat, lon, out + 3);
}

/* Patch (I, J)'s prediction for pixel (i, j): the exemplar in the tangent plane at the
 * patch centre, one equatorial pixel (2 pi / W radians) per pixel. */
static void patch_predict(const pg_exemplar *ex, int I, int J, int i, int j, float out[4]) {
    int W = ex->width, H = ex->height;
    double s = 2 * PI / W;
    double lat = PI / 2 - (J + 0.5) * PI / H, lon = -PI + (I + 0.5) * 2 * PI / W;
    double c[3], e[3] = {-sin(lon), cos(lon), 0},
                 nv[3] = {-sin(lat) * cos(lon), -sin(lat) * sin(lon), cos(lat)};
    latlon_dir(lat, lon, c);
    double de = (i - I) * s, dn = (J - j) * s, a = hypot(de, dn), d[3];
    for (int k = 0; k < 3; k++) {
        double t = a > 0 ? (de * e[k] + dn * nv[k]) / a : 0;
        d[k] = cos(a) * c[k] + sin(a) * t; /* the geodesic from c along the offset */
    }
    ex_at(ex, d, out);
}

/* Raised-cosine weight for offset d from a patch centre: sums to 1 over patches. */
static double window(double d) {
    double t = cos(PI * d / (2 * PATCH));
    return fabs(d) < PATCH ? t * t : 0;
}

/* The lat-lon "synthesis": an equirect RGB+height image on the exemplar's grid. */
static float *latlon_layout(const pg_exemplar *ex) {
    int W = ex->width, H = ex->height;
    float *img = calloc((size_t)W * H * 4, sizeof *img);
#pragma omp parallel for schedule(dynamic, 4)
    for (int j = 0; j < H; j++) {
        for (int i = 0; i < W; i++) {
            double acc[4] = {0}, wsum = 0;
            int J0 = (j / PATCH) * PATCH, I0 = (i / PATCH) * PATCH;
            for (int J = J0 - PATCH; J <= J0 + PATCH; J += PATCH)
                for (int I = I0 - PATCH; I <= I0 + PATCH; I += PATCH) {
                    double w = window(i - I) * window(j - J);
                    if (w <= 0) continue;
                    float v[4];
                    patch_predict(ex, I, J < 0 ? 0 : J >= H ? H - 1 : J, i, j, v);
                    for (int k = 0; k < 4; k++)
                        acc[k] += w * v[k];
                    wsum += w;
                }
            for (int k = 0; k < 4; k++)
                img[((size_t)j * W + i) * 4 + k] = (float)(acc[k] / wsum);
        }
    }
    return img;
}

/* The lat-lon layout mapped onto a planet of the Earth planet's geometry. */
static void latlon_planet(const fixture *fx, pg_planet *p) {
    pg_error err = {0};
    const pg_planet *e = &fx->earth;
    assert_int_equal(pg_planet_alloc(p, e->projection, e->tiles, e->tile_size, e->ellipsoid, &err),
                     PG_OK);
    float *img = latlon_layout(&fx->ex);
    size_t nn = (size_t)e->n * e->n;
    float *cube = malloc(6 * nn * 4 * sizeof *cube);
    assert_int_equal(pg_cube_from_equirect(e->projection, e->n, &e->ellipsoid, img, fx->ex.width,
                                           fx->ex.height, 4, 2, cube, &err),
                     PG_OK);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (size_t i = 0; i < nn; i++) {
            memcpy(p->albedo[f] + 3 * i, cube + ((size_t)f * nn + i) * 4, 3 * sizeof(float));
            p->height[f][i] = cube[((size_t)f * nn + i) * 4 + 3];
        }
    p->sea_level = e->sea_level;
    free(cube), free(img);
}

/* ---- tests ---- */

static void print_scores(const char *what, const pg_inspect_poles *s) {
    printf("%s:\n", what);
    for (int k = 0; k < PG_VIEWS_COUNT; k++)
        printf("  %-12s planet %.4f  exemplar-cube floor %.4f  planet vs cube %.4f\n",
               pg_views_centre_get(k)->name, s->d[PG_INSPECT_SRC_PLANET][k].distance,
               s->d[PG_INSPECT_SRC_EXCUBE][k].distance, s->d_vs_cube[k].distance);
    printf("  ratio north %.3f south %.3f -> %.3f (raw %.3f %.3f; exemplar cube %.3f)\n",
           s->ratio_north, s->ratio_south, s->pole_equator_ratio, s->raw_north, s->raw_south,
           s->floor_ratio);
}

static void scores_of(const fixture *fx, const pg_planet *p, pg_inspect_views *v,
                      pg_inspect_poles *s) {
    pg_error err = {0};
    assert_int_equal(pg_inspect_render_views(p, &fx->ex, PG_VIEWS_DEFAULT_SIZE, v, &err), PG_OK);
    pg_lpips_params lp;
    pg_lpips_params_default(&lp);
    assert_int_equal(pg_inspect_pole_scores(v, &lp, s, &err), PG_OK);
}

/* Both planets' poles side by side, for the eye: Earth north | lat-lon north |
 * Earth south | lat-lon south. */
static void write_montage(const pg_inspect_views *a, const pg_inspect_views *b) {
    const pg_view *row[4] = {
        &a->v[PG_INSPECT_SRC_PLANET][PG_VIEW_NORTH], &b->v[PG_INSPECT_SRC_PLANET][PG_VIEW_NORTH],
        &a->v[PG_INSPECT_SRC_PLANET][PG_VIEW_SOUTH], &b->v[PG_INSPECT_SRC_PLANET][PG_VIEW_SOUTH]};
    pg_image m;
    pg_error err = {0};
    assert_int_equal(pg_views_montage(row, 4, 8, &m, &err), PG_OK);
    char dir[1024], path[1100];
    pg_test_scratch_dir("inspect_poles", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/poles_cube_vs_latlon.png", dir);
    assert_int_equal(pg_image_write_png(path, &m, 8, &err), PG_OK);
    printf("pole views: %s\n", path);
    pg_image_free(&m);
}

static void test_pole_gate_and_negative_control(void **state) {
    fixture *fx = *state;
    pg_inspect_views ve, vl;
    pg_inspect_poles se, sl;
    scores_of(fx, &fx->earth, &ve, &se);
    print_scores("Earth on the cube", &se);
    pg_planet ll;
    latlon_planet(fx, &ll);
    scores_of(fx, &ll, &vl, &sl);
    print_scores("the same content laid out in lat-lon space", &sl);
    write_montage(&ve, &vl);
    /* the gate, both poles */
    assert_true(se.ratio_north <= PG_INSPECT_POLE_GATE);
    assert_true(se.ratio_south <= PG_INSPECT_POLE_GATE);
    /* the negative control fails it clearly */
    assert_true(sl.pole_equator_ratio > 2 * PG_INSPECT_POLE_GATE);
    /* and its equator is as good as the cube's: the failure is the poles' */
    assert_true(sl.equator_mean < 2 * se.equator_mean + 0.02);
    pg_inspect_views_free(&ve);
    pg_inspect_views_free(&vl);
    pg_planet_free(&ll);
}

/* Gaussian blur of one face of ch channels, sigma in texels, clamped at the face edge. */
static void blur_face(float *a, int64_t n, int ch, double sigma) {
    int r = (int)ceil(3 * sigma);
    double k[64], sum = 0;
    for (int t = -r; t <= r; t++)
        sum += k[t + r] = exp(-0.5 * t * t / (sigma * sigma));
    float *tmp = malloc((size_t)(n * n * ch) * sizeof *tmp);
    for (int pass = 0; pass < 2; pass++) {
        const float *in = pass ? tmp : a;
        float *out = pass ? a : tmp;
#pragma omp parallel for
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++)
                for (int c = 0; c < ch; c++) {
                    double acc = 0;
                    for (int t = -r; t <= r; t++) {
                        int64_t xx = pass ? x : x + t, yy = pass ? y + t : y;
                        xx = xx < 0 ? 0 : xx >= n ? n - 1 : xx;
                        yy = yy < 0 ? 0 : yy >= n ? n - 1 : yy;
                        acc += k[t + r] * in[(size_t)(yy * n + xx) * ch + c];
                    }
                    out[(size_t)(y * n + x) * ch + c] = (float)(acc / sum);
                }
    }
    free(tmp);
}

/* A positive control with distances well above JND: the Earth planet blurred by 2 texels
 * on every face. The six views sit at face centres, so the degradation is identical
 * under all of them; what remains of the ratio is how the metric's response depends on
 * the content (measured: north 1.07, south 0.76). It must stay within the gate. */
static void test_isotropic_degradation_passes(void **state) {
    fixture *fx = *state;
    pg_error err = {0};
    const pg_planet *e = &fx->earth;
    pg_planet q;
    assert_int_equal(pg_planet_alloc(&q, e->projection, e->tiles, e->tile_size, e->ellipsoid, &err),
                     PG_OK);
    size_t nn = (size_t)e->n * e->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        memcpy(q.albedo[f], e->albedo[f], nn * 3 * sizeof(float));
        memcpy(q.height[f], e->height[f], nn * sizeof(float));
        blur_face(q.albedo[f], e->n, 3, 2);
        blur_face(q.height[f], e->n, 1, 2);
    }
    pg_inspect_views v;
    pg_inspect_poles s;
    scores_of(fx, &q, &v, &s);
    print_scores("Earth blurred by 2 texels on every face", &s);
    assert_true(s.equator_mean > 2 * PG_INSPECT_JND); /* well above the JND floor */
    assert_true(s.ratio_north <= PG_INSPECT_POLE_GATE);
    assert_true(s.ratio_south <= PG_INSPECT_POLE_GATE);
    pg_inspect_views_free(&v);
    pg_planet_free(&q);
}

/* The seam statistic: ~1 on the reprojected Earth (no seams: within the seam gate);
 * clearly above once every tile's albedo and height are offset by its own constant, as
 * tiles made without their neighbours would be. */
static void test_seam_statistic(void **state) {
    fixture *fx = *state;
    pg_error err = {0};
    pg_inspect_seams s;
    assert_int_equal(pg_inspect_seams_compute(&fx->earth, &s, &err), PG_OK);
    printf("Earth: seam ratio height %.3f albedo %.3f (tile edges %.5f, face seams %.5f, "
           "interior %.5f)\n",
           s.height.ratio, s.albedo.ratio, s.albedo.tile_edge_mean, s.albedo.face_seam_mean,
           s.albedo.interior_mean);
    assert_true(s.ratio <= PG_INSPECT_SEAM_GATE && s.ratio > 0.9);
    /* 6 x 4 x 4 tiles + 3 x 3 x 3 interior tile edges per face direction */
    int64_t n = fx->earth.n;
    assert_true(s.height.seam_pairs == (uint64_t)(6 * 2 * 3 * n + 6 * 4 * n));
    pg_planet q;
    assert_int_equal(pg_planet_alloc(&q, fx->earth.projection, fx->earth.tiles, fx->earth.tile_size,
                                     fx->earth.ellipsoid, &err),
                     PG_OK);
    int S = q.tile_size;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < n * n; i++) {
            int64_t tile = (i / n / S) * 4 + (i % n) / S;
            float jump = (float)((tile * 7 + f * 3) % 5 - 2); /* -2..2 steps per tile */
            q.height[f][i] = fx->earth.height[f][i] + 50 * jump;
            for (int c = 0; c < 3; c++)
                q.albedo[f][3 * i + c] = fx->earth.albedo[f][3 * i + c] + 0.01f * jump;
        }
    assert_int_equal(pg_inspect_seams_compute(&q, &s, &err), PG_OK);
    printf("offset tiles: seam ratio height %.3f albedo %.3f\n", s.height.ratio, s.albedo.ratio);
    assert_true(s.height.ratio > 1.5 && s.albedo.ratio > 1.5);
    pg_planet_free(&q);
}

/* ---- neighbourhood fidelity ---- */

static void print_fid(const char *what, const pg_inspect_fidelity *f) {
    printf("%-28s fidelity %.3f  loo %.3f  ratio %.3f  random %.3f (%.2fx)  completeness %.3f "
           "(%.3fx)  detail %.3f / loo %.3f (%.3fx)  [%d^2, m %d, %d queries, %d entries]\n",
           what, f->fidelity, f->loo, f->ratio, f->random, f->random_ratio, f->completeness,
           f->structure_completeness_ratio, f->detail_completeness, f->detail_loo,
           f->detail_completeness_ratio, f->analysis_size, f->magnification, f->queries,
           f->database);
}

static void copy_geometry(const pg_planet *src, pg_planet *dst) {
    pg_error err = {0};
    assert_int_equal(
        pg_planet_alloc(dst, src->projection, src->tiles, src->tile_size, src->ellipsoid, &err),
        PG_OK);
    dst->sea_level = src->sea_level;
    /* every control keeps the copy's coordinate map: its texels still come from there */
    if (pg_planet_has_source(src)) {
        assert_int_equal(
            pg_planet_source_alloc(dst, src->source.face_size, src->source.projection, &err),
            PG_OK);
        for (int f = 0; f < PG_CUBE_NFACES; f++)
            memcpy(dst->source.coords[f], src->source.coords[f],
                   (size_t)(src->n * src->n) * sizeof(uint32_t));
    }
}

/* Uniform hashed noise in [-1, 1). */
static double noise(int f, int64_t i, int c) {
    return pg_synth_hash(78, 0, f, (long)i, c, 0) / 2147483648.0 - 1.0;
}

/* The planet plus texel noise: FID_NOISE_ALBEDO in each sRGB channel, FID_NOISE_HEIGHT_M. */
static void noisy(const pg_planet *src, pg_planet *dst) {
    copy_geometry(src, dst);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < src->n * src->n; i++) {
            for (int c = 0; c < 3; c++) {
                double v = src->albedo[f][3 * i + c] + FID_NOISE_ALBEDO * noise(f, i, c);
                dst->albedo[f][3 * i + c] = (float)(v < 0 ? 0 : v > 1 ? 1 : v);
            }
            dst->height[f][i] = (float)(src->height[f][i] + FID_NOISE_HEIGHT_M * noise(f, i, 3));
        }
}

/* Every texel from a hashed texel anywhere on the planet. */
static void shuffled(const pg_planet *src, pg_planet *dst) {
    copy_geometry(src, dst);
    int64_t n = src->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < n * n; i++) {
            uint32_t h = pg_synth_hash(77, 0, f, (long)i, 0, 0);
            int sf = (int)(pg_synth_hash(77, 0, f, (long)i, 1, 0) % 6);
            int64_t t = (int64_t)(h % (uint32_t)(n * n));
            memcpy(dst->albedo[f] + 3 * i, src->albedo[sf] + 3 * t, 3 * sizeof(float));
            dst->height[f][i] = src->height[sf][t];
        }
}

/* The planet blurred on every face (FID_BLUR_SIGMA planet texels). */
static void blurred(const pg_planet *src, pg_planet *dst) {
    copy_geometry(src, dst);
    size_t nn = (size_t)(src->n * src->n);
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        memcpy(dst->albedo[f], src->albedo[f], nn * 3 * sizeof(float));
        memcpy(dst->height[f], src->height[f], nn * sizeof(float));
        blur_face(dst->albedo[f], src->n, 3, FID_BLUR_SIGMA);
        blur_face(dst->height[f], src->n, 1, FID_BLUR_SIGMA);
    }
}

static void fidelity_of(const fixture *fx, const pg_planet *p, pg_inspect_fidelity *out) {
    pg_error err = {0};
    pg_status st = pg_inspect_fidelity_compute(p, &fx->ex, out, &err);
    if (st != PG_OK) fail_msg("%s", err.msg);
}

static const pg_inspect_fidelity *earth_fid(fixture *fx) {
    if (!fx->have_fid) fidelity_of(fx, &fx->earth, &fx->earth_fid);
    fx->have_fid = true;
    return &fx->earth_fid;
}

/* The copy of the exemplar scores at most leave-one-out; the baselines are sane. */
static void test_earth_scores_like_the_exemplar(void **state) {
    fixture *fx = *state;
    const pg_inspect_fidelity *e = earth_fid(fx);
    print_fid("Earth on the cube", e);
    assert_int_equal(e->analysis_size, 512);
    assert_int_equal(e->magnification, 2);
    assert_true(e->loo > 0 && e->fidelity > 0);
    assert_true(e->ratio <= FID_GATE_GOOD);
    assert_true(e->completeness_ratio <= FID_GATE_GOOD);
    /* with its own sources excluded, a copy is about as close to the exemplar as the
     * exemplar is to the rest of itself */
    assert_true(fabs(e->ratio - 1) < 0.1 && fabs(e->completeness_ratio - 1) < 0.1);
    /* structureless texture is far from everything */
    assert_true(e->random_ratio >= 5);
}

/* Negative controls: structure destroyed (shuffled) or buried in texel noise must
 * score clearly worse than the gate. Blur shows the one-sided measure's blind spot: a
 * blurred neighbourhood is close to the exemplar's own smooth ones (ocean, plains), so
 * fidelity *improves*; completeness on the detail amplitude (sharp exemplar
 * neighbourhoods whose detail the planet lacks) catches it. */
static void test_negative_controls(void **state) {
    fixture *fx = *state;
    const pg_inspect_fidelity *e = earth_fid(fx);
    pg_planet p;
    pg_inspect_fidelity fs, fn, fb;
    shuffled(&fx->earth, &p);
    fidelity_of(fx, &p, &fs);
    pg_planet_free(&p);
    noisy(&fx->earth, &p);
    fidelity_of(fx, &p, &fn);
    pg_planet_free(&p);
    blurred(&fx->earth, &p);
    fidelity_of(fx, &p, &fb);
    pg_planet_free(&p);
    print_fid("Earth on the cube", e);
    print_fid("shuffled texels (control)", &fs);
    print_fid("texel noise (control)", &fn);
    print_fid("blurred sigma 2 (control)", &fb);
    /* the baselines come from the exemplar alone: identical for every planet */
    assert_true(fs.loo == e->loo && fn.random == e->random && fb.loo == e->loo);
    assert_true(fs.ratio >= FID_GATE_BAD && fs.ratio >= 0.5 * fs.random_ratio);
    assert_true(fn.ratio >= FID_GATE_BAD);
    assert_true(fs.completeness_ratio >= FID_GATE_BAD && fn.completeness_ratio >= FID_GATE_BAD);
    /* blur: fidelity does not see it (smooth neighbourhoods match the exemplar's smooth
     * ones), and neither does the L2 completeness; the detail amplitude does, and a copy
     * blurred by 2 texels fails the completeness gate */
    assert_true(fb.ratio < FID_GATE_GOOD);
    assert_true(fb.detail_completeness_ratio > e->detail_completeness_ratio);
    assert_true(fb.completeness_ratio > FID_GATE_GOOD);
}

/* The same figures, bit for bit, with 1 and 2 threads. */
static void test_thread_count_independent(void **state) {
    fixture *fx = *state;
    pg_inspect_fidelity a, b;
    int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    fidelity_of(fx, &fx->earth, &a);
    omp_set_num_threads(2);
    fidelity_of(fx, &fx->earth, &b);
    omp_set_num_threads(saved);
    assert_memory_equal(&a, &b, sizeof a);
    assert_memory_equal(&a, earth_fid(fx), sizeof a);
}

/* Faces too small for the neighbourhoods: a clear error, not a crash. */
static void test_tiny_planet_rejected(void **state) {
    fixture *fx = *state;
    pg_planet p;
    pg_error err = {0};
    assert_int_equal(
        pg_planet_alloc(&p, PG_CUBE_DEFAULT_PROJECTION, 1, 4, pg_ellipsoid_sphere(), &err), PG_OK);
    pg_inspect_fidelity f;
    assert_int_equal(pg_inspect_fidelity_compute(&p, &fx->ex, &f, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "too small"));
    pg_planet_free(&p);
}

/* ---- Earth's side and its caches (pg_realism.h) ---- */

static void earth_side(const fixture *fx, const pg_planet *g, const char *dir, pg_realism *r,
                       pg_inspect_fid_exemplar **f, bool *cached) {
    pg_error err = {0};
    if (pg_realism_earth_cached(g, &fx->ex, dir, NULL, NULL, r, f, cached, &err) != PG_OK)
        fail_msg("%s", err.msg);
}

/* The second call reads what the first wrote, bit for bit; a damaged file or another
 * geometry is computed afresh, never read. */
static void test_earth_cache(void **state) {
    fixture *fx = *state;
    char dir[1024], path[1200];
    pg_test_scratch_dir("inspect_cache", dir, sizeof dir);
    pg_planet g;
    pg_error err = {0};
    assert_int_equal(
        pg_planet_alloc(&g, PG_CUBE_DEFAULT_PROJECTION, 1, 32, pg_ellipsoid_sphere(), &err), PG_OK);
    pg_realism *a = calloc(3, sizeof *a), *b = a + 1, *c = a + 2;
    pg_inspect_fid_exemplar *fa, *fb, *fc;
    bool cached;
    earth_side(fx, &g, dir, a, &fa, &cached);
    assert_false(cached);
    earth_side(fx, &g, dir, b, &fb, &cached);
    assert_true(cached);
    assert_memory_equal(a, b, sizeof *a);
    assert_true(a->pole_distortion_ratio < 1.01 && a->copy.earth_copy_fraction > 0.5);
    /* the cached exemplar side gives the same fidelity as the fresh one */
    pg_inspect_fidelity x, y;
    g.sea_level = fx->ex.sea_level;
    assert_int_equal(pg_planet_from_exemplar(&g, &fx->ex, 2, &err), PG_OK);
    assert_int_equal(pg_inspect_fidelity_with(&g, fa, &x, &err), PG_OK);
    assert_int_equal(pg_inspect_fidelity_with(&g, fb, &y, &err), PG_OK);
    assert_memory_equal(&x, &y, sizeof x);
    /* truncate every cache file: computed again, same figures */
    snprintf(path, sizeof path, "for f in '%s'/realism-*.bin; do truncate -s 100 \"$f\"; done",
             dir);
    assert_int_equal(system(path), 0);
    earth_side(fx, &g, dir, c, &fc, &cached);
    assert_false(cached);
    assert_true(c->fidelity.loo == a->fidelity.loo &&
                c->earthlike.land_fraction == a->earthlike.land_fraction);
    pg_inspect_fid_exemplar_free(fc);
    /* another projection is another key */
    pg_planet h;
    assert_int_equal(pg_planet_alloc(&h, PG_CUBE_GNOMONIC, 1, 32, pg_ellipsoid_sphere(), &err),
                     PG_OK);
    earth_side(fx, &h, dir, c, &fc, &cached);
    assert_false(cached);
    pg_inspect_fid_exemplar_free(fa), pg_inspect_fid_exemplar_free(fb);
    pg_inspect_fid_exemplar_free(fc);
    pg_planet_free(&g), pg_planet_free(&h);
    free(a);
}

/* ---- the CLI ---- */

static double json_number(const char *path, const char *key) {
    static char buf[1 << 20];
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    char pat[128];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *p = strstr(buf, pat);
    assert_non_null(p);
    return strtod(p + strlen(pat), NULL);
}

static void test_cli_report(void **state) {
    fixture *fx = *state;
    char json[1200], args[4096], out[8192], errb[2048];
    snprintf(json, sizeof json, "%s/../inspect_earth.json", fx->dir);
    snprintf(args, sizeof args, "inspect '%s' --json '%s' --cache-dir '%s/synth-cache'", fx->dir,
             json, getenv("PG_BUILD_DIR"));
    int rc = pg_test_run_cli(args, out, sizeof out, errb, sizeof errb);
    printf("%s%s", out, errb);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(out, "fixed Gabor features"));
    /* the saved Earth copy carries its identity map: a copy, undistorted, seamless */
    assert_true(json_number(json, "pole_distortion_ratio") < 1.01);
    assert_true(json_number(json, "earth_copy_fraction") >= 0.5);
    assert_true(json_number(json, "face_seam_ratio") <= PG_INSPECT_FACE_SEAM_GATE);
    assert_true(json_number(json, "face_seam_coherence") >= PG_INSPECT_FACE_COHERENCE_GATE);
    assert_true(json_number(json, "seam_ratio") <= PG_INSPECT_SEAM_GATE);
    assert_true(json_number(json, "depressions") >= 0);
    double fid = json_number(json, "fidelity_ratio");
    assert_true(fid > 0 && fid <= FID_GATE_GOOD);
    char views[1200];
    snprintf(views, sizeof views, "%s/inspect", fx->dir);
    /* the planet's and the exemplar's views (no resampling floor), poles.png, rivers.png */
    assert_int_equal(pg_test_count_files(views), 2 * PG_VIEWS_COUNT + 2);
    snprintf(views, sizeof views, "%s/inspect/rivers.png", fx->dir);
    assert_true(pg_test_file_nonempty(views));
    /* again: Earth's side now comes from the cache, as the struct's bytes, so nothing in
     * it may be a pointer (the worst seam's field once was, and this run crashed) */
    rc = pg_test_run_cli(args, out, sizeof out, errb, sizeof errb);
    assert_int_equal(rc, 0);
    assert_true(json_number(json, "face_seam_ratio") <= PG_INSPECT_FACE_SEAM_GATE);
    static char buf[1 << 20];
    FILE *f = fopen(json, "r");
    assert_non_null(f);
    buf[fread(buf, 1, sizeof buf - 1, f)] = 0;
    fclose(f);
    /* the cache was used (a stale pointer can still read right where the literal has
     * the same address in every process, without ASLR: the struct must hold none) */
    assert_non_null(strstr(buf, "\"earth_from_cache\": true"));
    int fields = 0;
    for (const char *p = buf; (p = strstr(p, "\"worst_seam_field\": \"")); p++) {
        const char *v = p + strlen("\"worst_seam_field\": \"");
        assert_true(!strncmp(v, "height\"", 7) || !strncmp(v, "albedo\"", 7));
        fields++;
    }
    assert_int_equal(fields, 2); /* the planet's and Earth's */
}

static void expect_bad(const char *args, const char *needle) {
    char errb[2048];
    int rc = pg_test_run_cli(args, NULL, 0, errb, sizeof errb);
    printf("%s -> %d: %s", args, rc, errb);
    assert_int_equal(rc, 2);
    assert_non_null(strstr(errb, needle));
}

static void test_cli_bad_input(void **state) {
    fixture *fx = *state;
    char dir[1024], args[4096], src[1200], dst[1200];
    pg_test_scratch_dir("inspect_bad", dir, sizeof dir);
    snprintf(args, sizeof args, "inspect '%s'", dir);
    expect_bad(args, "not a planet output");
    /* planet.json alone: the first missing face file is named */
    snprintf(src, sizeof src, "%s/planet.json", fx->dir);
    snprintf(dst, sizeof dst, "%s/planet.json", dir);
    char cmd[3000];
    snprintf(cmd, sizeof cmd, "cp '%s' '%s'", src, dst);
    assert_int_equal(system(cmd), 0);
    expect_bad(args, "missing albedo_+X.png");
    snprintf(args, sizeof args, "inspect '%s/nope'", dir);
    expect_bad(args, "not a directory");
    const char *sizes[] = {"300", "0", "-4", "255"};
    for (int i = 0; i < 4; i++) {
        snprintf(args, sizeof args, "inspect '%s' --view-size %s", fx->dir, sizes[i]);
        expect_bad(args, "--view-size: must be a positive power of two");
    }
    snprintf(args, sizeof args, "inspect '%s' --view-size 128", fx->dir);
    expect_bad(args, "--view-size: must be 256..2048");
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_pole_gate_and_negative_control),
                                       cmocka_unit_test(test_isotropic_degradation_passes),
                                       cmocka_unit_test(test_seam_statistic),
                                       cmocka_unit_test(test_earth_scores_like_the_exemplar),
                                       cmocka_unit_test(test_negative_controls),
                                       cmocka_unit_test(test_thread_count_independent),
                                       cmocka_unit_test(test_tiny_planet_rejected),
                                       cmocka_unit_test(test_earth_cache),
                                       cmocka_unit_test(test_cli_report),
                                       cmocka_unit_test(test_cli_bad_input)};
    return cmocka_run_group_tests(tests, setup, teardown);
}
