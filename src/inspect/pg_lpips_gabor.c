/* pg_lpips_gabor.c - the LPIPS-style distance of pg_lpips.h with a complex Gabor
 * filter bank in place of learned deep features.
 *
 * LPIPS (Zhang, Isola, Efros, Shechtman, Wang: "The Unreasonable Effectiveness of Deep
 * Features as a Perceptual Metric", CVPR 2018) compares two images by (1) extracting
 * feature stacks at several layers, (2) unit-normalising every pixel's feature vector
 * over the channels, (3) weighting channels, taking squared differences and averaging
 * them spatially, and (4) combining the layers. We keep (1), (2) and the spatial
 * average, use uniform channel weights (there are no learned ones), and average the
 * layers. The features are the energies of complex Gabor filters - the model of V1
 * complex cells (Daugman 1985) that the first layers of image networks rediscover -
 * at PG_LPIPS_ORIENTATIONS orientations on every octave of a Gaussian pyramid.
 * Energies (moduli) are phase-invariant, so a shift by a fraction of a wavelength
 * changes them little while blur, stretch or a different texture change them a lot.
 *
 * Every constant is documented where it is defined. Gabor filters with an isotropic
 * Gaussian envelope are separable into complex 1-D filters, so each response costs
 * two 1-D passes; rows run in parallel with OpenMP and every output value depends
 * only on its inputs, so results do not depend on the thread count. */
#include "planetgen/pg_lpips.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Tuned wavelength of every Gabor filter, in pixels of its own pyramid level: 4 px is
 * the shortest wavelength that is sampled well (Nyquist is 2 px) yet leaves the
 * envelope a compact support. Octave l therefore sees wavelengths of 4 * 2^l pixels
 * of the input image: 4, 8, 16, 32, 64 px for the default 5 octaves. */
#define LPIPS_WAVELENGTH_PX 4.0

/* Gaussian envelope sigma relative to the wavelength. 0.5622 gives a half-amplitude
 * bandwidth of one octave, sigma = lambda/pi * sqrt(ln 2 / 2) * (2^b + 1)/(2^b - 1)
 * with b = 1, so consecutive octaves tile the frequency axis without large gaps. */
#define LPIPS_SIGMA_PER_WAVELENGTH 0.5622

/* The kernel is cut at 3 sigma (radius 7 px for the default): beyond it the envelope
 * is below 1.2% of its peak. */
#define LPIPS_SUPPORT_SIGMAS 3.0

/* Contrast floor of the normalisation f / (|f| + eps), in units of a sinusoid's
 * amplitude in sRGB 0..1 (filters are scaled so a grating of amplitude A at the tuned
 * frequency gives energy A). LPIPS uses 1e-10; with hand-made features a flat area
 * (ice, open ocean) would then turn JPEG noise into unit vectors and dominate the
 * distance. 0.01 is about 2.5 grey levels of an 8-bit image, the size of JPEG and
 * 8-bit quantisation noise: texture weaker than that counts as flat. */
#define LPIPS_EPS 0.01

/* Metres of height that weigh like an sRGB amplitude of 1.0. Typical land relief at
 * 10..100 km scales has Gabor amplitudes of a few hundred metres, typical albedo texture
 * a few percent; 5000 m puts both on the same footing (200 m of relief ~ 0.04 albedo). */
#define LPIPS_HEIGHT_UNIT_M 5000.0

/* Pyramid filter: the 5-tap binomial [1 4 6 4 1]/16, a close Gaussian approximation
 * (Burt & Adelson 1983) that suppresses aliasing before decimation by 2. */
static const float lpips_binomial[5] = {1.f / 16, 4.f / 16, 6.f / 16, 4.f / 16, 1.f / 16};

static const double LPIPS_PI = 3.14159265358979323846;

void pg_lpips_params_default(pg_lpips_params *p) {
    p->octaves = PG_LPIPS_OCTAVES;
    p->height_unit_m = LPIPS_HEIGHT_UNIT_M;
    p->eps = LPIPS_EPS;
}

/* Mirror an index into [0, n) without repeating the edge pixel (n >= 2). */
static inline int reflect(int i, int n) {
    while (i < 0 || i >= n)
        i = i < 0 ? -i : 2 * n - 2 - i;
    return i;
}

/* dst = src convolved along rows (axis 0) or columns (axis 1) with a (2r+1)-tap kernel,
 * mirrored at the borders. Rows go through a padded line; columns accumulate whole
 * rows tap by tap. Both inner loops are plain and vectorise. src != dst. */
static void conv1d(const float *src, int w, int h, const float *k, int r, int axis, float *dst,
                   float *line) {
    for (int y = 0; y < h; y++) {
        float *o = dst + (size_t)y * w;
        if (!axis) {
            const float *s = src + (size_t)y * w;
            for (int x = -r; x < w + r; x++)
                line[x + r] = s[reflect(x, w)];
            for (int x = 0; x < w; x++) {
                float acc = 0;
                for (int t = 0; t <= 2 * r; t++)
                    acc += k[t] * line[x + t];
                o[x] = acc;
            }
        } else {
            for (int x = 0; x < w; x++)
                o[x] = 0;
            for (int t = -r; t <= r; t++) {
                const float *s = src + (size_t)reflect(y + t, h) * w;
                float kt = k[t + r];
                for (int x = 0; x < w; x++)
                    o[x] += kt * s[x];
            }
        }
    }
}

/* Binomial blur then keep every second pixel: (w, h) -> (w/2, h/2), in place; tmp and
 * tmp2 hold w*h floats, line w + 4. */
static void downsample(float *plane, int w, int h, float *tmp, float *tmp2, float *line) {
    conv1d(plane, w, h, lpips_binomial, 2, 0, tmp, line);
    conv1d(tmp, w, h, lpips_binomial, 2, 1, tmp2, line);
    int w2 = w / 2, h2 = h / 2;
    for (int y = 0; y < h2; y++)
        for (int x = 0; x < w2; x++)
            plane[(size_t)y * w2 + x] = tmp2[(size_t)(2 * y) * w + 2 * x];
}

/* The filter bank's 1-D pieces: a normalised Gaussian g (sum 1) and, per orientation,
 * g*cos(k t) and g*sin(k t) along x and along y, plus the Morlet DC correction kappa
 * that makes each complex filter exactly zero-mean on the discrete grid. */
typedef struct lpips_bank {
    int r;
    float g[32];
    float cx[PG_LPIPS_ORIENTATIONS][32], sx[PG_LPIPS_ORIENTATIONS][32];
    float cy[PG_LPIPS_ORIENTATIONS][32], sy[PG_LPIPS_ORIENTATIONS][32];
    double kappa[PG_LPIPS_ORIENTATIONS];
} lpips_bank;

static void bank_init(lpips_bank *b) {
    double sigma = LPIPS_SIGMA_PER_WAVELENGTH * LPIPS_WAVELENGTH_PX;
    b->r = (int)ceil(LPIPS_SUPPORT_SIGMAS * sigma);
    double sum = 0;
    for (int t = -b->r; t <= b->r; t++)
        sum += exp(-0.5 * t * t / (sigma * sigma));
    for (int t = -b->r; t <= b->r; t++)
        b->g[t + b->r] = (float)(exp(-0.5 * t * t / (sigma * sigma)) / sum);
    double k = 2 * LPIPS_PI / LPIPS_WAVELENGTH_PX;
    for (int o = 0; o < PG_LPIPS_ORIENTATIONS; o++) {
        double th = LPIPS_PI * o / PG_LPIPS_ORIENTATIONS, kx = k * cos(th), ky = k * sin(th);
        double mx = 0, my = 0; /* sum g cos: the filter's response to a constant */
        for (int t = -b->r; t <= b->r; t++) {
            double g = b->g[t + b->r];
            b->cx[o][t + b->r] = (float)(g * cos(kx * t));
            b->sx[o][t + b->r] = (float)(g * sin(kx * t));
            b->cy[o][t + b->r] = (float)(g * cos(ky * t));
            b->sy[o][t + b->r] = (float)(g * sin(ky * t));
            mx += g * cos(kx * t);
            my += g * cos(ky * t);
        }
        b->kappa[o] = mx * my; /* sum of g(x)g(y)e^{ik.x}: real because g is symmetric */
    }
}

/* Energies of one channel plane at every orientation into the planes c*O + o of feat
 * (planar layout: feature d of pixel i at feat[d*w*h + i], so channels never share a
 * cache line when they run in parallel).
 * buf holds 7*w*h floats, line w + 2r. */
static void channel_energy(const lpips_bank *b, const float *plane, int w, int h, float *feat,
                           int c, float *buf, float *line) {
    size_t np = (size_t)w * h;
    float *low = buf, *A = buf + np, *B = buf + 2 * np, *t1 = buf + 3 * np, *t2 = buf + 4 * np,
          *t3 = buf + 5 * np, *t4 = buf + 6 * np;
    int r = b->r;
    conv1d(plane, w, h, b->g, r, 0, t1, line);
    conv1d(t1, w, h, b->g, r, 1, low, line);
    for (int o = 0; o < PG_LPIPS_ORIENTATIONS; o++) {
        conv1d(plane, w, h, b->cx[o], r, 0, A, line);
        conv1d(plane, w, h, b->sx[o], r, 0, B, line);
        conv1d(A, w, h, b->cy[o], r, 1, t1, line);
        conv1d(B, w, h, b->sy[o], r, 1, t2, line);
        conv1d(B, w, h, b->cy[o], r, 1, t3, line);
        conv1d(A, w, h, b->sy[o], r, 1, t4, line);
        double kap = b->kappa[o];
        for (size_t i = 0; i < np; i++) {
            double re = (double)t1[i] - t2[i] - kap * low[i], im = (double)t3[i] + t4[i];
            /* x2: a grating of amplitude A at the tuned frequency gives energy A */
            feat[((size_t)c * PG_LPIPS_ORIENTATIONS + o) * np + i] =
                (float)(2 * sqrt(re * re + im * im));
        }
    }
}

/* f / (|f| + eps) per pixel (planar layout). */
static void normalise(float *f, size_t np, int dims, double eps) {
    for (size_t i = 0; i < np; i++) {
        double s = 0;
        for (int d = 0; d < dims; d++)
            s += (double)f[d * np + i] * f[d * np + i];
        double k = 1 / (sqrt(s) + eps);
        for (int d = 0; d < dims; d++)
            f[d * np + i] = (float)(f[d * np + i] * k);
    }
}

/* Channel planes at full resolution: an orthonormal opponent basis of sRGB,
 * L = (R+G+B)/sqrt3, RG = (R-G)/sqrt2, YB = (R+G-2B)/sqrt6 (orthonormal, so a colour
 * edge weighs exactly as much as a grey edge of the same RGB magnitude), then height. */
static void make_planes(const pg_lpips_image *img, double hunit, int nch, float **planes) {
    size_t np = (size_t)img->width * img->height;
    for (size_t i = 0; i < np; i++) {
        const float *p = img->rgb + 3 * i;
        planes[0][i] = (float)((p[0] + p[1] + p[2]) / sqrt(3.0));
        planes[1][i] = (float)((p[0] - p[1]) / sqrt(2.0));
        planes[2][i] = (float)((p[0] + p[1] - 2 * p[2]) / sqrt(6.0));
        if (nch > 3) planes[3][i] = (float)(img->height_m[i] / hunit);
    }
}

static pg_status check_params(const pg_lpips_image *img, const pg_lpips_params *p, pg_error *err) {
    if (p->octaves < 1 || p->octaves > PG_LPIPS_MAX_OCTAVES)
        return pg_error_set(err, PG_ERR_BADINPUT, "lpips: octaves must be 1..%d, got %d",
                            PG_LPIPS_MAX_OCTAVES, p->octaves);
    if (!(p->eps > 0) || !(p->height_unit_m >= 0) || !isfinite(p->height_unit_m))
        return pg_error_set(err, PG_ERR_BADINPUT, "lpips: eps must be > 0 and height unit >= 0");
    int need = PG_LPIPS_MIN_LEVEL << (p->octaves - 1);
    if (!img->rgb || img->width < need || img->height < need)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "lpips: image %dx%d is too small for %d octaves (need %dx%d)",
                            img->width, img->height, p->octaves, need, need);
    return PG_OK;
}

void pg_lpips_features_free(pg_lpips_features *f) {
    for (int l = 0; l < PG_LPIPS_MAX_OCTAVES; l++) {
        free(f->f[l]);
        f->f[l] = NULL;
    }
    f->layers = 0;
}

/* All layers of channel c: energies into every layer's features, then shrink the plane
 * to the next level. Channels write disjoint feature slots, so they run in parallel. */
static int channel_layers(const lpips_bank *b, float *plane, int c, pg_lpips_features *out) {
    size_t np = (size_t)out->w[0] * out->h[0];
    float *buf = malloc(np * 7 * sizeof *buf),
          *line = malloc(((size_t)out->w[0] + 64) * sizeof *line);
    int ok = buf && line;
    for (int l = 0; ok && l < out->layers; l++) {
        channel_energy(b, plane, out->w[l], out->h[l], out->f[l], c, buf, line);
        if (l + 1 < out->layers) downsample(plane, out->w[l], out->h[l], buf, buf + np, line);
    }
    free(buf), free(line);
    return ok ? 0 : -1;
}

pg_status pg_lpips_features_compute(const pg_lpips_image *img, const pg_lpips_params *p,
                                    pg_lpips_features *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    pg_status st = check_params(img, p, err);
    if (st != PG_OK) return st;
    int nch = (img->height_m && p->height_unit_m > 0) ? 4 : 3;
    size_t np = (size_t)img->width * img->height;
    float *planes[PG_LPIPS_MAX_CHANNELS] = {0};
    float *mem = malloc(np * nch * sizeof(float));
    if (!mem) return pg_error_set(err, PG_ERR_NOMEM, "lpips: out of memory");
    for (int c = 0; c < nch; c++)
        planes[c] = mem + np * c;
    make_planes(img, p->height_unit_m, nch, planes);
    lpips_bank b;
    bank_init(&b);
    out->layers = p->octaves;
    out->dims = nch * PG_LPIPS_ORIENTATIONS;
    int failed = 0;
    for (int l = 0; l < out->layers; l++) {
        out->w[l] = img->width >> l;
        out->h[l] = img->height >> l;
        out->f[l] = malloc((size_t)out->w[l] * out->h[l] * out->dims * sizeof(float));
        failed |= !out->f[l];
    }
#pragma omp parallel for schedule(dynamic, 1) reduction(| : failed)
    for (int c = 0; c < nch; c++)
        if (!failed) failed |= channel_layers(&b, planes[c], c, out);
    free(mem);
    if (failed) {
        pg_lpips_features_free(out);
        return pg_error_set(err, PG_ERR_NOMEM, "lpips: out of memory");
    }
    for (int l = 0; l < out->layers; l++)
        normalise(out->f[l], (size_t)out->w[l] * out->h[l], out->dims, p->eps);
    return PG_OK;
}

pg_status pg_lpips_compare(const pg_lpips_features *a, const pg_lpips_features *b,
                           pg_lpips_result *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    if (a->layers != b->layers || a->dims != b->dims || a->w[0] != b->w[0] || a->h[0] != b->h[0])
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "lpips: cannot compare %dx%d (%d layers, %d dims) with %dx%d (%d, %d)",
                            a->w[0], a->h[0], a->layers, a->dims, b->w[0], b->h[0], b->layers,
                            b->dims);
    out->layers = a->layers;
    for (int l = 0; l < a->layers; l++) {
        size_t n = (size_t)a->w[l] * a->h[l] * a->dims;
        double s = 0;
        for (size_t i = 0; i < n; i++) {
            double d = (double)a->f[l][i] - b->f[l][i];
            s += d * d;
        }
        /* /2: two non-negative unit vectors differ by at most 2 in squared length */
        out->layer[l] = s / 2 / ((double)a->w[l] * a->h[l]);
        out->distance += out->layer[l] / a->layers;
    }
    return PG_OK;
}

pg_status pg_lpips_distance(const pg_lpips_image *a, const pg_lpips_image *b,
                            const pg_lpips_params *p, pg_lpips_result *out, pg_error *err) {
    pg_lpips_image a2 = *a, b2 = *b;
    if (!a->height_m || !b->height_m) a2.height_m = b2.height_m = NULL;
    pg_lpips_features fa, fb;
    pg_status st = pg_lpips_features_compute(&a2, p, &fa, err);
    if (st != PG_OK) return st;
    st = pg_lpips_features_compute(&b2, p, &fb, err);
    if (st == PG_OK) st = pg_lpips_compare(&fa, &fb, out, err);
    pg_lpips_features_free(&fa);
    pg_lpips_features_free(&fb);
    return st;
}
