/* pg_inspect_distortion.h - the content-blind distortion check of `planetgen inspect`
 * (docs/inspect.md): how much a synthesized planet stretches, squeezes and shears
 * the exemplar it copied, read from its coordinate map (pg_planet_source) alone.
 *
 * THE MEASURE. Synthesis copies exemplar texels; where it copies faithfully, ground
 * distance on the planet equals ground distance in the exemplar. At a planet texel the
 * local linear map J from planet ground offsets to exemplar ground offsets (km per km,
 * both on the planet's sphere of mean radius) is estimated by least squares over the
 * 5x5 texels around it within its face (3x3 where the 5x5 straddles a patch seam):
 * planet offsets in the tangent plane at the texel, the offsets of their sources in the
 * tangent plane at its source. J's singular values s1 >= s2 give the scale
 * s = sqrt(s1 s2) and the anisotropy a = s1 / s2, and the texel's figure is max(s, 1/s) * a: 1 for
 * a faithful copy (turned or mirrored copies included), above 1 for any stretch. A texel counts (is
 * "coherent") when its window's sources fit one affine map to within one exemplar texel and J is
 * not degenerate; the others straddle the seams between copied patches.
 *
 * THE VIEWS. 26 caps of PG_INSPECT_DISTORTION_CAP_DEG around the cube's special points:
 * both poles and the four equator face centres (the six face centres), the 8 cube
 * corners and the 12 face-edge midpoints. A view's figure is the mean texel figure over
 * the coherent texels whose centre lies in the cap. The pole-distortion ratio is the
 * worst pole-or-corner view's figure divided by the mean figure of the 4 equator and 12
 * edge-midpoint views: a planet whose poles or cube corners are distorted more than its
 * equator scores above 1. Gate: <= PG_INSPECT_DISTORTION_GATE. A pole or corner cap
 * without a single coherent texel (nothing there is a faithful copy of anything, as at
 * the pinched poles of a lat-lon layout) fails the gate with a NaN ratio.
 *
 * MAGNIFICATION. A planet synthesized at N / m and magnified carries the same source
 * over aligned m x m blocks; the check then works on the blocks (windows at stride m,
 * block-centre positions), so m does not bias it. m is detected from the map. */
#ifndef PLANETGEN_PG_INSPECT_DISTORTION_H
#define PLANETGEN_PG_INSPECT_DISTORTION_H

#include "planetgen/pg_planet.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Gate: worst pole-or-corner figure <= this x mean equator-and-edge figure. */
#define PG_INSPECT_DISTORTION_GATE 1.15
/* Cap radius of a view, degrees: ~6500 texels of the default planet (N = 1024, 9 km
 * texels), 1/14 of the angle from a cube corner to a face centre. */
#define PG_INSPECT_DISTORTION_CAP_DEG 4.0
/* Coherent: max least-squares residual <= this many exemplar texels. */
#define PG_INSPECT_DISTORTION_RESIDUAL 1.0
/* Degenerate: per window step the sources move less than this many exemplar texels in
 * some direction (rounding can then make a 3x3 window's sources all equal). */
#define PG_INSPECT_DISTORTION_MIN_STEP 0.25
/* Fewest texels a coherent texel's window spans along each axis: a window two texels
 * wide (the 3 x 3 clipped at a face edge) fits any jump between its two columns as a
 * linear map - on a generated planet, sources 1500 texels apart passed the residual
 * test that way - so the fit must be over-determined along both axes. */
#define PG_INSPECT_DISTORTION_MIN_SPAN 3

#define PG_INSPECT_DISTORTION_NVIEWS 26

typedef enum pg_inspect_distortion_kind {
    PG_INSPECT_DISTORTION_POLE,    /* views 0, 1: north, south */
    PG_INSPECT_DISTORTION_EQUATOR, /* views 2..5: longitudes 0, 90E, 180, 90W */
    PG_INSPECT_DISTORTION_CORNER,  /* views 6..13: the 8 cube corners */
    PG_INSPECT_DISTORTION_EDGE     /* views 14..25: the 12 face-edge midpoints */
} pg_inspect_distortion_kind;

/* The local map at one planet texel (or block, when magnified). */
typedef struct pg_inspect_distortion_texel {
    int points;        /* window texels used (25 inside a face, fewer at its edges; 9 or
                          fewer for the 3x3 fallback) */
    double s1, s2;     /* singular values of J, km per km, s1 >= s2 */
    double scale;      /* sqrt(s1 s2) */
    double anisotropy; /* s1 / s2 (infinite when s2 = 0) */
    double figure;     /* max(scale, 1 / scale) * anisotropy */
    double residual;   /* max least-squares residual, in exemplar texels */
    double span;       /* smallest source displacement per window step, exemplar texels */
    bool mirrored;     /* det J < 0 */
    bool degenerate;   /* span < PG_INSPECT_DISTORTION_MIN_STEP, or J singular */
    bool coherent;     /* residual <= PG_INSPECT_DISTORTION_RESIDUAL, not degenerate, and
                          the window spans PG_INSPECT_DISTORTION_MIN_SPAN texels per axis */
} pg_inspect_distortion_texel;

typedef struct pg_inspect_distortion_view {
    const char *name; /* "north", "equator_90e", "corner_n45e", "edge_s90w", "edge_135e", ... */
    pg_inspect_distortion_kind kind;
    double dir[3];                      /* unit centre direction */
    int64_t texels;                     /* texels (blocks) whose centre lies in the cap */
    int64_t coherent;                   /* of those, coherent */
    int64_t degenerate;                 /* of those, with a degenerate J */
    double share;                       /* coherent / texels */
    double figure;                      /* mean figure over the coherent texels (NaN if none) */
    double mean_scale, mean_anisotropy; /* over the coherent texels */
} pg_inspect_distortion_view;

typedef struct pg_inspect_distortion {
    double cap_deg;    /* PG_INSPECT_DISTORTION_CAP_DEG */
    int magnification; /* m: the map is constant over aligned m x m blocks */
    pg_inspect_distortion_view views[PG_INSPECT_DISTORTION_NVIEWS];
    /* The worst pole-or-corner view: the first without coherent texels if any (nothing
     * there is a faithful copy: the gate fails), else the one of largest figure. */
    int worst;              /* its index, -1 without a map */
    const char *worst_name; /* its name, or "none" */
    double worst_figure;    /* its figure (NaN if it has no coherent texels) */
    double reference;       /* mean figure of the 4 equator and 12 edge-midpoint views */
    double ratio;           /* pole_distortion_ratio = worst_figure / reference; NaN when a
                               view has no coherent texels */
    double share_ratio;     /* lowest coherent share of the pole-or-corner views / mean
                               share of the equator and edge-midpoint views */
    bool gate_pass;         /* ratio <= PG_INSPECT_DISTORTION_GATE (false for NaN) */
} pg_inspect_distortion;

/* The largest power of two m dividing N such that every aligned m x m block of the map
 * holds one source (1 when the planet has no map). */
int pg_inspect_distortion_magnification(const pg_planet *p);

/* The local map at block (bx, by) of `face` for magnification m (block = texel when m =
 * 1; 0 <= bx, by < N / m). The map must be present and valid, N / m >= 2. */
void pg_inspect_distortion_texel_at(const pg_planet *p, int m, int face, int64_t bx, int64_t by,
                                    pg_inspect_distortion_texel *out);

/* The 26 views and the ratio. A planet without a map gets NaN figures and ratio (and
 * PG_OK); a map naming texels outside its exemplar cube is BADINPUT. Views without
 * coherent texels have a NaN figure; the ratio is then NaN and the gate fails. Runs with
 * OpenMP over views; each view sums in a fixed order, so the result does not depend on
 * the thread count. */
pg_status pg_inspect_distortion_compute(const pg_planet *p, pg_inspect_distortion *out,
                                        pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
