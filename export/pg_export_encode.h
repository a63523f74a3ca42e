/* pg_export_encode.h - encode an image into PNG or JPEG bytes in memory.
 *
 * The glTF writer embeds images as buffer views, so it needs the encoded bytes,
 * not a file. A thin C++ adapter (pg_export_encode.cpp) drives OpenImageIO with an
 * in-memory output proxy; no C++ type crosses this header. */
#ifndef PG_EXPORT_ENCODE_H
#define PG_EXPORT_ENCODE_H

#include "planetgen/pg_common.h"

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pg_export_codec { PG_EXPORT_CODEC_PNG, PG_EXPORT_CODEC_JPEG } pg_export_codec;

/* Encode width x height x channels floats in 0..1 (clamped, rounded) as PNG (bits
 * 8 or 16) or JPEG (8 bits, `quality` 1..100). `bottom_up`: the buffer's row 0 is
 * the image's bottom row (cube faces), so rows are flipped on the way out. On
 * success *bytes is malloc'ed (caller frees) and *size set. `what` names the image
 * in error messages. */
pg_status pg_export_encode(const float *data, int width, int height, int channels, int bits,
                           bool bottom_up, pg_export_codec codec, int quality, const char *what,
                           uint8_t **bytes, size_t *size, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
