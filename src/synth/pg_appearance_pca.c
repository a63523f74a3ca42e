/* pg_appearance_pca.c - appearance-space vectors of the exemplar (Lefebvre & Hoppe 2006,
 * "Appearance-space texture synthesis", SIGGRAPH, sections 4-5) with component 1
 * replaced by the local mean height (Gain, Marais & Strasser 2015, "Terrain sketching",
 * and J. J. Scott's thesis digest section 1.2).
 *
 * For every texel and level s (spacing h = 2^s) we gather the 5x5 neighbourhood at
 * spacing h from stack level s, each of its 25 samples [L, a, b, w*height] weighted by
 * a Gaussian g (sigma 1.25 samples): a 100-D vector x. Component 1 is the projection of
 * x on the unit vector e of the Gaussian weights on the height slots, so it equals
 * |g| * (Gaussian-weighted mean of the weighted height): a local mean height in the same
 * units as the other components, which is what makes Gain's height offsets a plain
 * additive shift of component 1. Components 2..d are the leading principal axes of the
 * covariance of x restricted to the complement of e (P C P, P = I - e e^T), so they are
 * orthogonal to component 1 and describe everything but the local mean height.
 *
 * Why it works: appearance-space distances between 8-D vectors approximate distances
 * between whole 5x5 neighbourhoods (LH2006 show that 8 components of a 5x5 transform
 * keep nearly all the energy), so synthesis can compare 4 diagonal 8-D vectors instead
 * of 25 raw samples.
 *
 * Determinism: covariance sums are accumulated per fixed chunk and reduced in chunk
 * order, so the basis does not depend on the thread count. The eigenvectors come from a
 * cyclic Jacobi iteration on the 100 x 100 matrix, with a sign convention (largest
 * |entry| positive). A constant exemplar has zero total variance: BADINPUT. */
#include "pg_huge.h"
#include "pg_synth_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SIGMA 1.25

const float *pg_appearance_weights(void) {
    /* exp(-(i^2 + j^2) / (2 sigma^2)), sigma = 1.25, for i, j in -2..2 */
    static const float g[25] = {0.07730474f, 0.20189652f, 0.27803730f, 0.20189652f, 0.07730474f,
                                0.20189652f, 0.52729242f, 0.72614904f, 0.52729242f, 0.20189652f,
                                0.27803730f, 0.72614904f, 1.00000000f, 0.72614904f, 0.27803730f,
                                0.20189652f, 0.52729242f, 0.72614904f, 0.52729242f, 0.20189652f,
                                0.07730474f, 0.20189652f, 0.27803730f, 0.20189652f, 0.07730474f};
    return g;
}

void pg_appearance_gather(const pg_synth_faces *f, int face, int x, int y, int h, float *raw) {
    const float *g = pg_appearance_weights();
    for (int j = -2; j <= 2; j++)
        for (int i = -2; i <= 2; i++) {
            const float *p = pg_synth_faces_at(f, face, x + i * h, y + j * h);
            int k = (j + 2) * 5 + (i + 2);
            for (int c = 0; c < PG_SYNTH_CH; c++)
                raw[k * PG_SYNTH_CH + c] = g[k] * p[c];
        }
}

void pg_appearance_project(const pg_synth_exemplar *ex, int scale, const float *raw, float *comps) {
    const float *mean = ex->pca_mean[scale];
    float centred[PG_SYNTH_RAW];
    for (int i = 0; i < PG_SYNTH_RAW; i++)
        centred[i] = raw[i] - mean[i];
    for (int c = 0; c < ex->dims; c++) {
        /* component 1 is not centred: it is the absolute local mean height */
        const float *b = ex->pca_basis[scale][c], *x = c == 0 ? raw : centred;
        float lane[4] = {0}; /* 4 independent sums in a fixed order: vectorises, exact */
        for (int i = 0; i < PG_SYNTH_RAW; i += 4)
            for (int l = 0; l < 4; l++)
                lane[l] += b[i + l] * x[i + l];
        comps[c] = (lane[0] + lane[1]) + (lane[2] + lane[3]);
    }
}

/* ---- covariance over a strided sample of texels, deterministic chunked sums ---- */

/* Each chunk's sums hold the upper triangle of the cross products only (row i from
 * column i on, rows packed): the lower half is the mirror image and was never read. */
#define COV_TRI (PG_SYNTH_RAW * (PG_SYNTH_RAW + 1) / 2)

typedef struct cov_acc {
    double sum[PG_SYNTH_RAW];
    double cross[COV_TRI];
    double n;
} cov_acc;

/* Where row i of the packed upper triangle starts (its column i). */
static int tri_row(int i) {
    return i * PG_SYNTH_RAW - i * (i - 1) / 2;
}

/* The chunk's sums over the sampled texels of row y. The accumulator is cleared here,
 * by the thread that fills it: its pages are written before they are read, one page
 * fault each (a calloc'd block is read as the shared zero page first, then faults
 * again, copy on write, with a TLB shootdown across cores). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
static void
accumulate_row(const pg_synth_faces *f, int face, int y, int h, int stride, cov_acc *a) {
    memset(a, 0, sizeof *a);
    float raw[PG_SYNTH_RAW];
    double rd[PG_SYNTH_RAW];
    for (int x = (y / stride) % stride; x < f->size; x += stride) {
        pg_appearance_gather(f, face, x, y, h, raw);
        for (int i = 0; i < PG_SYNTH_RAW; i++)
            rd[i] = raw[i];
        for (int i = 0; i < PG_SYNTH_RAW; i++) {
            a->sum[i] += rd[i];
            const double ri = rd[i];
            double *row = a->cross + (tri_row(i) - i); /* row[j], j >= i */
            for (int j = i; j < PG_SYNTH_RAW; j++)
                row[j] += ri * rd[j];
        }
        a->n += 1;
    }
}

static pg_status covariance(const pg_synth_faces *f, int h, double *mean, double *cov,
                            pg_error *err) {
    const int stride = f->size >= 256 ? 8 : (f->size >= 64 ? 4 : 1);
    const int rows_per_face = (f->size + stride - 1) / stride;
    const int nchunks = f->nfaces * rows_per_face;
    cov_acc *acc = pg_huge_malloc((size_t)nchunks * sizeof *acc);
    if (!acc) return pg_error_set(err, PG_ERR_NOMEM, "appearance PCA: out of memory");
#pragma omp parallel for schedule(dynamic, 1)
    for (int c = 0; c < nchunks; c++)
        accumulate_row(f, c / rows_per_face, (c % rows_per_face) * stride, h, stride, &acc[c]);
    double n = 0;
    memset(mean, 0, sizeof(double) * PG_SYNTH_RAW);
    memset(cov, 0, sizeof(double) * PG_SYNTH_RAW * PG_SYNTH_RAW);
    for (int c = 0; c < nchunks; c++) { /* fixed order: thread-count independent */
        n += acc[c].n;
        for (int i = 0; i < PG_SYNTH_RAW; i++)
            mean[i] += acc[c].sum[i];
        for (int i = 0; i < PG_SYNTH_RAW; i++) {
            const double *row = acc[c].cross + (tri_row(i) - i);
            for (int j = i; j < PG_SYNTH_RAW; j++)
                cov[i * PG_SYNTH_RAW + j] += row[j];
        }
    }
    free(acc);
    for (int i = 0; i < PG_SYNTH_RAW; i++)
        mean[i] /= n;
    for (int i = 0; i < PG_SYNTH_RAW; i++)
        for (int j = i; j < PG_SYNTH_RAW; j++) {
            double v = cov[i * PG_SYNTH_RAW + j] / n - mean[i] * mean[j];
            cov[i * PG_SYNTH_RAW + j] = cov[j * PG_SYNTH_RAW + i] = v;
        }
    return PG_OK;
}

/* ---- cyclic Jacobi eigen-decomposition of a symmetric n x n matrix ---- */

static void jacobi_rotate(double *a, double *v, int n, int p, int q) {
    double apq = a[p * n + q];
    if (fabs(apq) < 1e-300) return;
    double theta = (a[q * n + q] - a[p * n + p]) / (2 * apq);
    double t = (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
    double c = 1 / sqrt(t * t + 1), s = t * c;
    for (int k = 0; k < n; k++) { /* columns p, q */
        double akp = a[k * n + p], akq = a[k * n + q];
        a[k * n + p] = c * akp - s * akq;
        a[k * n + q] = s * akp + c * akq;
    }
    for (int k = 0; k < n; k++) { /* rows p, q */
        double apk = a[p * n + k], aqk = a[q * n + k];
        a[p * n + k] = c * apk - s * aqk;
        a[q * n + k] = s * apk + c * aqk;
    }
    for (int k = 0; k < n; k++) {
        double vkp = v[k * n + p], vkq = v[k * n + q];
        v[k * n + p] = c * vkp - s * vkq;
        v[k * n + q] = s * vkp + c * vkq;
    }
}

static void jacobi_eigen(double *a, double *v, int n) {
    for (int i = 0; i < n * n; i++)
        v[i] = 0;
    for (int i = 0; i < n; i++)
        v[i * n + i] = 1;
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = 0, diag = 0;
        for (int i = 0; i < n; i++) {
            diag += a[i * n + i] * a[i * n + i];
            for (int j = i + 1; j < n; j++)
                off += a[i * n + j] * a[i * n + j];
        }
        if (off <= 1e-22 * diag || off == 0) break;
        for (int p = 0; p < n; p++)
            for (int q = p + 1; q < n; q++)
                jacobi_rotate(a, v, n, p, q);
    }
}

/* Leading eigenvectors of P C P into ex->pca_basis[scale][1..dims-1]. */
static int principal_axes(double *cov, const float *e, pg_synth_exemplar *ex, int scale) {
    const int n = PG_SYNTH_RAW;
    double *pc = malloc(sizeof(double) * n * n * 2);
    if (!pc) return -1;
    double *vec = pc + n * n;
    double ce[PG_SYNTH_RAW], ece = 0;
    for (int i = 0; i < n; i++) {
        ce[i] = 0;
        for (int j = 0; j < n; j++)
            ce[i] += cov[i * n + j] * e[j];
    }
    for (int i = 0; i < n; i++)
        ece += e[i] * ce[i];
    for (int i = 0; i < n; i++) /* P C P = C - e ce^T - ce e^T + (e^T C e) e e^T */
        for (int j = 0; j < n; j++)
            pc[i * n + j] = cov[i * n + j] - e[i] * ce[j] - ce[i] * e[j] + ece * e[i] * e[j];
    jacobi_eigen(pc, vec, n);
    int used[PG_SYNTH_RAW] = {0};
    for (int c = 1; c < ex->dims; c++) {
        int best = -1;
        for (int i = 0; i < n; i++)
            if (!used[i] && (best < 0 || pc[i * n + i] > pc[best * n + best])) best = i;
        used[best] = 1;
        int big = 0;
        for (int k = 1; k < n; k++)
            if (fabs(vec[k * n + best]) > fabs(vec[big * n + best])) big = k;
        double sign = vec[big * n + best] < 0 ? -1 : 1;
        for (int k = 0; k < n; k++)
            ex->pca_basis[scale][c][k] = (float)(sign * vec[k * n + best]);
    }
    free(pc);
    return 0;
}

#define PROJECT_BATCH 16

#if defined(__GNUC__) || defined(__clang__)
/* pg_appearance_project on PROJECT_BATCH texels at once, one texel per vector lane:
 * each lane does the same IEEE operations in the same order as pg_appearance_project
 * (4 partial sums over i stepping by 4, then (l0 + l1) + (l2 + l3); GCC builds ISO C
 * without contracting into fused multiply-adds, and a compiler that contracts does so
 * in both forms alike), hence the same bits. One AVX-512 register holds the batch; the
 * AVX2 clone takes two, the baseline four. */
typedef float batch_v __attribute__((vector_size(4 * PROJECT_BATCH)));

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PROJECT_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define PROJECT_CLONES
#endif
/* forced inline into the clones, so that each is compiled for its own target */
#define PROJECT_HOT static inline __attribute__((always_inline))

PROJECT_HOT void project_lanes(const pg_synth_exemplar *ex, int scale,
                               const batch_v X[PG_SYNTH_RAW], float *out) {
    const float *mean = ex->pca_mean[scale];
    batch_v C[PG_SYNTH_RAW];
    for (int i = 0; i < PG_SYNTH_RAW; i++)
        C[i] = X[i] - mean[i];
    for (int c = 0; c < ex->dims; c++) {
        const float *b = ex->pca_basis[scale][c];
        const batch_v *x = c == 0 ? X : C; /* component 1 is not centred */
        batch_v l0 = {0}, l1 = {0}, l2 = {0}, l3 = {0};
        for (int i = 0; i < PG_SYNTH_RAW; i += 4) {
            l0 += b[i] * x[i];
            l1 += b[i + 1] * x[i + 1];
            l2 += b[i + 2] * x[i + 2];
            l3 += b[i + 3] * x[i + 3];
        }
        batch_v r = (l0 + l1) + (l2 + l3);
        for (int t = 0; t < PROJECT_BATCH; t++)
            out[(size_t)t * PG_SYNTH_MAX_DIMS + c] = r[t];
    }
}

PROJECT_CLONES static void project_batch(const pg_synth_exemplar *ex, int scale,
                                         const float (*raw)[PG_SYNTH_RAW], float *out) {
    batch_v X[PG_SYNTH_RAW];
    for (int i = 0; i < PG_SYNTH_RAW; i++)
        for (int t = 0; t < PROJECT_BATCH; t++)
            X[i][t] = raw[t][i];
    project_lanes(ex, scale, X, out);
}
#endif

#if defined(__GNUC__) && !defined(__clang__)
typedef int32_t batch_i __attribute__((vector_size(4 * PROJECT_BATCH)));

/* The raw vectors of the PROJECT_BATCH texels (x.., y) straight from the faces, lane t
 * for texel x + t: each of the 25 samples is a run of PROJECT_BATCH texels of 4
 * interleaved channels (64 floats), split into one vector per channel by shuffles and
 * weighted as pg_appearance_gather weights them (the same products: only data moves).
 * Precondition: every read is inside the stored face with its gutter (no clamping). */
PROJECT_HOT void load_rows(const pg_synth_faces *f, int face, int x, int y, int h,
                           batch_v X[PG_SYNTH_RAW]) {
    const batch_i pick[PG_SYNTH_CH] = {
        {0, 4, 8, 12, 16, 20, 24, 28, 0, 4, 8, 12, 16, 20, 24, 28},
        {1, 5, 9, 13, 17, 21, 25, 29, 1, 5, 9, 13, 17, 21, 25, 29},
        {2, 6, 10, 14, 18, 22, 26, 30, 2, 6, 10, 14, 18, 22, 26, 30},
        {3, 7, 11, 15, 19, 23, 27, 31, 3, 7, 11, 15, 19, 23, 27, 31}};
    const batch_i halves = {0, 1, 2, 3, 4, 5, 6, 7, 16, 17, 18, 19, 20, 21, 22, 23};
    const float *g = pg_appearance_weights();
    for (int j = -2; j <= 2; j++)
        for (int i = -2; i <= 2; i++) {
            const float *p =
                f->px + (((size_t)face * f->ext + (size_t)(y + j * h + f->gutter)) * f->ext +
                         (size_t)(x + i * h + f->gutter)) *
                            PG_SYNTH_CH;
            batch_v a[4];
            memcpy(a, p, sizeof a);
            const int k = (j + 2) * 5 + (i + 2);
            for (int c = 0; c < PG_SYNTH_CH; c++) {
                batch_v lo = __builtin_shuffle(a[0], a[1], pick[c]);
                batch_v hi = __builtin_shuffle(a[2], a[3], pick[c]);
                X[k * PG_SYNTH_CH + c] = g[k] * __builtin_shuffle(lo, hi, halves);
            }
        }
}

PROJECT_CLONES static void project_rows(const pg_synth_faces *f, const pg_synth_exemplar *ex,
                                        int scale, int face, int x, int y, float *out) {
    batch_v X[PG_SYNTH_RAW];
    load_rows(f, face, x, y, 1 << scale, X);
    project_lanes(ex, scale, X, out);
}
#define HAVE_PROJECT_ROWS 1
#endif

/* Project n raw vectors: PROJECT_BATCH at a time where the compiler has vector types,
 * the rest one by one; the same bits as pg_appearance_project on each. */
void pg_appearance_project_n(const pg_synth_exemplar *ex, int scale,
                             const float (*raw)[PG_SYNTH_RAW], int n, float *comps) {
    int t = 0;
#if defined(__GNUC__) || defined(__clang__)
    for (; t + PROJECT_BATCH <= n; t += PROJECT_BATCH)
        project_batch(ex, scale, raw + t, comps + (size_t)t * PG_SYNTH_MAX_DIMS);
#endif
    for (; t < n; t++)
        pg_appearance_project(ex, scale, raw[t], comps + (size_t)t * PG_SYNTH_MAX_DIMS);
}

void pg_appearance_project_span(const pg_synth_faces *f, const pg_synth_exemplar *ex, int scale,
                                int face, int x, int y, int n, float *comps) {
    const int h = 1 << scale;
    int t = 0;
#ifdef HAVE_PROJECT_ROWS
    /* without clamping: rows y +- 2h and columns x - 2h .. x + n - 1 + 2h are stored */
    const int reach = 2 * h, lo = -f->gutter, hi = f->ext - f->gutter;
    if (!f->torus && y - reach >= lo && y + reach < hi && x - reach >= lo)
        for (; t + PROJECT_BATCH <= n && x + t + PROJECT_BATCH - 1 + reach < hi; t += PROJECT_BATCH)
            project_rows(f, ex, scale, face, x + t, y, comps + (size_t)t * PG_SYNTH_MAX_DIMS);
#endif
    float raw[PROJECT_BATCH][PG_SYNTH_RAW];
    while (t < n) {
        int m = n - t < PROJECT_BATCH ? n - t : PROJECT_BATCH;
        for (int u = 0; u < m; u++)
            pg_appearance_gather(f, face, x + t + u, y, h, raw[u]);
        pg_appearance_project_n(ex, scale, (const float(*)[PG_SYNTH_RAW])raw, m,
                                comps + (size_t)t * PG_SYNTH_MAX_DIMS);
        t += m;
    }
}

static void project_all(const pg_synth_faces *f, pg_synth_exemplar *ex, int scale, float *out) {
    const int E = f->size;
#pragma omp parallel for schedule(dynamic, 4) collapse(2)
    for (int face = 0; face < f->nfaces; face++)
        for (int y = 0; y < E; y++)
            pg_appearance_project_span(f, ex, scale, face, 0, y, E,
                                       out + ((size_t)face * E + y) * E * PG_SYNTH_MAX_DIMS);
}

/* The float vectors to int16 at one scale per level, so that the largest |component|
 * becomes 32000. Components from dims on were never written into vals (a scratch reused
 * across levels) and are stored as 0. The maximum is exact in any order, so the threads
 * change no bit; they share the first touch of the level's fresh pages. */
static void quantize(pg_synth_exemplar *ex, int scale, const float *vals, size_t n) {
    const int dims = ex->dims;
    float mx = 1e-12f;
#pragma omp parallel for reduction(max : mx) schedule(static)
    for (size_t t = 0; t < n; t++)
        for (int c = 0; c < dims; c++) {
            float a = fabsf(vals[t * PG_SYNTH_MAX_DIMS + c]);
            if (a > mx) mx = a;
        }
    float q = 32000.0f / mx;
    ex->app_scale[scale] = 1.0f / q;
    int16_t *dst = ex->app[scale];
#pragma omp parallel for schedule(static)
    for (size_t t = 0; t < n; t++)
        for (int c = 0; c < PG_SYNTH_MAX_DIMS; c++)
            dst[t * PG_SYNTH_MAX_DIMS + c] =
                c < dims ? (int16_t)lrintf(vals[t * PG_SYNTH_MAX_DIMS + c] * q) : 0;
}

pg_status pg_appearance_pca_level(const pg_synth_faces *f, int scale, pg_synth_exemplar *ex,
                                  float *vals, pg_error *err) {
    const float *g = pg_appearance_weights();
    float *e = ex->pca_basis[scale][0];
    double gn = 0;
    for (int k = 0; k < PG_SYNTH_NB; k++)
        gn += (double)g[k] * g[k];
    gn = sqrt(gn);
    memset(e, 0, sizeof(float) * PG_SYNTH_RAW);
    for (int k = 0; k < PG_SYNTH_NB; k++)
        e[k * PG_SYNTH_CH + 3] = (float)(g[k] / gn);
    ex->metres_to_app = (float)(gn * ex->lab_height_scale);

    double *mean = malloc(sizeof(double) * (PG_SYNTH_RAW + PG_SYNTH_RAW * PG_SYNTH_RAW));
    if (!mean) return pg_error_set(err, PG_ERR_NOMEM, "appearance PCA: out of memory");
    double *cov = mean + PG_SYNTH_RAW;
    pg_status st = covariance(f, 1 << scale, mean, cov, err);
    if (st) {
        free(mean);
        return st;
    }
    double trace = 0;
    for (int i = 0; i < PG_SYNTH_RAW; i++)
        trace += cov[i * PG_SYNTH_RAW + i];
    if (!(trace > 1e-6)) {
        free(mean);
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "exemplar: appearance-space PCA is degenerate (total variance %.3g "
                            "at level %d): the exemplar is constant",
                            trace, scale);
    }
    for (int i = 0; i < PG_SYNTH_RAW; i++)
        ex->pca_mean[scale][i] = (float)mean[i];
    int bad = principal_axes(cov, e, ex, scale);
    free(mean);
    if (bad) return pg_error_set(err, PG_ERR_NOMEM, "appearance PCA: out of memory");

    project_all(f, ex, scale, vals);
    quantize(ex, scale, vals, (size_t)f->nfaces * f->size * f->size);
    return PG_OK;
}
