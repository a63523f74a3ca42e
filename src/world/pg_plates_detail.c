/* pg_plates_detail.c - the macro world on a finer cube with warped contours, for the
 * synthesis' controls (docs/generate.md, "Layout world").
 *
 * The plate and climate fields live on a cube of ~156 km texels. Sampled bilinearly at
 * every level, a threshold of them (the climate rule's ice margin, a plateau's edge)
 * runs as straight lines along that grid, and where it meets a face seam it follows the
 * seam. Domain warping (sampling a field at a displaced point, as in Perlin's turbulence
 * of textures, Perlin 1985 "An image synthesizer") bends those lines: each texel of the
 * finer cube takes the bilinear value at its direction moved by a displacement of value
 * noise (pg_plates_noise.c) on the sphere, a few source texels in wavelength and about
 * one in amplitude. The noise is a function of the 3-D direction, so the warp has no
 * seams and is the same for any thread or rank count. Values are samples of the source,
 * so the fields keep their range and their large-scale layout. */
#include "pg_plates_internal.h"

#include <stdlib.h>

/* The displacement's scale and the first octave's wavelength, in source texels (at a
 * face centre): the warp moves directions by 1.0 source texel on average, at most about
 * 2.7 (tests/test_plates.c). */
#define DETAIL_AMPLITUDE_TEXELS 2.5
#define DETAIL_WAVELENGTH_TEXELS 4.0
#define DETAIL_OCTAVES 2

pg_status pg_plates_detail(uint64_t seed, pg_cube_projection proj, int64_t n, const float *in,
                           int nch, int64_t m, float *out, pg_error *err) {
    if (n < 2 || m < n || nch < 1 || nch > 8 || !in || !out)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates detail: bad sizes");
    pg_cube_grid src, dst;
    pg_cube_sample_grid_init(&src, proj, n);
    pg_status st = pg_cube_grid_init(&dst, proj, 1, (int)m, err);
    if (st) return st;
    const double texel = PG_PLATES_PI / 2 / (double)n; /* radians, at a face centre */
    const double amp = DETAIL_AMPLITUDE_TEXELS * texel,
                 freq = 1.0 / (DETAIL_WAVELENGTH_TEXELS * texel);
#pragma omp parallel for schedule(static)
    for (int64_t id = 0; id < 6 * m * m; id++) {
        double p[3], q[3];
        pg_cube_texel_dir(&dst, id, p);
        for (int k = 0; k < 3; k++)
            q[k] = p[k] + amp * pg_plates_fbm(seed, PG_PLATES_S_DETAIL + 4 * (uint64_t)k, p, freq,
                                              DETAIL_OCTAVES);
        pg_vec3_normalize(q);
        pg_cube_sample_grid(&src, in, nch, q, out + (size_t)id * nch);
    }
    return PG_OK;
}
