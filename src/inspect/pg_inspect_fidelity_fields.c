/* pg_inspect_fidelity_fields.c - the analysis fields of the neighbourhood-fidelity
 * measure (pg_inspect_fidelity.c; docs/inspect.md, "Neighbourhood fidelity"): planet
 * and exemplar texels box-averaged to one analysis spacing, colour in CIE Lab and
 * height scaled to the colours' spread, so that one L2 distance weighs both; and the
 * detail amplitude D = sqrt(box5(hp^2)), hp = x - binomial3(x), the phase-free field
 * that tells a blurred planet from a sharp one. Each output texel depends only on its
 * inputs, so the fields do not depend on the thread count. */
#include "pg_inspect_fidelity_internal.h"

#include "pg_synth_internal.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#define CH PG_INSPECT_FID_CHANNELS

/* ---- the analysis fields ---- */

static void to_lab(float *px, size_t count) {
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < count; i++) {
        float rgb[3] = {px[i * CH], px[i * CH + 1], px[i * CH + 2]};
        pg_synth_srgb_to_lab(rgb, px + i * CH);
    }
}

/* Lab units per metre: the height std made equal to the Lab std (as the synthesis
 * weights height, pg_synth_exemplar_params.height_weight = 1). */
double fid_height_scale(const fid_field *f) {
    size_t count = (size_t)6 * f->n * f->n;
    double s[CH] = {0}, s2[CH] = {0};
    for (size_t i = 0; i < count; i++)
        for (int c = 0; c < CH; c++) {
            s[c] += f->px[i * CH + c];
            s2[c] += (double)f->px[i * CH + c] * f->px[i * CH + c];
        }
    double var[CH];
    for (int c = 0; c < CH; c++)
        var[c] = fmax(0, s2[c] / count - (s[c] / count) * (s[c] / count));
    double lab = sqrt(var[0] + var[1] + var[2]), h = sqrt(var[3]);
    return h > 1e-6 ? lab / h : 1.0;
}

void fid_scale_height(fid_field *f, double scale) {
    size_t count = (size_t)6 * f->n * f->n;
    for (size_t i = 0; i < count; i++)
        f->px[i * CH + 3] *= (float)scale;
}

/* Full-resolution texels of either side: sRGB and height in metres at any strides (the
 * planet's faces, or a packed exemplar cube of 4 floats per texel). */
fid_src fid_planet_src(const pg_planet *p) {
    fid_src s = {p->n, {0}, {0}, 3, 1};
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        s.rgb[f] = p->albedo[f], s.h[f] = p->height[f];
    return s;
}

fid_src fid_packed_src(const float *cube, int64_t n) {
    fid_src s = {n, {0}, {0}, 4, 4};
    for (int f = 0; cube && f < PG_CUBE_NFACES; f++) {
        s.rgb[f] = cube + (size_t)f * (size_t)(n * n) * 4;
        s.h[f] = s.rgb[f] + 3;
    }
    return s;
}

/* Where the source of analysis texel (f, x, y) lies on the analysis cube: the source of
 * the planet texel at the centre of its m x m block, as face * n * n + y * n + x. */
static int32_t source_index(const pg_planet *p, int m, int n, int f, int x, int y) {
    double d[3], u, v;
    int sf;
    pg_planet_source_dir(p, f, (int64_t)x * m + m / 2, (int64_t)y * m + m / 2, d);
    pg_cube_from_dir(p->projection, d, &sf, &u, &v);
    int sx = (int)((u + 1) * 0.5 * n), sy = (int)((v + 1) * 0.5 * n);
    sx = sx < 0 ? 0 : (sx >= n ? n - 1 : sx);
    sy = sy < 0 ? 0 : (sy >= n ? n - 1 : sy);
    return (int32_t)(((int64_t)sf * n + sy) * n + sx);
}

/* A side box-averaged by m (sRGB averaged as stored, like the exemplar cube's taps),
 * then Lab. */
pg_status fid_box_field(const fid_src *sr, int m, fid_field *out, pg_error *err) {
    int n = (int)(sr->n / m);
    out->n = n;
    out->src = NULL;
    out->px = malloc((size_t)6 * n * n * CH * sizeof *out->px);
    if (!out->px) return pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory for a field");
    double w = 1.0 / ((double)m * m);
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * n; row++) {
        int f = row / n, y = row % n;
        for (int x = 0; x < n; x++) {
            double acc[CH] = {0};
            for (int j = 0; j < m; j++)
                for (int i = 0; i < m; i++) {
                    size_t t = (size_t)(y * m + j) * (size_t)sr->n + (size_t)x * m + i;
                    for (int c = 0; c < 3; c++)
                        acc[c] += sr->rgb[f][t * (size_t)sr->rgb_stride + c];
                    acc[3] += sr->h[f][t * (size_t)sr->h_stride];
                }
            float *d = out->px + (((size_t)f * n + y) * n + x) * CH;
            for (int c = 0; c < CH; c++)
                d[c] = (float)(acc[c] * w);
        }
    }
    to_lab(out->px, (size_t)6 * n * n);
    return PG_OK;
}

/* The planet's analysis field, and each analysis texel's source when it has a map. */
pg_status fid_planet_field(const pg_planet *p, int m, fid_field *out, pg_error *err) {
    fid_src sr = fid_planet_src(p);
    pg_status st = fid_box_field(&sr, m, out, err);
    if (st != PG_OK || !pg_planet_has_source(p)) return st;
    int n = out->n;
    if (!(out->src = malloc((size_t)6 * n * n * sizeof *out->src)))
        return pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory for the planet");
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * n; row++)
        for (int x = 0; x < n; x++)
            out->src[(size_t)row * n + x] = source_index(p, m, n, row / n, x, row % n);
    return PG_OK;
}

/* ---- the detail amplitude ---- */

/* Clamped read of channel c at (x, y) of one face of n x n texels of CH floats. */
static float at(const float *face, int64_t n, int64_t x, int64_t y, int c) {
    x = x < 0 ? 0 : (x >= n ? n - 1 : x);
    y = y < 0 ? 0 : (y >= n ? n - 1 : y);
    return face[(size_t)(y * n + x) * CH + c];
}

/* One face at full resolution as Lab and height x hscale. */
static void full_face(const fid_src *sr, int f, double hscale, float *out) {
    size_t nn = (size_t)(sr->n * sr->n);
#pragma omp parallel for schedule(static)
    for (size_t t = 0; t < nn; t++) {
        float rgb[3];
        for (int c = 0; c < 3; c++)
            rgb[c] = sr->rgb[f][t * (size_t)sr->rgb_stride + c];
        pg_synth_srgb_to_lab(rgb, out + t * CH);
        out[t * CH + 3] = (float)(sr->h[f][t * (size_t)sr->h_stride] * hscale);
    }
}

/* Squared high-pass of one texel and channel: x - [1 2 1]/4 x [1 2 1]/4 x. */
static float highpass2(const float *face, int64_t n, int64_t x, int64_t y, int c) {
    static const float w[3] = {0.25f, 0.5f, 0.25f};
    float lo = 0;
    for (int j = -1; j <= 1; j++)
        for (int i = -1; i <= 1; i++)
            lo += w[i + 1] * w[j + 1] * at(face, n, x + i, y + j, c);
    float hp = at(face, n, x, y, c) - lo;
    return hp * hp;
}

/* Box mean of radius 2 along x (step 1) or y (step n) of one channel-interleaved face,
 * edges clamped: a running sum, so the cost does not grow with the radius. */
static void box5(const float *in, int64_t n, bool along_y, float *out) {
#pragma omp parallel for schedule(static)
    for (int64_t line = 0; line < n; line++)
        for (int c = 0; c < CH; c++) {
            double s = 0;
            for (int64_t k = -2; k <= 2; k++) {
                int64_t t = k < 0 ? 0 : k;
                s += along_y ? in[(size_t)(t * n + line) * CH + c]
                             : in[(size_t)(line * n + t) * CH + c];
            }
            for (int64_t k = 0; k < n; k++) {
                size_t at_k = along_y ? (size_t)(k * n + line) : (size_t)(line * n + k);
                out[at_k * CH + c] = (float)(s / 5);
                int64_t add = k + 3 >= n ? n - 1 : k + 3, sub = k - 2 < 0 ? 0 : k - 2;
                size_t ia = along_y ? (size_t)(add * n + line) : (size_t)(line * n + add);
                size_t is = along_y ? (size_t)(sub * n + line) : (size_t)(line * n + sub);
                s += (double)in[ia * CH + c] - in[is * CH + c];
            }
        }
}

/* The detail amplitude at full resolution, D = sqrt of the 5 x 5 box mean of the
 * squared high-pass per face (edges clamped) and channel, box-averaged by m into the
 * analysis grid. It is measured where the detail is, before the analysis grid's own
 * averaging would remove the finest octave. */
pg_status fid_detail_field(const fid_src *sr, int m, double hscale, fid_field *out, pg_error *err) {
    int64_t N = sr->n;
    int n = (int)(N / m);
    size_t nn = (size_t)(N * N);
    float *a = malloc(nn * CH * sizeof *a), *b = malloc(nn * CH * sizeof *b);
    out->n = n;
    out->src = NULL;
    out->px = calloc((size_t)6 * n * n * CH, sizeof *out->px);
    if (!a || !b || !out->px) {
        free(a), free(b), free(out->px);
        out->px = NULL;
        return pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory for the detail field");
    }
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        full_face(sr, f, hscale, a);
#pragma omp parallel for schedule(static)
        for (int64_t y = 0; y < N; y++)
            for (int64_t x = 0; x < N; x++)
                for (int c = 0; c < CH; c++)
                    b[(size_t)(y * N + x) * CH + c] = highpass2(a, N, x, y, c);
        box5(b, N, false, a);
        box5(a, N, true, b);
        double w = 1.0 / ((double)m * m);
#pragma omp parallel for schedule(static)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++)
                for (int c = 0; c < CH; c++) {
                    double acc = 0;
                    for (int j = 0; j < m; j++)
                        for (int i = 0; i < m; i++)
                            acc += sqrt(fmax(
                                0,
                                b[((size_t)(y * m + j) * (size_t)N + (size_t)x * m + i) * CH + c]));
                    out->px[(((size_t)f * n + y) * n + x) * CH + c] = (float)(acc * w);
                }
    }
    free(a), free(b);
    return PG_OK;
}
