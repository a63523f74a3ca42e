/* pg_image.h - image input/output for planetgen, as a C API.
 *
 * Reading goes through OpenImageIO (JPEG, PNG 8/16, TIFF/GeoTIFF 8/16/32f, EXR, ...),
 * in a thin C++ adapter (src/adapters/pg_oiio.cpp). Pixels come back as interleaved
 * floats holding the file's raw numeric values (a uint8 255 stays 255.0, an int16
 * -400 stays -400.0), with `unit_scale` saying how to map integer formats onto 0..1.
 * Keeping raw values matters for heights: a 16-bit GeoTIFF in metres must not be
 * normalised. Row 0 is the top of the image.
 *
 * Writing: PNG 8/16-bit through OpenImageIO (values 0..1, clamped); float EXR
 * through OpenEXR's C API (pg_exr.c). */
#ifndef PLANETGEN_PG_IMAGE_H
#define PLANETGEN_PG_IMAGE_H

#include "planetgen/pg_common.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pg_image_sample_type {
    PG_SAMPLE_UINT8,
    PG_SAMPLE_INT8,
    PG_SAMPLE_UINT16,
    PG_SAMPLE_INT16,
    PG_SAMPLE_UINT32,
    PG_SAMPLE_INT32,
    PG_SAMPLE_HALF,
    PG_SAMPLE_FLOAT,
    PG_SAMPLE_DOUBLE
} pg_image_sample_type;

typedef struct pg_image {
    int width, height, channels;
    float *data; /* width*height*channels, interleaved, caller frees with pg_image_free */
    pg_image_sample_type src_type;
    float unit_scale;     /* multiply to get 0..1 for integer types; 1 for float types */
    char format_name[32]; /* e.g. "jpeg", "png", "tiff", "openexr" */
} pg_image;

/* How every PNG planetgen writes is encoded (files and the textures inside .glb):
 * zlib's Z_RLE strategy (matches at distance 1 only, so the level does not matter),
 * after libpng's row filter PG_PNG_FILTER (a PNG_FILTER_* bit of png.h). On the
 * default planet's images this encodes 2-4 times as fast as zlib level 3 with
 * libpng's adaptive filters, and most files come out smaller: the filtered rows of
 * smooth terrain are runs. PNG encoding was the largest part of writing the previews
 * and the globe (docs/generate.md, "Performance of the whole run"). */
#define PG_PNG_COMPRESSION_LEVEL 3
#define PG_PNG_STRATEGY "rle"
#define PG_PNG_FILTER 0x40 /* PNG_FILTER_AVG */

/* Default refusal limit for pg_image_read: 2^31 pixels (about 46k x 46k). */
#define PG_IMAGE_DEFAULT_MAX_PIXELS (UINT64_C(1) << 31)

/* Read an image. Refuses (PG_ERR_BADINPUT, before allocating pixel memory) images
 * with more than max_pixels pixels (0 = default), missing, empty, directory,
 * truncated or non-image files, always naming the path. */
pg_status pg_image_read(const char *path, uint64_t max_pixels, pg_image *out, pg_error *err);

/* Read just the geometry (no pixels). */
pg_status pg_image_probe(const char *path, int *width, int *height, int *channels, pg_error *err);

void pg_image_free(pg_image *img);

/* Structural check of a PNG (chunk lengths and CRCs up to IEND); PG_OK for files
 * that are not PNGs. pg_image_read calls it first. */
pg_status pg_image_png_check(const char *path, pg_error *err);

/* Marker walk of a JPEG up to its scan: refuses an APP13 IPTC block that declares more
 * bytes than its segment holds (OpenImageIO 2.4 would read past the segment); PG_OK for
 * files that are not JPEGs. pg_image_read calls it first. */
pg_status pg_image_jpeg_check(const char *path, pg_error *err);

/* Header check of an OpenEXR file through OpenEXR's C API, which checks every declared
 * size against the file; PG_OK for files that are not EXRs. pg_image_read calls it
 * first: OpenImageIO's C++ EXR reader allocates what a header claims before checking. */
pg_status pg_image_exr_check(const char *path, pg_error *err);

/* Allocate a zeroed image. */
pg_status pg_image_alloc(pg_image *img, int width, int height, int channels, pg_error *err);

/* Write a PNG with 8 or 16 bits per sample; data values 0..1 are clamped and rounded. */
pg_status pg_image_write_png(const char *path, const pg_image *img, int bits, pg_error *err);

/* The same PNG's bytes in memory, byte for byte the file pg_image_write_png writes.
 * On success *bytes is malloc'ed (the caller frees it) and *size set. */
pg_status pg_image_encode_png(const pg_image *img, int bits, uint8_t **bytes, size_t *size,
                              pg_error *err);

/* Write a single-part float32 OpenEXR (OpenEXR C API). Channels are named Y (1),
 * Y+A (2), R,G,B (3) or R,G,B,A (4); `channel_names` overrides when not NULL. */
pg_status pg_image_write_exr(const char *path, const pg_image *img, const char **channel_names,
                             pg_error *err);

/* Read a float EXR part by name (NULL = first part) through the OpenEXR C API. */
pg_status pg_image_read_exr(const char *path, const char *part_name, pg_image *out, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
