/* pg_inspect_fidelity_internal.h - what the two files of the neighbourhood-fidelity
 * measure share (docs/inspect.md, "Neighbourhood fidelity"): the analysis fields both
 * sides are compared on (pg_inspect_fidelity_fields.c builds them: colour in Lab, scaled
 * height, box-averaged to the analysis size, and the detail amplitude) and the search
 * over them (pg_inspect_fidelity.c). */
#ifndef PLANETGEN_PG_INSPECT_FIDELITY_INTERNAL_H
#define PLANETGEN_PG_INSPECT_FIDELITY_INTERNAL_H

#include "planetgen/pg_inspect.h"

#include <stdint.h>

#define PG_INSPECT_FID_CHANNELS 4 /* L, a, b, scaled height */

/* A cube of analysis texels: 6 * n * n * PG_INSPECT_FID_CHANNELS floats, face-major; src (planet
 * only, or NULL) holds each texel's source on the analysis cube, face * n * n + y * n + x, or -1.
 */
typedef struct fid_field {
    int n;
    float *px;
    int32_t *src;
} fid_field;

typedef struct fid_src {
    int64_t n;
    const float *rgb[PG_CUBE_NFACES], *h[PG_CUBE_NFACES];
    int rgb_stride, h_stride;
} fid_src;

/* Where a field's texels come from: per face, an RGB (or packed RGBA) and a height
 * plane with their strides in floats. */
fid_src fid_planet_src(const pg_planet *p);
/* A packed cube of 6 * n * n RGBA+height texels (4 floats each), or NULL. */
fid_src fid_packed_src(const float *cube, int64_t n);

/* The analysis field of a source box-averaged by m (colour in Lab); the planet's also
 * carries each analysis texel's source (fid_field.src). Caller frees px and src. */
pg_status fid_box_field(const fid_src *sr, int m, fid_field *out, pg_error *err);
pg_status fid_planet_field(const pg_planet *p, int m, fid_field *out, pg_error *err);
/* The detail amplitude field (phase-free local contrast per channel), heights scaled
 * by hscale first. */
pg_status fid_detail_field(const fid_src *sr, int m, double hscale, fid_field *out, pg_error *err);
/* The height channel's scale that gives it the colour channels' spread, and applying it. */
double fid_height_scale(const fid_field *f);
void fid_scale_height(fid_field *f, double scale);

#endif
