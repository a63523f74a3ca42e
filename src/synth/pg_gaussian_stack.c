/* pg_gaussian_stack.c - the Gaussian stack of the exemplar (Lefebvre & Hoppe 2005,
 * "Parallel controllable texture synthesis", SIGGRAPH, section 3.1).
 *
 * A stack keeps every level at full resolution: level s is the exemplar low-passed as
 * a Gaussian pyramid level of spacing h = 2^s would be, but not subsampled, so every
 * exemplar texel has a neighbourhood at every level. It is built "a trous": level s is
 * level s-1 filtered by the 5-tap binomial kernel [1 4 6 4 1]/16 with its taps 2^(s-1)
 * texels apart. Because the pyramid's REDUCE is the same filter followed by dropping
 * every other sample, sampling level s at any lattice of spacing 2^s gives exactly a
 * pyramid level; the stack is the union of all such shifted pyramids.
 *
 * Precondition: the faces carry a gutter at least 2*(2^s - 1) wide for levels up to s
 * on a cube (reads clamp at the outer gutter edge), or are toroidal (reads wrap). */
#include "pg_synth_internal.h"

#include <string.h>

static const float binomial5[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16, 1.0f / 16};

/* Index of extended coordinate i (0..ext-1) moved by d, clamped or wrapped. */
static inline int step(const pg_synth_faces *f, int i, int d) {
    int j = i + d;
    if (f->torus) return j & (f->ext - 1);
    return j < 0 ? 0 : (j >= f->ext ? f->ext - 1 : j);
}

static void filter_pass(const pg_synth_faces *f, const float *src, float *dst, int tap,
                        int horizontal) {
    const int ext = f->ext;
#pragma omp parallel for schedule(static) collapse(2)
    for (int face = 0; face < f->nfaces; face++)
        for (int y = 0; y < ext; y++) {
            const float *base = src + (size_t)face * ext * ext * PG_SYNTH_CH;
            float *out = dst + (((size_t)face * ext + y) * ext) * PG_SYNTH_CH;
            for (int x = 0; x < ext; x++) {
                float acc[PG_SYNTH_CH] = {0};
                for (int k = -2; k <= 2; k++) {
                    int sx = horizontal ? step(f, x, k * tap) : x;
                    int sy = horizontal ? y : step(f, y, k * tap);
                    const float *p = base + ((size_t)sy * ext + sx) * PG_SYNTH_CH;
                    for (int c = 0; c < PG_SYNTH_CH; c++)
                        acc[c] += binomial5[k + 2] * p[c];
                }
                memcpy(out + (size_t)x * PG_SYNTH_CH, acc, sizeof acc);
            }
        }
}

void pg_gaussian_stack_next(pg_synth_faces *f, int scale, float *tmp) {
    int tap = 1 << (scale - 1);
    filter_pass(f, f->px, tmp, tap, 1);
    filter_pass(f, tmp, f->px, tap, 0);
}
