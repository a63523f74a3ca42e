/* pg_plates_boundaries.c - plate boundaries and their kind from relative plate motion.
 *
 * A texel is on a boundary when one of its 4 edge neighbours lies on another plate.
 * At its centre p, plate a moves with v_a = omega_a x p (a rigid rotation about its
 * Euler pole). The other side moves with the mean v_b over the texels of other plates
 * within PG_PLATES_NORMAL_RADIUS texel widths of p, and the outward boundary normal nhat
 * is the normalised sum of the unit tangents from p towards those texels. Over such a
 * disc a boundary that crosses the grid obliquely has the normal of its own course; over
 * the 8 neighbours the normal turned by up to 45 degrees from step to step of the
 * grid's staircase and the kind flickered along the boundary (docs/world.md,
 * "Boundaries that hold their kind"). The relative velocity v = v_b - v_a splits into
 * vn = v . nhat and the tangential rest vt:
 *
 *     |vn| < 0.5 |vt|  transform (the plates slide past each other within ~27 degrees)
 *     vn < 0           convergent (the other plate comes towards this one)
 *     vn > 0           divergent
 *
 * This is the usual kinematic classification (e.g. Bird 2003, "An updated digital model
 * of plate boundaries", which types boundary steps by the relative velocity's angle to
 * the boundary); the 0.5 ratio is ours. Both sides of a boundary get the same kind,
 * because swapping a and b flips both v and nhat.
 *
 * With the simulation's fronts (pg_plates_classify_fronts: texels where crust was
 * overridden in its last steps), a boundary texel with a front in its disc whose plates
 * approach (vn < 0) is convergent even when the motion is oblique: crust is being
 * consumed there, as at Earth's oblique subduction zones (the Aleutians), and that is
 * where the simulation raised its arcs and ranges. */
#include "pg_plates_internal.h"

#include <math.h>
#include <stdlib.h>

#define PG_PLATES_TRANSFORM_RATIO 0.5
#define PG_PLATES_NORMAL_RADIUS 2.5 /* texel widths */
#define PG_PLATES_DISC_MAX 64       /* a disc of radius 2.5 holds about 21 texels */

/* The texels within PG_PLATES_NORMAL_RADIUS texel widths of t's centre (t included),
 * found ring by ring through the 8-neighbourhood (which crosses face seams); returns
 * how many, at most cap. */
static int pg_plates_disc(const pg_plates_grid *g, int64_t t, double cos_r, int64_t *out, int cap) {
    const double *p = g->dir + 3 * t;
    int n = 0, head = 0;
    out[n++] = t;
    while (head < n) {
        int64_t u = out[head++];
        for (int d = 0; d < 8; d++) {
            int64_t q = g->nbr[8 * u + d];
            if (pg_vec3_dot(g->dir + 3 * q, p) < cos_r) continue;
            int seen = 0;
            for (int k = 0; k < n && !seen; k++)
                seen = out[k] == q;
            if (!seen && n < cap) out[n++] = q;
        }
    }
    return n;
}

static uint8_t pg_plates_kind_at(const pg_plates_grid *g, const uint8_t *plate,
                                 const double (*omega)[3], const uint8_t *front, double cos_r,
                                 int64_t t) {
    const double *p = g->dir + 3 * t;
    int a = plate[t], edge = 0, others = 0;
    for (int d = 0; d < 4; d++)
        edge |= plate[g->nbr[8 * t + d]] != a;
    if (!edge) return PG_PLATES_INTERIOR;
    int64_t disc[PG_PLATES_DISC_MAX];
    const int nd = pg_plates_disc(g, t, cos_r, disc, PG_PLATES_DISC_MAX);
    int at_front = 0;
    for (int d = 0; front && d < nd; d++)
        at_front |= front[disc[d]];
    double nrm[3] = {0, 0, 0}, vb[3] = {0, 0, 0}, va[3];
    for (int d = 0; d < nd; d++) {
        int64_t q = disc[d];
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
    if (at_front && vn < 0) return PG_PLATES_CONVERGENT;
    if (fabs(vn) < PG_PLATES_TRANSFORM_RATIO * vt || (vn == 0 && vt == 0))
        return PG_PLATES_TRANSFORM;
    return vn < 0 ? PG_PLATES_CONVERGENT : PG_PLATES_DIVERGENT;
}

pg_status pg_plates_classify_fronts(int64_t n, pg_cube_projection proj, const uint8_t *plate,
                                    int nplates, const double (*omega)[3], const uint8_t *front,
                                    uint8_t *kind, pg_error *err) {
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
    const double cos_r = cos(PG_PLATES_NORMAL_RADIUS * (M_PI / 2) / (double)n);
#pragma omp parallel for schedule(static)
    for (int64_t t = 0; t < g.count; t++)
        kind[t] = pg_plates_kind_at(&g, plate, omega, front, cos_r, t);
    pg_plates_grid_free(&g);
    return PG_OK;
}

pg_status pg_plates_classify(int64_t n, pg_cube_projection proj, const uint8_t *plate, int nplates,
                             const double (*omega)[3], uint8_t *kind, pg_error *err) {
    return pg_plates_classify_fronts(n, proj, plate, nplates, omega, NULL, kind, err);
}
