/* pg_cube_projection.c - faces, frames and the three face projections.
 *
 * Every projection is "pick the face by the largest |component|, then warp the
 * face-local direction": gnomonic is the plain central projection onto the cube;
 * equi-angular (the default) warps each grid axis by tan(pi u / 4) so that texels
 * subtend equal angles along the face axes (area ratio sqrt 2 instead of 3^1.5);
 * equal-area is Rosca & Plonka's map (pg_cube_equal_area_rosca_plonka.c). All are
 * closed-form both ways, so round trips are at round-off level. */
#include "pg_cube_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double PG_PI = 3.14159265358979323846;

/* The face frames documented in pg_cube.h: normal, e_u, e_v; e_u x e_v = n. */
static const int FRAMES[PG_CUBE_NFACES][3][3] = {
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},   /* +X */
    {{-1, 0, 0}, {0, -1, 0}, {0, 0, 1}}, /* -X */
    {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}},  /* +Y */
    {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},  /* -Y */
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   /* +Z */
    {{0, 0, -1}, {1, 0, 0}, {0, -1, 0}}, /* -Z */
};

static const char *const FACE_NAMES[PG_CUBE_NFACES] = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};
static const char *const PROJ_NAMES[3] = {"gnomonic", "equi-angular", "equal-area"};

const char *pg_cube_face_name(int face) {
    return face >= 0 && face < PG_CUBE_NFACES ? FACE_NAMES[face] : "?";
}

void pg_cube_face_frame(int face, int n[3], int eu[3], int ev[3]) {
    for (int i = 0; i < 3; i++) {
        n[i] = FRAMES[face][0][i];
        eu[i] = FRAMES[face][1][i];
        ev[i] = FRAMES[face][2][i];
    }
}

const char *pg_cube_projection_name(pg_cube_projection p) {
    return (unsigned)p < 3 ? PROJ_NAMES[p] : "?";
}

pg_status pg_cube_projection_parse(const char *name, const char *option, pg_cube_projection *out,
                                   pg_error *err) {
    for (int i = 0; i < 3; i++) {
        if (name && !strcmp(name, PROJ_NAMES[i])) {
            *out = (pg_cube_projection)i;
            return PG_OK;
        }
    }
    return pg_error_set(err, PG_ERR_BADINPUT,
                        "%s: unknown projection '%s' (gnomonic, equi-angular, equal-area)", option,
                        name ? name : "");
}

void pg_cube_to_dir(pg_cube_projection p, int face, double u, double v, double dir[3]) {
    double l[3]; /* face-local: along e_u, e_v, n */
    if (p == PG_CUBE_EQUALAREA) {
        pg_cube_rp_forward(u, v, l);
    } else {
        double a = u, b = v;
        if (p == PG_CUBE_EQUIANGULAR) a = tan(PG_PI / 4 * u), b = tan(PG_PI / 4 * v);
        double r = sqrt(1 + a * a + b * b);
        l[0] = a / r, l[1] = b / r, l[2] = 1 / r;
    }
    const int(*F)[3] = FRAMES[face];
    for (int i = 0; i < 3; i++)
        dir[i] = F[0][i] * l[2] + F[1][i] * l[0] + F[2][i] * l[1];
}

/* Face of a direction: the largest |component|, ties to the lowest face id. */
static int face_of(const double d[3]) {
    int best = 0;
    double bv = -1;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        const int *n = FRAMES[f][0];
        double c = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        if (c > bv) bv = c, best = f;
    }
    return best;
}

void pg_cube_from_dir(pg_cube_projection p, const double dir[3], int *face, double *u, double *v) {
    int f = face_of(dir);
    const int(*F)[3] = FRAMES[f];
    double l[3];
    for (int k = 0; k < 3; k++) {
        const int *e = F[(k + 1) % 3]; /* l[0]: e_u, l[1]: e_v, l[2]: n */
        l[k] = e[0] * dir[0] + e[1] * dir[1] + e[2] * dir[2];
    }
    *face = f;
    if (p == PG_CUBE_EQUALAREA) {
        pg_cube_rp_inverse(l, u, v);
    } else if (p == PG_CUBE_EQUIANGULAR) {
        *u = atan2(l[0], l[2]) * (4 / PG_PI);
        *v = atan2(l[1], l[2]) * (4 / PG_PI);
    } else {
        *u = l[0] / l[2];
        *v = l[1] / l[2];
    }
    /* round-off at an edge must not leave the face */
    *u = *u > 1 ? 1 : *u < -1 ? -1 : *u;
    *v = *v > 1 ? 1 : *v < -1 ? -1 : *v;
}

/* ---- texel of a direction ---- */

#define FINDER_NEAR 1e-9 /* in the tangent coordinate, whose range is [-1, 1] */

static int64_t texel_exact(pg_cube_projection p, int64_t n, const double dir[3]) {
    int face;
    double u, v;
    pg_cube_from_dir(p, dir, &face, &u, &v);
    int64_t x = (int64_t)floor((u + 1) * 0.5 * (double)n);
    int64_t y = (int64_t)floor((v + 1) * 0.5 * (double)n);
    x = x < 0 ? 0 : (x >= n ? n - 1 : x);
    y = y < 0 ? 0 : (y >= n ? n - 1 : y);
    return ((int64_t)face * n + y) * n + x;
}

pg_status pg_cube_texel_finder_init(pg_cube_texel_finder *f, pg_cube_projection p, int64_t n,
                                    pg_error *err) {
    memset(f, 0, sizeof *f);
    f->proj = p, f->n = n;
    if (p == PG_CUBE_EQUALAREA) return PG_OK;
    f->edge = malloc((size_t)(n + 1) * sizeof *f->edge);
    f->start = malloc((size_t)(2 * n) * sizeof *f->start);
    if (!f->edge || !f->start) {
        pg_cube_texel_finder_free(f);
        return pg_error_set(err, PG_ERR_NOMEM, "cube: out of memory for %lld edges",
                            (long long)n + 1);
    }
    for (int64_t j = 0; j <= n; j++) {
        double u = 2.0 * (double)j / (double)n - 1;
        f->edge[j] = p == PG_CUBE_EQUIANGULAR ? tan(PG_PI / 4 * u) : u;
    }
    for (int64_t b = 0, x = 0; b < 2 * n; b++) { /* the cell of each bucket's lower end */
        double t = -1 + (double)b / (double)n;
        while (x + 1 < n && f->edge[x + 1] <= t)
            x++;
        f->start[b] = x;
    }
    return PG_OK;
}

void pg_cube_texel_finder_free(pg_cube_texel_finder *f) {
    free(f->edge);
    free(f->start);
    memset(f, 0, sizeof *f);
}

/* The cell [edge[x], edge[x + 1]) of t (edge[0] and edge[n] as -inf and +inf), or -1
 * within FINDER_NEAR of an inner edge. 2n equal buckets over [-1, 1] give a start: a
 * cell spans 1 to 2 buckets, so a step or two finds it. */
static int64_t finder_cell(const pg_cube_texel_finder *f, double t) {
    const int64_t n = f->n;
    int64_t b = (int64_t)((t + 1) * (double)n);
    b = b < 0 ? 0 : (b >= 2 * n ? 2 * n - 1 : b);
    int64_t x = f->start[b];
    while (x > 0 && f->edge[x] > t)
        x--;
    while (x + 1 < n && f->edge[x + 1] <= t)
        x++;
    if (x > 0 && t - f->edge[x] < FINDER_NEAR) return -1;
    if (x + 1 < n && f->edge[x + 1] - t < FINDER_NEAR) return -1;
    return x;
}

int64_t pg_cube_texel_find(const pg_cube_texel_finder *f, const double dir[3]) {
    if (!f->edge) return texel_exact(f->proj, f->n, dir);
    int face = face_of(dir);
    const int(*F)[3] = FRAMES[face];
    double l[3];
    for (int k = 0; k < 3; k++) {
        const int *e = F[(k + 1) % 3];
        l[k] = e[0] * dir[0] + e[1] * dir[1] + e[2] * dir[2];
    }
    int64_t x = finder_cell(f, l[0] / l[2]), y = finder_cell(f, l[1] / l[2]);
    if (x < 0 || y < 0) return texel_exact(f->proj, f->n, dir);
    return ((int64_t)face * f->n + y) * f->n + x;
}
