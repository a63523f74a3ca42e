/* test_climate.c - the climate model (pg_climate.h): its calibration and validation on
 * Earth against Marble's climate maps (fit on the northern hemisphere, correlations
 * on the southern), and its physical properties on constructed worlds: temperature
 * falls towards the poles and is symmetric at tilt 0, the lapse rate, a rain shadow,
 * a dry continental interior, the temperature offset, the axial tilt, and thread
 * independence. docs/world.md, "Climate", reports the figures printed here.
 * Over 600 lines because one file holds every case of the module, each independent. */
#include "pg_test.h"

#include "planetgen/pg_climate.h"
#include "pg_marble.h"
#include "planetgen/pg_equirect.h"
#include "planetgen/pg_exemplar.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PROJ PG_CUBE_DEFAULT_PROJECTION
#define EARTH_N 64
#define FLAT_N 48

/* ---------------------------------------------------------------- helpers */

static void texel_dir(int64_t n, int64_t id, double dir[3]) {
    int64_t face = id / (n * n), r = id % (n * n);
    double u = (2.0 * (double)(r % n) + 1.0) / (double)n - 1.0;
    double v = (2.0 * (double)(r / n) + 1.0) / (double)n - 1.0;
    pg_cube_to_dir(PROJ, (int)face, u, v, dir);
}

static void dir_latlon(const double d[3], double *lat, double *lon) {
    *lat = asin(fmax(-1.0, fmin(1.0, d[2]))) * 180.0 / M_PI;
    *lon = atan2(d[1], d[0]) * 180.0 / M_PI;
}

static void texel_latlon(int64_t n, int64_t id, double *lat, double *lon) {
    double d[3];
    texel_dir(n, id, d);
    dir_latlon(d, lat, lon);
}

/* Solid angle of a texel: two spherical triangles over its corners. */
static double texel_area(int64_t n, int64_t id) {
    int64_t face = id / (n * n), r = id % (n * n), x = r % n, y = r / n;
    double c[4][3];
    for (int k = 0; k < 4; k++) {
        double u = 2.0 * (double)(x + (k == 1 || k == 2)) / (double)n - 1.0;
        double v = 2.0 * (double)(y + (k >= 2)) / (double)n - 1.0;
        pg_cube_to_dir(PROJ, (int)face, u, v, c[k]);
    }
    return pg_cube_spherical_triangle(c[0], c[1], c[2]) +
           pg_cube_spherical_triangle(c[0], c[2], c[3]);
}

static double weighted_pearson(const double *a, const double *b, const double *w, size_t m) {
    double sw = 0, ma = 0, mb = 0;
    for (size_t i = 0; i < m; i++) {
        sw += w[i];
        ma += w[i] * a[i];
        mb += w[i] * b[i];
    }
    ma /= sw;
    mb /= sw;
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < m; i++) {
        sab += w[i] * (a[i] - ma) * (b[i] - mb);
        saa += w[i] * (a[i] - ma) * (a[i] - ma);
        sbb += w[i] * (b[i] - mb) * (b[i] - mb);
    }
    return sab / sqrt(saa * sbb);
}

typedef struct keyed {
    double v;
    size_t i;
} keyed;

static int cmp_keyed(const void *x, const void *y) {
    const keyed *a = x, *b = y;
    if (a->v != b->v) return a->v < b->v ? -1 : 1;
    return a->i < b->i ? -1 : (a->i > b->i);
}

/* Area-weighted ranks: the weighted mid-rank (cumulative weight below plus half the
 * weight of the tie group), so that ties share a rank. */
static void weighted_ranks(const double *a, const double *w, size_t m, double *rank) {
    keyed *k = malloc(m * sizeof *k);
    for (size_t i = 0; i < m; i++)
        k[i] = (keyed){a[i], i};
    qsort(k, m, sizeof *k, cmp_keyed);
    double below = 0;
    for (size_t s = 0; s < m;) {
        size_t e = s;
        double tw = 0;
        while (e < m && k[e].v == k[s].v)
            tw += w[k[e++].i];
        for (size_t j = s; j < e; j++)
            rank[k[j].i] = below + 0.5 * tw;
        below += tw;
        s = e;
    }
    free(k);
}

static double weighted_spearman(const double *a, const double *b, const double *w, size_t m) {
    double *ra = malloc(m * sizeof *ra), *rb = malloc(m * sizeof *rb);
    weighted_ranks(a, w, m, ra);
    weighted_ranks(b, w, m, rb);
    double r = weighted_pearson(ra, rb, w, m);
    free(ra);
    free(rb);
    return r;
}

/* Solve the k x k system A x = b (Gaussian elimination with partial pivoting). */
static void solve(int k, double A[][5], double *b, double *x) {
    for (int c = 0; c < k; c++) {
        int piv = c;
        for (int r = c + 1; r < k; r++)
            if (fabs(A[r][c]) > fabs(A[piv][c])) piv = r;
        for (int j = 0; j < k; j++) {
            double t = A[c][j];
            A[c][j] = A[piv][j];
            A[piv][j] = t;
        }
        double t = b[c];
        b[c] = b[piv];
        b[piv] = t;
        for (int r = c + 1; r < k; r++) {
            double f = A[r][c] / A[c][c];
            for (int j = c; j < k; j++)
                A[r][j] -= f * A[c][j];
            b[r] -= f * b[c];
        }
    }
    for (int r = k - 1; r >= 0; r--) {
        double s = b[r];
        for (int j = r + 1; j < k; j++)
            s -= A[r][j] * x[j];
        x[r] = s / A[r][r];
    }
}

/* ---------------------------------------------------------------- Earth */

typedef struct earth {
    int64_t n, total;
    float *elev;                  /* metres above sea level on the cube */
    double *t_obs, *p_obs, *area; /* Marble: (July + December) / 2, deg C and mm/yr */
    double *lat, *lon;
} earth;

static earth g_earth;

/* A Marble map in physical units, area-averaged down by `shrink`. */
static float *marble_map(const char *name, int precip, int shrink, int *w, int *h) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s/%s.jpg", PG_MARBLE_DIR, name, name);
    pg_image im;
    pg_error err = {0};
    if (pg_image_read(path, 0, &im, &err) != PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return NULL;
    }
    size_t np = (size_t)im.width * im.height;
    float *v = malloc(np * sizeof(float)), *out = NULL;
    for (size_t i = 0; i < np; i++) {
        double g = im.data[i * im.channels]; /* 8-bit samples are read as 0..255 */
        v[i] = (float)(precip ? pg_climate_marble_precip_mm(g) : pg_climate_marble_temp_c(g));
    }
    *w = im.width / shrink;
    *h = im.height / shrink;
    pg_equirect_resample(v, im.width, im.height, 1, *w, *h, &out, &err);
    pg_image_free(&im);
    free(v);
    return out;
}

static int earth_setup(void **state) {
    (void)state;
    earth *e = &g_earth;
    pg_error err = {0};
    pg_exemplar ex;
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    if (pg_exemplar_load(&o, &ex, &err) != PG_OK) {
        fprintf(stderr, "cannot load the default exemplar: %s\n", err.msg);
        return -1;
    }
    size_t np = (size_t)ex.width * ex.height;
    for (size_t i = 0; i < np; i++)
        ex.elevation[i] -= ex.sea_level;
    e->n = EARTH_N;
    e->total = 6 * e->n * e->n;
    e->elev = malloc((size_t)e->total * sizeof(float));
    if (pg_cube_from_equirect(PROJ, e->n, NULL, ex.elevation, ex.width, ex.height, 1, 4, e->elev,
                              &err) != PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    pg_exemplar_free(&ex);
    const char *names[4] = {"temp-july", "temp-dec", "precip-july", "precip-dec"};
    float *m[4];
    int w = 0, h = 0;
    for (int k = 0; k < 4; k++)
        if (!(m[k] = marble_map(names[k], k >= 2, 4, &w, &h))) return -1;
    e->t_obs = malloc((size_t)e->total * sizeof(double));
    e->p_obs = malloc((size_t)e->total * sizeof(double));
    e->area = malloc((size_t)e->total * sizeof(double));
    e->lat = malloc((size_t)e->total * sizeof(double));
    e->lon = malloc((size_t)e->total * sizeof(double));
    for (int64_t id = 0; id < e->total; id++) {
        texel_latlon(e->n, id, &e->lat[id], &e->lon[id]);
        e->area[id] = texel_area(e->n, id);
        float s[4];
        for (int k = 0; k < 4; k++)
            pg_equirect_sample(m[k], w, h, 1, e->lat[id], e->lon[id], &s[k]);
        e->t_obs[id] = 0.5 * (s[0] + s[1]);
        e->p_obs[id] = 12.0 * 0.5 * (s[2] + s[3]);
    }
    for (int k = 0; k < 4; k++)
        free(m[k]);
    return 0;
}

static int earth_teardown(void **state) {
    (void)state;
    free(g_earth.elev);
    free(g_earth.t_obs);
    free(g_earth.p_obs);
    free(g_earth.area);
    free(g_earth.lat);
    free(g_earth.lon);
    return 0;
}

/* Does texel id belong to the sample: hemisphere (+1 north, -1 south), land only? */
static int in_sample(const earth *e, int64_t id, int hemi, int land_only) {
    if (land_only && e->elev[id] <= 0.0f) return 0;
    return hemi > 0 ? e->lat[id] >= 0.0 : e->lat[id] < 0.0;
}

/* Correlation of a model field with an observed one over a sample. */
static double correlate(const earth *e, const float *model, const double *obs, int hemi,
                        int land_only, int spearman) {
    size_t m = 0;
    double *a = malloc((size_t)e->total * sizeof(double)),
           *b = malloc((size_t)e->total * sizeof(double));
    double *w = malloc((size_t)e->total * sizeof(double));
    for (int64_t id = 0; id < e->total; id++) {
        if (!in_sample(e, id, hemi, land_only)) continue;
        a[m] = model[id];
        b[m] = obs[id];
        w[m++] = e->area[id];
    }
    double r = spearman ? weighted_spearman(a, b, w, m) : weighted_pearson(a, b, w, m);
    free(a);
    free(b);
    free(w);
    return r;
}

/* Least squares of the temperature constants on one hemisphere (land + sea):
 * T_obs + lapse cooling = a + b Q + b2 (Q - 300)^2 + cont (k0 + k1 cos 2 lat). */
static void fit_temperature(const earth *e, const pg_climate *c, const pg_climate_params *p,
                            int hemi, double coef[5]) {
    double A[5][5] = {{0}}, rhs[5] = {0};
    for (int64_t id = 0; id < e->total; id++) {
        if (!in_sample(e, id, hemi, 0)) continue;
        double cool = p->lapse_rate_K_per_km * fmax((double)e->elev[id], 0.0) / 1000.0;
        double cont = c->continentality[id];
        double dq = c->insolation_wm2[id] - 300.0;
        double x[5] = {1.0, c->insolation_wm2[id], dq * dq, cont,
                       cont * cos(2.0 * e->lat[id] * M_PI / 180.0)};
        double y = e->t_obs[id] + cool, w = e->area[id];
        for (int i = 0; i < 5; i++) {
            rhs[i] += w * x[i] * y;
            for (int j = 0; j < 5; j++)
                A[i][j] += w * x[i] * x[j];
        }
    }
    solve(5, A, rhs, coef);
}

static void run(const pg_climate_params *p, int64_t n, const float *elev, pg_climate *c) {
    pg_error err = {0};
    pg_status st = pg_climate_compute(p, PROJ, n, elev, c, &err);
    if (st) fprintf(stderr, "%s\n", err.msg);
    assert_int_equal(st, PG_OK);
}

/* The precipitation constants searched on the northern hemisphere's land. */
static const double k_land_decay[] = {400.0, 800.0, 1600.0};
static const double k_orographic[] = {400.0, 800.0, 1600.0};
static const double k_floor[] = {0.2, 0.4, 0.6};

static void test_earth_validation(void **state) {
    (void)state;
    earth *e = &g_earth;
    pg_climate_params p;
    pg_climate_params_default(&p);
    pg_climate c;
    pg_climate_init(&c);

    /* precipitation: grid search on the north, land only */
    double best = -2.0, best_l = 0, best_o = 0, best_f = 0;
    for (size_t i = 0; i < 3; i++)
        for (size_t j = 0; j < 3; j++)
            for (size_t k = 0; k < 3; k++) {
                pg_climate_params q = p;
                q.land_decay_km = k_land_decay[i];
                q.orographic_m = k_orographic[j];
                q.precip_floor = k_floor[k];
                run(&q, e->n, e->elev, &c);
                double r = correlate(e, c.precipitation_mm, e->p_obs, +1, 1, 1);
                if (r > best)
                    best = r, best_l = q.land_decay_km, best_o = q.orographic_m,
                    best_f = q.precip_floor;
            }
    printf("precipitation fit (north, land): land_decay_km %.0f orographic_m %.0f precip_floor "
           "%.2f, Spearman %.3f\n",
           best_l, best_o, best_f, best);

    /* temperature: least squares on the north with the default climate's features */
    run(&p, e->n, e->elev, &c);
    double coef[5];
    fit_temperature(e, &c, &p, +1, coef);
    printf("temperature fit (north, land+sea): temp_intercept_c %.2f temp_per_wm2 %.4f "
           "temp_per_wm2_sq %.3e cont_const_K %.2f cont_cos2lat_K %.2f\n",
           coef[0], coef[1], coef[2], coef[3], coef[4]);

    /* validation on the south with the defaults */
    double rt_all = correlate(e, c.temperature_c, e->t_obs, -1, 0, 0);
    double rt_land = correlate(e, c.temperature_c, e->t_obs, -1, 1, 0);
    double rp_land = correlate(e, c.precipitation_mm, e->p_obs, -1, 1, 1);
    double rp_all = correlate(e, c.precipitation_mm, e->p_obs, -1, 0, 1);
    double rt_n = correlate(e, c.temperature_c, e->t_obs, +1, 0, 0);
    double rp_n = correlate(e, c.precipitation_mm, e->p_obs, +1, 1, 1);
    printf("south: temperature Pearson r land+sea %.3f, land %.3f; precipitation Spearman land "
           "%.3f, land+sea %.3f\n",
           rt_all, rt_land, rp_land, rp_all);
    printf("north (fitted): temperature r land+sea %.3f; precipitation Spearman land %.3f\n", rt_n,
           rp_n);
    double ice_land = 0, land = 0, desert_land = 0, ice_obs = 0, desert_obs = 0;
    for (int64_t id = 0; id < e->total; id++)
        if (e->elev[id] > 0.0f) {
            land += e->area[id];
            ice_obs += pg_climate_is_ice((float)e->t_obs[id]) ? e->area[id] : 0.0;
            desert_obs +=
                pg_climate_is_desert((float)e->t_obs[id], (float)e->p_obs[id]) ? e->area[id] : 0.0;
            ice_land += pg_climate_is_ice(c.temperature_c[id]) ? e->area[id] : 0.0;
            desert_land += pg_climate_is_desert(c.temperature_c[id], c.precipitation_mm[id])
                               ? e->area[id]
                               : 0.0;
        }
    printf("Earth land: ice %.3f (Marble %.3f), warm desert %.3f (Marble %.3f) of the area\n",
           ice_land / land, ice_obs / land, desert_land / land, desert_obs / land);

    if (getenv("PG_CLIMATE_DIAG")) {
        double pts[][2] = {{62, 129.7}, {55.75, 37.6}, {51.5, 0}, {24, 12},   {-3, -60},
                           {0, 20},     {-25, 134},    {72, -40}, {-80, 100}, {40, -100},
                           {75, 0},     {-60, -40},    {32, 90},  {30, 110}};
        for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
            double d[3] = {cos(pts[k][0] * M_PI / 180) * cos(pts[k][1] * M_PI / 180),
                           cos(pts[k][0] * M_PI / 180) * sin(pts[k][1] * M_PI / 180),
                           sin(pts[k][0] * M_PI / 180)};
            int f;
            double u, v;
            pg_cube_from_dir(PROJ, d, &f, &u, &v);
            int64_t x = (int64_t)((u + 1) / 2 * e->n), y = (int64_t)((v + 1) / 2 * e->n);
            if (x >= e->n) x = e->n - 1;
            if (y >= e->n) y = e->n - 1;
            int64_t id = (f * e->n + y) * e->n + x;
            printf("%6.1f %6.1f h %6.0f Q %5.1f cont %.2f moist %.2f T %6.1f obs %6.1f P %6.0f obs "
                   "%6.0f\n",
                   pts[k][0], pts[k][1], e->elev[id], c.insolation_wm2[id], c.continentality[id],
                   c.moisture[id], c.temperature_c[id], e->t_obs[id], c.precipitation_mm[id],
                   e->p_obs[id]);
        }
    }
    /* preview next to Marble's, for looking at */
    char dir[512], path[600];
    pg_test_scratch_dir("climate", dir, sizeof dir);
    pg_image img;
    pg_error err = {0};
    assert_int_equal(pg_climate_render_preview(&c, e->elev, 720, &img, &err), PG_OK);
    snprintf(path, sizeof path, "%s/earth_model.png", dir);
    assert_int_equal(pg_image_write_png(path, &img, 8, &err), PG_OK);
    pg_image_free(&img);
    pg_climate obs;
    pg_climate_init(&obs);
    run(&p, e->n, e->elev, &obs);
    for (int64_t id = 0; id < e->total; id++) {
        obs.temperature_c[id] = (float)e->t_obs[id];
        obs.precipitation_mm[id] = (float)e->p_obs[id];
    }
    assert_int_equal(pg_climate_render_preview(&obs, e->elev, 720, &img, &err), PG_OK);
    snprintf(path, sizeof path, "%s/earth_marble.png", dir);
    assert_int_equal(pg_image_write_png(path, &img, 8, &err), PG_OK);
    printf("previews: %s/earth_model.png, earth_marble.png\n", dir);
    pg_image_free(&img);
    pg_climate_free(&obs);

    /* the defaults are the fit */
    assert_true(fabs(p.land_decay_km - best_l) < 1e-9);
    assert_true(fabs(p.orographic_m - best_o) < 1e-9);
    assert_true(fabs(p.precip_floor - best_f) < 1e-9);
    assert_true(fabs(p.temp_intercept_c - coef[0]) < 0.05);
    assert_true(fabs(p.temp_per_wm2 - coef[1]) < 0.0005);
    assert_true(fabs(p.temp_per_wm2_sq - coef[2]) < 2e-6);
    assert_true(fabs(p.cont_const_K - coef[3]) < 0.05);
    assert_true(fabs(p.cont_cos2lat_K - coef[4]) < 0.05);

    assert_true(rt_all >= 0.85);
    assert_true(rt_land >= 0.85);
    assert_true(rp_land >= 0.5);
    pg_climate_free(&c);
}

/* ---------------------------------------------------------------- constructed worlds */

typedef int (*land_fn)(double lat, double lon, float *h);

static float *make_world(int64_t n, land_fn f) {
    float *e = malloc((size_t)(6 * n * n) * sizeof(float));
    for (int64_t id = 0; id < 6 * n * n; id++) {
        double lat, lon;
        texel_latlon(n, id, &lat, &lon);
        float h = -3000.0f;
        f(lat, lon, &h);
        e[id] = h;
    }
    return e;
}

static int water_world(double lat, double lon, float *h) {
    (void)lat, (void)lon, (void)h;
    return 0;
}

static void test_water_world_temperature(void **state) {
    (void)state;
    int64_t n = FLAT_N;
    float *elev = make_world(n, water_world);
    pg_climate_params p;
    pg_climate_params_default(&p);
    p.axial_tilt_deg = 0.0;
    pg_climate c;
    pg_climate_init(&c);
    run(&p, n, elev, &c);
    /* symmetric N/S at tilt 0: texel (x, y) of an equatorial face mirrors (x, n-1-y) */
    for (int f = 0; f < 4; f++)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                int64_t a = (f * n + y) * n + x, b = (f * n + (n - 1 - y)) * n + x;
                assert_true(fabsf(c.temperature_c[a] - c.temperature_c[b]) < 1e-3f);
            }
    /* falls with |latitude|: every pair of texels */
    p.axial_tilt_deg = 23.4;
    run(&p, n, elev, &c);
    double lat_prev = -1.0, t_prev = 1e9;
    /* walk the meridian of face +X and then up face +Z's centre column */
    for (int64_t y = n / 2; y < n; y++) {
        int64_t id = (0 * n + y) * n + n / 2;
        double lat, lon;
        texel_latlon(n, id, &lat, &lon);
        assert_true(lat > lat_prev);
        assert_true(c.temperature_c[id] < t_prev);
        lat_prev = lat, t_prev = c.temperature_c[id];
    }
    for (int64_t y = 0; y < n / 2; y++) { /* face +Z: y grows towards +Y; x = n/2 is lon 0 */
        int64_t id = (4 * n + y) * n + n / 2;
        double lat, lon;
        texel_latlon(n, id, &lat, &lon);
        if (lat <= lat_prev) continue;
        assert_true(c.temperature_c[id] < t_prev);
        lat_prev = lat, t_prev = c.temperature_c[id];
    }
    pg_climate_free(&c);
    free(elev);
}

static float g_plateau_h;
static int plateau(double lat, double lon, float *h) {
    if (fabs(lat) < 40.0 && fabs(lon) < 50.0) *h = g_plateau_h;
    return 0;
}

static void test_lapse_rate(void **state) {
    (void)state;
    int64_t n = FLAT_N;
    g_plateau_h = 10.0f;
    float *low = make_world(n, plateau);
    g_plateau_h = 1010.0f;
    float *high = make_world(n, plateau);
    pg_climate_params p;
    pg_climate_params_default(&p);
    pg_climate a, b;
    pg_climate_init(&a);
    pg_climate_init(&b);
    run(&p, n, low, &a);
    run(&p, n, high, &b);
    int checked = 0;
    for (int64_t id = 0; id < 6 * n * n; id++) {
        if (low[id] <= 0.0f) continue;
        double d = a.temperature_c[id] - b.temperature_c[id];
        assert_true(fabs(d - 6.5) < 0.01);
        checked++;
    }
    assert_true(checked > 100);
    pg_climate_free(&a);
    pg_climate_free(&b);
    free(low);
    free(high);
}

/* A continent at 200 m between 30 and 62 N, 10 W to 30 E, with a coastal range (like
 * the Cascades or Norway's): 3000 m, 3 degrees wide, along 4 W from 38 to 55 N, in
 * the westerlies. */
static int ridge_world(double lat, double lon, float *h) {
    if (lat > 30.0 && lat < 62.0 && lon > -10.0 && lon < 30.0) {
        *h = 200.0f;
        if (lat > 38.0 && lat < 55.0 && fabs(lon + 4.0) < 1.5) *h = 3000.0f;
    }
    return 0;
}

static void test_rain_shadow(void **state) {
    (void)state;
    int64_t n = 96;
    float *elev = make_world(n, ridge_world);
    pg_climate_params p;
    pg_climate_params_default(&p);
    pg_climate c;
    pg_climate_init(&c);
    run(&p, n, elev, &c);
    double west = 0, east = 0;
    int nw = 0, ne = 0;
    for (int64_t id = 0; id < 6 * n * n; id++) {
        double lat, lon;
        texel_latlon(n, id, &lat, &lon);
        if (lat < 42.0 || lat > 48.0) continue;
        if (lon > -9.0 && lon < -5.5) west += c.precipitation_mm[id], nw++;
        if (lon > -2.5 && lon < 1.0) east += c.precipitation_mm[id], ne++;
    }
    assert_true(nw > 0 && ne > 0);
    west /= nw;
    east /= ne;
    printf("ridge at 45 N: west (windward) %.0f mm/yr, east (lee) %.0f mm/yr\n", west, east);
    assert_true(west > 1.2 * east);
    pg_climate_free(&c);
    free(elev);
}

/* A flat continent at 300 m, 10 to 50 N, 60 W to 60 E. */
static int big_continent(double lat, double lon, float *h) {
    if (lat > 10.0 && lat < 50.0 && fabs(lon) < 60.0) *h = 300.0f;
    return 0;
}

static void test_dry_interior(void **state) {
    (void)state;
    int64_t n = FLAT_N;
    float *elev = make_world(n, big_continent);
    pg_climate_params p;
    pg_climate_params_default(&p);
    pg_climate c;
    pg_climate_init(&c);
    run(&p, n, elev, &c);
    double coast = 0, inner = 0;
    int nc = 0, ni = 0;
    for (int64_t id = 0; id < 6 * n * n; id++) {
        if (elev[id] <= 0.0f) continue;
        double lat, lon;
        texel_latlon(n, id, &lat, &lon);
        double edge = fmin(fmin(lat - 10.0, 50.0 - lat), 60.0 - fabs(lon));
        if (edge < 4.0) coast += c.precipitation_mm[id], nc++;
        if (edge > 12.0) inner += c.precipitation_mm[id], ni++;
    }
    assert_true(nc > 0 && ni > 0);
    coast /= nc;
    inner /= ni;
    printf("flat continent: coast %.0f mm/yr, interior %.0f mm/yr\n", coast, inner);
    assert_true(inner < coast);
    pg_climate_free(&c);
    free(elev);
}

static void test_offset_and_tilt(void **state) {
    (void)state;
    int64_t n = FLAT_N;
    float *elev = make_world(n, big_continent);
    pg_climate_params p;
    pg_climate_params_default(&p);
    pg_climate a, b;
    pg_climate_init(&a);
    pg_climate_init(&b);
    run(&p, n, elev, &a);
    p.temperature_offset_K = -7.5;
    run(&p, n, elev, &b);
    for (int64_t id = 0; id < 6 * n * n; id++)
        assert_true(fabs(b.temperature_c[id] - a.temperature_c[id] + 7.5) < 1e-4);
    /* polar temperature: a tilted planet's poles see the sun half the year */
    p.temperature_offset_K = 0.0;
    p.axial_tilt_deg = 0.0;
    run(&p, n, elev, &a);
    p.axial_tilt_deg = 45.0;
    run(&p, n, elev, &b);
    double ta = 0, tb = 0;
    int m = 0;
    for (int64_t id = 0; id < 6 * n * n; id++) {
        double lat, lon;
        texel_latlon(n, id, &lat, &lon);
        if (fabs(lat) < 80.0) continue;
        ta += a.temperature_c[id];
        tb += b.temperature_c[id];
        m++;
    }
    printf("poles: tilt 0 %.1f C, tilt 45 %.1f C\n", ta / m, tb / m);
    assert_true(tb / m > ta / m + 5.0);
    /* and the insolation itself: the pole at tilt t gets S0/pi sin t */
    assert_true(fabs(pg_climate_annual_insolation(90.0, 45.0, 1361.0) -
                     1361.0 / M_PI * sin(M_PI / 4)) < 0.5);
    assert_true(fabs(pg_climate_annual_insolation(0.0, 0.0, 1361.0) - 1361.0 / M_PI) < 1e-6);
    /* the table computes the declinations once and gives the same values as single calls */
    double table[181];
    pg_climate_annual_insolation_table(-90.0, 1.0, 181, 23.4, 1361.0, table);
    for (int i = 0; i < 181; i++)
        assert_true(table[i] == pg_climate_annual_insolation(-90.0 + 1.0 * i, 23.4, 1361.0));
    pg_climate_free(&a);
    pg_climate_free(&b);
    free(elev);
}

static void test_threads(void **state) {
    (void)state;
    int64_t n = FLAT_N;
    float *elev = make_world(n, ridge_world);
    pg_climate_params p;
    pg_climate_params_default(&p);
    pg_climate a, b;
    pg_climate_init(&a);
    pg_climate_init(&b);
    omp_set_num_threads(1);
    run(&p, n, elev, &a);
    omp_set_num_threads(2);
    run(&p, n, elev, &b);
    size_t bytes = (size_t)(6 * n * n) * sizeof(float);
    assert_memory_equal(a.temperature_c, b.temperature_c, bytes);
    assert_memory_equal(a.precipitation_mm, b.precipitation_mm, bytes);
    pg_climate_free(&a);
    pg_climate_free(&b);
    free(elev);
}

static void test_bad_input(void **state) {
    (void)state;
    pg_climate_params p;
    pg_climate_params_default(&p);
    pg_climate c;
    pg_climate_init(&c);
    pg_error err = {0};
    float e[6] = {0};
    assert_int_equal(pg_climate_compute(&p, PROJ, 0, e, &c, &err), PG_ERR_BADINPUT);
    pg_error_clear(&err);
    p.axial_tilt_deg = 120.0;
    assert_int_equal(pg_climate_compute(&p, PROJ, 1, e, &c, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "axial_tilt_deg"));
    pg_error_clear(&err);
    pg_climate_params_default(&p);
    e[3] = NAN;
    assert_int_equal(pg_climate_compute(&p, PROJ, 1, e, &c, &err), PG_ERR_BADINPUT);
    pg_climate_free(&c);
    /* the helpers */
    assert_true(pg_climate_is_ice(-30.0f));
    assert_false(pg_climate_is_ice(5.0f));
    assert_true(pg_climate_is_desert(25.0f, 50.0f));
    assert_false(pg_climate_is_desert(25.0f, 2000.0f));
    assert_false(pg_climate_is_desert(-20.0f, 50.0f));
    assert_true(pg_climate_pet_ratio(25.0f, 100.0f) > 8.0);
    for (int g = 1; g < 256; g++) {
        assert_true(pg_climate_marble_temp_c(g) > pg_climate_marble_temp_c(g - 1));
        assert_true(pg_climate_marble_precip_mm(g) > pg_climate_marble_precip_mm(g - 1));
    }
}

int main(void) {
    const struct CMUnitTest earth_tests[] = {
        cmocka_unit_test(test_earth_validation),
    };
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_water_world_temperature),
        cmocka_unit_test(test_lapse_rate),
        cmocka_unit_test(test_rain_shadow),
        cmocka_unit_test(test_dry_interior),
        cmocka_unit_test(test_offset_and_tilt),
        cmocka_unit_test(test_threads),
        cmocka_unit_test(test_bad_input),
    };
    int fails = cmocka_run_group_tests(tests, NULL, NULL);
    fails += cmocka_run_group_tests(earth_tests, earth_setup, earth_teardown);
    return fails;
}
