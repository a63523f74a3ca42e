/* pg_guide.h - the elevation guide (Scott & Dodgson 2021 soft constraints): a grey
 * equirectangular sketch that planet synthesis (pg_planet_synth.h) blends into the
 * reconstructed heights, with a weight halving at each finer level. */
#ifndef PLANETGEN_PG_GUIDE_H
#define PLANETGEN_PG_GUIDE_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An equirectangular grey elevation sketch, white high, black low: grey g in 0..1 is
 * g_low_m + g * (g_high_m - g_low_m) metres. */
typedef struct pg_guide {
    int width, height;
    float *metres;
} pg_guide;
#define PG_GUIDE_LOW_M (-4000.0)
#define PG_GUIDE_HIGH_M 4000.0
pg_status pg_guide_load(const char *path, pg_guide *g, pg_error *err);
void pg_guide_free(pg_guide *g);
/* Read an equirectangular image for `option` (BADINPUT naming it and the path if it is
 * unreadable or not 2:1). */
pg_status pg_guide_read_equirect(const char *path, const char *option, pg_image *img,
                                 pg_error *err);

/* Blend weight of the guide at scale s when the coarsest scale is s_top:
 * alpha * 2^-(s_top - s) (halves at each finer level). */
double pg_guide_weight(double alpha, int s_top, int scale);

#ifdef __cplusplus
}
#endif

#endif
