/* test_pits_cli.c - `planetgen pits` end to end: each method turns a pitted EXR and
 * a 16-bit PNG into DEMs that the independent checker finds pit-free, --stats and
 * --json report the depressions, --verbose cites the paper, and bad input (NaN
 * without --nodata, a lakes mask of the wrong size, a negative limit, an unknown
 * method, a planet directory before the planet format exists) exits 2 with a clear
 * message and leaves no output behind. */
#include "pg_test.h"
#include "pits_checker.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_image.h"
#include "planetgen/pg_pits.h"
#include "planetgen/pg_planet.h"

#include <stdio.h>
#include <sys/stat.h>

static char dir[1024];

/* A 64x48 DEM: a tilted plane with bumps and a few closed pits. */
static void make_dem(float *d, int w, int h) {
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            d[y * w + x] = (float)(200 + 3 * x + 2 * y + 40 * sin(x * 0.5) * cos(y * 0.4));
    for (int k = 0; k < 4; k++) {
        int x = (12 + 11 * k) % w, y = (10 + 8 * k) % h;
        d[y * w + x] = 5.0f;
    }
}

static void write_exr(const char *path, const float *d, int w, int h) {
    pg_image img = {.width = w, .height = h, .channels = 1, .data = (float *)d};
    assert_int_equal(pg_image_write_exr(path, &img, NULL, NULL), PG_OK);
}

static float *read_back(const char *path, int w, int h, float scale) {
    pg_image img;
    assert_int_equal(pg_image_read(path, 0, &img, NULL), PG_OK);
    assert_int_equal(img.width, w);
    assert_int_equal(img.height, h);
    float *d = malloc(sizeof(float) * w * h);
    for (int i = 0; i < w * h; i++)
        d[i] = img.data[i] * scale;
    pg_image_free(&img);
    return d;
}

static int setup(void **state) {
    (void)state;
    pg_test_scratch_dir("pits_cli", dir, sizeof dir);
    return 0;
}

static void test_methods_exr(void **state) {
    (void)state;
    int w = 64, h = 48;
    float d[64 * 48];
    make_dem(d, w, h);
    char in[1200], out[1200], args[4096], so[8192], se[4096];
    snprintf(in, sizeof in, "%s/dem.exr", dir);
    write_exr(in, d, w, h);
    chk_graph g = chk_grid_graph(w, h);
    uint8_t *sk = chk_sinks(d, g.n, 0, 0, NULL, 1, w, h);
    assert_true(chk_undrained(&g, d, sk, 0) > 0);
    const char *methods[] = {"fill", "breach", "hybrid"};
    for (int m = 0; m < 3; m++)
        for (int eps = 0; eps < 2; eps++) {
            snprintf(out, sizeof out, "%s/out_%s_%d.exr", dir, methods[m], eps);
            snprintf(args, sizeof args,
                     "pits --method %s %s --max-depth 30 --max-length 4 -v '%s' -o '%s' "
                     "--json '%s/r.json'",
                     methods[m], eps ? "--epsilon" : "", in, out, dir);
            assert_int_equal(pg_test_run_cli(args, so, sizeof so, se, sizeof se), 0);
            assert_non_null(strstr(so, m == 0 ? "Barnes" : m == 1 ? "Soille" : "Lindsay"));
            float *r = read_back(out, w, h, 1.0f);
            assert_int_equal(chk_undrained(&g, r, sk, eps), 0);
            free(r);
            char json[8192] = {0};
            snprintf(args, sizeof args, "%s/r.json", dir);
            FILE *f = fopen(args, "r");
            assert_non_null(f);
            size_t nread = fread(json, 1, sizeof json - 1, f);
            fclose(f);
            assert_true(nread > 0);
            assert_non_null(strstr(json, "\"depression_area_m2\""));
            assert_non_null(strstr(json, "\"depression_volume_m3\""));
            /* headline = after: 0; before: the 4 pits (maybe more from the bumps) */
            const char *after = strstr(json, "\"after\"");
            assert_non_null(after);
            assert_non_null(strstr(after, "\"depressions\": 0"));
        }
    snprintf(args, sizeof args, "pits --stats '%s' --json '%s/s.json'", in, dir);
    assert_int_equal(pg_test_run_cli(args, so, sizeof so, se, sizeof se), 0);
    assert_non_null(strstr(so, "depressions"));
    assert_null(strstr(so, " 0 depressions"));
    chk_graph_free(&g);
    free(sk);
}

/* 16-bit PNG in and out: heights are rounded back to integer steps, which keeps
 * every path non-ascending. */
static void test_png16(void **state) {
    (void)state;
    int w = 64, h = 48;
    float d[64 * 48], q[64 * 48];
    make_dem(d, w, h);
    pg_image img = {.width = w, .height = h, .channels = 1, .data = q};
    for (int i = 0; i < w * h; i++)
        q[i] = floorf(d[i]) / 65535.0f;
    char in[1200], out[1200], args[4096], se[4096];
    snprintf(in, sizeof in, "%s/dem16.png", dir);
    assert_int_equal(pg_image_write_png(in, &img, 16, NULL), PG_OK);
    for (int i = 0; i < w * h; i++)
        q[i] = floorf(d[i]);
    chk_graph g = chk_grid_graph(w, h);
    uint8_t *sk = chk_sinks(q, g.n, 0, 0, NULL, 1, w, h);
    for (int m = 0; m < 2; m++) {
        snprintf(out, sizeof out, "%s/out16_%d.png", dir, m);
        snprintf(args, sizeof args, "pits --method %s --epsilon '%s' -o '%s'",
                 m ? "breach" : "fill", in, out);
        assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
        float *r = read_back(out, w, h, 1.0f); /* raw 16-bit values */
        for (int i = 0; i < w * h; i++) {
            assert_true(fabsf(r[i] - roundf(r[i])) < 1e-2f);
            r[i] = roundf(r[i]);
            if (m)
                assert_true(r[i] <= q[i]);
            else
                assert_true(r[i] >= q[i]);
        }
        assert_int_equal(chk_undrained(&g, r, sk, 0), 0);
        free(r);
    }
    chk_graph_free(&g);
    free(sk);
}

/* TIFF in and out: a float TIFF written by -o X.tif reads back with the same heights
 * as the EXR output, and a TIFF input works the same as the EXR it came from. */
static void test_tiff(void **state) {
    (void)state;
    int w = 64, h = 48;
    float d[64 * 48];
    make_dem(d, w, h);
    char in[1200], exr[1200], tif[1200], tif2[1200], args[4096], se[4096];
    snprintf(in, sizeof in, "%s/t_in.exr", dir);
    write_exr(in, d, w, h);
    snprintf(exr, sizeof exr, "%s/t_out.exr", dir);
    snprintf(tif, sizeof tif, "%s/t_out.tif", dir);
    snprintf(tif2, sizeof tif2, "%s/t_out2.tiff", dir);
    snprintf(args, sizeof args, "pits --method breach --epsilon '%s' -o '%s'", in, exr);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    snprintf(args, sizeof args, "pits --method breach --epsilon '%s' -o '%s'", in, tif);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    snprintf(args, sizeof args, "pits --method breach --epsilon '%s' -o '%s'", tif, tif2);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0); /* TIFF in */
    float *a = read_back(exr, w, h, 1.0f), *b = read_back(tif, w, h, 1.0f),
          *c = read_back(tif2, w, h, 1.0f);
    assert_memory_equal(a, b, sizeof(float) * w * h);
    assert_memory_equal(b, c, sizeof(float) * w * h); /* already pit-free: unchanged */
    free(a);
    free(b);
    free(c);
}

/* --threads 1 and --threads 2 write the same heights (plain fill takes the tiled
 * parallel path with 2 threads). */
static void test_threads_identical(void **state) {
    (void)state;
    int w = 160, h = 120;
    float *d = malloc(sizeof(float) * w * h);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            d[y * w + x] =
                (float)(100 + 30 * sin(x * 0.37) * cos(y * 0.29) + ((x * 31 + y * 17) % 7));
    char in[1200], a[1200], b[1200], args[4096];
    snprintf(in, sizeof in, "%s/thr.exr", dir);
    write_exr(in, d, w, h);
    for (int m = 0; m < 2; m++) {
        const char *method = m ? "breach --epsilon" : "fill";
        snprintf(a, sizeof a, "%s/thr1.exr", dir);
        snprintf(b, sizeof b, "%s/thr2.exr", dir);
        snprintf(args, sizeof args, "pits --method %s --threads 1 '%s' -o '%s'", method, in, a);
        assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
        snprintf(args, sizeof args, "pits --method %s --threads 2 '%s' -o '%s'", method, in, b);
        assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
        float *ra = read_back(a, w, h, 1.0f), *rb = read_back(b, w, h, 1.0f);
        assert_memory_equal(ra, rb, sizeof(float) * w * h);
        free(ra);
        free(rb);
    }
    free(d);
}

static void expect_exit2(const char *args, const char *needle) {
    char se[4096] = {0};
    int rc = pg_test_run_cli(args, NULL, 0, se, sizeof se);
    if (rc != 2 || !strstr(se, needle)) fprintf(stderr, "args: %s\nstderr: %s\n", args, se);
    assert_int_equal(rc, 2);
    assert_non_null(strstr(se, needle));
}

static void test_bad_input(void **state) {
    (void)state;
    int w = 16, h = 12;
    float d[16 * 12];
    make_dem(d, w, h);
    d[5 * w + 7] = NAN;
    char nan_in[1200], ok_in[1200], lakes[1200], args[4096], out[1200];
    snprintf(nan_in, sizeof nan_in, "%s/nan.exr", dir);
    write_exr(nan_in, d, w, h);
    d[5 * w + 7] = 1.0f;
    snprintf(ok_in, sizeof ok_in, "%s/ok.exr", dir);
    write_exr(ok_in, d, w, h);
    snprintf(lakes, sizeof lakes, "%s/lakes.exr", dir);
    write_exr(lakes, d, w - 1, h);
    snprintf(out, sizeof out, "%s/bad/out.exr", dir);
    char outdir[1200];
    snprintf(outdir, sizeof outdir, "%s/bad", dir);
    mkdir(outdir, 0755);

    snprintf(args, sizeof args, "pits --method fill '%s' -o '%s'", nan_in, out);
    expect_exit2(args, "no-data");
    snprintf(args, sizeof args, "pits --method fill --nodata -9999 '%s' -o '%s'", nan_in, out);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    remove(out);
    snprintf(args, sizeof args, "pits --method fill --lakes '%s' '%s' -o '%s'", lakes, ok_in, out);
    expect_exit2(args, "--lakes");
    snprintf(args, sizeof args, "pits --method hybrid --max-depth -1 '%s' -o '%s'", ok_in, out);
    expect_exit2(args, "--max-depth");
    snprintf(args, sizeof args, "pits --method hybrid --max-length -3 '%s' -o '%s'", ok_in, out);
    expect_exit2(args, "--max-length");
    snprintf(args, sizeof args, "pits --method carve '%s' -o '%s'", ok_in, out);
    expect_exit2(args, "--method");
    snprintf(args, sizeof args, "pits --stats '%s'", outdir);
    expect_exit2(args, "not a planet output");
    snprintf(args, sizeof args, "pits --method fill '%s' -o '%s'", outdir, out);
    expect_exit2(args, "--stats only");
    assert_int_equal(pg_test_count_files(outdir), 0); /* nothing left behind */
}

/* --stats PLANET_DIR counts globally across seams, as the library does. */
static void test_planet_stats(void **state) {
    (void)state;
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo);
    pg_exemplar ex;
    assert_int_equal(pg_exemplar_load(&eo, &ex, NULL), PG_OK);
    pg_planet p;
    assert_int_equal(pg_planet_alloc(&p, PG_CUBE_EQUIANGULAR, 2, 64, pg_ellipsoid_sphere(), NULL),
                     PG_OK);
    assert_int_equal(pg_planet_from_exemplar(&p, &ex, 2, NULL), PG_OK);
    p.sea_level = 0;
    char pdir[1200], args[4096], so[8192], se[4096];
    snprintf(pdir, sizeof pdir, "%s/planet", dir);
    mkdir(pdir, 0755);
    assert_int_equal(pg_planet_save_dir(&p, pdir, NULL), PG_OK);
    /* the library's count */
    size_t nn = (size_t)p.n * p.n;
    float *h = malloc(6 * nn * sizeof *h);
    for (int f = 0; f < 6; f++)
        memcpy(h + f * nn, p.height[f], nn * sizeof *h);
    pg_pits_topo t;
    pg_pits_topo_cube(&t, (uint32_t)p.n, NULL);
    pg_pits_opts o;
    pg_pits_opts_default(&o);
    o.has_sea_level = true;
    o.sea_level = 0;
    pg_pits_stats st;
    assert_int_equal(pg_pits_stats_compute(&t, h, &o, NULL, &st, NULL), PG_OK);
    assert_true(st.depressions > 0);
    snprintf(args, sizeof args, "pits --stats '%s' --json '%s/p.json'", pdir, dir);
    assert_int_equal(pg_test_run_cli(args, so, sizeof so, se, sizeof se), 0);
    char want[64];
    snprintf(want, sizeof want, " %llu depressions", (unsigned long long)st.depressions);
    assert_non_null(strstr(so, want));
    free(h);
    pg_planet_free(&p);
    pg_exemplar_free(&ex);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_methods_exr),       cmocka_unit_test(test_png16),
        cmocka_unit_test(test_threads_identical), cmocka_unit_test(test_tiff),
        cmocka_unit_test(test_bad_input),         cmocka_unit_test(test_planet_stats),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
