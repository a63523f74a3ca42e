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
    return pg_cube_from_equirect(PG_CUBE_DEFAULT_PROJECTION, r, NULL, g->metres, g->width,
                                 g->height, 1, samples, c->guide, err);
}

/* The blend on the n texels of the reconstruction R and the offsets Vc (as V += w (G -
 * R), so that R stays E_s(S) + V). */
void pg_ps_guide_blend(const pg_ps_ctx *c, int scale, size_t n, float *R, float *Vc) {
    float w = (float)pg_guide_weight(c->p->guide_alpha, c->s_top, scale);
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        float d = w * (c->guide[i] - R[i]);
        Vc[i] += d;
        R[i] += d;
    }
}
