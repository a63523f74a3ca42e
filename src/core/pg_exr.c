/* pg_exr.c - EXR writing and reading with OpenEXR's C API.
 *
 * Float parts: scanlines, uncompressed, every channel FLOAT. Why no compression: ZIP
 * gains about 1% on noisy float heights, and the ZIP encoder of Debian 12's OpenEXR
 * 3.1.5 corrupts a chunk whose compressed size equals its raw size (the reader then
 * takes the zlib bytes for raw pixels; upstream issue #2306). Real planets hit that
 * case, as tests/test_planet.c showed, so we do not use it there.
 *
 * Integer parts (the coordinate map): scanlines, UINT channels, ZIP. Coordinates
 * copied in patches run in steps of one texel, which ZIP's byte predictor turns into
 * long runs (28x smaller than raw on the default planet), so ZIP is worth it here.
 * The equal-size bug is sidestepped by a guard around the library's compressor that
 * stores the raw bytes when the sizes tie, which is what the file format prescribes
 * and what later OpenEXR releases do (test_planet.c, test_exr_uint_zip_size_tie, hits
 * the tie). Rows are streamed through caller callbacks a chunk at a time.
 *
 * Both: the coding pipeline lists channels in the file's (alphabetical) order, so each
 * is matched to the caller's interleaved channel by name. Errors from the library are
 * captured through the context's error handler so the caller gets one line naming the
 * file. */
#include "planetgen/pg_exr.h"

#include <openexr.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct exr_msg {
    char text[256];
} exr_msg;

static void capture_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
    void *ud = NULL;
    exr_get_user_data(ctxt, &ud);
    exr_msg *m = ud;
    if (m && !m->text[0])
        snprintf(m->text, sizeof m->text, "%s: %s", exr_get_error_code_as_string(code),
                 msg ? msg : "");
}

static pg_status exr_fail(pg_error *err, pg_status st, const char *path, const exr_msg *m,
                          exr_result_t rv) {
    return pg_error_set(err, st, "%s: OpenEXR error: %s", path,
                        m->text[0] ? m->text : exr_get_error_code_as_string(rv));
}

/* Open path for reading; the library's error text lands in *m. */
static exr_result_t exr_open_read(const char *path, exr_context_t *ctxt, exr_msg *m) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = capture_error;
    init.user_data = m;
    *ctxt = NULL;
    return exr_start_read(ctxt, path, &init);
}

static const char *default_channel_name(int nch, int c) {
    static const char *const names[5][4] = {{"", "", "", ""},
                                            {"Y", "", "", ""},
                                            {"Y", "A", "", ""},
                                            {"R", "G", "B", ""},
                                            {"R", "G", "B", "A"}};
    return nch >= 1 && nch <= 4 ? names[nch][c] : "";
}

static const char *channel_name(const char **names, int nch, int c) {
    return names ? names[c] : default_channel_name(nch, c);
}

static int find_channel(const pg_image *img, const char **names, const char *want) {
    for (int c = 0; c < img->channels; c++)
        if (strcmp(channel_name(names, img->channels, c), want) == 0) return c;
    return -1;
}

static exr_result_t define_part(exr_context_t ctxt, const char *name, const pg_image *img,
                                const char **names) {
    int idx;
    exr_result_t rv = exr_add_part(ctxt, name, EXR_STORAGE_SCANLINE, &idx);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctxt, idx, img->width, img->height,
                                                 EXR_COMPRESSION_NONE);
    for (int c = 0; rv == EXR_ERR_SUCCESS && c < img->channels; c++)
        rv = exr_add_channel(ctxt, idx, channel_name(names, img->channels, c), EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LINEAR, 1, 1);
    return rv;
}

/* The library's compressor, kept for the guard below. */
typedef struct zip_guard {
    exr_result_t (*compress)(exr_encode_pipeline_t *enc);
} zip_guard;

/* A chunk whose zlib output is exactly as long as its raw bytes is read back as raw
 * bytes by every reader (sizes equal means stored), but OpenEXR 3.1.5 stores the zlib
 * bytes then. Storing the raw bytes instead makes the chunk read back as written. */
static exr_result_t compress_guarded(exr_encode_pipeline_t *enc) {
    const zip_guard *g = enc->encoding_user_data;
    exr_result_t rv = g->compress(enc);
    if (rv == EXR_ERR_SUCCESS && enc->compressed_bytes == enc->packed_bytes &&
        enc->compressed_buffer != enc->packed_buffer)
        memcpy(enc->compressed_buffer, enc->packed_buffer, enc->packed_bytes);
    return rv;
}

/* Point the pipeline's channels at rows [y, y + rows) of the caller's data. */
typedef void (*chunk_bind_fn)(exr_encode_pipeline_t *enc, int y, int rows, void *user);

/* Encode every chunk of scanline part `part` (height rows), the rows bound by bind.
 * A compressor the library picks runs behind the size-tie guard. */
static exr_result_t encode_chunks(exr_context_t ctxt, int part, int height, chunk_bind_fn bind,
                                  void *user) {
    int32_t lines;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
    exr_encode_pipeline_t enc;
    memset(&enc, 0, sizeof enc);
    zip_guard guard = {NULL};
    bool inited = false;
    for (int y = 0; rv == EXR_ERR_SUCCESS && y < height; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(ctxt, part, y, &ci);
        if (rv != EXR_ERR_SUCCESS) break;
        rv = inited ? exr_encoding_update(ctxt, part, &ci, &enc)
                    : exr_encoding_initialize(ctxt, part, &ci, &enc);
        if (rv != EXR_ERR_SUCCESS) break;
        bind(&enc, y, ci.height, user);
        if (!inited &&
            (rv = exr_encoding_choose_default_routines(ctxt, part, &enc)) == EXR_ERR_SUCCESS &&
            enc.compress_fn) {
            guard.compress = enc.compress_fn;
            enc.compress_fn = compress_guarded;
            enc.encoding_user_data = &guard;
        }
        inited = true;
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(ctxt, part, &enc);
    }
    if (inited) exr_encoding_destroy(ctxt, &enc);
    return rv;
}

typedef struct float_part {
    const pg_image *img;
    const char **names;
} float_part;

static void bind_float(exr_encode_pipeline_t *enc, int y, int rows, void *user) {
    (void)rows;
    const float_part *fp = user;
    const pg_image *img = fp->img;
    int32_t stride = (int32_t)sizeof(float) * img->channels;
    for (int c = 0; c < enc->channel_count; c++) {
        int ic = find_channel(img, fp->names, enc->channels[c].channel_name);
        size_t off = ((size_t)y * img->width) * img->channels + (size_t)ic;
        enc->channels[c].encode_from_ptr = (const uint8_t *)(img->data + off);
        enc->channels[c].user_pixel_stride = stride;
        enc->channels[c].user_line_stride = stride * img->width;
        enc->channels[c].user_data_type = EXR_PIXEL_FLOAT;
        enc->channels[c].user_bytes_per_element = 4;
    }
}

static exr_result_t write_part_pixels(exr_context_t ctxt, int part, const pg_image *img,
                                      const char **names) {
    float_part fp = {img, names};
    return encode_chunks(ctxt, part, img->height, bind_float, &fp);
}

/* Open path for writing, directly (callers already write to a temporary name and
 * rename); the library's error text lands in *m. */
static exr_result_t exr_open_write(const char *path, exr_context_t *ctxt, exr_msg *m) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = capture_error;
    init.user_data = m;
    *ctxt = NULL;
    return exr_start_write(ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
}

/* Finish a file being written after rv; a failed file is removed. */
static pg_status exr_close_write(exr_context_t *ctxt, const char *path, const exr_msg *m,
                                 exr_result_t rv, pg_error *err) {
    exr_result_t fin = exr_finish(ctxt);
    if (rv == EXR_ERR_SUCCESS) rv = fin;
    if (rv == EXR_ERR_SUCCESS) return PG_OK;
    remove(path);
    return exr_fail(err, PG_ERR_IO, path, m, rv);
}

pg_status pg_exr_write_parts(const char *path, int n, const char *const *part_names,
                             const pg_image *imgs, const char **channel_names, pg_error *err) {
    exr_msg m = {{0}};
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_open_write(path, &ctxt, &m);
    if (rv != EXR_ERR_SUCCESS) return exr_fail(err, PG_ERR_IO, path, &m, rv);
    for (int i = 0; rv == EXR_ERR_SUCCESS && i < n; i++)
        rv = define_part(ctxt, part_names ? part_names[i] : NULL, &imgs[i], channel_names);
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctxt);
    for (int i = 0; rv == EXR_ERR_SUCCESS && i < n; i++)
        rv = write_part_pixels(ctxt, i, &imgs[i], channel_names);
    return exr_close_write(&ctxt, path, &m, rv, err);
}

pg_status pg_image_write_exr(const char *path, const pg_image *img, const char **channel_names,
                             pg_error *err) {
    return pg_exr_write_parts(path, 1, NULL, img, channel_names, err);
}

/* The most raw bytes one packed byte can stand for, per compression. Deflate (ZIP,
 * ZIPS) never exceeds 1032:1; RLE's runs give at most 64:1; PXR24 zips 24-bit floats
 * (1032 x 4/3); B44 turns 32 bytes into at least 3. PIZ's Huffman runs stay under
 * about 500:1; DWA zips one DC value per 8x8 block, so a flat image can reach about
 * 128 x 1032. Each bound is padded, so no real file is refused. */
static uint64_t exr_max_ratio(exr_compression_t c) {
    switch (c) {
    case EXR_COMPRESSION_NONE:
        return 1;
    case EXR_COMPRESSION_RLE:
        return 128;
    case EXR_COMPRESSION_ZIPS:
    case EXR_COMPRESSION_ZIP:
        return 1100;
    case EXR_COMPRESSION_PXR24:
        return 1500;
    case EXR_COMPRESSION_B44:
    case EXR_COMPRESSION_B44A:
        return 16;
    case EXR_COMPRESSION_PIZ:
        return 1024;
    default:
        return UINT64_C(1) << 18; /* DWAA, DWAB */
    }
}

/* Before the image is allocated, every chunk of the part must be in the file and
 * able to hold the rows it claims: a 637-byte file whose data window said 100663328
 * x 16 asked for 6.4 GB (found by fuzz_image). exr_read_scanline_chunk_info checks a
 * chunk's offset and packed size against the file; the ratio bound above checks that
 * so few bytes can decompress to that many rows. */
static pg_status check_chunks(exr_context_t ctxt, int part, const exr_attr_box2i_t *dw,
                              const char *path, const exr_msg *m, pg_error *err) {
    exr_storage_t storage;
    int32_t lines = 0;
    exr_result_t rv = exr_get_storage(ctxt, part, &storage);
    if (rv == EXR_ERR_SUCCESS && storage != EXR_STORAGE_SCANLINE)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: tiled or deep EXR; planetgen reads scanline EXR only", path);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
    if (rv == EXR_ERR_SUCCESS && lines <= 0) rv = EXR_ERR_BAD_CHUNK_LEADER;
    for (int64_t y = dw->min.y; rv == EXR_ERR_SUCCESS && y <= dw->max.y; y += lines) {
        exr_chunk_info_t ci;
        if ((rv = exr_read_scanline_chunk_info(ctxt, part, (int)y, &ci)) != EXR_ERR_SUCCESS) break;
        if (ci.unpacked_size > exr_max_ratio(ci.compression) * ci.packed_size + 4096)
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "%s: chunk at row %lld holds %llu bytes but claims %llu raw; "
                                "the file is truncated or corrupt",
                                path, (long long)y, (unsigned long long)ci.packed_size,
                                (unsigned long long)ci.unpacked_size);
    }
    return rv == EXR_ERR_SUCCESS ? PG_OK : exr_fail(err, PG_ERR_BADINPUT, path, m, rv);
}

static exr_result_t read_pixels(exr_context_t ctxt, int part, pg_image *img,
                                const exr_attr_chlist_t *cl, int y0) {
    int32_t lines;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
    exr_decode_pipeline_t dec;
    memset(&dec, 0, sizeof dec);
    bool inited = false;
    int32_t stride = (int32_t)sizeof(float) * img->channels;
    for (int y = 0; rv == EXR_ERR_SUCCESS && y < img->height; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_read_scanline_chunk_info(ctxt, part, y0 + y, &ci);
        if (rv != EXR_ERR_SUCCESS) break;
        rv = inited ? exr_decoding_update(ctxt, part, &ci, &dec)
                    : exr_decoding_initialize(ctxt, part, &ci, &dec);
        if (rv != EXR_ERR_SUCCESS) break;
        for (int c = 0; c < dec.channel_count; c++) {
            int ic = c;
            for (int k = 0; k < cl->num_channels; k++)
                if (strcmp(cl->entries[k].name.str, dec.channels[c].channel_name) == 0) ic = k;
            size_t off = ((size_t)y * img->width) * img->channels + (size_t)ic;
            dec.channels[c].decode_to_ptr = (uint8_t *)(img->data + off);
            dec.channels[c].user_pixel_stride = stride;
            dec.channels[c].user_line_stride = stride * img->width;
            dec.channels[c].user_data_type = EXR_PIXEL_FLOAT;
            dec.channels[c].user_bytes_per_element = 4;
        }
        if (!inited) rv = exr_decoding_choose_default_routines(ctxt, part, &dec);
        inited = true;
        if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(ctxt, part, &dec);
    }
    if (inited) exr_decoding_destroy(ctxt, &dec);
    return rv;
}

static int find_part(exr_context_t ctxt, const char *want) {
    int count = 0;
    exr_get_count(ctxt, &count);
    if (!want) return count > 0 ? 0 : -1;
    for (int i = 0; i < count; i++) {
        const char *name = NULL;
        if (exr_get_name(ctxt, i, &name) == EXR_ERR_SUCCESS && name && !strcmp(name, want))
            return i;
    }
    return -1;
}

pg_status pg_image_read_exr(const char *path, const char *part_name, pg_image *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    exr_msg m = {{0}};
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_open_read(path, &ctxt, &m);
    if (rv != EXR_ERR_SUCCESS) return exr_fail(err, PG_ERR_BADINPUT, path, &m, rv);
    int part = find_part(ctxt, part_name);
    pg_status st = PG_OK;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *cl = NULL;
    if (part < 0) {
        st = pg_error_set(err, PG_ERR_BADINPUT, "%s: no part named '%s'", path,
                          part_name ? part_name : "(first)");
    } else if ((rv = exr_get_data_window(ctxt, part, &dw)) != EXR_ERR_SUCCESS ||
               (rv = exr_get_channels(ctxt, part, &cl)) != EXR_ERR_SUCCESS) {
        st = exr_fail(err, PG_ERR_BADINPUT, path, &m, rv);
    } else {
        int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
        if (w <= 0 || h <= 0 || w > INT32_MAX || h > INT32_MAX ||
            (uint64_t)w * (uint64_t)h > PG_IMAGE_DEFAULT_MAX_PIXELS)
            st = pg_error_set(err, PG_ERR_BADINPUT, "%s: absurd data window %lldx%lld", path,
                              (long long)w, (long long)h);
        else if ((st = check_chunks(ctxt, part, &dw, path, &m, err)) == PG_OK)
            st = pg_image_alloc(out, (int)w, (int)h, cl->num_channels, err);
        if (st == PG_OK && (rv = read_pixels(ctxt, part, out, cl, dw.min.y)) != EXR_ERR_SUCCESS) {
            st = exr_fail(err, PG_ERR_BADINPUT, path, &m, rv);
            pg_image_free(out);
        }
        out->src_type = PG_SAMPLE_FLOAT;
        out->unit_scale = 1.0f;
        snprintf(out->format_name, sizeof out->format_name, "openexr");
    }
    exr_finish(&ctxt);
    return st;
}

/* OpenEXR's C++ reader, which OpenImageIO uses, trusts an attribute's declared size and
 * allocates it before finding the file too short: a 277-byte file claiming a 1.9 GB string
 * took 2 GB of memory (found by fuzz_image). The C API checks every header size against
 * the file, so pg_image_read runs the headers through it first, as it walks PNG chunks. */
pg_status pg_image_exr_check(const char *path, pg_error *err) {
    static const unsigned char magic[4] = {0x76, 0x2f, 0x31, 0x01};
    unsigned char head[4];
    FILE *f = fopen(path, "rb");
    if (!f) return PG_OK; /* the reader reports unopenable files itself */
    size_t n = fread(head, 1, 4, f);
    fclose(f);
    if (n != 4 || memcmp(head, magic, 4) != 0) return PG_OK; /* not an EXR */
    exr_msg m = {{0}};
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_open_read(path, &ctxt, &m);
    if (rv != EXR_ERR_SUCCESS) return exr_fail(err, PG_ERR_BADINPUT, path, &m, rv);
    /* OpenImageIO reads the first part; a scanline one gets the chunk check too (the
     * C++ reader also allocates the whole data window before decoding). */
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    pg_status st = PG_OK;
    int count = 0;
    if (exr_get_count(ctxt, &count) == EXR_ERR_SUCCESS && count > 0 &&
        exr_get_storage(ctxt, 0, &storage) == EXR_ERR_SUCCESS && storage == EXR_STORAGE_SCANLINE &&
        exr_get_data_window(ctxt, 0, &dw) == EXR_ERR_SUCCESS)
        st = check_chunks(ctxt, 0, &dw, path, &m, err);
    exr_finish(&ctxt);
    if (st != PG_OK) return st;
    /* The parser skips a bad optional attribute, reports it and succeeds (a 1.7 GB
     * 'Software' string after a valid one did that): any report means corrupt. */
    return m.text[0] ? pg_error_set(err, PG_ERR_BADINPUT, "%s: OpenEXR error: %s", path, m.text)
                     : PG_OK;
}

pg_status pg_exr_list_parts(const char *path, int *nparts, char (*names)[64], int max_names,
                            pg_error *err) {
    exr_msg m = {{0}};
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_open_read(path, &ctxt, &m);
    if (rv != EXR_ERR_SUCCESS) return exr_fail(err, PG_ERR_BADINPUT, path, &m, rv);
    exr_get_count(ctxt, nparts);
    for (int i = 0; i < *nparts && i < max_names; i++) {
        const char *name = NULL;
        exr_get_name(ctxt, i, &name);
        snprintf(names[i], 64, "%s", name ? name : "");
    }
    exr_finish(&ctxt);
    return PG_OK;
}

/* ---- 32-bit unsigned integer parts ---- */

#define EXR_UINT_MAX_CHANNELS 8
/* zlib level 4: the default planet's map (6 x 1024^2, 75 MB raw) takes 2.7 MB in 0.5 s;
 * level 6 gives 2.25 MB in 0.67 s, level 1 3.6 MB in 0.4 s. */
#define EXR_UINT_ZIP_LEVEL 4

static int name_index(int nch, const char *const *names, const char *want) {
    for (int c = 0; c < nch; c++)
        if (strcmp(names[c], want) == 0) return c;
    return -1;
}

static exr_result_t define_uint_part(exr_context_t ctxt, const char *name, int w, int h, int nch,
                                     const char *const *names) {
    int idx;
    exr_result_t rv = exr_add_part(ctxt, name, EXR_STORAGE_SCANLINE, &idx);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctxt, idx, w, h, EXR_COMPRESSION_ZIP);
    if (rv == EXR_ERR_SUCCESS) rv = exr_set_zip_compression_level(ctxt, idx, EXR_UINT_ZIP_LEVEL);
    for (int c = 0; rv == EXR_ERR_SUCCESS && c < nch; c++)
        rv = exr_add_channel(ctxt, idx, names[c], EXR_PIXEL_UINT, EXR_PERCEPTUALLY_LOGARITHMIC, 1,
                             1);
    return rv;
}

/* Point the pipeline's channels at the interleaved rows of buf (by name: the
 * pipeline lists channels in the file's alphabetical order). */
static void bind_uint_channels(exr_coding_channel_info_t *ch, int count, int w, int nch,
                               const char *const *names, uint32_t *buf) {
    int32_t stride = (int32_t)sizeof(uint32_t) * nch;
    for (int c = 0; c < count; c++) {
        int ic = name_index(nch, names, ch[c].channel_name);
        ch[c].decode_to_ptr = (uint8_t *)(buf + (ic < 0 ? 0 : ic));
        ch[c].user_pixel_stride = stride;
        ch[c].user_line_stride = stride * w;
        ch[c].user_data_type = EXR_PIXEL_UINT;
        ch[c].user_bytes_per_element = 4;
    }
}

typedef struct uint_io {
    int w, h, nch;
    const char *const *names;
    uint32_t *buf; /* one chunk of rows */
} uint_io;

typedef struct uint_part {
    const uint_io *io;
    int part;
    pg_exr_uint_fill_fn fill;
    void *user;
} uint_part;

static void bind_uint(exr_encode_pipeline_t *enc, int y, int rows, void *user) {
    const uint_part *up = user;
    up->fill(up->part, y, rows, up->io->buf, up->user);
    bind_uint_channels(enc->channels, enc->channel_count, up->io->w, up->io->nch, up->io->names,
                       up->io->buf);
}

static exr_result_t write_uint_pixels(exr_context_t ctxt, int part, const uint_io *io,
                                      pg_exr_uint_fill_fn fill, void *user) {
    uint_part up = {io, part, fill, user};
    return encode_chunks(ctxt, part, io->h, bind_uint, &up);
}

pg_status pg_exr_write_uint_parts(const char *path, int nparts, const char *const *part_names,
                                  int width, int height, int nch, const char *const *channel_names,
                                  pg_exr_uint_fill_fn fill, void *user, pg_error *err) {
    if (nparts < 1 || width < 1 || height < 1 || nch < 1 || nch > EXR_UINT_MAX_CHANNELS)
        return pg_error_set(err, PG_ERR_RUNTIME, "%s: bad integer EXR layout", path);
    exr_msg m = {{0}};
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_open_write(path, &ctxt, &m);
    if (rv != EXR_ERR_SUCCESS) return exr_fail(err, PG_ERR_IO, path, &m, rv);
    for (int i = 0; rv == EXR_ERR_SUCCESS && i < nparts; i++)
        rv = define_uint_part(ctxt, part_names[i], width, height, nch, channel_names);
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(ctxt);
    int32_t lines = 0;
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
    uint_io io = {width, height, nch, channel_names, NULL};
    if (rv == EXR_ERR_SUCCESS &&
        !(io.buf = malloc((size_t)lines * (size_t)width * (size_t)nch * sizeof(uint32_t)))) {
        exr_finish(&ctxt);
        remove(path);
        return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", path);
    }
    for (int i = 0; rv == EXR_ERR_SUCCESS && i < nparts; i++)
        rv = write_uint_pixels(ctxt, i, &io, fill, user);
    free(io.buf);
    return exr_close_write(&ctxt, path, &m, rv, err);
}

/* Exactly the wanted channels, each UINT and unsampled. */
static bool uint_channels_match(const exr_attr_chlist_t *cl, int nch, const char *const *names) {
    if (cl->num_channels != nch) return false;
    for (int k = 0; k < cl->num_channels; k++) {
        const exr_attr_chlist_entry_t *e = &cl->entries[k];
        if (name_index(nch, names, e->name.str) < 0 || e->pixel_type != EXR_PIXEL_UINT ||
            e->x_sampling != 1 || e->y_sampling != 1)
            return false;
    }
    return true;
}

/* Decode every chunk of the part into io->buf and hand its rows to take. EXR errors
 * come back as *rv (the caller words them); take's own status is returned. */
static pg_status read_uint_pixels(exr_context_t ctxt, int part, const exr_attr_box2i_t *dw,
                                  const uint_io *io, pg_exr_uint_take_fn take, void *user,
                                  exr_result_t *rv, pg_error *err) {
    int32_t lines = 0;
    exr_decode_pipeline_t dec;
    memset(&dec, 0, sizeof dec);
    bool inited = false;
    pg_status st = PG_OK;
    *rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
    for (int y = dw->min.y; *rv == EXR_ERR_SUCCESS && st == PG_OK && y <= dw->max.y; y += lines) {
        exr_chunk_info_t ci;
        if ((*rv = exr_read_scanline_chunk_info(ctxt, part, y, &ci)) != EXR_ERR_SUCCESS) break;
        *rv = inited ? exr_decoding_update(ctxt, part, &ci, &dec)
                     : exr_decoding_initialize(ctxt, part, &ci, &dec);
        if (*rv != EXR_ERR_SUCCESS) break;
        bind_uint_channels(dec.channels, dec.channel_count, io->w, io->nch, io->names, io->buf);
        if (!inited) *rv = exr_decoding_choose_default_routines(ctxt, part, &dec);
        inited = true;
        if (*rv == EXR_ERR_SUCCESS) *rv = exr_decoding_run(ctxt, part, &dec);
        if (*rv == EXR_ERR_SUCCESS)
            st = take(ci.start_y - dw->min.y, ci.height, io->buf, user, err);
    }
    if (inited) exr_decoding_destroy(ctxt, &dec);
    return st;
}

/* The part's size and channels against the caller's expectations (one line each). */
static pg_status check_uint_part(exr_context_t ctxt, int part, const char *path,
                                 const char *part_name, const uint_io *io, exr_attr_box2i_t *dw,
                                 const exr_msg *m, pg_error *err) {
    const exr_attr_chlist_t *cl = NULL;
    exr_result_t rv = exr_get_data_window(ctxt, part, dw);
    if (rv == EXR_ERR_SUCCESS) rv = exr_get_channels(ctxt, part, &cl);
    if (rv != EXR_ERR_SUCCESS) return exr_fail(err, PG_ERR_BADINPUT, path, m, rv);
    int64_t w = (int64_t)dw->max.x - dw->min.x + 1, h = (int64_t)dw->max.y - dw->min.y + 1;
    if (w != io->w || h != io->h)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: part %s is %lldx%lld, expected %dx%d", path,
                            part_name, (long long)w, (long long)h, io->w, io->h);
    if (!uint_channels_match(cl, io->nch, io->names))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: part %s does not hold exactly the %d expected 32-bit unsigned "
                            "channels",
                            path, part_name, io->nch);
    return PG_OK;
}

pg_status pg_exr_read_uint_part(const char *path, const char *part_name, int width, int height,
                                int nch, const char *const *channel_names, pg_exr_uint_take_fn take,
                                void *user, pg_error *err) {
    exr_msg m = {{0}};
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_open_read(path, &ctxt, &m);
    if (rv != EXR_ERR_SUCCESS) return exr_fail(err, PG_ERR_BADINPUT, path, &m, rv);
    int part = find_part(ctxt, part_name);
    uint_io io = {width, height, nch, channel_names, NULL};
    exr_attr_box2i_t dw;
    pg_status st =
        part < 0 ? pg_error_set(err, PG_ERR_BADINPUT, "%s: no part named '%s'", path, part_name)
                 : check_uint_part(ctxt, part, path, part_name, &io, &dw, &m, err);
    int32_t lines = 0;
    if (st == PG_OK && (rv = exr_get_scanlines_per_chunk(ctxt, part, &lines)) != EXR_ERR_SUCCESS)
        st = exr_fail(err, PG_ERR_BADINPUT, path, &m, rv);
    if (st == PG_OK && (lines < 1 || lines > 256 ||
                        !(io.buf = malloc((size_t)lines * width * nch * sizeof(uint32_t)))))
        st = pg_error_set(err, lines < 1 || lines > 256 ? PG_ERR_BADINPUT : PG_ERR_NOMEM,
                          "%s: cannot buffer %d scanlines", path, lines);
    if (st == PG_OK) {
        st = read_uint_pixels(ctxt, part, &dw, &io, take, user, &rv, err);
        if (st == PG_OK && rv != EXR_ERR_SUCCESS) st = exr_fail(err, PG_ERR_BADINPUT, path, &m, rv);
    }
    free(io.buf);
    exr_finish(&ctxt);
    return st;
}
