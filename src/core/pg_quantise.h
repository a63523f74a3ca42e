/* pg_quantise.h - rounding floats to image integers, exactly as lround does, without
 * its library call (which was a twentieth of writing the previews and the globe).
 *
 * For 0 <= x < 2^52, (x + 2^52) - 2^52 is x rounded to the nearest integer, ties to
 * even (the FPU's default mode; the compiler may not reassociate it without
 * -ffast-math). lround breaks ties away from zero instead, so a tie is moved up. The
 * tie test is exact: r - x is computed without error, by Sterbenz's lemma when r >= 1
 * (then x > r - 1/2 >= r/2) and trivially when r = 0. */
#ifndef PG_QUANTISE_H
#define PG_QUANTISE_H

/* lround(x) for 0 <= x < 2^52, as a double. */
static inline double pg_round_half_up(double x) {
    double r = (x + 0x1p52) - 0x1p52;
    return r - x == -0.5 ? r + 1 : r;
}

#endif
