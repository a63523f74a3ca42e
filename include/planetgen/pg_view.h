/* pg_view.h - one rendered square view of a planet (pg_views.h renders them): RGB and
 * height images of the same size, owned by the view. */
#ifndef PLANETGEN_PG_VIEW_H
#define PLANETGEN_PG_VIEW_H

#include "planetgen/pg_image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A rendered view: size x size, rgb interleaved, height in metres, row 0 at the top. */
typedef struct pg_view {
    int size;
    float *rgb;
    float *height;
} pg_view;
void pg_view_free(pg_view *v);

/* The view's RGB as an image (data aliases v->rgb: do not free it separately). */
pg_image pg_view_rgb_image(const pg_view *v);

#ifdef __cplusplus
}
#endif

#endif
