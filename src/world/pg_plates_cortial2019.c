/* pg_plates_cortial2019.c - plate motion with subduction, collision, ridges and
 * hotspots: a simplified take on Cortial, Peytavie, Galin and Guerin 2019, "Procedural
 * Tectonic Planets" (Computer Graphics Forum 38(2), HAL hal-02136820), sections 4-5.
 *
 * REPRESENTATION. Each plate k keeps its crust in its own body frame: a cube field
 * (alive, crust type, age, relief) that does not move, and an orientation matrix R_k,
 * advanced each step by the rotation of angle |omega_k| dt about its Euler pole, so
 * body texel b sits at world direction R_k b. Keeping the crust in body frames means a plate never
 * loses resolution to resampling however small a step's motion (a few tens of km against 140 km
 * texels): positions are exact rotations, only the lookups are nearest-texel.
 *
 *     body[k].alive[b]   crust present at body texel b of plate k
 *     body[k].crust[b]   oceanic or continental
 *     body[k].age[b]     Myr
 *     body[k].relief[b]  tectonic uplift in m, added to the crust's base elevation
 *
 * ONE STEP (t -> t + dt), each stage computing every output from inputs only:
 *  1. World gather (semi-Lagrangian, parallel over world texels): plate k covers world
 *     texel p if its body texel nearest to R_k^T p is alive. Several candidates
 *     overlap: continental crust overrides oceanic (oceanic subducts), younger oceanic
 *     overrides older (older is denser), and continent against continent is a
 *     collision won by the lower plate id (a fixed order, so a front does not flicker).
 *     The winner's texel is a subduction front (overriding continent or ocean) or a
 *     collision front.
 *  2. Gaps (no candidate) are divergence: new oceanic crust of age 0, given to a
 *     neighbouring plate by a synchronous flood (each round, a gap texel takes the
 *     lowest plate id among labelled edge neighbours), so a gap splits between its
 *     two sides.
 *  3. Uplift rates from the fronts, by distance d along the overriding plate
 *     (Dijkstra over texels of the same plate): subduction raises the overriding side
 *     with the profile (d/d0) exp(1 - d/d0), d0 = 150 km, peaking at the arc (Cortial
 *     et al.'s distance profile f(d), here in closed form); collision raises a plateau
 *     of full rate to 250 km tapering to 0 at 700 km (their orogeny + plateau).
 *  4. Body update (parallel over body texels): crust now under another plate's crust
 *     is removed (subducted, or consumed by the collision whose uplift stands for its
 *     thickening); crust on top ages by dt, gains uplift and decays towards its base
 *     level (erosion and thermal subsidence of arcs, e-folding 50 Myr on continents,
 *     30 Myr in oceans); crust over a fixed hotspot gains volcanic relief, so moving
 *     plates leave chains.
 *  5. New crust from step 2 is written into its plate's body field (serial, in texel
 *     order), and small holes in each body field left by nearest-texel sampling are
 *     closed (a dead texel with >= 6 of 8 alive neighbours takes their mean).
 *  6. Collision slows the collider: the first time continental crust of plate k is
 *     overridden by continental crust of plate j, omega_k becomes
 *     omega_j + 0.1 (omega_k - omega_j), so k keeps converging slowly (the front stays
 *     convergent and keeps rising, as India still pushes into Asia) without consuming
 *     its whole continent (a stand-in for Cortial et al.'s terrane transfer).
 * A plate reduced below 0.15% of the texels is protected: it overrides any other and
 * loses no crust, so no plate disappears (a microplate riding along).
 * After the last step a final world gather gives the world state.
 *
 * SIMPLIFICATIONS against the paper: fixed Euler poles except for the collision
 * slow-down (no plate rifting, no terrane transfer), uplift rates independent of the convergence
 * speed, no slab pull, and no amplification here (that is the synthesis stage's job). */
#include "pg_plates_internal.h"

#include <stdlib.h>
#include <string.h>

#define PG_PLATES_GAP 255
#define PG_PLATES_SUB_D0_KM 150.0
#define PG_PLATES_SUB_RATE 120.0 /* m/Myr at the profile's peak, continent overriding */
#define PG_PLATES_ARC_RATE 110.0 /* m/Myr, ocean overriding ocean: island arcs */
#define PG_PLATES_COL_RATE 180.0 /* m/Myr, collision plateau */
#define PG_PLATES_COL_FLAT_KM 250.0
#define PG_PLATES_COL_END_KM 700.0
#define PG_PLATES_TAU_CONT 50.0
#define PG_PLATES_TAU_OCEAN 30.0
#define PG_PLATES_HOT_RATE 1100.0 /* m/Myr at a hotspot's centre */
#define PG_PLATES_HOT_KM 130.0
#define PG_PLATES_SLOWDOWN 0.1
#define PG_PLATES_PROTECT 0.0015 /* share of texels below which a plate is protected */

enum { PG_PLATES_EV_NONE, PG_PLATES_EV_ANDEAN, PG_PLATES_EV_ARC, PG_PLATES_EV_COLLISION };
#define PG_PLATES_NKINDS (PG_PLATES_EV_COLLISION - PG_PLATES_EV_ANDEAN + 1) /* kinds of front */

typedef struct pg_plates_body {
    uint8_t *alive, *crust;
    float *age, *relief;
} pg_plates_body;

typedef struct pg_plates_sim {
    const pg_plates_grid *g;
    pg_plates_world *w;
    int np;
    pg_plates_body *body;
    double rot[PG_PLATES_MAX][9]; /* body -> world, row-major */
    uint8_t protect[PG_PLATES_MAX];
    uint8_t slowed[PG_PLATES_MAX][PG_PLATES_MAX];
    int64_t *wbody; /* world texel -> winner's body texel */
    uint8_t *ev;    /* world texel -> front event */
    uint8_t *loser; /* world texel -> a continental loser of a collision, or GAP */
    uint8_t *fresh; /* world texel -> new crust this step */
    uint8_t *mark;  /* scratch, NKINDS count (a slot per kind of front in the uplift) */
    uint8_t *snap;  /* alive flags of every plate before the update, np * count */
    uint8_t *fill;  /* closing marks, np * count */
    float *dist;    /* NKINDS count, as mark */
    float *uplift;
    /* Each plate's cap for the gather: world direction cap[k] and cos_reach[k] such that
     * a world texel p with p . cap[k] < cos_reach[k] cannot see an alive texel of k
     * (pg_plates_caps). */
    double cap[PG_PLATES_MAX][3];
    double cos_reach[PG_PLATES_MAX];
    bool caps; /* use them (pg_plates_generate_uncapped turns them off) */
} pg_plates_sim;

static void pg_plates_to_body(const pg_plates_sim *m, int k, const double p[3], double out[3]) {
    const double *r = m->rot[k];
    for (int i = 0; i < 3; i++)
        out[i] = r[i] * p[0] + r[3 + i] * p[1] + r[6 + i] * p[2];
}

static void pg_plates_to_world(const pg_plates_sim *m, int k, const double b[3], double out[3]) {
    const double *r = m->rot[k];
    for (int i = 0; i < 3; i++)
        out[i] = r[3 * i] * b[0] + r[3 * i + 1] * b[1] + r[3 * i + 2] * b[2];
}

/* R_k <- Rot(omega_k dt) R_k, column by column. */
static void pg_plates_advance(pg_plates_sim *m, int k, double dt) {
    const double *om = m->w->plates[k].omega;
    double rate = sqrt(pg_vec3_dot(om, om));
    if (rate == 0) return;
    double axis[3] = {om[0] / rate, om[1] / rate, om[2] / rate};
    for (int c = 0; c < 3; c++) {
        double col[3] = {m->rot[k][c], m->rot[k][3 + c], m->rot[k][6 + c]}, out[3];
        pg_plates_rotate(axis, rate * dt, col, out);
        for (int i = 0; i < 3; i++)
            m->rot[k][3 * i + c] = out[i];
    }
}

/* Does candidate (k, b) override the current winner (w, wb)? */
static int pg_plates_overrides(const pg_plates_sim *m, int k, int64_t b, int w, int64_t wb) {
    const pg_plates_body *K = &m->body[k], *W = &m->body[w];
    if (m->protect[k] != m->protect[w]) return m->protect[k];
    if (K->crust[b] != W->crust[wb]) return K->crust[b] == PG_PLATES_CONTINENTAL;
    if (K->crust[b] == PG_PLATES_OCEANIC && K->age[b] != W->age[wb]) return K->age[b] < W->age[wb];
    return k < w;
}

/* The caps that let the gather skip plates far from a world texel. Plate k's alive body
 * texels lie within angle theta of their mean direction c. The body texel nearest to
 * R_k^T p is the one whose cell contains that direction, so its centre lies within the
 * grid's texel reach rho of it: if angle(p, R_k c) > theta + rho, no alive texel of k is
 * nearest, and the lookup can be skipped without changing any result. The test uses
 * twice rho, which also covers cells whose edges bulge past their corners and the
 * rounding of the dot products. A plate with no alive texel gets an empty cap. */
static void pg_plates_caps(pg_plates_sim *m) {
    const pg_plates_grid *g = m->g;
#pragma omp parallel for schedule(dynamic, 1)
    for (int k = 0; k < m->np; k++) {
        const uint8_t *alive = m->body[k].alive;
        double c[3] = {0, 0, 0};
        int64_t nalive = 0;
        for (int64_t b = 0; b < g->count; b++)
            if (alive[b]) {
                nalive++;
                for (int i = 0; i < 3; i++)
                    c[i] += g->dir[3 * b + i];
            }
        double len = sqrt(pg_vec3_dot(c, c)), lo = -1; /* crust whose directions cancel: no cap */
        if (len > 0) {
            lo = 1;
            for (int i = 0; i < 3; i++)
                c[i] /= len;
            for (int64_t b = 0; b < g->count; b++)
                if (alive[b]) {
                    double d = pg_vec3_dot(c, g->dir + 3 * b);
                    lo = d < lo ? d : lo;
                }
        } else {
            c[0] = 1;
        }
        double reach = acos(lo > 1 ? 1 : (lo < -1 ? -1 : lo)) + 2 * g->texel_reach;
        m->cos_reach[k] = !m->caps      ? -2
                          : nalive == 0 ? 2
                                        : (reach >= PG_PLATES_PI ? -2 : cos(reach));
        pg_plates_to_world(m, k, c, m->cap[k]);
    }
}

static void pg_plates_gather(pg_plates_sim *m, pg_plates_state *s) {
    const pg_plates_grid *g = m->g;
    pg_plates_caps(m);
#pragma omp parallel for schedule(static)
    for (int64_t p = 0; p < g->count; p++) {
        int win = -1, lost_ocean = 0;
        int64_t wb = -1;
        uint8_t lost_cont = PG_PLATES_GAP;
        for (int k = 0; k < m->np; k++) {
            if (pg_vec3_dot(g->dir + 3 * p, m->cap[k]) < m->cos_reach[k]) continue;
            double q[3];
            pg_plates_to_body(m, k, g->dir + 3 * p, q);
            int64_t b = pg_plates_grid_nearest(g, q);
            if (!m->body[k].alive[b]) continue;
            int lk = k; /* the loser of this comparison */
            int64_t lb = b;
            if (win < 0 || pg_plates_overrides(m, k, b, win, wb)) {
                lk = win;
                lb = wb;
                win = k;
                wb = b;
            }
            if (lk < 0) continue;
            if (m->body[lk].crust[lb] == PG_PLATES_OCEANIC)
                lost_ocean = 1;
            else if (lost_cont == PG_PLATES_GAP)
                lost_cont = (uint8_t)lk;
        }
        m->fresh[p] = win < 0;
        m->wbody[p] = wb;
        m->ev[p] = PG_PLATES_EV_NONE;
        m->loser[p] = PG_PLATES_GAP;
        if (win < 0) {
            s->plate[p] = PG_PLATES_GAP;
            s->crust[p] = PG_PLATES_OCEANIC;
            s->age[p] = 0;
            s->relief[p] = 0;
            continue;
        }
        const pg_plates_body *B = &m->body[win];
        s->plate[p] = (uint8_t)win;
        s->crust[p] = B->crust[wb];
        s->age[p] = B->age[wb];
        s->relief[p] = B->relief[wb];
        if (lost_cont != PG_PLATES_GAP && B->crust[wb] == PG_PLATES_CONTINENTAL) {
            m->ev[p] = PG_PLATES_EV_COLLISION;
            m->loser[p] = lost_cont;
        } else if (lost_ocean || lost_cont != PG_PLATES_GAP) {
            m->ev[p] =
                B->crust[wb] == PG_PLATES_CONTINENTAL ? PG_PLATES_EV_ANDEAN : PG_PLATES_EV_ARC;
        }
    }
}

/* Step 2: synchronous flood of gap texels from their labelled edge neighbours. */
static void pg_plates_fill_gaps(pg_plates_sim *m, uint8_t *plate) {
    const pg_plates_grid *g = m->g;
    for (int changed = 1; changed;) {
        changed = 0;
#pragma omp parallel for schedule(static) reduction(| : changed)
        for (int64_t p = 0; p < g->count; p++) {
            uint8_t best = PG_PLATES_GAP;
            if (plate[p] == PG_PLATES_GAP)
                for (int d = 0; d < 4; d++) {
                    uint8_t q = plate[g->nbr[8 * p + d]];
                    if (q != PG_PLATES_GAP && (best == PG_PLATES_GAP || q < best)) best = q;
                }
            m->mark[p] = best;
            changed |= best != PG_PLATES_GAP;
        }
        for (int64_t p = 0; p < g->count; p++)
            if (plate[p] == PG_PLATES_GAP) plate[p] = m->mark[p];
    }
}

static double pg_plates_sub_profile(double d) {
    double x = d / PG_PLATES_SUB_D0_KM;
    return x * exp(1 - x);
}

static double pg_plates_col_profile(double d) {
    if (d <= PG_PLATES_COL_FLAT_KM) return 1;
    if (d >= PG_PLATES_COL_END_KM) return 0;
    double s = (d - PG_PLATES_COL_FLAT_KM) / (PG_PLATES_COL_END_KM - PG_PLATES_COL_FLAT_KM);
    return (1 - s * s) * (1 - s * s);
}

/* Step 3: uplift rate (m/Myr) per world texel. The distances to the three kinds of
 * front are three independent floods (serial each), so they run at once, into their
 * own slots of mark and dist; the uplift takes the maximum over kinds, in kind order. */
static pg_status pg_plates_uplift(pg_plates_sim *m, const pg_plates_state *s, pg_error *err) {
    const pg_plates_grid *g = m->g;
    const int64_t c = g->count;
    memset(m->uplift, 0, sizeof(float) * (size_t)c);
    int any[PG_PLATES_NKINDS] = {0};
    for (int j = 0; j < PG_PLATES_NKINDS; j++)
        for (int64_t p = 0; p < c; p++)
            any[j] |= (m->mark[j * c + p] = m->ev[p] == PG_PLATES_EV_ANDEAN + j);
    pg_status sk[PG_PLATES_NKINDS] = {PG_OK};
    pg_error e[PG_PLATES_NKINDS];
    memset(e, 0, sizeof e);
#pragma omp parallel for schedule(dynamic, 1)
    for (int j = 0; j < PG_PLATES_NKINDS; j++)
        if (any[j])
            sk[j] = pg_plates_grid_distance(g, m->mark + j * c, s->plate, m->dist + j * c, &e[j]);
    for (int j = 0; j < PG_PLATES_NKINDS; j++)
        if (sk[j] != PG_OK) return pg_error_set(err, sk[j], "%s", e[j].msg);
    for (int j = 0; j < PG_PLATES_NKINDS; j++) {
        if (!any[j]) continue;
        const int kind = PG_PLATES_EV_ANDEAN + j;
        const float *dist = m->dist + j * c;
#pragma omp parallel for schedule(static)
        for (int64_t p = 0; p < c; p++) {
            double d = dist[p];
            if (!isfinite(d)) continue;
            double r = kind == PG_PLATES_EV_COLLISION
                           ? PG_PLATES_COL_RATE * pg_plates_col_profile(d)
                       : kind == PG_PLATES_EV_ARC ? PG_PLATES_ARC_RATE * pg_plates_sub_profile(d)
                                                  : PG_PLATES_SUB_RATE * pg_plates_sub_profile(d);
            m->uplift[p] = (float)fmax(m->uplift[p], r);
        }
    }
    return PG_OK;
}

/* A hotspot reaches 3 PG_PLATES_HOT_KM. Most body texels are far from every hotspot, so a
 * dot product against cos_far (the cosine of a slightly larger angle, less a margin for
 * the dot product's rounding; -2 when that angle reaches pi) skips the exact angle (an
 * atan2) where it cannot be in reach; the texels it keeps get the same figure as
 * without it. */
static double pg_plates_hotspot(const pg_plates_world *w, const double p[3], double radius_km,
                                double cos_far) {
    double r = 0;
    for (int h = 0; h < w->nhotspots; h++) {
        if (pg_vec3_dot(p, w->hotspot_dir[h]) < cos_far) continue;
        double d = pg_plates_angle(p, w->hotspot_dir[h]) * radius_km / PG_PLATES_HOT_KM;
        if (d < 3) r += exp(-d * d);
    }
    return r * PG_PLATES_HOT_RATE;
}

/* Step 4, all plates in one parallel loop over (plate, body texel). */
static void pg_plates_update_bodies(pg_plates_sim *m, double dt, const pg_plates_state *s) {
    const pg_plates_grid *g = m->g;
    int64_t c = g->count;
    for (int k = 0; k < m->np; k++)
        memcpy(m->snap + k * c, m->body[k].alive, (size_t)c);
    double keep_c = exp(-dt / PG_PLATES_TAU_CONT), keep_o = exp(-dt / PG_PLATES_TAU_OCEAN);
    const double far = 1.01 * 3 * PG_PLATES_HOT_KM / g->radius_km,
                 cos_far = far >= PG_PLATES_PI ? -2 : cos(far) - 1e-12;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < m->np * c; i++) {
        int k = (int)(i / c);
        int64_t b = i % c;
        const uint8_t *snap = m->snap + k * c;
        pg_plates_body *B = &m->body[k];
        if (!snap[b]) continue;
        double q[3], r[3];
        pg_plates_to_world(m, k, g->dir + 3 * b, q);
        int64_t p = pg_plates_grid_nearest(g, q);
        if (m->fresh[p]) continue;
        if (s->plate[p] != k) {
            /* Removed only if this plate's crust really was a losing candidate at p
             * (subducted, or consumed by a collision); otherwise b sits at the plate's
             * edge and p merely maps back onto a dead neighbour of b. */
            pg_plates_to_body(m, k, g->dir + 3 * p, r);
            if (!m->protect[k] && snap[pg_plates_grid_nearest(g, r)]) B->alive[b] = 0;
            continue;
        }
        int cont = B->crust[b] == PG_PLATES_CONTINENTAL;
        double hot = pg_plates_hotspot(m->w, q, g->radius_km, cos_far) * (cont ? 0.25 : 1.0);
        B->relief[b] = (float)(B->relief[b] * (cont ? keep_c : keep_o) + (m->uplift[p] + hot) * dt);
        B->age[b] += (float)dt;
    }
}

/* Step 5a: new crust into body fields (serial: scattered writes in texel order). */
static void pg_plates_new_crust(pg_plates_sim *m, const pg_plates_state *s) {
    const pg_plates_grid *g = m->g;
    for (int64_t p = 0; p < g->count; p++) {
        if (!m->fresh[p] || s->plate[p] == PG_PLATES_GAP) continue;
        int k = s->plate[p];
        double q[3];
        pg_plates_to_body(m, k, g->dir + 3 * p, q);
        int64_t b = pg_plates_grid_nearest(g, q);
        pg_plates_body *B = &m->body[k];
        if (B->alive[b]) continue;
        B->alive[b] = 1;
        B->crust[b] = PG_PLATES_OCEANIC;
        B->age[b] = 0;
        B->relief[b] = 0;
    }
}

/* Step 5b: close sampling holes of every body field: a dead texel with >= 6 of 8 alive
 * neighbours takes their mean age and relief and their majority crust. */
static void pg_plates_close(pg_plates_sim *m) {
    const pg_plates_grid *g = m->g;
    int64_t c = g->count;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < m->np * c; i++) {
        const pg_plates_body *B = &m->body[i / c];
        int64_t b = i % c;
        int alive = 0;
        if (!B->alive[b])
            for (int d = 0; d < 8; d++)
                alive += B->alive[g->nbr[8 * b + d]];
        m->fill[i] = alive >= 6;
    }
    for (int64_t i = 0; i < m->np * c; i++) {
        if (!m->fill[i]) continue;
        pg_plates_body *B = &m->body[i / c];
        int64_t b = i % c;
        double age = 0, relief = 0;
        int n = 0, cont = 0;
        for (int d = 0; d < 8; d++) {
            int64_t q = g->nbr[8 * b + d];
            if (!B->alive[q] || m->fill[i - b + q]) continue;
            age += B->age[q];
            relief += B->relief[q];
            cont += B->crust[q] == PG_PLATES_CONTINENTAL;
            n++;
        }
        if (n == 0) continue;
        /* writes go to texels no other fill reads (filled texels are skipped above) */
        B->alive[b] = 1;
        B->age[b] = (float)(age / n);
        B->relief[b] = (float)(relief / n);
        B->crust[b] = 2 * cont > n ? PG_PLATES_CONTINENTAL : PG_PLATES_OCEANIC;
    }
}

/* Step 6: slow a continent's plate down on its first collision with another. */
static void pg_plates_collide(pg_plates_sim *m, const pg_plates_state *s) {
    const pg_plates_grid *g = m->g;
    for (int64_t p = 0; p < g->count; p++) {
        if (m->ev[p] != PG_PLATES_EV_COLLISION) continue;
        int k = m->loser[p], j = s->plate[p];
        if (j == PG_PLATES_GAP || k == j || m->slowed[k][j]) continue;
        m->slowed[k][j] = m->slowed[j][k] = 1;
        pg_plates_plate *K = &m->w->plates[k];
        const pg_plates_plate *J = &m->w->plates[j];
        for (int i = 0; i < 3; i++)
            K->omega[i] = J->omega[i] + PG_PLATES_SLOWDOWN * (K->omega[i] - J->omega[i]);
        K->speed_cm_yr = sqrt(pg_vec3_dot(K->omega, K->omega)) * g->radius_km / 10;
    }
}

static void pg_plates_protect(pg_plates_sim *m) {
    int64_t c = m->g->count;
    for (int k = 0; k < m->np; k++) {
        int64_t alive = 0;
        for (int64_t b = 0; b < c; b++)
            alive += m->body[k].alive[b];
        m->protect[k] = (double)alive < PG_PLATES_PROTECT * (double)c;
    }
}

static pg_status pg_plates_sim_alloc(pg_plates_sim *m, pg_error *err) {
    size_t c = (size_t)m->g->count, np = (size_t)m->np;
    m->body = calloc(np, sizeof *m->body);
    m->wbody = malloc(sizeof(int64_t) * c);
    m->ev = malloc(c);
    m->loser = malloc(c);
    m->fresh = malloc(c);
    m->mark = malloc(PG_PLATES_NKINDS * c);
    m->snap = malloc(np * c);
    m->fill = malloc(np * c);
    m->dist = malloc(sizeof(float) * PG_PLATES_NKINDS * c);
    m->uplift = malloc(sizeof(float) * c);
    int ok = m->body && m->wbody && m->ev && m->loser && m->fresh && m->mark && m->snap &&
             m->fill && m->dist && m->uplift;
    for (int k = 0; ok && k < m->np; k++) {
        pg_plates_body *B = &m->body[k];
        B->alive = malloc(c);
        B->crust = malloc(c);
        B->age = malloc(sizeof(float) * c);
        B->relief = malloc(sizeof(float) * c);
        ok = B->alive && B->crust && B->age && B->relief;
    }
    return ok ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "plates: out of memory for plate crust");
}

static void pg_plates_sim_free(pg_plates_sim *m) {
    for (int k = 0; m->body && k < m->np; k++) {
        free(m->body[k].alive);
        free(m->body[k].crust);
        free(m->body[k].age);
        free(m->body[k].relief);
    }
    free(m->body);
    free(m->wbody);
    free(m->ev);
    free(m->loser);
    free(m->fresh);
    free(m->mark);
    free(m->snap);
    free(m->fill);
    free(m->dist);
    free(m->uplift);
}

pg_status pg_plates_simulate(const pg_plates_params *p, const pg_plates_grid *g, pg_plates_world *w,
                             pg_plates_state *s, bool caps, pg_error *err) {
    pg_plates_sim m = {.g = g, .w = w, .np = p->plates, .caps = caps};
    pg_status st = pg_plates_sim_alloc(&m, err);
    if (st != PG_OK) goto done;
    for (int k = 0; k < m.np; k++) {
        for (int i = 0; i < 9; i++)
            m.rot[k][i] = i % 4 == 0;
        pg_plates_body *B = &m.body[k];
        for (int64_t t = 0; t < g->count; t++) {
            B->alive[t] = s->plate[t] == k;
            B->crust[t] = s->crust[t];
            B->age[t] = s->age[t];
            B->relief[t] = s->relief[t];
        }
    }
    double dt = p->step_myr;
    for (int step = 1; step <= p->steps && st == PG_OK; step++) {
        pg_plates_protect(&m);
        for (int k = 0; k < m.np; k++)
            pg_plates_advance(&m, k, dt);
        pg_plates_gather(&m, s);
        pg_plates_fill_gaps(&m, s->plate);
        st = pg_plates_uplift(&m, s, err);
        if (st != PG_OK) break;
        pg_plates_update_bodies(&m, dt, s);
        pg_plates_new_crust(&m, s);
        pg_plates_close(&m);
        pg_plates_collide(&m, s);
    }
    if (st == PG_OK && p->steps > 0) {
        pg_plates_protect(&m);
        pg_plates_gather(&m, s);
        pg_plates_fill_gaps(&m, s->plate);
    }
done:
    pg_plates_sim_free(&m);
    return st;
}
