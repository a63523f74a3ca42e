/* pg_image.c - the format-independent parts of pg_image.h (allocation). */
#include "planetgen/pg_image.h"

#include <stdlib.h>
#include <string.h>

pg_status pg_image_alloc(pg_image *img, int width, int height, int channels, pg_error *err) {
    memset(img, 0, sizeof *img);
    if (width <= 0 || height <= 0 || channels <= 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "image size %dx%dx%d is not positive", width,
                            height, channels);
    size_t n = (size_t)width * (size_t)height * (size_t)channels;
    img->data = calloc(n, sizeof(float));
    if (!img->data)
        return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate %.0f MB for a %dx%d image",
                            n * 4.0 / 1e6, width, height);
    img->width = width;
    img->height = height;
    img->channels = channels;
    img->src_type = PG_SAMPLE_FLOAT;
    img->unit_scale = 1.0f;
    return PG_OK;
}

void pg_image_free(pg_image *img) {
    if (!img) return;
    free(img->data);
    img->data = NULL;
    img->width = img->height = img->channels = 0;
}
