/* pg_plates_noise.c - the only source of randomness of the plate model: a hash of
 * (seed, stream, index) and smooth value noise built from it.
 *
 * The hash is the SplitMix64 finaliser (Steele, Lea and Flood 2014) applied to a
 * combination of the three words; each step is a bijection with good avalanche, so
 * neighbouring indices give unrelated values. The noise is classic lattice value
 * noise in 3-D (Perlin 1985's lattice idea with values instead of gradients): hashed
 * values at integer points, blended with the quintic fade, summed over octaves. Being
 * evaluated on 3-D directions it has no seams or pole singularities on the sphere. */
#include "pg_plates_internal.h"

static uint64_t pg_plates_mix(uint64_t z) {
    z += UINT64_C(0x9e3779b97f4a7c15);
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    return z ^ (z >> 31);
}

uint64_t pg_plates_hash(uint64_t seed, uint64_t stream, uint64_t index) {
    return pg_plates_mix(pg_plates_mix(pg_plates_mix(seed) ^ stream) ^ index);
}

double pg_plates_unit(uint64_t seed, uint64_t stream, uint64_t index) {
    return (double)(pg_plates_hash(seed, stream, index) >> 11) * (1.0 / 9007199254740992.0);
}

void pg_plates_random_dir(uint64_t seed, uint64_t stream, uint64_t index, double out[3]) {
    /* Archimedes: z uniform in [-1, 1] and a uniform longitude is uniform on the sphere. */
    double z = 2 * pg_plates_unit(seed, stream, 2 * index) - 1;
    double phi = 2 * PG_PLATES_PI * pg_plates_unit(seed, stream, 2 * index + 1);
    double r = sqrt(fmax(0, 1 - z * z));
    out[0] = r * cos(phi);
    out[1] = r * sin(phi);
    out[2] = z;
}

/* The lattice value at (x, y, z): 2 pg_plates_unit(seed, stream, i) - 1 for the point's
 * index i, with key = pg_plates_mix(pg_plates_mix(seed) ^ stream) computed once per
 * noise evaluation (the first two rounds of pg_plates_hash). */
static double pg_plates_lattice(uint64_t key, int64_t x, int64_t y, int64_t z) {
    uint64_t i = (uint64_t)x * UINT64_C(73856093) ^ (uint64_t)y * UINT64_C(19349663) ^
                 (uint64_t)z * UINT64_C(83492791);
    return 2 * ((double)(pg_plates_mix(key ^ i) >> 11) * (1.0 / 9007199254740992.0)) - 1;
}

static double pg_plates_fade(double t) {
    return t * t * t * (t * (t * 6 - 15) + 10);
}

static double pg_plates_value(uint64_t seed, uint64_t stream, const double p[3]) {
    double fl[3], f[3];
    int64_t c[3];
    for (int k = 0; k < 3; k++) {
        fl[k] = floor(p[k]);
        c[k] = (int64_t)fl[k];
        f[k] = pg_plates_fade(p[k] - fl[k]);
    }
    const uint64_t key = pg_plates_mix(pg_plates_mix(seed) ^ stream);
    double acc = 0;
    for (int corner = 0; corner < 8; corner++) {
        int dx = corner & 1, dy = (corner >> 1) & 1, dz = corner >> 2;
        double w = (dx ? f[0] : 1 - f[0]) * (dy ? f[1] : 1 - f[1]) * (dz ? f[2] : 1 - f[2]);
        acc += w * pg_plates_lattice(key, c[0] + dx, c[1] + dy, c[2] + dz);
    }
    return acc;
}

double pg_plates_fbm(uint64_t seed, uint64_t stream, const double p[3], double freq, int octaves) {
    double sum = 0, amp = 1, norm = 0;
    for (int o = 0; o < octaves; o++) {
        double q[3] = {p[0] * freq + 17.3 * o, p[1] * freq - 5.1 * o, p[2] * freq + 3.7 * o};
        sum += amp * pg_plates_value(seed, stream * 64 + (uint64_t)o, q);
        norm += amp;
        amp *= 0.5;
        freq *= 2;
    }
    return sum / norm;
}

void pg_plates_rotate(const double k[3], double ang, const double v[3], double out[3]) {
    double c = cos(ang), s = sin(ang), kv[3];
    pg_vec3_cross(k, v, kv);
    double kd = pg_vec3_dot(k, v) * (1 - c);
    for (int i = 0; i < 3; i++)
        out[i] = v[i] * c + kv[i] * s + k[i] * kd;
}
