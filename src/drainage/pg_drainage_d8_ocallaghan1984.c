/* pg_drainage_d8_ocallaghan1984.c - D8 flow directions on the cube sphere (pg_drainage.h).
 *
 * D8 (O'Callaghan & Mark 1984, "The extraction of drainage networks from digital
 * elevation data", CVGIP 28): every cell drains to the one neighbour of steepest
 * descent, drop / distance. On the cube sphere the 8 neighbours come from the seam maps
 * of pg_pits.h (7 at the cube-corner texels), and distances are not constant: they are
 * the chords between the texel centres on the ellipsoid (a texel's direction d meets
 * the ellipsoid x^2/a^2 + y^2/a^2 + z^2/b^2 = 1 at r(d) d). Between neighbours the
 * chord is shorter than the geodesic by about theta^2 / 24: 1e-7 at the default
 * planet's 9 km texels.
 *
 * Speed: interior texels of a face read their centres from one of two tables, made
 * from the face-local centres (pg_drainage_internal.h): +X for the equatorial faces,
 * +Z for the polar ones. The other equatorial faces are rotations of +X about the
 * polar axis and -Z is +Z turned 180 degrees about the x axis; both maps preserve the
 * ellipsoid, so distances between texels of one face are those of its table's face.
 * Border texels, whose neighbours lie on other faces, take their centres from
 * pg_cube_texel_dir directly.
 *
 * Preconditions: heights finite (NaN is refused). Determinism: each cell is decided
 * from its own neighbourhood only, with ties to the lowest id, so rows run in parallel
 * and the result does not depend on the thread count. */
#include "pg_huge.h"
#include "pg_drainage_internal.h"
#include "planetgen/pg_pits.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>

typedef struct d8_ctx {
    int64_t n;
    pg_cube_grid grid; /* T = n, S = 1: texel ids are global ids */
    pg_pits_topo topo;
    double a_km, b_km;
    double *table[2]; /* n*n*3 centres of face +X (equatorial) and +Z (polar), km */
    const float *const *h;
    float sea;
} d8_ctx;

static void texel_point(const d8_ctx *c, int64_t id, double p[3]) {
    double d[3];
    pg_cube_texel_dir(&c->grid, id, d);
    pg_drainage_surface_point(d, c->a_km, c->b_km, p);
}

static pg_status ctx_init(d8_ctx *c, int64_t n, pg_cube_projection proj, const pg_ellipsoid *ell,
                          pg_error *err) {
    pg_ellipsoid e = ell ? *ell : pg_ellipsoid_sphere();
    c->n = n;
    c->a_km = e.a / 1000.0;
    c->b_km = c->a_km * (1.0 - e.f);
    c->table[0] = c->table[1] = NULL;
    pg_status s = pg_cube_grid_init(&c->grid, proj, (int)n, 1, err);
    if (!s) s = pg_pits_topo_cube(&c->topo, (uint32_t)n, err);
    if (s) return s;
    size_t nn = (size_t)n * (size_t)n;
    for (int k = 0; k < 2; k++)
        if (!(c->table[k] = pg_huge_malloc(nn * 3 * sizeof(double))))
            return pg_error_set(err, PG_ERR_NOMEM, "drainage: out of memory for texel centres");
    double *l = c->table[1];
    pg_drainage_local_centres(proj, n, l); /* in place: +Z's point overwrites its l last */
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < (int64_t)nn; i++)
        for (int k = 0; k < 2; k++) {
            double d[3];
            pg_drainage_local_to_dir(l + 3 * i, k, d);
            pg_drainage_surface_point(d, c->a_km, c->b_km, c->table[k] + 3 * i);
        }
    return PG_OK;
}

static double dist3(const double *p, const double *q) {
    double d[3];
    pg_vec3_sub(p, q, d);
    return pg_vec3_length(d);
}

static float height_of(const d8_ctx *c, uint32_t id) {
    uint64_t nn = (uint64_t)c->n * (uint64_t)c->n;
    return c->h[id / nn][id % nn];
}

/* The running choice of one cell: steepest slope so far, its neighbour and distance. */
typedef struct d8_best {
    double slope, dist;
    int64_t id;
} d8_best;

static void offer(d8_best *b, double drop, double dist, int64_t id) {
    if (!(drop > 0)) return;
    double s = drop / dist;
    if (s > b->slope || (s == b->slope && id < b->id)) b->slope = s, b->dist = dist, b->id = id;
}

/* A texel on a face border: neighbours across seams, centres computed directly. */
static void border_cell(const d8_ctx *c, uint32_t id, float hi, d8_best *b) {
    uint32_t nb[8];
    int k = pg_pits_neighbours_slow(&c->topo, id, nb);
    double p[3], q[3];
    texel_point(c, id, p);
    for (int j = 0; j < k; j++) {
        double drop = (double)hi - (double)height_of(c, nb[j]);
        if (!(drop > 0)) continue;
        texel_point(c, nb[j], q);
        offer(b, drop, dist3(p, q), nb[j]);
    }
}

/* An interior texel (x, y) of face f: all 8 neighbours on the same face. */
static void interior_cell(const d8_ctx *c, int f, int64_t x, int64_t y, float hi, d8_best *b) {
    const int64_t n = c->n;
    const float *h = c->h[f];
    const double *t = c->table[f >= PG_CUBE_FACE_PZ];
    const double *p = t + 3 * (y * n + x);
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            int64_t j = (y + dy) * n + (x + dx);
            double drop = (double)hi - (double)h[j];
            if ((dx || dy) && drop > 0) offer(b, drop, dist3(p, t + 3 * j), f * n * n + j);
        }
}

/* One face row; returns the number of NaN heights met. */
static int64_t d8_row(const d8_ctx *c, int64_t row, int32_t *recv, float *len, uint8_t *flags) {
    const int64_t n = c->n;
    const int f = (int)(row / n);
    const int64_t y = row % n;
    int64_t nans = 0;
    for (int64_t x = 0; x < n; x++) {
        int64_t id = row * n + x;
        float hi = c->h[f][y * n + x];
        recv[id] = -1, flags[id] = 0;
        if (len) len[id] = 0.0f;
        if (isnan(hi)) nans++;
        if (!(hi > c->sea)) continue;
        flags[id] = PG_DRAINAGE_LAND;
        d8_best b = {0.0, 0.0, -1};
        if (x > 0 && y > 0 && x < n - 1 && y < n - 1)
            interior_cell(c, f, x, y, hi, &b);
        else
            border_cell(c, (uint32_t)id, hi, &b);
        if (b.id >= 0) recv[id] = (int32_t)b.id;
        if (b.id >= 0 && len) len[id] = (float)b.dist;
    }
    return nans;
}

pg_status pg_drainage_cube_d8(const float *const heights[PG_CUBE_NFACES], int64_t n,
                              pg_cube_projection p, const pg_ellipsoid *ell, float sea_level,
                              int32_t *receiver, float *length_km, uint8_t *flags, pg_error *err) {
    if (n < 2 || 6 * n * n >= (INT64_C(1) << 31))
        return pg_error_set(err, PG_ERR_BADINPUT, "drainage: face size %lld outside 2..18918",
                            (long long)n);
    if (isnan(sea_level)) return pg_error_set(err, PG_ERR_BADINPUT, "drainage: sea level is NaN");
    d8_ctx c;
    pg_status s = ctx_init(&c, n, p, ell, err);
    c.h = heights;
    c.sea = sea_level;
    int64_t nans = 0;
    if (!s) {
#pragma omp parallel for schedule(dynamic, 16) reduction(+ : nans)
        for (int64_t row = 0; row < 6 * n; row++)
            nans += d8_row(&c, row, receiver, length_km, flags);
    }
    free(c.table[0]), free(c.table[1]);
    if (!s && nans)
        s = pg_error_set(err, PG_ERR_BADINPUT, "drainage: %lld heights are NaN", (long long)nans);
    return s;
}
