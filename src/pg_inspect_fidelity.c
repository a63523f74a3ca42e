/* pg_inspect_fidelity.c - neighbourhood fidelity of a planet against its exemplar
 * (pg_inspect.h, issue 8).
 *
 * Source: the texture energy of Kwatra, Essa, Bobick & Kwatra 2005 ("Texture
 * Optimization for Example-based Synthesis", SIGGRAPH) - the sum over output
 * neighbourhoods of the squared distance to the nearest exemplar neighbourhood - and
 * the same nearest-neighbourhood matching in Lefebvre & Hoppe 2005/2006. We report its
 * per-query mean as an RMS difference per texel and channel: the mean over hashed
 * output texels of sqrt(min over exemplar neighbourhoods of |q - e|^2 / 100).
 *
 * A number alone does not say what "good" is, so the same search is run for two
 * baselines against the same exemplar database:
 *  - leave-one-out: queries on the exemplar itself, skipping every database entry on
 *    the same face within 2R texels (any neighbourhood sharing a texel with the
 *    query). That is how close the exemplar is to the rest of itself: a synthesis made
 *    of exemplar patches scores about this, a copy of the exemplar scores below it;
 *  - random: each of the 25 texels drawn from a hashed exemplar texel, i.e. the
 *    exemplar's colours and heights with the structure destroyed.
 *
 * Preconditions and scale: planet and exemplar are compared at one texel spacing.
 * Planets are synthesized at the exemplar cube's scale (E = 512) and magnified at
 * delivery, so the planet's faces are box-averaged by the smallest integer factor m
 * that brings them to at most PG_INSPECT_FID_FACE texels, and the exemplar is
 * reprojected onto a cube of that size with the planet's projection. Neighbourhoods
 * stay inside faces (centres R texels or more from an edge), so no seam handling is
 * needed and both sides are read the same way.
 *
 * The search is exact. Each neighbourhood is stored as the orthonormal 5x5 DCT-II of
 * each channel - a rotation of the 100-D space, so every distance is unchanged - with
 * coefficients ordered by spatial frequency: first the four channel means, then the
 * first gradients. Natural texture keeps most of its energy there, so the squared
 * distance over the first PG_INSPECT_FID_PREFIX coefficients, a lower bound of the
 * full one, rejects almost every database entry; the survivors are completed in
 * chunks with early termination. Correct because a partial sum of non-negative terms
 * never exceeds the full sum.
 *
 * Determinism: query positions are pg_synth_hash of (salt, face, index); each query's
 * search runs in one thread in database order; sums run in query order. So the figures
 * do not depend on the thread count. */
#include "planetgen/pg_inspect.h"
#include "planetgen/pg_synth.h"

#include "pg_synth_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define R PG_INSPECT_FID_RADIUS
#define SIDE (2 * R + 1)
#define NB (SIDE * SIDE)
#define CH 4 /* L, a, b, scaled height */
#define DIM (NB * CH)
#define PFX PG_INSPECT_FID_PREFIX
#define REST (DIM - PFX)
#define CHUNK 12  /* early-termination check every CHUNK coefficients */
#define QBLOCK 16 /* queries per database pass (16 x 400 B stay in L1) */
#if PFX % 4 || REST % CHUNK || CHUNK % 4
#error "prefix and chunks must split the coefficients into multiples of 4"
#endif

/* hash salts: one stream per use */
enum { SALT_PLANET = 1, SALT_LOO = 2, SALT_RANDOM = 3 };
static const uint64_t FID_SEED = 0x5eed;

/* A cube of analysis texels: 6 * n * n * CH floats, face-major. */
typedef struct fid_field {
    int n;
    float *px;
} fid_field;

/* DCT basis and the frequency order of the DIM coefficients. */
typedef struct fid_dct {
    double c[SIDE][SIDE]; /* c[k][i] = a_k cos(pi (i + 1/2) k / SIDE) */
    int order[DIM];       /* order[j] = index (channel * NB + kv * SIDE + ku) of coefficient j */
} fid_dct;

/* The exemplar database: lattice neighbourhoods, prefix and rest stored apart so
 * the bound scan reads a compact array. */
typedef struct fid_db {
    size_t count;
    float *pre, *rest;
    int *face, *x, *y;
} fid_db;

static void dct_init(fid_dct *d) {
    const double pi = 3.14159265358979323846;
    for (int k = 0; k < SIDE; k++)
        for (int i = 0; i < SIDE; i++)
            d->c[k][i] = sqrt((k ? 2.0 : 1.0) / SIDE) * cos(pi * (i + 0.5) * k / SIDE);
    int j = 0;
    for (int s = 0; s <= 2 * (SIDE - 1); s++) /* total frequency, then channel, then ku */
        for (int c = 0; c < CH; c++)
            for (int ku = 0; ku < SIDE; ku++) {
                int kv = s - ku;
                if (kv >= 0 && kv < SIDE) d->order[j++] = c * NB + kv * SIDE + ku;
            }
}

static const float *texel(const fid_field *f, int face, int x, int y) {
    return f->px + (((size_t)face * f->n + y) * f->n + x) * CH;
}

/* Frequency-ordered DCT coefficients of a neighbourhood given as NB texels of CH. */
static void transform(const fid_dct *d, const float *nb, float *out) {
    double t[CH][SIDE][SIDE], coef[DIM];
    for (int c = 0; c < CH; c++) /* rows: x -> ku */
        for (int y = 0; y < SIDE; y++)
            for (int ku = 0; ku < SIDE; ku++) {
                double s = 0;
                for (int x = 0; x < SIDE; x++)
                    s += d->c[ku][x] * nb[(y * SIDE + x) * CH + c];
                t[c][y][ku] = s;
            }
    for (int c = 0; c < CH; c++) /* columns: y -> kv */
        for (int kv = 0; kv < SIDE; kv++)
            for (int ku = 0; ku < SIDE; ku++) {
                double s = 0;
                for (int y = 0; y < SIDE; y++)
                    s += d->c[kv][y] * t[c][y][ku];
                coef[c * NB + kv * SIDE + ku] = s;
            }
    for (int j = 0; j < DIM; j++)
        out[j] = (float)coef[d->order[j]];
}

/* The neighbourhood centred on (x, y) of a face (R <= x, y < n - R). */
static void gather(const fid_field *f, int face, int x, int y, float *nb) {
    for (int dy = -R; dy <= R; dy++)
        for (int dx = -R; dx <= R; dx++)
            memcpy(nb + ((dy + R) * SIDE + dx + R) * CH, texel(f, face, x + dx, y + dy),
                   CH * sizeof *nb);
}

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
static double height_scale(const fid_field *f) {
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

static void scale_height(fid_field *f, double scale) {
    size_t count = (size_t)6 * f->n * f->n;
    for (size_t i = 0; i < count; i++)
        f->px[i * CH + 3] *= (float)scale;
}

/* The planet box-averaged by m (sRGB averaged as stored, like the exemplar cube's
 * taps), then Lab. */
static pg_status planet_field(const pg_planet *p, int m, fid_field *out, pg_error *err) {
    int n = (int)(p->n / m);
    out->n = n;
    out->px = malloc((size_t)6 * n * n * CH * sizeof *out->px);
    if (!out->px) return pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory for the planet");
    double w = 1.0 / ((double)m * m);
#pragma omp parallel for schedule(static)
    for (int row = 0; row < 6 * n; row++) {
        int f = row / n, y = row % n;
        for (int x = 0; x < n; x++) {
            double acc[CH] = {0};
            for (int j = 0; j < m; j++)
                for (int i = 0; i < m; i++) {
                    size_t t = (size_t)(y * m + j) * p->n + (size_t)x * m + i;
                    for (int c = 0; c < 3; c++)
                        acc[c] += p->albedo[f][t * 3 + c];
                    acc[3] += p->height[f][t];
                }
            float *d = out->px + (((size_t)f * n + y) * n + x) * CH;
            for (int c = 0; c < CH; c++)
                d[c] = (float)(acc[c] * w);
        }
    }
    to_lab(out->px, (size_t)6 * n * n);
    return PG_OK;
}

static pg_status exemplar_field(const pg_planet *p, const pg_exemplar *ex, int n, fid_field *out,
                                pg_error *err) {
    out->n = n;
    pg_status st = pg_inspect_exemplar_cube(p, n, ex, &out->px, err);
    if (st == PG_OK) to_lab(out->px, (size_t)6 * n * n);
    return st;
}

/* ---- database and search ---- */

static void db_free(fid_db *d) {
    free(d->pre), free(d->rest), free(d->face);
    memset(d, 0, sizeof *d);
}

static pg_status db_build(const fid_dct *dct, const fid_field *f, fid_db *d, pg_error *err) {
    memset(d, 0, sizeof *d);
    int per = (f->n - 2 * R + PG_INSPECT_FID_STRIDE - 1) / PG_INSPECT_FID_STRIDE;
    d->count = (size_t)6 * per * per;
    d->pre = malloc(d->count * PFX * sizeof *d->pre);
    d->rest = malloc(d->count * REST * sizeof *d->rest);
    d->face = malloc(d->count * 3 * sizeof *d->face);
    if (!d->pre || !d->rest || !d->face) {
        db_free(d);
        return pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory for the database");
    }
    d->x = d->face + d->count, d->y = d->x + d->count;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < d->count; i++) {
        int face = (int)(i / ((size_t)per * per)), k = (int)(i % ((size_t)per * per));
        int x = R + (k % per) * PG_INSPECT_FID_STRIDE, y = R + (k / per) * PG_INSPECT_FID_STRIDE;
        float nb[DIM], v[DIM];
        gather(f, face, x, y, nb);
        transform(dct, nb, v);
        memcpy(d->pre + i * PFX, v, PFX * sizeof *v);
        memcpy(d->rest + i * REST, v + PFX, REST * sizeof *v);
        d->face[i] = face, d->x[i] = x, d->y[i] = y;
    }
    return PG_OK;
}

/* Squared distance over k in [k0, k1) (a multiple of 4 long) in four fixed lanes:
 * independent sums the compiler can keep in one vector register, added in a fixed
 * order, so the result does not depend on how it is compiled or threaded. */
static float sq_lanes(const float *q, const float *a, int len) {
    typedef float v4 __attribute__((vector_size(16)));
    v4 l = {0, 0, 0, 0};
    for (int k = 0; k < len; k += 4) {
        v4 x, y;
        memcpy(&x, q + k, sizeof x);
        memcpy(&y, a + k, sizeof y);
        l += (x - y) * (x - y);
    }
    return (l[0] + l[1]) + (l[2] + l[3]);
}

/* One query: frequency-ordered coefficients, its centre for the leave-one-out
 * exclusion (excl > 0: skip database entries on `face` within excl texels of (x, y)),
 * and the smallest squared distance found so far. */
typedef struct fid_query {
    float q[DIM];
    int face, x, y, excl;
    float best;
} fid_query;

/* Entry i against query t: lower bound first, then the rest in chunks until the partial
 * sum reaches the best so far. Exact: an entry is dropped only when a partial sum (of
 * non-negative terms) already reaches the best full distance. */
static void visit(const fid_db *d, size_t i, fid_query *t) {
    float s = sq_lanes(t->q, d->pre + i * PFX, PFX);
    if (s >= t->best) return;
    if (t->excl > 0 && d->face[i] == t->face && abs(d->x[i] - t->x) <= t->excl &&
        abs(d->y[i] - t->y) <= t->excl)
        return;
    const float *b = d->rest + i * REST;
    for (int k = 0; k < REST && s < t->best; k += CHUNK)
        s += sq_lanes(t->q + PFX + k, b + k, CHUNK);
    if (s < t->best) t->best = s;
}

/* Exact nearest neighbours of a block of queries. The database streams through the
 * cache once per block instead of once per query (the scan is memory-bound); each
 * query still sees the entries in database order. */
static void nearest_block(const fid_db *d, fid_query *qs, int count) {
    for (int t = 0; t < count; t++)
        qs[t].best = INFINITY;
    for (size_t i = 0; i < d->count; i++)
        for (int t = 0; t < count; t++)
            visit(d, i, &qs[t]);
}

/* ---- the three measures ---- */

/* Q_COMPLETE reuses the leave-one-out query texels (searched in the planet's
 * database), so completeness and its baseline differ only in what is searched. */
typedef enum { Q_PLANET, Q_LOO, Q_RANDOM, Q_COMPLETE } query_kind;

static int hashed_coord(uint32_t h, int n) {
    return R + (int)(h % (uint32_t)(n - 2 * R));
}

/* The neighbourhood of query `i` (face i / Q): a hashed centre on the planet or the
 * exemplar, or 25 hashed exemplar texels. Sets the centre for the exclusion. */
static void query_nb(query_kind kind, const fid_field *planet, const fid_field *exf, int i,
                     float *nb, int *face, int *x, int *y) {
    const int Q = PG_INSPECT_FID_QUERIES;
    *face = i / Q;
    if (kind == Q_RANDOM) {
        int n = exf->n;
        for (int t = 0; t < NB; t++) {
            uint32_t h = pg_synth_hash(FID_SEED, 0, i, t, 0, SALT_RANDOM);
            uint32_t g = pg_synth_hash(FID_SEED, 0, i, t, 1, SALT_RANDOM);
            memcpy(nb + t * CH, texel(exf, (int)(g % 6), (int)(h % n), (int)((h >> 16) % n)),
                   CH * sizeof *nb);
        }
        *x = *y = -1;
        return;
    }
    const fid_field *f = kind == Q_PLANET ? planet : exf;
    int salt = kind == Q_PLANET ? SALT_PLANET : SALT_LOO; /* Q_LOO and Q_COMPLETE */
    *x = hashed_coord(pg_synth_hash(FID_SEED, 0, *face, i, 0, salt), f->n);
    *y = hashed_coord(pg_synth_hash(FID_SEED, 0, *face, i, 1, salt), f->n);
    gather(f, *face, *x, *y, nb);
}

/* Mean over 6 * Q queries of the RMS difference per texel and channel to the nearest
 * database neighbourhood. */
static int query_count(query_kind kind) {
    return 6 * (kind == Q_RANDOM ? PG_INSPECT_FID_RANDOM_QUERIES : PG_INSPECT_FID_QUERIES);
}

static double measure(query_kind kind, const fid_dct *dct, const fid_db *d, const fid_field *planet,
                      const fid_field *exf, float *dist) {
    const int nq = query_count(kind), nblocks = (nq + QBLOCK - 1) / QBLOCK;
#pragma omp parallel for schedule(dynamic, 1)
    for (int blk = 0; blk < nblocks; blk++) {
        fid_query qs[QBLOCK];
        int i0 = blk * QBLOCK, count = nq - i0 < QBLOCK ? nq - i0 : QBLOCK;
        for (int t = 0; t < count; t++) {
            float nb[DIM];
            query_nb(kind, planet, exf, i0 + t, nb, &qs[t].face, &qs[t].x, &qs[t].y);
            transform(dct, nb, qs[t].q);
            qs[t].excl = kind == Q_LOO ? 2 * R : 0;
        }
        nearest_block(d, qs, count);
        for (int t = 0; t < count; t++)
            dist[i0 + t] = sqrtf(qs[t].best / DIM);
    }
    double sum = 0;
    for (int i = 0; i < nq; i++) /* query order: thread-count independent */
        sum += dist[i];
    return sum / nq;
}

/* The smallest box factor m dividing n with n / m <= PG_INSPECT_FID_FACE. */
static int analysis_factor(int64_t n) {
    for (int64_t m = 1; m <= n; m++)
        if (n % m == 0 && n / m <= PG_INSPECT_FID_FACE) return (int)m;
    return (int)n;
}

static pg_status run_measures(const fid_field *pf, const fid_field *ef, pg_inspect_fidelity *out,
                              pg_error *err) {
    fid_dct dct;
    dct_init(&dct);
    fid_db de, dp; /* exemplar and planet databases */
    float *dist = malloc((size_t)6 * PG_INSPECT_FID_QUERIES * sizeof *dist);
    pg_status st = dist ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory");
    if (st == PG_OK) st = db_build(&dct, ef, &de, err);
    if (st == PG_OK) {
        out->database = (int)de.count;
        out->queries = query_count(Q_PLANET);
        out->random_queries = query_count(Q_RANDOM);
        out->fidelity = measure(Q_PLANET, &dct, &de, pf, ef, dist);
        out->loo = measure(Q_LOO, &dct, &de, pf, ef, dist);
        out->random = measure(Q_RANDOM, &dct, &de, pf, ef, dist);
        db_free(&de);
        st = db_build(&dct, pf, &dp, err);
    }
    if (st == PG_OK) {
        out->completeness = measure(Q_COMPLETE, &dct, &dp, pf, ef, dist);
        db_free(&dp);
    }
    out->ratio = out->loo > 0 ? out->fidelity / out->loo : NAN;
    out->random_ratio = out->loo > 0 ? out->random / out->loo : NAN;
    out->completeness_ratio = out->loo > 0 ? out->completeness / out->loo : NAN;
    free(dist);
    return st;
}

pg_status pg_inspect_fidelity_compute(const pg_planet *p, const pg_exemplar *ex,
                                      pg_inspect_fidelity *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    int m = analysis_factor(p->n), n = (int)(p->n / m);
    if (n < 2 * R + 2)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "fidelity: faces of %lld texels are too small for %dx%d "
                            "neighbourhoods",
                            (long long)p->n, SIDE, SIDE);
    out->analysis_size = n;
    out->magnification = m;
    fid_field pf = {0, NULL}, ef = {0, NULL};
    pg_status st = exemplar_field(p, ex, n, &ef, err);
    if (st == PG_OK) st = planet_field(p, m, &pf, err);
    if (st == PG_OK) {
        out->height_scale = height_scale(&ef);
        scale_height(&ef, out->height_scale);
        scale_height(&pf, out->height_scale);
        st = run_measures(&pf, &ef, out, err);
    }
    free(pf.px), free(ef.px);
    return st;
}
