/* test_inspect_distortion.c - the content-blind distortion check
 * (pg_inspect_distortion.h) on coordinate maps built in memory, with known answers.
 *
 * Faithful copies must pass with every view at 1: the exact copy (identity map, the
 * exemplar cube's grid = the planet's), the same magnified 2x (one source per 2x2
 * block), each face turned a quarter or mirrored (J orthogonal). A faithful copy from
 * an exemplar cube of another projection, rounded to whole exemplar texels, keeps
 * scale 1 and ratio 1 but its rounding noise lifts the figures (to <= 1.3).
 * A known anisotropic map (u kept, v halved) gives s1 = 1, s2 = 1/2 at a face centre.
 * Control 1, content laid out in lat-lon space (patches of the lat-lon grid filled as
 * a flat image, one equatorial exemplar texel per pixel), must fail: at latitude phi
 * it is squeezed east-west by cos(phi), figure cos(phi)^-1.5, and near the poles no
 * window is an affine copy: the pole caps have no coherent texel, the ratio is NaN.
 * Control 2, faces of a gnomonic planet filled texel for texel from an exemplar face's
 * centre, must fail at the cube corners, whose texels are 60/120-degree rhombi of a
 * fifth of the centre's area. The same construction on the default equi-angular grid
 * is measured and reported. Bad maps are BADINPUT; no map gives NaN; the result does
 * not depend on the thread count. */
#include "pg_test.h"

#include "planetgen/pg_inspect_distortion.h"
#include "planetgen/pg_synth.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

#define PATCH 32 /* control patches: texels (pixels) per patch edge */
#define SEED 20261202u

/* Source of planet texel (face, x, y) with centre direction d. */
typedef uint32_t (*map_fn)(const pg_planet *p, int face, int64_t x, int64_t y, const double d[3],
                           const void *user);

static void make_planet(pg_planet *p, pg_cube_projection proj, int n) {
    pg_error err = {0};
    memset(p, 0, sizeof *p);
    assert_int_equal(pg_planet_alloc(p, proj, 1, n, pg_ellipsoid_sphere(), &err), PG_OK);
}

static void fill_map(pg_planet *p, int e, pg_cube_projection eproj, map_fn fn, const void *user) {
    pg_error err = {0};
    assert_int_equal(pg_planet_source_alloc(p, e, eproj, &err), PG_OK);
    const int64_t n = p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                double d[3];
                pg_cube_to_dir(p->projection, f, (2.0 * x + 1) / n - 1, (2.0 * y + 1) / n - 1, d);
                p->source.coords[f][y * n + x] = fn(p, f, x, y, d, user);
            }
}

/* Nearest exemplar texel of a direction (as pg_planet_source_identity rounds). */
static uint32_t nearest_source(const pg_planet *p, const double d[3]) {
    int f, e = p->source.face_size, t[2];
    double uv[2];
    pg_cube_from_dir(p->source.projection, d, &f, &uv[0], &uv[1]);
    for (int i = 0; i < 2; i++) {
        t[i] = (int)((uv[i] + 1.0) * 0.5 * e);
        t[i] = t[i] < 0 ? 0 : (t[i] >= e ? e - 1 : t[i]);
    }
    return pg_synth_pack(f, t[0], t[1]);
}

static void compute(const pg_planet *p, const char *label, pg_inspect_distortion *d) {
    pg_error err = {0};
    assert_int_equal(pg_inspect_distortion_compute(p, d, &err), PG_OK);
    print_message("%s (N = %lld, %s; exemplar E = %d, %s; m = %d): ratio %.3f, worst %s %.3f, "
                  "reference %.3f\n",
                  label, (long long)p->n, pg_cube_projection_name(p->projection),
                  p->source.face_size, pg_cube_projection_name(p->source.projection),
                  d->magnification, d->ratio, d->worst_name, d->worst_figure, d->reference);
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++) {
        const pg_inspect_distortion_view *v = &d->views[i];
        print_message("  %-13s figure %7.3f  s %6.3f  a %6.3f  coherent %5lld / %5lld (%.3f), "
                      "degenerate %lld\n",
                      v->name, v->figure, v->mean_scale, v->mean_anisotropy, (long long)v->coherent,
                      (long long)v->texels, v->share, (long long)v->degenerate);
    }
}

static double mean_of_kind(const pg_inspect_distortion *d, pg_inspect_distortion_kind k) {
    double s = 0;
    int c = 0;
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++)
        if (d->views[i].kind == k) {
            s += d->views[i].figure;
            c++;
        }
    return s / c;
}

/* ---- faithful copies ---- */

static void assert_faithful(const pg_inspect_distortion *d, double tol, double min_share) {
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++) {
        const pg_inspect_distortion_view *v = &d->views[i];
        assert_true(v->texels > 0);
        assert_true(v->share >= min_share);
        assert_true(fabs(v->figure - 1) <= tol);
        assert_true(fabs(v->mean_scale - 1) <= tol);
    }
    assert_true(fabs(d->ratio - 1) <= tol);
    assert_true(d->gate_pass);
}

static void test_identity(void **state) {
    (void)state;
    const pg_cube_projection projs[3] = {PG_CUBE_EQUIANGULAR, PG_CUBE_GNOMONIC, PG_CUBE_EQUALAREA};
    for (int k = 0; k < 3; k++) {
        pg_planet p;
        pg_error err = {0};
        pg_inspect_distortion d;
        make_planet(&p, projs[k], 128);
        assert_int_equal(pg_planet_source_identity(&p, 128, projs[k], &err), PG_OK);
        compute(&p, "identity", &d);
        assert_int_equal(d.magnification, 1);
        assert_faithful(&d, 1e-3, 1.0);
        pg_planet_free(&p);
    }
}

/* A patch seam one texel from a face edge: the edge column's sources jump 40 texels
 * along u (a jump along v would make J a shear, rejected as degenerate anyway).
 * A window two texels wide (the 3 x 3 clipped at the edge) fits that jump as a linear
 * map with a tiny residual; such texels must not count as coherent copies (they once
 * did, and a single one raised a cap's mean figure from 1.5 to 38). */
static void test_edge_column_jump_not_coherent(void **state) {
    (void)state;
    pg_planet p;
    pg_error err = {0};
    make_planet(&p, PG_CUBE_EQUIANGULAR, 64);
    assert_int_equal(pg_planet_source_identity(&p, 64, PG_CUBE_EQUIANGULAR, &err), PG_OK);
    for (int64_t y = 0; y < 64; y++) { /* face +X, column x = 0: sources 40 texels on */
        uint32_t c = p.source.coords[0][y * 64];
        p.source.coords[0][y * 64] =
            pg_synth_pack(pg_synth_face(c), (pg_synth_u(c) + 40) % 64, pg_synth_v(c));
    }
    for (int64_t y = 8; y < 56; y += 8) {
        pg_inspect_distortion_texel t;
        pg_inspect_distortion_texel_at(&p, 1, 0, 0, y, &t);
        assert_false(t.coherent);
        pg_inspect_distortion_texel_at(&p, 1, 0, 2, y, &t); /* its window stays clear */
        assert_true(t.coherent);
        assert_true(fabs(t.figure - 1) < 0.05);
    }
    pg_planet_free(&p);
}

/* One source per 2x2 block: the windows run on the block grid. */
static void test_identity_magnified(void **state) {
    (void)state;
    pg_planet p;
    pg_error err = {0};
    pg_inspect_distortion d;
    make_planet(&p, PG_CUBE_EQUIANGULAR, 256);
    assert_int_equal(pg_planet_source_identity(&p, 128, PG_CUBE_EQUIANGULAR, &err), PG_OK);
    compute(&p, "identity magnified", &d);
    assert_int_equal(d.magnification, 2);
    assert_faithful(&d, 1e-3, 1.0);
    /* One 2x2 block with two sources, and the map is not magnified. */
    p.source.coords[3][2 * 256 + 1] = pg_synth_pack(3, 5, 5);
    assert_int_equal(pg_inspect_distortion_magnification(&p), 1);
    pg_planet_free(&p);
}

/* Quarter turn (x, y) -> (n-1-y, x), or a mirror x -> n-1-x, within each face: the
 * equi-angular face grid has both symmetries, so J is orthogonal everywhere. */
static uint32_t turned(const pg_planet *p, int f, int64_t x, int64_t y, const double d[3],
                       const void *user) {
    (void)d;
    int n = (int)p->n;
    return *(const int *)user ? pg_synth_pack(f, n - 1 - (int)x, (int)y)
                              : pg_synth_pack(f, n - 1 - (int)y, (int)x);
}

static void test_turned_and_mirrored(void **state) {
    (void)state;
    for (int mirror = 0; mirror < 2; mirror++) {
        pg_planet p;
        pg_inspect_distortion d;
        make_planet(&p, PG_CUBE_EQUIANGULAR, 128);
        fill_map(&p, 128, PG_CUBE_EQUIANGULAR, turned, &mirror);
        compute(&p, mirror ? "mirrored faces" : "turned faces", &d);
        assert_faithful(&d, 1e-3, 1.0);
        pg_inspect_distortion_texel t;
        pg_inspect_distortion_texel_at(&p, 1, 2, 40, 90, &t);
        assert_true(t.coherent && fabs(t.figure - 1) < 1e-6);
        assert_true(t.mirrored == (mirror == 1));
        pg_planet_free(&p);
    }
}

/* A faithful copy from an exemplar cube of another projection and size: the true map
 * is the identity on the sphere, rounded to whole exemplar texels. */
static uint32_t nearest(const pg_planet *p, int f, int64_t x, int64_t y, const double d[3],
                        const void *user) {
    (void)f, (void)x, (void)y, (void)user;
    return nearest_source(p, d);
}

static void test_quantised_copy(void **state) {
    (void)state;
    const pg_cube_projection eprojs[2] = {PG_CUBE_GNOMONIC, PG_CUBE_EQUALAREA};
    const int sizes[2] = {301, 237};
    for (int k = 0; k < 2; k++) {
        pg_planet p;
        pg_inspect_distortion d;
        make_planet(&p, PG_CUBE_EQUIANGULAR, 256);
        fill_map(&p, sizes[k], eprojs[k], nearest, NULL);
        compute(&p, "quantised copy", &d);
        assert_int_equal(d.magnification, 1);
        for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++) {
            const pg_inspect_distortion_view *v = &d.views[i];
            assert_true(v->share >= 0.98);
            assert_true(fabs(v->mean_scale - 1) <= 0.05);
            assert_true(v->figure <= 1.3);
        }
        assert_true(fabs(d.ratio - 1) <= 0.05);
        pg_planet_free(&p);
    }
}

/* ---- a known anisotropic map ---- */

/* Exemplar cube of 2n: u index 2x (the planet's grid coordinate less half an exemplar
 * texel: the same u step), v index
 * y + n/2 (half the planet's v step, starting at the face centre's row). */
static uint32_t halve_v(const pg_planet *p, int f, int64_t x, int64_t y, const double d[3],
                        const void *user) {
    (void)d, (void)user;
    return pg_synth_pack(f, 2 * (int)x, (int)(y + p->n / 2));
}

static void test_known_anisotropy(void **state) {
    (void)state;
    pg_planet p;
    pg_inspect_distortion_texel t;
    make_planet(&p, PG_CUBE_EQUIANGULAR, 128);
    fill_map(&p, 256, PG_CUBE_EQUIANGULAR, halve_v, NULL);
    /* Planet texel (64, 64) sits at grid (0.008, 0.008), its source at (0.004, 0.004):
     * both at a face centre, where the equi-angular grid is uniform and isotropic. */
    pg_inspect_distortion_texel_at(&p, 1, 0, 64, 64, &t);
    print_message("halved v: s1 %.4f s2 %.4f figure %.4f residual %.3f span %.3f\n", t.s1, t.s2,
                  t.figure, t.residual, t.span);
    assert_true(t.coherent);
    assert_true(fabs(t.s1 - 1.0) < 0.01);
    assert_true(fabs(t.s2 - 0.5) < 0.01);
    assert_true(fabs(t.figure - 2 * sqrt(2.0)) < 0.05);
    assert_int_equal(t.points, 25);
    /* At a face corner only the part of the 5x5 inside the face is used. */
    pg_inspect_distortion_texel_at(&p, 1, 0, 0, 0, &t);
    assert_int_equal(t.points, 9);
    pg_planet_free(&p);
}

/* ---- control 1: content laid out in lat-lon space ---- */

typedef struct latlon {
    int w, h; /* lat-lon grid: one equatorial exemplar texel per pixel */
} latlon;

static uint32_t latlon_source(const pg_planet *p, int f, int64_t x, int64_t y, const double d[3],
                              const void *user) {
    (void)f, (void)x, (void)y;
    const latlon *g = user;
    double lat = asin(d[2] / sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    double lon = atan2(d[1], d[0]);
    double ic = (lon + PI) / (2 * PI) * g->w, jc = (PI / 2 - lat) / PI * g->h;
    long pi = (long)(ic / PATCH), pj = (long)(jc / PATCH);
    pi = pi >= g->w / PATCH ? g->w / PATCH - 1 : pi;
    pj = pj >= g->h / PATCH ? g->h / PATCH - 1 : pj;
    /* The patch's place in the exemplar: its south-west corner at a hashed longitude and
     * within half a patch south of the equator; pixel offsets become ground offsets of
     * one equatorial pixel (2 pi / W radians) east and north of it. */
    double lon0 = 2 * PI * (pg_synth_hash(SEED, 0, 0, pi, pj, 1) / 4294967296.0);
    double lat0 = -(PI / g->h) * PATCH * (pg_synth_hash(SEED, 0, 0, pi, pj, 2) / 4294967296.0);
    double a[3] = {cos(lat0) * cos(lon0), cos(lat0) * sin(lon0), sin(lat0)};
    double e[3] = {-sin(lon0), cos(lon0), 0};
    double n[3] = {-sin(lat0) * cos(lon0), -sin(lat0) * sin(lon0), cos(lat0)};
    double te = (ic - pi * PATCH) * 2 * PI / g->w, tn = ((pj + 1) * PATCH - jc) * PI / g->h;
    double t = sqrt(te * te + tn * tn), s[3];
    for (int i = 0; i < 3; i++)
        s[i] = cos(t) * a[i] + (t > 0 ? sin(t) / t : 1.0) * (te * e[i] + tn * n[i]);
    return nearest_source(p, s);
}

static void test_latlon_control_fails(void **state) {
    (void)state;
    pg_planet p;
    pg_inspect_distortion d;
    make_planet(&p, PG_CUBE_EQUIANGULAR, 256);
    latlon g = {4 * 256, 2 * 256};
    fill_map(&p, 256, PG_CUBE_EQUIANGULAR, latlon_source, &g);
    compute(&p, "lat-lon layout", &d);
    /* Squeezed east-west by cos(phi): s = cos^-1/2, a = cos^-1, figure cos^-3/2, plus
     * the rounding noise of a non-integer map (up to ~15%, test_quantised_copy). */
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++) {
        const pg_inspect_distortion_view *v = &d.views[i];
        if (v->kind == PG_INSPECT_DISTORTION_POLE) {
            /* Windows within 4 degrees of a pole span more longitude than a patch and
             * their sources are not affine: nothing there is a copy. */
            assert_true(v->share < 0.05);
            continue;
        }
        double phi = asin(fabs(v->dir[2]));
        double want = pow(cos(phi), -1.5);
        assert_true(v->share > 0.7);
        assert_true(v->figure >= 0.97 * want && v->figure <= 1.2 * want);
    }
    assert_string_equal(d.worst_name, "north");
    assert_true(isnan(d.ratio));
    assert_true(d.share_ratio < 0.1);
    assert_false(d.gate_pass);
    pg_planet_free(&p);
}

/* ---- control 2: texel for texel from an exemplar face's centre ---- */

static uint32_t texel_for_texel(const pg_planet *p, int f, int64_t x, int64_t y, const double d[3],
                                const void *user) {
    (void)p, (void)f, (void)d, (void)user;
    int e = p->source.face_size;
    return pg_synth_pack(0, e / 2 - PATCH / 2 + (int)(x % PATCH),
                         e / 2 - PATCH / 2 + (int)(y % PATCH));
}

/* Bounds on a view kind's mean scale and anisotropy. */
typedef struct expect {
    double s_lo, s_hi, a_lo, a_hi;
} expect;

static void assert_expect(const pg_inspect_distortion_view *v, const expect *e) {
    assert_true(v->mean_scale > e->s_lo && v->mean_scale <= e->s_hi);
    assert_true(v->mean_anisotropy > e->a_lo && v->mean_anisotropy <= e->a_hi);
}

/* Fill a planet of this projection texel for texel from an exemplar face of e, check the
 * face centres are faithful, edges and corners as expected, a corner the worst view. */
static void texel_for_texel_case(pg_cube_projection proj, int e, const char *label,
                                 const expect *edge, const expect *corner,
                                 pg_inspect_distortion *d) {
    pg_planet p;
    make_planet(&p, proj, 256);
    fill_map(&p, e, PG_CUBE_EQUIANGULAR, texel_for_texel, NULL);
    compute(&p, label, d);
    print_message("  mean figure: equator %.3f, edges %.3f, corners %.3f\n",
                  mean_of_kind(d, PG_INSPECT_DISTORTION_EQUATOR),
                  mean_of_kind(d, PG_INSPECT_DISTORTION_EDGE),
                  mean_of_kind(d, PG_INSPECT_DISTORTION_CORNER));
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++) {
        const pg_inspect_distortion_view *v = &d->views[i];
        if (v->kind == PG_INSPECT_DISTORTION_EDGE)
            assert_expect(v, edge);
        else if (v->kind == PG_INSPECT_DISTORTION_CORNER)
            assert_expect(v, corner);
        else
            assert_true(fabs(v->figure - 1) < 0.03);
    }
    assert_int_equal(d->views[d->worst].kind, PG_INSPECT_DISTORTION_CORNER);
    pg_planet_free(&p);
}

static void test_gnomonic_texel_for_texel_fails(void **state) {
    (void)state;
    /* Gnomonic texels at an edge midpoint: 1/2 x 1/sqrt(2) of the centre's (s = 2^(3/4) =
     * 1.68, a = sqrt 2); at a corner: 60/120 rhombi of area 3^(-3/2) (s = 3^(3/4) = 2.28,
     * a = sqrt 3). The caps average towards the milder inside, so a little less. A
     * gnomonic face centre spans 2/N rad per texel, an equi-angular one pi/(2E): with
     * E = pi N / 4 = 201 the face centres are copied at scale 1. */
    const expect edge = {1.5, 1.69, 1.3, 1.42}, corner = {1.9, 2.28, 1.5, 1.74};
    pg_inspect_distortion d;
    texel_for_texel_case(PG_CUBE_GNOMONIC, 201, "gnomonic texel for texel", &edge, &corner, &d);
    assert_true(d.ratio > 1.5);
    assert_false(d.gate_pass);
}

static void test_equiangular_texel_for_texel(void **state) {
    (void)state;
    /* Equi-angular texels: square at a face centre; at an edge midpoint pi/4 across the
     * edge but pi/(4 sqrt 2) along it (a = sqrt 2, s = 2^(1/4) = 1.19); at a corner 60/120
     * rhombi with sides 0.94 of the centre's (a = sqrt 3, s = 1.14). */
    const expect edge = {1.1, 1.19, 1.3, 1.42}, corner = {1.05, 1.15, 1.5, 1.74};
    pg_inspect_distortion d;
    texel_for_texel_case(PG_CUBE_EQUIANGULAR, 256, "equi-angular texel for texel", &edge, &corner,
                         &d);
    assert_false(d.gate_pass);
}

/* ---- no map, bad maps, threads ---- */

static void test_no_map(void **state) {
    (void)state;
    pg_planet p;
    pg_error err = {0};
    pg_inspect_distortion d;
    make_planet(&p, PG_CUBE_EQUIANGULAR, 128);
    assert_int_equal(pg_inspect_distortion_compute(&p, &d, &err), PG_OK);
    assert_true(isnan(d.ratio) && isnan(d.views[0].figure));
    assert_int_equal(d.views[0].texels, 0);
    assert_int_equal(d.worst, -1);
    assert_false(d.gate_pass);
    pg_planet_free(&p);
}

static void test_bad_map(void **state) {
    (void)state;
    const uint32_t bad[3] = {pg_synth_pack(6, 0, 0), pg_synth_pack(0, 128, 5),
                             pg_synth_pack(3, 7, 200)};
    for (int k = 0; k < 3; k++) {
        pg_planet p;
        pg_error err = {0};
        pg_inspect_distortion d;
        make_planet(&p, PG_CUBE_EQUIANGULAR, 128);
        assert_int_equal(pg_planet_source_identity(&p, 128, PG_CUBE_EQUIANGULAR, &err), PG_OK);
        p.source.coords[4][5 * 128 + 9] = bad[k];
        assert_int_equal(pg_inspect_distortion_compute(&p, &d, &err), PG_ERR_BADINPUT);
        print_message("%s\n", err.msg);
        assert_non_null(strstr(err.msg, "(+Z, 9, 5)"));
        pg_planet_free(&p);
    }
}

static void test_threads(void **state) {
    (void)state;
    pg_planet p;
    pg_error err = {0};
    pg_inspect_distortion d1, d2;
    make_planet(&p, PG_CUBE_EQUIANGULAR, 128);
    latlon g = {4 * 128, 2 * 128};
    fill_map(&p, 128, PG_CUBE_EQUIANGULAR, latlon_source, &g);
    int before = omp_get_max_threads();
    omp_set_num_threads(1);
    assert_int_equal(pg_inspect_distortion_compute(&p, &d1, &err), PG_OK);
    omp_set_num_threads(3);
    assert_int_equal(pg_inspect_distortion_compute(&p, &d2, &err), PG_OK);
    omp_set_num_threads(before);
    assert_memory_equal(&d1, &d2, sizeof d1);
    pg_planet_free(&p);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_identity),
        cmocka_unit_test(test_identity_magnified),
        cmocka_unit_test(test_edge_column_jump_not_coherent),
        cmocka_unit_test(test_turned_and_mirrored),
        cmocka_unit_test(test_quantised_copy),
        cmocka_unit_test(test_known_anisotropy),
        cmocka_unit_test(test_latlon_control_fails),
        cmocka_unit_test(test_gnomonic_texel_for_texel_fails),
        cmocka_unit_test(test_equiangular_texel_for_texel),
        cmocka_unit_test(test_no_map),
        cmocka_unit_test(test_bad_map),
        cmocka_unit_test(test_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
