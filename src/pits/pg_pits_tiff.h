/* pg_pits_tiff.h - float32 TIFF output for `planetgen pits`, so GIS users get a
 * GeoTIFF back when they give one: the georeferencing attributes OpenImageIO reads
 * from the input ("GeoTIFF:*") are copied to the output. A C header over the thin
 * OpenImageIO adapter src/adapters/pg_pits_tiff.cpp. */
#ifndef PG_PITS_TIFF_H
#define PG_PITS_TIFF_H

#include "planetgen/pg_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Write w x h floats (row 0 at the top) as a single-channel float32 TIFF at path.
 * like (may be NULL): a file whose GeoTIFF attributes are copied. */
pg_status pg_pits_write_tiff(const char *path, const float *data, int w, int h, const char *like,
                             pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
