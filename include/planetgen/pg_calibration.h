/* pg_calibration.h - the grey -> metres mapping of an 8-bit relief (data/README.md):
 * piecewise linear through knots fitted on the Blue Marble water mask
 * (pg_exemplar_calibrate) or set from surveyed reference points of Marble's relief. */
#ifndef PLANETGEN_PG_CALIBRATION_H
#define PLANETGEN_PG_CALIBRATION_H

#include "planetgen/pg_image.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The grey -> metres mapping: piecewise linear through knots (grey, metres). */
#define PG_CALIBRATION_MAX_KNOTS 16
typedef struct pg_calibration {
    int nknots;
    float grey[PG_CALIBRATION_MAX_KNOTS];
    float metres[PG_CALIBRATION_MAX_KNOTS];
    float sea_grey;        /* grey level of sea level, estimated from the water mask */
    double mask_agreement; /* fraction of pixels where (h < 0) == Blue Marble water */
    bool reference_points; /* knots from surveyed reference points (Marble relief) */
} pg_calibration;

/* Replace c's knots by the reference-point calibration of Marble's relief: the grey
 * at each surveyed point (median of a 7x7 window of the full-resolution relief)
 * becomes a knot at that point's elevation; the sea-level knot c->sea_grey stays. */
pg_status pg_calibration_marble_refs(const pg_image *relief, pg_calibration *c, pg_error *err);

float pg_calibration_apply(const pg_calibration *c, float grey);

#ifdef __cplusplus
}
#endif

#endif
