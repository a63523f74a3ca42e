/* test_image_io.c - image round trips through planetgen's own readers and writers,
 * and reading the formats users bring (TIFF made by oiiotool, grey, alpha), and how PNGs
 * are encoded (the zlib strategy and the row filter of both encoders). */
#include "pg_test.h"

#include "pg_export_encode.h"
#include "planetgen/pg_exr.h"
#include "planetgen/pg_image.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

static void fill_pattern(pg_image *img) {
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            for (int c = 0; c < img->channels; c++)
                img->data[((size_t)y * img->width + x) * img->channels + c] =
                    (float)((x * 7 + y * 13 + c * 101) % 256) / 255.0f;
}

static void roundtrip_png(int bits, int channels) {
    char dir[1024], path[1100];
    pg_test_scratch_dir(bits == 8 ? "io_png8" : "io_png16", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/img_%d.png", dir, channels);
    pg_image a, b;
    pg_error err = {0};
    assert_int_equal(pg_image_alloc(&a, 37, 23, channels, &err), PG_OK);
    fill_pattern(&a);
    assert_int_equal(pg_image_write_png(path, &a, bits, &err), PG_OK);
    assert_int_equal(pg_image_read(path, 0, &b, &err), PG_OK);
    assert_int_equal(b.width, 37);
    assert_int_equal(b.height, 23);
    assert_int_equal(b.channels, channels);
    assert_int_equal(b.src_type, bits == 8 ? PG_SAMPLE_UINT8 : PG_SAMPLE_UINT16);
    double maxv = bits == 8 ? 255.0 : 65535.0;
    for (size_t i = 0; i < (size_t)37 * 23 * channels; i++) {
        /* raw values come back unnormalised; unit_scale maps them to 0..1 */
        assert_float_equal(b.data[i], lround(a.data[i] * maxv), 0.0);
        assert_float_equal(b.data[i] * b.unit_scale, a.data[i], 0.5 / maxv + 1e-6);
    }
    pg_image_free(&a);
    pg_image_free(&b);
}

static void test_png8_roundtrip(void **s) {
    (void)s;
    roundtrip_png(8, 1);
    roundtrip_png(8, 3);
    roundtrip_png(8, 4);
}

static void test_png16_roundtrip(void **s) {
    (void)s;
    roundtrip_png(16, 1);
    roundtrip_png(16, 3);
}

static void test_exr_float_roundtrip(void **s) {
    (void)s;
    char dir[1024], path[1100];
    pg_test_scratch_dir("io_exr", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/h.exr", dir);
    pg_image a, b;
    pg_error err = {0};
    assert_int_equal(pg_image_alloc(&a, 61, 17, 1, &err), PG_OK);
    for (int i = 0; i < 61 * 17; i++)
        a.data[i] = -10935.25f + 19.783f * i; /* metres */
    assert_int_equal(pg_image_write_exr(path, &a, NULL, &err), PG_OK);
    /* both our OpenEXR-core reader and OpenImageIO must read back the exact floats */
    assert_int_equal(pg_image_read_exr(path, NULL, &b, &err), PG_OK);
    assert_int_equal(b.width, 61);
    assert_memory_equal(a.data, b.data, 61 * 17 * sizeof(float));
    pg_image_free(&b);
    assert_int_equal(pg_image_read(path, 0, &b, &err), PG_OK);
    assert_int_equal(b.src_type, PG_SAMPLE_FLOAT);
    assert_memory_equal(a.data, b.data, 61 * 17 * sizeof(float));
    pg_image_free(&a);
    pg_image_free(&b);
}

static void test_exr_multipart(void **s) {
    (void)s;
    char dir[1024], path[1100];
    pg_test_scratch_dir("io_exr_multi", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/faces.exr", dir);
    pg_image parts[3];
    const char *names[3] = {"+X", "-X", "+Y"};
    pg_error err = {0};
    for (int p = 0; p < 3; p++) {
        assert_int_equal(pg_image_alloc(&parts[p], 16, 16, 1, &err), PG_OK);
        for (int i = 0; i < 256; i++)
            parts[p].data[i] = p * 1000.0f + i;
    }
    assert_int_equal(pg_exr_write_parts(path, 3, names, parts, NULL, &err), PG_OK);
    int n = 0;
    char got[8][64];
    assert_int_equal(pg_exr_list_parts(path, &n, got, 8, &err), PG_OK);
    assert_int_equal(n, 3);
    for (int p = 0; p < 3; p++) {
        assert_string_equal(got[p], names[p]);
        pg_image b;
        assert_int_equal(pg_image_read_exr(path, names[p], &b, &err), PG_OK);
        assert_memory_equal(b.data, parts[p].data, 256 * sizeof(float));
        pg_image_free(&b);
        pg_image_free(&parts[p]);
    }
}

/* TIFF in 8-bit, 16-bit and float, as produced by a real tool (oiiotool). */
static void test_tiff_via_oiiotool(void **s) {
    (void)s;
    char dir[1024], png[1100], cmd[4096];
    pg_test_scratch_dir("io_tiff", dir, sizeof dir);
    snprintf(png, sizeof png, "%s/src.png", dir);
    pg_image a;
    pg_error err = {0};
    assert_int_equal(pg_image_alloc(&a, 40, 20, 1, &err), PG_OK);
    fill_pattern(&a);
    assert_int_equal(pg_image_write_png(png, &a, 16, &err), PG_OK);
    const char *fmts[] = {"uint8", "uint16", "float"};
    const pg_image_sample_type want[] = {PG_SAMPLE_UINT8, PG_SAMPLE_UINT16, PG_SAMPLE_FLOAT};
    for (int i = 0; i < 3; i++) {
        char tif[1100];
        snprintf(tif, sizeof tif, "%s/t_%s.tif", dir, fmts[i]);
        snprintf(cmd, sizeof cmd, "oiiotool '%s' -d %s -o '%s'", png, fmts[i], tif);
        assert_int_equal(system(cmd), 0);
        pg_image b;
        assert_int_equal(pg_image_read(tif, 0, &b, &err), PG_OK);
        assert_int_equal(b.src_type, want[i]);
        assert_int_equal(b.width, 40);
        for (int k = 0; k < 800; k++)
            assert_float_equal(b.data[k] * b.unit_scale, a.data[k], 1.0 / 255);
        pg_image_free(&b);
    }
    pg_image_free(&a);
}

static void test_pixel_limit_refused_before_alloc(void **s) {
    (void)s;
    char dir[1024], path[1100];
    pg_test_scratch_dir("io_limit", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/big.png", dir);
    pg_image a, b;
    pg_error err = {0};
    assert_int_equal(pg_image_alloc(&a, 200, 100, 1, &err), PG_OK);
    assert_int_equal(pg_image_write_png(path, &a, 8, &err), PG_OK);
    assert_int_equal(pg_image_read(path, 19999, &b, &err), PG_ERR_BADINPUT);
    assert_non_null(strstr(err.msg, "above the limit"));
    assert_non_null(strstr(err.msg, path));
    assert_null(b.data);
    pg_image_free(&a);
}

/* A PNG as written by both encoders (PG_PNG_STRATEGY, PG_PNG_FILTER in pg_image.h):
 * the zlib header's FLEVEL bits (RFC 1950) are 0, which zlib writes for the Z_RLE
 * strategy whatever the level (it wrote 1 for level 3 with the default strategy), and
 * every inflated row starts with the Average filter's type byte (PNG spec 9.2: type k
 * is the mask 0x08 << k). */
static void check_png_encoding(const unsigned char *b, size_t n, int w, int h, int bytes_pp) {
    assert_true(n > 8 && !memcmp(b, "\x89PNG", 4));
    unsigned char *z = malloc(n);
    size_t zn = 0;
    for (size_t i = 8; i + 12 <= n;) {
        size_t len = (size_t)b[i] << 24 | (size_t)b[i + 1] << 16 | (size_t)b[i + 2] << 8 | b[i + 3];
        assert_true(i + 12 + len <= n);
        if (!memcmp(b + i + 4, "IDAT", 4)) memcpy(z + zn, b + i + 8, len), zn += len;
        i += len + 12;
    }
    assert_true(zn > 2);
    assert_int_equal(z[0] & 0x0f, 8); /* deflate */
    assert_int_equal(z[1] >> 6, 0);
    size_t row = 1 + (size_t)w * bytes_pp, want = row * (size_t)h;
    unsigned char *raw = malloc(want + 1);
    uLongf got = (uLongf)want + 1;
    assert_int_equal(uncompress(raw, &got, z, (uLong)zn), Z_OK);
    assert_int_equal(got, want);
    int type = 0;
    while ((0x08 << type) != PG_PNG_FILTER)
        type++;
    assert_int_equal(type, 3); /* Average */
    for (int y = 0; y < h; y++)
        assert_int_equal(raw[(size_t)y * row], type);
    free(raw);
    free(z);
}

static void test_png_encoding(void **s) {
    (void)s;
    char dir[1024], path[1100];
    pg_test_scratch_dir("io_png_encoding", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/level.png", dir);
    pg_image a;
    pg_error err = {0};
    assert_int_equal(pg_image_alloc(&a, 64, 48, 3, &err), PG_OK);
    fill_pattern(&a);
    for (int bits = 8; bits <= 16; bits += 8) { /* the file writer */
        assert_int_equal(pg_image_write_png(path, &a, bits, &err), PG_OK);
        FILE *f = fopen(path, "rb");
        assert_non_null(f);
        unsigned char b[1 << 16];
        size_t n = fread(b, 1, sizeof b, f);
        fclose(f);
        check_png_encoding(b, n, 64, 48, 3 * bits / 8);
        uint8_t *m = NULL; /* in memory: the file's bytes */
        size_t mn = 0;
        assert_int_equal(pg_image_encode_png(&a, bits, &m, &mn, &err), PG_OK);
        assert_int_equal(mn, n);
        assert_memory_equal(m, b, n);
        free(m);
    }
    for (int bits = 8; bits <= 16; bits += 8) { /* the textures inside .glb */
        uint8_t *b = NULL;
        size_t n = 0;
        assert_int_equal(pg_export_encode(a.data, 64, 48, 3, bits, true, PG_EXPORT_CODEC_PNG, 90,
                                          "test", &b, &n, &err),
                         PG_OK);
        check_png_encoding(b, n, 64, 48, 3 * bits / 8);
        free(b);
    }
    pg_image_free(&a);
}

/* Copy a fuzz corpus entry (minus the harness's selector byte) to dir/name. */
static void corpus_file(const char *entry, const char *dir, const char *name, char *out,
                        size_t size) {
    char src[1200];
    snprintf(src, sizeof src, "%s/tests/fuzz/corpus/image/%s", pg_test_source_dir(), entry);
    snprintf(out, size, "%s/%s", dir, name);
    FILE *in = fopen(src, "rb"), *o = fopen(out, "wb");
    assert_non_null(in);
    assert_non_null(o);
    int c = fgetc(in);
    while ((c = fgetc(in)) != EOF)
        fputc(c, o);
    fclose(in), fclose(o);
}

/* Read path in a child (through OpenImageIO, or OpenEXR's C API when core); returns
 * the status and the child's peak RSS (KB), err in msg. */
static int read_in_child_with(const char *path, int core, long *peak_kb, char *msg, size_t size) {
    int fd[2];
    assert_int_equal(pipe(fd), 0);
    pid_t pid = fork();
    if (pid == 0) {
        pg_image img;
        pg_error err = {0};
        pg_status st =
            core ? pg_image_read_exr(path, NULL, &img, &err) : pg_image_read(path, 0, &img, &err);
        struct rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        dprintf(fd[1], "%d %ld %s", (int)st, ru.ru_maxrss, err.msg);
        _exit(0);
    }
    close(fd[1]);
    memset(msg, 0, size);
    ssize_t n = read(fd[0], msg, size - 1);
    close(fd[0]);
    int status, st = -1;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_true(n > 0 && sscanf(msg, "%d %ld", &st, peak_kb) == 2);
    return st;
}

static int read_in_child(const char *path, long *peak_kb, char *msg, size_t size) {
    return read_in_child_with(path, 0, peak_kb, msg, size);
}

/* fuzz_image found it (corpus entry exr-huge-data-window): a 637-byte ZIP EXR whose data
 * window says 100663328 x 16, so both readers allocated 6.4 GB before decoding its one
 * small chunk. Now every chunk is checked against the file first: it must be there, and
 * its packed bytes must be able to expand to the rows it claims. */
static void test_exr_huge_data_window_refused_before_alloc(void **s) {
    (void)s;
    char dir[1024], exr[1200], msg[600];
    pg_test_scratch_dir("io_exr_window", dir, sizeof dir);
    corpus_file("exr-huge-data-window", dir, "window.exr", exr, sizeof exr);
    for (int core = 0; core < 2; core++) {
        long peak_kb = -1;
        int st = read_in_child_with(exr, core, &peak_kb, msg, sizeof msg);
        print_message("%s (%s reader: status, child's peak KB)\n", msg,
                      core ? "OpenEXR core" : "OpenImageIO");
        assert_int_equal(st, PG_ERR_BADINPUT);
        assert_non_null(strstr(msg, exr));
        /* refused by the chunk check, not by a decoder after the allocation */
        assert_non_null(strstr(msg, "holds 51 bytes but claims 6442452992 raw"));
        assert_null(strchr(msg, '\n'));
        assert_true(peak_kb > 0 && peak_kb < 400 * 1024); /* the claim is 6 400 MB */
    }
}

/* The chunk check must not refuse real files: a flat image, the best case for every
 * compressor, in each compression oiiotool writes, reads back through both readers. */
static void test_exr_every_compression_reads(void **s) {
    (void)s;
    static const char *const comps[] = {"none",  "rle", "zips", "zip",  "piz",
                                        "pxr24", "b44", "b44a", "dwaa", "dwab"};
    char dir[1024], path[1200], cmd[2600];
    pg_test_scratch_dir("io_exr_comp", dir, sizeof dir);
    for (size_t i = 0; i < sizeof comps / sizeof comps[0]; i++) {
        for (int half = 0; half < 2; half++) {
            snprintf(path, sizeof path, "%s/flat-%s-%s.exr", dir, comps[i],
                     half ? "half" : "float");
            snprintf(cmd, sizeof cmd,
                     "oiiotool --pattern constant:color=0.5 8192x64 1 -d %s --compression %s "
                     "-o '%s'",
                     half ? "half" : "float", comps[i], path);
            assert_int_equal(system(cmd), 0);
            pg_image img;
            pg_error err = {0};
            for (int core = 0; core < 2; core++) {
                pg_status st = core ? pg_image_read_exr(path, NULL, &img, &err)
                                    : pg_image_read(path, 0, &img, &err);
                if (st != PG_OK) print_message("%s\n", err.msg);
                assert_int_equal(st, PG_OK);
                assert_int_equal(img.width, 8192);
                assert_int_equal(img.height, 64);
                assert_float_equal(img.data[8192 * 64 - 1] * img.unit_scale, 0.5, 1e-3);
                pg_image_free(&img);
            }
        }
    }
}

/* fuzz_image found both (corpus entries exr-huge-attribute, exr-bad-second-attribute):
 * EXRs of a few hundred bytes whose header claims a 1.9 GB or 1.7 GB string attribute
 * (the second after a valid one, which OpenEXR's C API skips with a report and no
 * failure). OpenImageIO's C++ EXR reader allocated the claim before noticing the file
 * was too short (2 GB peak); now the header goes through the C API first, and any
 * report refuses the file with one line. Checked in a child process, whose peak memory
 * must stay far below the claims. */
static void test_exr_absurd_attribute_refused_before_alloc(void **s) {
    (void)s;
    static const char *const entries[] = {"exr-huge-attribute", "exr-bad-second-attribute"};
    char dir[1024], exr[1200], msg[600];
    pg_test_scratch_dir("io_exr_attr", dir, sizeof dir);
    for (int i = 0; i < 2; i++) {
        corpus_file(entries[i], dir, i ? "claims-1.7GB.exr" : "claims-1.9GB.exr", exr, sizeof exr);
        long peak_kb = -1;
        int st = read_in_child(exr, &peak_kb, msg, sizeof msg);
        print_message("%s (first: status, child's peak KB)\n", msg);
        assert_int_equal(st, PG_ERR_BADINPUT);
        assert_non_null(strstr(msg, exr));
        assert_non_null(strstr(msg, "OpenEXR"));
        assert_null(strchr(msg, '\n'));
        assert_true(peak_kb > 0 && peak_kb < 400 * 1024); /* the claims are 1 700+ MB */
    }
}

/* fuzz_image found it (corpus entry jpeg-iptc-overrun): a JPEG whose APP13 IPTC block
 * declares 2 364 bytes in a segment of 86. OpenImageIO 2.4 read past the segment (ASan:
 * heap-buffer-overflow in decode_iptc_iim); now the marker walk refuses it with one line.
 * A JPEG with a well-formed IPTC block, as oiiotool writes it, still reads. */
static void test_jpeg_iptc_overrun_refused(void **s) {
    (void)s;
    char dir[1024], bad[1200], good[1200], cmd[2600];
    pg_test_scratch_dir("io_jpeg_iptc", dir, sizeof dir);
    corpus_file("jpeg-iptc-overrun", dir, "overrun.jpg", bad, sizeof bad);
    pg_image img;
    pg_error err = {0};
    assert_int_equal(pg_image_read(bad, 0, &img, &err), PG_ERR_BADINPUT);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, bad));
    assert_non_null(strstr(err.msg, "IPTC"));
    assert_null(img.data);
    snprintf(good, sizeof good, "%s/iptc.jpg", dir);
    snprintf(cmd, sizeof cmd,
             "oiiotool --pattern checker 32x16 3 --attrib IPTC:Caption caption -o '%s'", good);
    assert_int_equal(system(cmd), 0);
    err.msg[0] = 0;
    assert_int_equal(pg_image_read(good, 0, &img, &err), PG_OK);
    assert_int_equal(img.width, 32);
    pg_image_free(&img);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_png8_roundtrip),
        cmocka_unit_test(test_png16_roundtrip),
        cmocka_unit_test(test_png_encoding),
        cmocka_unit_test(test_exr_float_roundtrip),
        cmocka_unit_test(test_exr_multipart),
        cmocka_unit_test(test_tiff_via_oiiotool),
        cmocka_unit_test(test_pixel_limit_refused_before_alloc),
        cmocka_unit_test(test_exr_absurd_attribute_refused_before_alloc),
        cmocka_unit_test(test_jpeg_iptc_overrun_refused),
        cmocka_unit_test(test_exr_huge_data_window_refused_before_alloc),
        cmocka_unit_test(test_exr_every_compression_reads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
