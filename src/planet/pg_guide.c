/* pg_guide.c - the elevation guide of `planetgen generate --guide`: an equirectangular
 * grey sketch (white high, black low) used as a soft constraint, after Scott & Dodgson
 * 2021 ("Evaluating realism in example-based terrain synthesis", §4.2): after each
 * correction pass the reconstruction is blended with the guide, R <- w G + (1 - w) R,
 * and the weight halves at each finer level (their exponential weighting), so the
 * sketch drives the large-scale shape and the exemplar the detail.
 *
 * Grey g in 0..1 (the mean of the colour channels) maps linearly to PG_GUIDE_LOW_M ..
 * PG_GUIDE_HIGH_M metres: mid grey is sea level's neighbourhood, black deep ocean,
 * white high mountains. */
#include "planetgen/pg_guide.h"

#include "planetgen/pg_image.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

pg_status pg_guide_read_equirect(const char *path, const char *option, pg_image *img,
                                 pg_error *err) {
    pg_status st = pg_image_read(path, 0, img, err);
    if (st) {
        char msg[sizeof err->msg];
        memcpy(msg, err->msg, sizeof msg);
        pg_error_clear(err);
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: %s", option, msg);
    }
    if (img->width != 2 * img->height) {
        int w = img->width, h = img->height;
        pg_image_free(img);
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s %s: %d x %d is not an equirectangular 2:1 image", option, path, w,
                            h);
    }
    return PG_OK;
}

pg_status pg_guide_load(const char *path, pg_guide *g, pg_error *err) {
    memset(g, 0, sizeof *g);
    pg_image img;
    pg_status st = pg_guide_read_equirect(path, "--guide", &img, err);
    if (st) return st;
    size_t n = (size_t)img.width * img.height;
    g->metres = malloc(n * sizeof(float));
    if (!g->metres) {
        pg_image_free(&img);
        return pg_error_set(err, PG_ERR_NOMEM, "--guide %s: out of memory", path);
    }
    int ch = img.channels >= 3 ? 3 : 1;
    for (size_t i = 0; i < n; i++) {
        float s = 0;
        for (int k = 0; k < ch; k++)
            s += img.data[i * img.channels + k] * img.unit_scale;
        float grey = s / (float)ch;
        grey = grey < 0 ? 0 : (grey > 1 ? 1 : grey);
        g->metres[i] = (float)(PG_GUIDE_LOW_M + grey * (PG_GUIDE_HIGH_M - PG_GUIDE_LOW_M));
    }
    g->width = img.width;
    g->height = img.height;
    pg_image_free(&img);
    return PG_OK;
}

void pg_guide_free(pg_guide *g) {
    free(g->metres);
    memset(g, 0, sizeof *g);
}

double pg_guide_weight(double alpha, int s_top, int scale) {
    return alpha * ldexp(1.0, -(s_top - scale));
}
