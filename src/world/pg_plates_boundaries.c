/* pg_plates_boundaries.c - plate boundaries and their kind from relative plate motion.
 *
 * A texel is on a boundary when one of its 4 edge neighbours lies on another plate.
 * At its centre p, plate a moves with v_a = omega_a x p (a rigid rotation about its
 * Euler pole). The other side moves with the mean v_b over the 8 neighbours on other
 * plates, and the outward boundary normal nhat is the normalised sum of the unit
 * tangents from p towards those neighbours. The relative velocity v = v_b - v_a splits
 * into vn = v . nhat and the tangential rest vt:
 *
 *     |vn| < 0.5 |vt|  transform (the plates slide past each other within ~27 degrees)
 *     vn < 0           convergent (the other plate comes towards this one)
 *     vn > 0           divergent
 *
 * This is the usual kinematic classification (e.g. Bird 2003, "An updated digital model
 * of plate boundaries", which types boundary steps by the relative velocity's angle to
 * the boundary); the 0.5 ratio is ours. Both sides of a boundary get the same kind,
 * because swapping a and b flips both v and nhat. */
#include "pg_plates_internal.h"

#include <stdlib.h>

#define PG_PLATES_TRANSFORM_RATIO 0.5

static uint8_t pg_plates_kind_at(const pg_plates_grid *g, const uint8_t *plate,
                                 const double (*omega)[3], int64_t t) {
    const double *p = g->dir + 3 * t;
    int a = plate[t], edge = 0, others = 0;
    for (int d = 0; d < 4; d++)
        edge |= plate[g->nbr[8 * t + d]] != a;
    if (!edge) return PG_PLATES_INTERIOR;
    double nrm[3] = {0, 0, 0}, vb[3] = {0, 0, 0}, va[3];
    for (int d = 0; d < 8; d++) {
        int64_t q = g->nbr[8 * t + d];
        if (plate[q] == a) continue;
        const double *pq = g->dir + 3 * q;
        double c = pg_vec3_dot(pq, p),
               tq[3] = {pq[0] - c * p[0], pq[1] - c * p[1], pq[2] - c * p[2]};
        pg_vec3_normalize(tq);
        double v[3];
        pg_vec3_cross(omega[plate[q]], p, v);
        for (int i = 0; i < 3; i++) {
            nrm[i] += tq[i];
            vb[i] += v[i];
        }
        others++;
    }
    pg_vec3_normalize(nrm);
    pg_vec3_cross(omega[a], p, va);
    double v[3];
    for (int i = 0; i < 3; i++)
        v[i] = vb[i] / others - va[i];
    double vn = pg_vec3_dot(v, nrm);
    double vt2 = pg_vec3_dot(v, v) - vn * vn;
    double vt = sqrt(fmax(0, vt2));
    if (fabs(vn) < PG_PLATES_TRANSFORM_RATIO * vt || (vn == 0 && vt == 0))
        return PG_PLATES_TRANSFORM;
    return vn < 0 ? PG_PLATES_CONVERGENT : PG_PLATES_DIVERGENT;
}

pg_status pg_plates_classify(int64_t n, pg_cube_projection proj, const uint8_t *plate, int nplates,
                             const double (*omega)[3], uint8_t *kind, pg_error *err) {
    if (n < 2 || n > 4096)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: n = %lld is outside 2..4096",
                            (long long)n);
    if (nplates < 1 || nplates > 255)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: nplates = %d is outside 1..255",
                            nplates);
    if (!plate || !omega || !kind)
        return pg_error_set(err, PG_ERR_BADINPUT, "plates: classify needs plate, omega and kind");
    for (int64_t t = 0; t < 6 * n * n; t++)
        if (plate[t] >= nplates)
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "plates: plate id %d at texel %lld is not below nplates = %d",
                                plate[t], (long long)t, nplates);
    pg_plates_grid g;
    pg_status st = pg_plates_grid_init(&g, n, proj, 1.0, err);
    if (st != PG_OK) return st;
#pragma omp parallel for schedule(static)
    for (int64_t t = 0; t < g.count; t++)
        kind[t] = pg_plates_kind_at(&g, plate, omega, t);
    pg_plates_grid_free(&g);
    return PG_OK;
}
