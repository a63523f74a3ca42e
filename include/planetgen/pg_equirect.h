/* pg_equirect.h - sampling and resampling equirectangular maps (row 0 the north edge,
 * +90 deg; column 0 the west edge, -180 deg), interleaved float channels. */
#ifndef PLANETGEN_PG_EQUIRECT_H
#define PLANETGEN_PG_EQUIRECT_H

#include "planetgen/pg_common.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bilinear sample of an equirectangular map at (lat, lon) in degrees, wrapping in
 * longitude and clamping at the poles. */
void pg_equirect_sample(const float *img, int width, int height, int channels, double lat_deg,
                        double lon_deg, float *out);

/* Resample an equirectangular map to a new size: area average when shrinking by an
 * integer factor, bilinear otherwise. */
pg_status pg_equirect_resample(const float *src, int sw, int sh, int channels, int dw, int dh,
                               float **out, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
