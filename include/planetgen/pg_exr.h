/* pg_exr.h - OpenEXR files through OpenEXR's C API (OpenEXRCore).
 *
 * planetgen stores heights in metres as float32 EXR: one part for a flat map, or
 * one part per cube face (named after the face) for a planet. pg_image.h's
 * pg_image_write_exr/pg_image_read_exr are the single-part conveniences.
 *
 * Integer data (the planet's coordinate map, source.exr) goes into parts of 32-bit
 * unsigned channels (EXR_PIXEL_UINT), ZIP compressed. Those are streamed: the writer
 * asks the caller for a block of rows at a time and the reader hands blocks of rows
 * to the caller, so neither holds a second copy of the data. */
#ifndef PLANETGEN_PG_EXR_H
#define PLANETGEN_PG_EXR_H

#include "planetgen/pg_image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Write n parts, part i named part_names[i] (NULL names allowed only for n == 1),
 * holding imgs[i] as float32 scanlines with ZIP compression. Channel names follow
 * pg_image_write_exr's rule unless channel_names is given (applies to every part). */
pg_status pg_exr_write_parts(const char *path, int n, const char *const *part_names,
                             const pg_image *imgs, const char **channel_names, pg_error *err);

/* Number of parts and their names (names point into a static-lifetime copy owned by
 * the caller's buffer: names[i] is written into name_buf rows of 64 bytes). */
pg_status pg_exr_list_parts(const char *path, int *nparts, char (*names)[64], int max_names,
                            pg_error *err);

/* ---- 32-bit unsigned integer parts ---- */

/* Fill rows [y0, y0 + rows) of part `part` into buf: rows * width * nch values, row by
 * row, the nch channels of a pixel interleaved in the order of channel_names. Rows are
 * file rows (top-down). */
typedef void (*pg_exr_uint_fill_fn)(int part, int y0, int rows, uint32_t *buf, void *user);

/* Write nparts parts of width x height pixels, part i named part_names[i], each with
 * the nch (1..8) EXR_PIXEL_UINT channels channel_names, ZIP compressed, rows supplied
 * by fill. The file is written directly (callers stage it under a temporary name) and
 * removed on failure. */
pg_status pg_exr_write_uint_parts(const char *path, int nparts, const char *const *part_names,
                                  int width, int height, int nch, const char *const *channel_names,
                                  pg_exr_uint_fill_fn fill, void *user, pg_error *err);

/* Take rows [y0, y0 + rows) of the part being read (layout as for the fill function);
 * a status other than PG_OK stops the read and is returned as is. */
typedef pg_status (*pg_exr_uint_take_fn)(int y0, int rows, const uint32_t *buf, void *user,
                                         pg_error *err);

/* Read part `part_name` of path, which must be width x height pixels with exactly the
 * nch channels channel_names, all EXR_PIXEL_UINT and unsampled; rows go to take in
 * blocks, top to bottom. Anything else (no such part, another size or channel set, a
 * truncated or corrupt chunk) is PG_ERR_BADINPUT naming the file. */
pg_status pg_exr_read_uint_part(const char *path, const char *part_name, int width, int height,
                                int nch, const char *const *channel_names, pg_exr_uint_take_fn take,
                                void *user, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
