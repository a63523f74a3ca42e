/* pg_inspect_fidelity.c - neighbourhood fidelity of a planet against its exemplar
 * (pg_inspect.h, docs/inspect.md "Neighbourhood fidelity").
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
 *    the same face within PG_INSPECT_FID_EXCLUDE texels of the query. That is how close
 *    the exemplar is to the rest of itself;
 *  - random: each of the 25 texels drawn from a hashed exemplar texel, i.e. the
 *    exemplar's colours and heights with the structure destroyed.
 *
 * Copies do not count. A planet texel's own source (the planet's coordinate map,
 * pg_planet_source) would match it exactly, so a copy of the exemplar would score far
 * better than the exemplar scores against itself. Each planet query therefore skips
 * the database entries within PG_INSPECT_FID_EXCLUDE texels of its source, the radius
 * leave-one-out skips around its own centre; completeness does the same the other way
 * (an exemplar query skips planet entries whose source lies near it). So all three
 * ask the same question: how close is this neighbourhood to material taken from
 * elsewhere. A planet without a map is searched without the exclusion.
 *
 * Blur. The nearest neighbour in L2 prefers smooth candidates: for stochastic texture a
 * smooth neighbourhood is closer to a sharp one than another sharp instance with other
 * phases is, so a blurred planet scores a *better* completeness than an exact copy.
 * Completeness is therefore also measured on the local detail amplitude, a
 * phase-free field: per channel D = sqrt(box5(hp^2)), hp = x - binomial3(x) (the
 * finest octave of a Laplacian pyramid, squared and averaged like a complex cell's
 * energy, as in the LPIPS-style features). Two sharp instances of one texture have
 * nearly the same D; a blurred one has far less. completeness_ratio is the larger of
 * the two ratios, each against its own leave-one-out.
 *
 * Preconditions and scale: planet and exemplar are compared at one texel spacing.
 * Faces finer than PG_INSPECT_FID_FACE keep the search within a few seconds: the planet's faces are
 * box-averaged by the smallest integer factor m that brings them to at most PG_INSPECT_FID_FACE
 * texels, and the exemplar is reprojected onto a cube of that size with the planet's projection.
 * Neighbourhoods stay inside faces (centres R texels or more from an edge), so no seam handling is
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
#include "pg_inspect_fidelity_internal.h"
#include "planetgen/pg_synth.h"

#include "pg_synth_internal.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define R PG_INSPECT_FID_RADIUS
#define SIDE (2 * R + 1)
#define NB (SIDE * SIDE)
#define CH PG_INSPECT_FID_CHANNELS
#define DIM (NB * CH)
#define PFX PG_INSPECT_FID_PREFIX
#define REST (DIM - PFX)
_Static_assert(PG_INSPECT_FID_RANDOM_QUERIES <= PG_INSPECT_FID_QUERIES,
               "the distance buffer holds 6 x PG_INSPECT_FID_QUERIES queries");
#define CHUNK 12  /* early-termination check every CHUNK coefficients */
#define QBLOCK 16 /* queries per database pass (16 x 400 B stay in L1) */
#if PFX % 4 || REST % CHUNK || CHUNK % 4
#error "prefix and chunks must split the coefficients into multiples of 4"
#endif

/* hash salts: one stream per use */
enum { SALT_PLANET = 1, SALT_LOO = 2, SALT_RANDOM = 3 };
static const uint64_t FID_SEED = 0x5eed;

/* DCT basis and the frequency order of the DIM coefficients. */
typedef struct fid_dct {
    double c[SIDE][SIDE]; /* c[k][i] = a_k cos(pi (i + 1/2) k / SIDE) */
    int order[DIM];       /* order[j] = index (channel * NB + kv * SIDE + ku) of coefficient j */
} fid_dct;

/* The exemplar database: lattice neighbourhoods, prefix and rest stored apart so
 * the bound scan reads a compact array. face, x, y: where the entry came from on the
 * exemplar (its own centre, or a planet entry's source; face -1 = unknown), for the
 * exclusion. */
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
        if (f->src) { /* a planet entry is known by its source */
            int32_t c = f->src[((size_t)face * f->n + y) * f->n + x];
            d->face[i] = c / (f->n * f->n);
            d->x[i] = c % f->n, d->y[i] = (c / f->n) % f->n;
        }
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

/* One query: frequency-ordered coefficients, where it came from on the exemplar for the
 * exclusion (excl > 0: skip database entries on `face` within excl texels of (x, y);
 * face -1: nothing excluded), and the smallest squared distance found so far. */
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
 * exemplar, or 25 hashed exemplar texels. Sets the exemplar position for the
 * exclusion: a planet query's source (face -1 without a map), else its own centre. */
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
    if (kind == Q_PLANET) {
        int32_t c = planet->src ? planet->src[((size_t)*face * f->n + *y) * f->n + *x] : -1;
        *face = c < 0 ? -1 : c / (f->n * f->n);
        *x = c < 0 ? -1 : c % f->n;
        *y = c < 0 ? -1 : (c / f->n) % f->n;
    }
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
            /* completeness excludes planet entries by their sources: none without a map */
            bool none = kind == Q_RANDOM || qs[t].face < 0 || (kind == Q_COMPLETE && !planet->src);
            qs[t].excl = none ? 0 : PG_INSPECT_FID_EXCLUDE;
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

/* The searches that read the planet: fidelity against the exemplar's database,
 * completeness against the planet's, on the analysis field and on the detail
 * amplitude. The baselines are already in out. */
static pg_status planet_measures(const fid_field *pf, const fid_field *ef, const fid_field *pd,
                                 const fid_field *ed, pg_inspect_fidelity *out, pg_error *err) {
    fid_dct dct;
    dct_init(&dct);
    fid_db d;
    float *dist = malloc((size_t)6 * PG_INSPECT_FID_QUERIES * sizeof *dist);
    pg_status st = dist ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory");
    if (st == PG_OK) st = db_build(&dct, ef, &d, err);
    if (st == PG_OK) {
        out->fidelity = measure(Q_PLANET, &dct, &d, pf, ef, dist);
        db_free(&d);
        st = db_build(&dct, pf, &d, err);
    }
    if (st == PG_OK) {
        out->completeness = measure(Q_COMPLETE, &dct, &d, pf, ef, dist);
        db_free(&d);
        st = db_build(&dct, pd, &d, err);
    }
    if (st == PG_OK) {
        out->detail_completeness = measure(Q_COMPLETE, &dct, &d, pd, ed, dist);
        db_free(&d);
    }
    out->ratio = out->loo > 0 ? out->fidelity / out->loo : NAN;
    out->random_ratio = out->loo > 0 ? out->random / out->loo : NAN;
    out->structure_completeness_ratio = out->loo > 0 ? out->completeness / out->loo : NAN;
    out->detail_completeness_ratio =
        out->detail_loo > 0 ? out->detail_completeness / out->detail_loo : NAN;
    out->completeness_ratio =
        fmax(out->structure_completeness_ratio, out->detail_completeness_ratio);
    free(dist);
    return st;
}

/* ---- the exemplar's side ---- */

struct pg_inspect_fid_exemplar {
    int64_t N; /* planet face size it was made for */
    int n, m;  /* analysis face size, box factor */
    int projection;
    double height_scale, loo, random, detail_loo;
    int database;
    fid_field ef, ed; /* analysis field and detail amplitude, height scaled */
};

/* The figures that only read the exemplar: leave-one-out and random on the analysis
 * field, leave-one-out on the detail amplitude. */
static pg_status exemplar_baselines(pg_inspect_fid_exemplar *fx, pg_error *err) {
    fid_dct dct;
    dct_init(&dct);
    fid_db d;
    float *dist = malloc((size_t)6 * PG_INSPECT_FID_QUERIES * sizeof *dist);
    pg_status st = dist ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory");
    if (st == PG_OK) st = db_build(&dct, &fx->ef, &d, err);
    if (st == PG_OK) {
        fx->database = (int)d.count;
        fx->loo = measure(Q_LOO, &dct, &d, NULL, &fx->ef, dist);
        fx->random = measure(Q_RANDOM, &dct, &d, NULL, &fx->ef, dist);
        db_free(&d);
        st = db_build(&dct, &fx->ed, &d, err);
    }
    if (st == PG_OK) {
        fx->detail_loo = measure(Q_LOO, &dct, &d, NULL, &fx->ed, dist);
        db_free(&d);
    }
    free(dist);
    return st;
}

void pg_inspect_fid_exemplar_free(pg_inspect_fid_exemplar *fx) {
    if (!fx) return;
    free(fx->ef.px), free(fx->ed.px);
    free(fx);
}

/* The smallest box factor m dividing n with n / m <= PG_INSPECT_FID_FACE. */
static int analysis_factor(int64_t n) {
    for (int64_t m = 1; m <= n; m++)
        if (n % m == 0 && n / m <= PG_INSPECT_FID_FACE) return (int)m;
    return (int)n;
}

static pg_status check_size(int64_t N, pg_error *err) {
    int m = analysis_factor(N);
    if (N / m < 2 * R + 2)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "fidelity: faces of %lld texels are too small for %dx%d "
                            "neighbourhoods",
                            (long long)N, SIDE, SIDE);
    return PG_OK;
}

pg_status pg_inspect_fid_exemplar_build(const pg_planet *geometry, const pg_exemplar *ex,
                                        pg_inspect_fid_exemplar **out, pg_error *err) {
    *out = NULL;
    pg_status st = check_size(geometry->n, err);
    if (st != PG_OK) return st;
    pg_inspect_fid_exemplar *fx = calloc(1, sizeof *fx);
    if (!fx) return pg_error_set(err, PG_ERR_NOMEM, "fidelity: out of memory");
    fx->N = geometry->n;
    fx->m = analysis_factor(fx->N);
    fx->n = (int)(fx->N / fx->m);
    fx->projection = geometry->projection;
    float *cube = NULL; /* the exemplar on a cube of the planet's size: both sides alike */
    st = pg_inspect_exemplar_cube(geometry, fx->N, ex, &cube, err);
    fid_src es = fid_packed_src(cube, fx->N); /* empty when the cube failed */
    if (st == PG_OK) st = fid_box_field(&es, fx->m, &fx->ef, err);
    if (st == PG_OK) {
        fx->height_scale = fid_height_scale(&fx->ef);
        fid_scale_height(&fx->ef, fx->height_scale);
        st = fid_detail_field(&es, fx->m, fx->height_scale, &fx->ed, err);
    }
    free(cube);
    if (st == PG_OK) st = exemplar_baselines(fx, err);
    if (st != PG_OK) {
        pg_inspect_fid_exemplar_free(fx);
        return st;
    }
    *out = fx;
    return PG_OK;
}

#define FID_MAGIC "PGFIDX01"

/* The header: magic, key, the scalars; then the two fields. Raw, like the synthesis
 * exemplar cache: read only by the build that wrote it. */
typedef struct fid_header {
    char magic[8];
    uint64_t key;
    int64_t N;
    int32_t n, m, projection, database;
    double height_scale, loo, random, detail_loo;
} fid_header;

pg_status pg_inspect_fid_exemplar_save(const pg_inspect_fid_exemplar *fx, const char *path,
                                       uint64_t key, pg_error *err) {
    char tmp[1100];
    snprintf(tmp, sizeof tmp, "%s.%ld.tmp", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) return pg_error_set(err, PG_ERR_IO, "%s: cannot write the cache", tmp);
    fid_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, FID_MAGIC, 8);
    h.key = key, h.N = fx->N, h.n = fx->n, h.m = fx->m, h.projection = fx->projection;
    h.database = fx->database, h.height_scale = fx->height_scale, h.loo = fx->loo;
    h.random = fx->random, h.detail_loo = fx->detail_loo;
    size_t count = (size_t)6 * fx->n * fx->n * CH;
    bool ok = fwrite(&h, sizeof h, 1, f) == 1 &&
              fwrite(fx->ef.px, sizeof(float), count, f) == count &&
              fwrite(fx->ed.px, sizeof(float), count, f) == count;
    if (fclose(f) != 0) ok = false;
    if (!ok || rename(tmp, path) != 0) {
        remove(tmp);
        return pg_error_set(err, PG_ERR_IO, "%s: cannot write the cache", path);
    }
    return PG_OK;
}

pg_inspect_fid_exemplar *pg_inspect_fid_exemplar_load(const char *path, uint64_t key) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fid_header h;
    pg_inspect_fid_exemplar *fx = calloc(1, sizeof *fx);
    bool ok = fx && fread(&h, sizeof h, 1, f) == 1 && !memcmp(h.magic, FID_MAGIC, 8) &&
              h.key == key && h.n > 2 * R && h.n <= (1 << 16) && h.m >= 1;
    if (ok) {
        size_t count = (size_t)6 * h.n * h.n * CH;
        fx->N = h.N, fx->n = h.n, fx->m = h.m, fx->projection = h.projection;
        fx->database = h.database, fx->height_scale = h.height_scale, fx->loo = h.loo;
        fx->random = h.random, fx->detail_loo = h.detail_loo;
        fx->ef = (fid_field){h.n, malloc(count * sizeof(float)), NULL};
        fx->ed = (fid_field){h.n, malloc(count * sizeof(float)), NULL};
        ok = fx->ef.px && fx->ed.px && fread(fx->ef.px, sizeof(float), count, f) == count &&
             fread(fx->ed.px, sizeof(float), count, f) == count;
    }
    fclose(f);
    if (!ok) pg_inspect_fid_exemplar_free(fx), fx = NULL;
    return fx;
}

/* ---- the planet's side ---- */

pg_status pg_inspect_fidelity_with(const pg_planet *p, const pg_inspect_fid_exemplar *fx,
                                   pg_inspect_fidelity *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    if (fx->N != p->n || fx->projection != (int)p->projection)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "fidelity: the exemplar side was made for faces of %lld texels, the "
                            "planet has %lld",
                            (long long)fx->N, (long long)p->n);
    out->analysis_size = fx->n;
    out->magnification = fx->m;
    out->height_scale = fx->height_scale;
    out->loo = fx->loo, out->random = fx->random, out->detail_loo = fx->detail_loo;
    out->database = fx->database;
    out->queries = query_count(Q_PLANET);
    out->random_queries = query_count(Q_RANDOM);
    fid_field pf = {0, NULL, NULL}, pd = {0, NULL, NULL};
    fid_src ps = fid_planet_src(p);
    pg_status st = fid_planet_field(p, fx->m, &pf, err);
    if (st == PG_OK) {
        fid_scale_height(&pf, fx->height_scale);
        st = fid_detail_field(&ps, fx->m, fx->height_scale, &pd, err);
    }
    pd.src = pf.src; /* planet entries are known by their sources */
    if (st == PG_OK) st = planet_measures(&pf, &fx->ef, &pd, &fx->ed, out, err);
    free(pf.px), free(pf.src), free(pd.px);
    return st;
}

pg_status pg_inspect_fidelity_compute(const pg_planet *p, const pg_exemplar *ex,
                                      pg_inspect_fidelity *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    pg_inspect_fid_exemplar *fx = NULL;
    pg_status st = pg_inspect_fid_exemplar_build(p, ex, &fx, err);
    if (st == PG_OK) st = pg_inspect_fidelity_with(p, fx, out, err);
    pg_inspect_fid_exemplar_free(fx);
    return st;
}
