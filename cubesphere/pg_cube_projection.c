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
