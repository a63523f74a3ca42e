/* pg_vec3.h - 3-vectors of doubles (double[3]): the small helpers every module used to
 * write out again.
 *
 * The arithmetic is spelled out so results are reproducible bit for bit: dot is
 * (a0 b0 + a1 b1) + a2 b2, left to right; length is sqrt(dot(v, v)); normalize divides
 * each component by that length (it does not multiply by a reciprocal, which rounds
 * differently). The library is compiled as ISO C11, where floating contraction is off,
 * so an inlined helper computes exactly what the same expression written in place
 * would. Outputs are arrays the caller owns; `o` may alias an input in every helper
 * but cross. Library-internal: not part of the installed API. */
#ifndef PG_VEC3_H
#define PG_VEC3_H

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

/* o = a + b */
static inline void pg_vec3_add(const double a[3], const double b[3], double o[3]) {
    o[0] = a[0] + b[0];
    o[1] = a[1] + b[1];
    o[2] = a[2] + b[2];
}

/* o = a - b */
static inline void pg_vec3_sub(const double a[3], const double b[3], double o[3]) {
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

/* o = s a */
static inline void pg_vec3_scale(const double a[3], double s, double o[3]) {
    o[0] = s * a[0];
    o[1] = s * a[1];
    o[2] = s * a[2];
}

static inline double pg_vec3_dot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* o = a x b; o must not alias a or b. */
static inline void pg_vec3_cross(const double a[3], const double b[3], double o[3]) {
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double pg_vec3_length(const double v[3]) {
    return sqrt(pg_vec3_dot(v, v));
}

/* v /= |v| in place; the zero vector stays zero. */
static inline void pg_vec3_normalize(double v[3]) {
    double l = pg_vec3_length(v);
    if (l > 0) v[0] /= l, v[1] /= l, v[2] /= l;
}

#ifdef __cplusplus
}
#endif

#endif
