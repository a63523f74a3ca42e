/* pg_exr.h - float32 OpenEXR files through OpenEXR's C API (OpenEXRCore).
 *
 * planetgen stores heights in metres as float32 EXR: one part for a flat map, or
 * one part per cube face (named after the face) for a planet. pg_image.h's
 * pg_image_write_exr/pg_image_read_exr are the single-part conveniences. */
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

#ifdef __cplusplus
}
#endif

#endif
