/* pg_image.c - the format-independent parts of pg_image.h: allocation, and a
 * structural check of PNG files.
 *
 * Why check PNGs ourselves: when libpng meets a truncated or corrupt file inside
 * OpenImageIO, libpng's fallback error handler prints "libpng error: ..." straight
 * to stderr before OpenImageIO reports the failure, which breaks our one-line
 * error rule. Walking the chunk list (length, type, CRC) up to IEND finds those
 * files first, without decoding a pixel.
 *
 * JPEGs get a narrower check for the same kind of reason: OpenImageIO 2.4 decodes the
 * IPTC block of an APP13 "Photoshop 3.0" segment with the size the block declares, not
 * the segment's, and reads past the segment when the two disagree (a heap over-read
 * fuzz_image found). Walking the markers up to the scan finds those files first. */
#include "planetgen/pg_image.h"

#include "pg_huge.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

static uint32_t be32(const unsigned char *b) {
    return ((uint32_t)b[0] << 24) | ((uint32_t)b[1] << 16) | ((uint32_t)b[2] << 8) | b[3];
}

/* Verify one chunk's CRC by streaming its type and data through zlib's crc32. */
static int chunk_crc_ok(FILE *f, const unsigned char type[4], uint32_t len) {
    uLong crc = crc32(0L, type, 4);
    unsigned char buf[65536];
    while (len > 0) {
        size_t want = len < sizeof buf ? len : sizeof buf;
        if (fread(buf, 1, want, f) != want) return 0;
        crc = crc32(crc, buf, (uInt)want);
        len -= (uint32_t)want;
    }
    unsigned char c[4];
    return fread(c, 1, 4, f) == 4 && be32(c) == (uint32_t)crc;
}

pg_status pg_image_png_check(const char *path, pg_error *err) {
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    FILE *f = fopen(path, "rb");
    if (!f) return PG_OK; /* the reader reports unopenable files itself */
    unsigned char head[8];
    pg_status st = PG_OK;
    if (fread(head, 1, 8, f) != 8 || memcmp(head, sig, 8) != 0) {
        fclose(f);
        return PG_OK; /* not a PNG: another decoder's business */
    }
    for (;;) {
        unsigned char h[8];
        if (fread(h, 1, 8, f) != 8) {
            st = pg_error_set(err, PG_ERR_BADINPUT, "%s: truncated PNG (no IEND chunk)", path);
            break;
        }
        uint32_t len = be32(h);
        if (len > 0x7fffffffu || !chunk_crc_ok(f, h + 4, len)) {
            st = pg_error_set(err, PG_ERR_BADINPUT, "%s: corrupt or truncated PNG chunk '%.4s'",
                              path, (const char *)h + 4);
            break;
        }
        if (memcmp(h + 4, "IEND", 4) == 0) break;
    }
    fclose(f);
    return st;
}

/* An APP13 segment's data as OpenImageIO reads it: "Photoshop 3.0\0", "8BIM", type 0x0404
 * (IPTC), 4 bytes it skips, a 2-byte size, then that many bytes. Returns whether those
 * reads stay inside the n bytes the segment holds. */
static int iptc_fits(const unsigned char *d, size_t n) {
    static const char ps[] = "Photoshop 3.0";
    if (n < sizeof ps || memcmp(d, ps, sizeof ps) != 0) return 1; /* not read as IPTC */
    if (n < 26) return 0; /* OpenImageIO reads 26 header bytes regardless */
    if (memcmp(d + 14, "8BIM", 4) != 0 || d[18] != 0x04 || d[19] != 0x04) return 1;
    return 26 + (((size_t)d[24] << 8) | d[25]) <= n;
}

pg_status pg_image_jpeg_check(const char *path, pg_error *err) {
    FILE *f = fopen(path, "rb");
    if (!f) return PG_OK; /* the reader reports unopenable files itself */
    unsigned char h[4], d[65536];
    pg_status st = PG_OK;
    if (fread(h, 1, 2, f) != 2 || h[0] != 0xff || h[1] != 0xd8) {
        fclose(f);
        return PG_OK; /* not a JPEG */
    }
    /* Segments up to the scan; a file that ends early is libjpeg's to report. Bytes
     * between segments are skipped up to the next 0xFF, as libjpeg's next_marker does
     * ("extraneous bytes before marker"): it goes on reading the segments after them,
     * so this check must see those too. */
    for (;;) {
        int c = fgetc(f);
        if (c == EOF) break;
        if (c != 0xff) continue; /* extraneous byte */
        do
            c = fgetc(f);
        while (c == 0xff); /* fill bytes: the marker follows */
        if (c == EOF) break;
        int marker = c;
        if (marker == 0) continue;                                          /* not a marker */
        if (marker == 0xd9 || marker == 0xda) break;                        /* EOI, SOS */
        if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7)) continue; /* no length */
        if (fread(h, 1, 2, f) != 2) break;
        size_t len = ((size_t)h[0] << 8) | h[1];
        if (len < 2) break;
        size_t n = fread(d, 1, len - 2, f);
        if (marker == 0xed && !iptc_fits(d, n)) {
            st = pg_error_set(err, PG_ERR_BADINPUT,
                              "%s: corrupt JPEG (its IPTC block is larger than its APP13 segment)",
                              path);
            break;
        }
        if (n != len - 2) break;
    }
    fclose(f);
    return st;
}

pg_status pg_image_alloc(pg_image *img, int width, int height, int channels, pg_error *err) {
    memset(img, 0, sizeof *img);
    if (width <= 0 || height <= 0 || channels <= 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "image size %dx%dx%d is not positive", width,
                            height, channels);
    size_t n = (size_t)width * (size_t)height * (size_t)channels;
    img->data = pg_huge_calloc(n, sizeof(float));
    if (!img->data)
        return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate %.0f MB for a %dx%d image",
                            n * 4.0 / 1e6, width, height);
    img->width = width;
    img->height = height;
    img->channels = channels;
    img->src_type = PG_SAMPLE_FLOAT;
    img->unit_scale = 1.0f;
    return PG_OK;
}

void pg_image_free(pg_image *img) {
    if (!img) return;
    free(img->data);
    img->data = NULL;
    img->width = img->height = img->channels = 0;
}
