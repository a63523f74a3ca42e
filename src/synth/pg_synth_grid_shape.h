/* pg_synth_grid_shape.h - the grid-shape term of the correction near the cube's corners
 * (not public API; used by pg_synth_lefebvre_hoppe.c, tested by test_synth_grid_shape).
 *
 * Idea. A copy takes whole texels to whole texels, so it keeps ground lengths and angles
 * only where the exemplar texel's grid has the output texel's shape. The equi-angular
 * grid is square at a face's centre, has sides in the ratio 1 : 0.71 at an edge's
 * midpoint, and is a rhombus of 60 and 120 degrees at a corner, where a copy of square
 * texels is stretched by up to 1.7 (docs/inspect.md, "Distortion"). Near the corners the
 * correction therefore multiplies each candidate's penalty by 1 + w s d:
 *  - G = (gxx, gyy, gxy), the Gram matrix of one texel's steps along x and y on the unit
 *    sphere over that at a face centre, is for face angles with tangents X and Y and
 *    p = 1 + X^2 + Y^2:
 *      gxx = (1 + X^2)^2 (1 + Y^2) / p^2,  gyy = (1 + Y^2)^2 (1 + X^2) / p^2,
 *      gxy = -(1 + X^2) (1 + Y^2) X Y / p^2
 *    (the derivatives of (X, Y, 1) / sqrt(p)), the same function on every face in the
 *    face's own frame, for the output's cube and the exemplar's alike. A candidate
 *    turned by an odd number of quarter turns into the output's frame swaps gxx and gyy
 *    and negates gxy. d is the Frobenius norm of the difference of the two G.
 *  - s, the output texel's nearness to a corner, is 0 where either face coordinate lies
 *    within PG_SYNTH_SHAPE_A0 of the centre (a half-width is 1) and rises linearly to 1
 *    at the corner. It fades to 0 over the last PG_SYNTH_SHAPE_FADE texels (of the level)
 *    before a face edge. The fade is for the seams: the grid kinks where two faces meet
 *    (the steps across a seam turn, except at its midpoint), so a patch that continues
 *    across a seam has the shape of one side at most; without the fade the term broke
 *    the patches there (docs/synthesis.md, "Grid shape at the cube's corners").
 * Positions go to PG_SYNTH_SHAPE_Q bins along a face's edge (pg_synth_shape_bin).
 *
 * Why it keeps the correction exact: the factor is a pure function of the texel's
 * global position at its level, the level's face size and the candidate, so it depends on
 * no tile, order, thread or rank (pg_synth_lefebvre_hoppe.c, "order-independent"). */
#ifndef PG_SYNTH_GRID_SHAPE_H
#define PG_SYNTH_GRID_SHAPE_H

#include "planetgen/pg_synth.h"

#include <math.h>
#include <stdint.h>

#define PG_SYNTH_SHAPE_Q 256
#define PG_SYNTH_SHAPE_A0 0.5f   /* s = 0 where either face coordinate is within this */
#define PG_SYNTH_SHAPE_FADE 4.0f /* s fades to 0 over this many texels to a face edge */

/* tanq[i]: the tangent of the face angle at the centre of bin i. */
static inline void pg_synth_shape_table(float tanq[PG_SYNTH_SHAPE_Q]) {
    for (int i = 0; i < PG_SYNTH_SHAPE_Q; i++)
        tanq[i] = (float)tan(((i + 0.5) / PG_SYNTH_SHAPE_Q - 0.5) * (3.14159265358979323846 / 2));
}

/* The bin of texel x of n along a face's edge: the bin that holds the texel's first
 * edge. For n a multiple of 2 PG_SYNTH_SHAPE_Q (the finest levels of the default planet,
 * and the exemplar) that is the bin of its centre, and texels mirrored about the face's
 * centre line land in mirrored bins. At coarser levels the texel is taken half a texel
 * off its centre, so mirrored texels differ by up to 1/n of a half-width in s (at most 6%
 * of its range at n = 32). Centring it was measured and changed no figure beyond the
 * seeds' noise (docs/generate.md, "Grid shape at the corners"). */
static inline int pg_synth_shape_bin(int64_t x, int64_t n) {
    return (int)(x * PG_SYNTH_SHAPE_Q / n);
}

/* G at the face angles whose tangents are X and Y. */
static inline void pg_synth_grid_gram(float X, float Y, float g[3]) {
    const float x2 = 1 + X * X, y2 = 1 + Y * Y, p = x2 + Y * Y, inv = 1.0f / (p * p);
    g[0] = x2 * x2 * y2 * inv;
    g[1] = y2 * y2 * x2 * inv;
    g[2] = -x2 * y2 * X * Y * inv;
}

/* g seen from a frame turned by `turns` quarter turns (pg_synth_orient_apply's rotations,
 * which take the view's offsets into the texel's frame): an odd number swaps the two
 * steps and negates their product. */
static inline void pg_synth_grid_gram_turned(const float g[3], int turns, float out[3]) {
    const int odd = turns & 1;
    out[0] = g[odd];
    out[1] = g[1 - odd];
    out[2] = odd ? -g[2] : g[2];
}

/* An output texel as the term sees it: its nearness s and its G. */
typedef struct pg_synth_shape_texel {
    float s;
    float g[3];
} pg_synth_shape_texel;

/* Texel (x, y) of a face of r x r texels; false (s = 0, nothing to weigh) away from the
 * corners and on the face's edges. */
static inline int pg_synth_shape_texel_at(const float *tanq, int64_t r, int64_t x, int64_t y,
                                          pg_synth_shape_texel *t) {
    const int iu = pg_synth_shape_bin(x, r), iv = pg_synth_shape_bin(y, r);
    const float a = fabsf((iu + 0.5f) * (2.0f / PG_SYNTH_SHAPE_Q) - 1.0f),
                b = fabsf((iv + 0.5f) * (2.0f / PG_SYNTH_SHAPE_Q) - 1.0f);
    float s = ((a < b ? a : b) - PG_SYNTH_SHAPE_A0) / (1.0f - PG_SYNTH_SHAPE_A0);
    int64_t e = x < r - 1 - x ? x : r - 1 - x; /* texels to the nearest face edge */
    if (y < e) e = y;
    if (r - 1 - y < e) e = r - 1 - y;
    if (e < PG_SYNTH_SHAPE_FADE) s *= (float)e / PG_SYNTH_SHAPE_FADE;
    t->s = s > 0 ? s : 0;
    if (t->s > 0) pg_synth_grid_gram(tanq[iu], tanq[iv], t->g);
    return t->s > 0;
}

/* 1 + ws d for candidate q (an exemplar cube of e texels a face edge); ws = w s. */
static inline float pg_synth_shape_factor(const float *tanq, const pg_synth_shape_texel *t,
                                          float ws, int e, uint32_t q) {
    float ge[3], gt[3];
    pg_synth_grid_gram(tanq[pg_synth_shape_bin(pg_synth_u(q), e)],
                       tanq[pg_synth_shape_bin(pg_synth_v(q), e)], ge);
    pg_synth_grid_gram_turned(ge, pg_synth_orient(q), gt);
    const float dxx = t->g[0] - gt[0], dyy = t->g[1] - gt[1], dxy = t->g[2] - gt[2];
    return 1.0f + ws * sqrtf(dxx * dxx + dyy * dyy + 2 * dxy * dxy);
}

#endif
