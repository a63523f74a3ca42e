/* pg_planet_synth_guide.c - Scott & Dodgson 2021's guide (§4.2) in the planet synthesis:
 * the elevation sketch resampled onto every level, and the soft constraint after each
 * correction pass, R <- w G + (1 - w) R with w halving per finer level (pg_guide_weight;
 * docs/generate.md, "Method": "Guide").
 *
 * The blend is per texel and runs on the whole level after the pass's sub-passes, so it
 * depends on no tile size, order or thread count. */
#include "pg_planet_synth_internal.h"

#include <math.h>

pg_status pg_ps_guide_level(pg_ps_ctx *c, int r, pg_error *err) {
    if (!c->p->guide) return PG_OK;
    const pg_guide *g = c->p->guide;
    int samples = (int)ceil((double)g->width / (4.0 * r));
    if (samples < 1) samples = 1;
    if (samples > 8) samples = 8;
    pg_status st = PG_OK;
    for (int f = 0; f < 6 && !st; f++) { /* distributed: the rows of the owned tiles */
        int y0, y1;
        pg_ps_owned_rows(c, r, f, &y0, &y1);
        if (y0 < y1)
            st = pg_cube_from_equirect_rows(PG_CUBE_DEFAULT_PROJECTION, r, NULL, g->metres,
                                            g->width, g->height, 1, samples, (int64_t)f * r + y0,
                                            (int64_t)f * r + y1, c->guide, err);
    }
    return st;
}

float pg_ps_guide_w(const pg_ps_ctx *c, int scale) {
    return (float)pg_guide_weight(c->p->guide_alpha, c->s_top, scale);
}

/* The blend on n texels of the reconstruction R, the offsets Vc and the guide G (as V
 * += w (G - R), so that R stays E_s(S) + V). */
void pg_ps_guide_blend(const pg_ps_ctx *c, int scale, size_t n, float *R, float *Vc,
                       const float *G) {
    float w = pg_ps_guide_w(c, scale);
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        float d = w * (G[i] - R[i]);
        Vc[i] += d;
        R[i] += d;
    }
}
