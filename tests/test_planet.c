/* test_planet.c - the planet directory format: a planet reprojected from the real
 * exemplar survives save and load, and damaged directories are refused by name. */
#include "pg_test.h"

#include "planetgen/pg_exr.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_synth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void test_roundtrip_real_exemplar(void **s) {
    (void)s;
    pg_error err = {0};
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    pg_exemplar ex;
    assert_int_equal(pg_exemplar_load(&o, &ex, &err), PG_OK);
    pg_planet p, q;
    assert_int_equal(pg_planet_alloc(&p, PG_CUBE_EQUIANGULAR, 2, 64, pg_ellipsoid_sphere(), &err),
                     PG_OK);
    p.seed = 12345678901234567ULL;
    assert_int_equal(pg_planet_from_exemplar(&p, &ex, 2, &err), PG_OK);
    /* +Z is north: the north face centre is Arctic ocean (below sea level), the south
     * face centre is the Antarctic ice sheet (kilometres up) */
    int64_t c = (p.n / 2) * p.n + p.n / 2;
    assert_true(p.height[PG_CUBE_FACE_PZ][c] < 0);
    assert_true(p.height[PG_CUBE_FACE_NZ][c] > 2000);
    char dir[1024];
    pg_test_scratch_dir("planet_rt", dir, sizeof dir);
    assert_int_equal(pg_planet_save_dir(&p, dir, &err), PG_OK);
    assert_int_equal(pg_test_count_files(dir), 8);
    assert_int_equal(pg_planet_load(dir, &q, &err), PG_OK);
    assert_int_equal(q.n, p.n);
    assert_int_equal(q.tiles, 2);
    assert_int_equal(q.projection, PG_CUBE_EQUIANGULAR);
    assert_true(q.seed == p.seed);
    assert_float_equal(q.ellipsoid.a, p.ellipsoid.a, 0);
    size_t nn = (size_t)p.n * p.n;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        assert_memory_equal(q.height[f], p.height[f], nn * sizeof(float)); /* float exact */
        for (size_t i = 0; i < nn * 3; i++)
            assert_float_equal(q.albedo[f][i], p.albedo[f][i], 0.5 / 255 + 1e-6); /* 8-bit */
    }
    pg_planet_free(&q);
    /* a missing face file is named */
    char path[1300];
    snprintf(path, sizeof path, "%s/albedo_-Y.png", dir);
    remove(path);
    pg_error_clear(&err);
    assert_int_equal(pg_planet_load(dir, &q, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "missing albedo_-Y.png"));
    /* a directory without planet.json is not a planet */
    snprintf(path, sizeof path, "%s/planet.json", dir);
    remove(path);
    pg_error_clear(&err);
    assert_int_equal(pg_planet_load(dir, &q, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "not a planet output"));
    pg_planet_free(&p);
    pg_exemplar_free(&ex);
}

/* ---- the coordinate map (source.exr) ---- */

/* A small planet (6 x n^2) with distinct heights, so a mix-up of faces would show. */
static void small_planet(pg_planet *p, int n) {
    pg_error err = {0};
    assert_int_equal(pg_planet_alloc(p, PG_CUBE_EQUIANGULAR, 1, n, pg_ellipsoid_sphere(), &err),
                     PG_OK);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int i = 0; i < n * n; i++)
            p->height[f][i] = (float)(1000 * f + i);
}

/* A map of hashed coordinates covering all of 0..e-1 and all six faces. */
static void hashed_map(pg_planet *p, int e) {
    pg_error err = {0};
    assert_int_equal(pg_planet_source_alloc(p, e, PG_CUBE_GNOMONIC, &err), PG_OK);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < p->n * p->n; i++) {
            uint32_t h = pg_synth_hash(99, 0, f, (long)i, 0, 1);
            p->source.coords[f][i] = pg_synth_pack((int)(h % 6), (int)((h >> 3) % (uint32_t)e),
                                                   (int)((h >> 16) % (uint32_t)e));
        }
}

static void expect_same_map(const pg_planet *a, const pg_planet *b) {
    assert_true(pg_planet_has_source(b));
    assert_int_equal(b->source.face_size, a->source.face_size);
    assert_int_equal(b->source.projection, a->source.projection);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        assert_memory_equal(b->source.coords[f], a->source.coords[f],
                            (size_t)a->n * (size_t)a->n * sizeof(uint32_t));
}

/* The file itself, read without pg_planet_load: file row 0 is the face's top row
 * (y = n - 1, north up like the PNGs) and channels face, u, v hold the unpacked
 * coordinate. */
typedef struct file_rows {
    const pg_planet *p;
    int face, rows_seen;
} file_rows;

static pg_status take_file_rows(int y0, int rows, const uint32_t *buf, void *user, pg_error *err) {
    (void)err;
    file_rows *r = user;
    const int64_t n = r->p->n;
    for (int k = 0; k < rows; k++)
        for (int64_t x = 0; x < n; x++) {
            uint32_t c = r->p->source.coords[r->face][(n - 1 - (y0 + k)) * n + x];
            const uint32_t *px = buf + ((size_t)k * n + x) * 3;
            assert_int_equal(px[0], pg_synth_face(c));
            assert_int_equal(px[1], pg_synth_u(c));
            assert_int_equal(px[2], pg_synth_v(c));
        }
    r->rows_seen += rows;
    return PG_OK;
}

static void check_file_layout(const pg_planet *p, const char *dir) {
    char path[1200];
    snprintf(path, sizeof path, "%s/source.exr", dir);
    const char *chan[3] = {"face", "u", "v"};
    pg_error err = {0};
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        file_rows r = {p, f, 0};
        assert_int_equal(pg_exr_read_uint_part(path, pg_cube_face_name(f), (int)p->n, (int)p->n, 3,
                                               chan, take_file_rows, &r, &err),
                         PG_OK);
        assert_int_equal(r.rows_seen, p->n);
    }
}

/* Save, load, compare: the map, its exemplar cube, the closed-land share. */
static void roundtrip(const pg_planet *p, const char *tag) {
    char dir[1024];
    pg_error err = {0};
    pg_planet q;
    pg_test_scratch_dir(tag, dir, sizeof dir);
    assert_int_equal(pg_planet_save_dir(p, dir, &err), PG_OK);
    assert_int_equal(pg_test_count_files(dir), 9); /* 6 faces, height, source, json */
    check_file_layout(p, dir);
    if (pg_planet_load(dir, &q, &err) != PG_OK) fail_msg("%s", err.msg);
    expect_same_map(p, &q);
    assert_float_equal(q.closed_land_share_before_final, p->closed_land_share_before_final, 0);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        assert_memory_equal(q.height[f], p->height[f], (size_t)p->n * p->n * sizeof(float));
    pg_planet_free(&q);
}

static void test_source_roundtrip(void **s) {
    (void)s;
    pg_planet p;
    pg_error err = {0};
    small_planet(&p, 32);
    p.closed_land_share_before_final = 0.125;
    /* the identity map of an exemplar cube of the planet's size */
    assert_int_equal(pg_planet_source_identity(&p, 32, PG_CUBE_EQUIANGULAR, &err), PG_OK);
    roundtrip(&p, "planet_src_identity");
    /* every face and coordinate value, an exemplar larger than the planet: rows and
     * faces must come back where they were (a flip or swap would not) */
    hashed_map(&p, 512);
    roundtrip(&p, "planet_src_hashed");
    /* the largest coordinates the packing holds */
    hashed_map(&p, 8192);
    roundtrip(&p, "planet_src_8192");
    pg_planet_free(&p);
}

static void test_source_absent_loads(void **s) {
    (void)s;
    pg_planet p, q;
    pg_error err = {0};
    char dir[1024], path[1200];
    small_planet(&p, 32);
    pg_test_scratch_dir("planet_src_absent", dir, sizeof dir);
    assert_int_equal(pg_planet_save_dir(&p, dir, &err), PG_OK);
    assert_int_equal(pg_test_count_files(dir), 8); /* no source.exr without a map */
    snprintf(path, sizeof path, "%s/source.exr", dir);
    assert_false(pg_test_file_nonempty(path));
    if (pg_planet_load(dir, &q, &err) != PG_OK) fail_msg("%s", err.msg);
    assert_false(pg_planet_has_source(&q));
    assert_true(isnan(q.closed_land_share_before_final));
    pg_planet_free(&q);
    pg_planet_free(&p);
}

/* Load dir, expecting refusal with a message holding both strings. */
static void expect_refused(const char *dir, const char *what, const char *problem) {
    pg_planet q;
    pg_error err = {0};
    pg_status st = pg_planet_load(dir, &q, &err);
    if (st == PG_OK) {
        pg_planet_free(&q);
        fail_msg("loaded a planet whose %s is damaged", what);
    }
    assert_int_equal(st, PG_ERR_BADINPUT);
    print_message("%s: %s\n", what, err.msg);
    if (!strstr(err.msg, "source.exr") || !strstr(err.msg, problem))
        fail_msg("%s: message '%s' lacks 'source.exr' or '%s'", what, err.msg, problem);
    assert_null(strchr(err.msg, '\n'));
}

static void copy_file(const char *from, const char *to) {
    FILE *a = fopen(from, "rb"), *b = fopen(to, "wb");
    assert_non_null(a);
    assert_non_null(b);
    char buf[65536];
    size_t k;
    while ((k = fread(buf, 1, sizeof buf, a)) > 0)
        assert_int_equal(fwrite(buf, 1, k, b), k);
    fclose(a);
    assert_int_equal(fclose(b), 0);
}

/* Replace `from` by `to` in a text file (once). */
static void edit_file(const char *path, const char *from, const char *to) {
    static char text[65536], out[65536];
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    char *at = strstr(text, from);
    assert_non_null(at);
    snprintf(out, sizeof out, "%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
    f = fopen(path, "wb");
    assert_non_null(f);
    fputs(out, f);
    assert_int_equal(fclose(f), 0);
}

static long file_size(const char *path) {
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fclose(f);
    return n;
}

/* Overwrite len bytes at offset with 0xa5. */
static void smash(const char *path, long offset, size_t len) {
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    fseek(f, offset, SEEK_SET);
    for (size_t i = 0; i < len; i++)
        fputc(0xa5, f);
    assert_int_equal(fclose(f), 0);
}

/* A planet directory with a hashed map on an exemplar of e, and a pristine copy of
 * its source.exr and planet.json to restore between the damages. */
static void damaged_setup(char *dir, size_t size, int n, int e, char *src, char *keep, char *meta,
                          char *keep_meta) {
    pg_planet p;
    pg_error err = {0};
    small_planet(&p, n);
    hashed_map(&p, e);
    pg_test_scratch_dir("planet_src_bad", dir, size);
    assert_int_equal(pg_planet_save_dir(&p, dir, &err), PG_OK);
    pg_planet_free(&p);
    sprintf(src, "%s/source.exr", dir);
    sprintf(keep, "%s/source.keep", dir);
    sprintf(meta, "%s/planet.json", dir);
    sprintf(keep_meta, "%s/planet.keep", dir);
    copy_file(src, keep);
    copy_file(meta, keep_meta);
}

static void test_source_damaged_refused(void **s) {
    (void)s;
    char dir[1024], src[1200], keep[1200], meta[1200], keep_meta[1200], other[1024];
    damaged_setup(dir, sizeof dir, 32, 512, src, keep, meta, keep_meta);
    long size = file_size(src);
    /* truncated: the second half of the chunks is gone */
    assert_int_equal(truncate(src, size / 2), 0);
    expect_refused(dir, "truncated file", "source.exr");
    /* zlib data overwritten in the middle of the file */
    copy_file(keep, src);
    smash(src, size / 2, 64);
    expect_refused(dir, "corrupt chunk", "OpenEXR");
    /* coordinates beyond the exemplar cube planet.json names */
    copy_file(keep, src);
    edit_file(meta, "\"exemplar_face_size\": 512", "\"exemplar_face_size\": 300");
    expect_refused(dir, "exemplar face size", "outside");
    copy_file(keep_meta, meta);
    /* a map of another planet size */
    pg_planet p;
    pg_error err = {0};
    small_planet(&p, 16);
    hashed_map(&p, 512);
    pg_test_scratch_dir("planet_src_other", other, sizeof other);
    assert_int_equal(pg_planet_save_dir(&p, other, &err), PG_OK);
    pg_planet_free(&p);
    char path[1200];
    snprintf(path, sizeof path, "%s/source.exr", other);
    copy_file(path, src);
    expect_refused(dir, "wrong size", "16x16, expected 32x32");
    /* named in planet.json but missing */
    remove(src);
    expect_refused(dir, "missing file", "missing");
    copy_file(keep, src);
    pg_planet q;
    assert_int_equal(pg_planet_load(dir, &q, &err), PG_OK); /* restored: loads again */
    pg_planet_free(&q);
}

/* Face ids 6 and 7 fit the packing but name no face: refused on load. */
static void test_source_bad_face_refused(void **s) {
    (void)s;
    pg_planet p;
    pg_error err = {0};
    char dir[1024];
    small_planet(&p, 32);
    assert_int_equal(pg_planet_source_identity(&p, 32, PG_CUBE_EQUIANGULAR, &err), PG_OK);
    p.source.coords[PG_CUBE_FACE_NZ][5 * 32 + 7] = pg_synth_pack(7, 3, 4);
    pg_test_scratch_dir("planet_src_face", dir, sizeof dir);
    assert_int_equal(pg_planet_save_dir(&p, dir, &err), PG_OK);
    pg_planet_free(&p);
    expect_refused(dir, "face id", "(face 7, u 3, v 4) outside");
}

/* ---- integer EXR parts and the ZIP size tie ----
 * OpenEXR 3.1.5 stores the zlib bytes of a chunk whose zlib output is exactly as long
 * as its raw bytes, and readers take such a chunk for raw pixels. pg_exr guards
 * against it. Rows of hashed values shifted right by 0..31 bits, after a run of
 * zeros of 0..31 pixels, sweep the compressed size across the raw size in small steps,
 * so a few of these 1024 one-chunk files hit the tie exactly (checked: with the guard
 * removed this test fails). */

#define TIE_W 32

static void fill_tie(int part, int y0, int rows, uint32_t *buf, void *user) {
    (void)part, (void)y0, (void)rows;
    memcpy(buf, user, TIE_W * sizeof(uint32_t));
}

typedef struct tie_read {
    uint32_t got[TIE_W];
} tie_read;

static pg_status take_tie(int y0, int rows, const uint32_t *buf, void *user, pg_error *err) {
    (void)err;
    assert_int_equal(y0, 0);
    assert_int_equal(rows, 1);
    memcpy(((tie_read *)user)->got, buf, TIE_W * sizeof(uint32_t));
    return PG_OK;
}

static void test_exr_uint_zip_size_tie(void **s) {
    (void)s;
    char dir[1024], path[1200];
    pg_test_scratch_dir("exr_uint_tie", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/tie.exr", dir);
    const char *part[1] = {"p"}, *chan[1] = {"id"};
    int bad = 0;
    for (int shift = 0; shift < 32; shift++)
        for (int zeros = 0; zeros < 32; zeros++) {
            uint32_t row[TIE_W];
            for (int i = 0; i < TIE_W; i++)
                row[i] = i < zeros ? 0 : pg_synth_hash(5, 0, 0, i, shift, zeros) >> shift;
            pg_error err = {0};
            assert_int_equal(
                pg_exr_write_uint_parts(path, 1, part, TIE_W, 1, 1, chan, fill_tie, row, &err),
                PG_OK);
            tie_read r;
            memset(&r, 0, sizeof r);
            if (pg_exr_read_uint_part(path, "p", TIE_W, 1, 1, chan, take_tie, &r, &err) != PG_OK ||
                memcmp(r.got, row, sizeof row) != 0) {
                print_message("shift %d zeros %d: %s\n", shift, zeros,
                              err.msg[0] ? err.msg : "values differ");
                bad++;
            }
        }
    assert_int_equal(bad, 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_roundtrip_real_exemplar),
                                       cmocka_unit_test(test_source_roundtrip),
                                       cmocka_unit_test(test_source_absent_loads),
                                       cmocka_unit_test(test_source_damaged_refused),
                                       cmocka_unit_test(test_source_bad_face_refused),
                                       cmocka_unit_test(test_exr_uint_zip_size_tie)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
