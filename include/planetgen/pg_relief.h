/* pg_relief.h - shaded relief previews of equirectangular height maps (metres). */
#ifndef PLANETGEN_PG_RELIEF_H
#define PLANETGEN_PG_RELIEF_H

#include "planetgen/pg_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Shaded relief preview (RGB 0..1): hypsometric tint times hill shading, lit from
 * the north-west, with the slope taken in metres on the sphere. */
void pg_relief_shade(const float *height, int width, int height_px, float sea_level,
                     float *rgb_out);

#ifdef __cplusplus
}
#endif

#endif
