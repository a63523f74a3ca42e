/* pg_hash.h - the project's one source of randomness: a hash of (seed, level, face, x,
 * y, salt), inline.
 *
 * Every random choice (jitter, draws, noise lattices) is a pure function of the seed
 * and of where it is made, never of a generator's state, so a planet is the same for any
 * thread count, tiling or rank count. The hash is four rounds of SplitMix64's finaliser
 * (Steele, Lea & Flood 2014, "Fast splittable pseudorandom number generators"), one per
 * group of arguments: seed; level, face and salt; x; y. It is inline because its callers
 * hash neighbouring lattice points of one call (a noise's 8 corners, a draw's 8 salts):
 * inlined, the rounds that depend only on arguments the calls share are computed once.
 * pg_synth_hash (the public API) returns exactly this. Library-internal: not part of the
 * installed API. */
#ifndef PG_HASH_H
#define PG_HASH_H

#include <stdint.h>

static inline uint64_t pg_hash_mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* Uniform in [0, 2^32). */
static inline uint32_t pg_hash_texel(uint64_t seed, int scale, int face, long x, long y, int salt) {
    uint64_t h = pg_hash_mix64(seed + 0x9e3779b97f4a7c15ULL);
    h = pg_hash_mix64(h ^ ((uint64_t)(uint32_t)scale << 40) ^ ((uint64_t)(uint32_t)face << 32) ^
                      (uint32_t)salt);
    h = pg_hash_mix64(h ^ (uint64_t)x);
    h = pg_hash_mix64(h ^ ((uint64_t)y * 0xd6e8feb86659fd93ULL));
    return (uint32_t)(h >> 32);
}

#endif
