/* pg_synth_lefebvre_hoppe.c - the per-level operations of parallel texture synthesis
 * (Lefebvre & Hoppe 2005, "Parallel controllable texture synthesis", SIGGRAPH;
 * Lefebvre & Hoppe 2006, "Appearance-space texture synthesis", SIGGRAPH) with the height
 * offsets of Gain, Marais & Strasser 2015 ("Terrain sketching", I3D).
 *
 * The synthesized level S_s holds exemplar coordinates; h = 2^s is the exemplar spacing
 * of one output texel at scale s.
 *  - upsample: S_s[2p + d] = S_{s+1}[p] + floor(h (d - 1/2)), V copied (LH2005 eq. 1);
 *  - jitter:   S_s[p] += floor(h H(p) r + 1/2), H a hash of (seed, s, face, x, y) in
 *              [-1, 1]^2 (LH2005 eq. 2);
 *  - correct:  for each texel of one 2x2 parity class, the target neighbourhood N_S(p)
 *              is the appearance at the 4 diagonal positions p + D, each predicted from
 *              the 3 synthesized texels adjacent to it, p + e for e in {D, (Dx,0),
 *              (0,Dy)}, as A(S[p+e] + h (D - e)) (LH2006 section 5, "reduced runtime
 *              neighbourhood"). Candidates are the coherent ones S[p+e] - h e for e in
 *              the 3x3 neighbourhood and their k-coherence entries (LH2005 section 3.4;
 *              those cost (1 + kappa) times more: the jump penalty). For each candidate
 *              q the offset hq = mean over D of (N_S,1 - A_1(q + hD)) is the best shift
 *              of component 1, the local mean height (Gain et al.); the candidate's
 *              distance uses component 1 shifted by hq. With albedo in the appearance
 *              an unpenalised shift would let ocean-coloured patches float at any
 *              height, so a shift costs lambda * 4 * hq^2 (lambda = offset_penalty;
 *              0 is Gain's original), which shrinks hq to mean / (1 + lambda). The winner sets S[p]
 * = q and V[p] = hq (replaced, not accumulated).
 *
 * Why sub-passes are order-independent: a texel of parity class c reads only texels of
 * other classes and its own (incumbent) value, and writes only itself; so every
 * texel's result is a function of the state before the sub-pass. Tiles, threads and
 * scan order cannot change it. Halo texels across a cube seam carry an orientation:
 * offsets into them are rotated into their frame (docs/synthesis.md, "Reuse by the planet").
 * Ties keep the incumbent, then the earliest candidate, so results are exact. */
#include "pg_hash.h"
#include "pg_synth_grid_shape.h"
#include "pg_synth_internal.h"

#include <math.h>
#include <string.h>

const int pg_synth_subpass_order[4] = {0, 3, 1, 2}; /* (0,0), (1,1), (1,0), (0,1) */

uint32_t pg_synth_hash(uint64_t seed, int scale, int face, long x, long y, int salt) {
    return pg_hash_texel(seed, scale, face, x, y, salt);
}

/* Continue a move past a face edge on the neighbouring face. pg_cube_wrap's rot takes
 * vectors of the face landed on into the origin's frame, so the landed face's frame is
 * reached from the origin's by 4 - rot more quarter turns. */
static uint32_t offset_across_seam(const pg_synth_exemplar *ex, int face, int u, int v, int o) {
    const int E = ex->face_size;
    u = u < -E + 1 ? -E + 1 : (u > 2 * E - 2 ? 2 * E - 2 : u);
    v = v < -E + 1 ? -E + 1 : (v > 2 * E - 2 ? 2 * E - 2 : v);
    int rot;
    int64_t id = pg_cube_wrap(&ex->grid, face, u, v, &rot);
    int64_t per = (int64_t)E * E;
    uint32_t c = pg_synth_pack((int)(id / per), (int)(id % per % E), (int)(id % per / E));
    return pg_synth_with_orient(c, o + 4 - rot);
}

/* The hot path of pg_synth_offset, inlined into the correction loops. */
static inline uint32_t offs(const pg_synth_exemplar *ex, uint32_t c, int du, int dv) {
    const int E = ex->face_size;
    if (c & PG_SYNTH_ORIENT_MASK) return pg_synth_offset(ex, c, du, dv);
    int u = pg_synth_u(c) + du, v = pg_synth_v(c) + dv;
    if ((unsigned)u < (unsigned)E && (unsigned)v < (unsigned)E)
        return (c & 0xfc000000u) | ((uint32_t)v << 13) | (uint32_t)u;
    return pg_synth_offset(ex, c, du, dv);
}

uint32_t pg_synth_offset(const pg_synth_exemplar *ex, uint32_t c, int du, int dv) {
    const int E = ex->face_size, o = pg_synth_orient(c);
    if (o) pg_synth_orient_apply(o, &du, &dv);
    int u = pg_synth_u(c) + du, v = pg_synth_v(c) + dv;
    if (ex->torus) {
        u &= E - 1;
        v &= E - 1;
    } else if ((unsigned)u >= (unsigned)E || (unsigned)v >= (unsigned)E) {
        return offset_across_seam(ex, pg_synth_face(c), u, v, o);
    }
    return pg_synth_with_orient(pg_synth_pack(pg_synth_face(c), u, v), o);
}

uint32_t pg_synth_view_move(const pg_synth_exemplar *ex, const pg_synth_view *v, ptrdiff_t i,
                            int dx, int dy) {
    int s = v->orient ? v->orient[i] : 0;
    if (s) pg_synth_orient_apply(s, &dx, &dy);
    uint32_t q = pg_synth_offset(ex, v->S[i], dx, dy);
    return s ? pg_synth_with_orient(q, pg_synth_orient(q) + s) : q;
}

void pg_synth_orient_apply(int o, int *dx, int *dy) {
    int x = *dx, y = *dy;
    if (o & 4) x = -x;
    for (int r = 0; r < (o & 3); r++) {
        int t = x;
        x = -y;
        y = t;
    }
    *dx = x;
    *dy = y;
}

void pg_synth_params_default(pg_synth_params *p) {
    memset(p, 0, sizeof *p);
    p->seed = 1;
    p->jitter = 0.4;
    for (int i = 0; i < PG_SYNTH_MAX_LEVELS + 8; i++)
        p->jitter_level[i] = -1;
    p->passes = 2;
    p->kappa = 0.1;
    p->height_offsets = true;
    p->offset_penalty = 1.0;
    p->tile_size = 0;
}

double pg_synth_jitter_for(const pg_synth_params *p, int scale) {
    if (scale >= 0 && scale < PG_SYNTH_MAX_LEVELS + 8 && p->jitter_level[scale] >= 0)
        return p->jitter_level[scale];
    return p->jitter;
}

/* The move from a parent to its child (dx, dy) in {0,1}^2, in the output frame, for a
 * parent of orientation o: floor(h (d - 1/2)) taken in the EXEMPLAR's frame. For h >= 2
 * the half-offset is a whole number of texels and turning commutes with the floor. For
 * h = 1 it is +-1/2, and the floor must round in the exemplar's frame, where the 2 x 2
 * children are always the texels u + {-1, 0}^2 of the parent u: rounded in the output
 * frame and then turned, they were u + R_o {-1, 0}^2, a block that moves with o. Two
 * coherent parents across a turned cube seam hold different orientations, so their
 * children landed a texel apart and the finest level lost the seam's coherence
 * (docs/generate.md, "Quality": 0.53 -> 0.05 across the turned seams). */
static void child_move(int h, int o, int dx, int dy, int *mx, int *my) {
    if (h >= 2) {
        *mx = dx ? h / 2 : -h / 2, *my = dy ? h / 2 : -h / 2;
        return;
    }
    int ex = 2 * dx - 1, ey = 2 * dy - 1;         /* 2 (d - 1/2) */
    pg_synth_orient_apply(o, &ex, &ey);           /* into the exemplar's frame */
    ex = ex < 0 ? -1 : 0, ey = ey < 0 ? -1 : 0;   /* floor(+-1/2) */
    pg_synth_orient_apply((4 - o) & 3, &ex, &ey); /* back: pg_synth_offset turns it by o */
    *mx = ex, *my = ey;
}

void pg_synth_upsample(const pg_synth_exemplar *ex, int scale, const pg_synth_view *parent,
                       pg_synth_view *child) {
    const int h = 1 << scale;
    int move[4][4][2]; /* [orientation][child dy * 2 + dx] */
    for (int o = 0; o < 4; o++)
        for (int d = 0; d < 4; d++)
            child_move(h, o, d & 1, d >> 1, &move[o][d][0], &move[o][d][1]);
#pragma omp parallel for schedule(static) if (parent->w * parent->h >= 4096)
    for (int y = 0; y < parent->h; y++)
        for (int x = 0; x < parent->w; x++) {
            uint32_t c = parent->S[y * parent->stride + x];
            float vv = parent->V[y * parent->stride + x];
            const int(*m)[2] = move[pg_synth_orient(c)];
            for (int d = 0; d < 4; d++) {
                ptrdiff_t i = (2 * y + (d >> 1)) * child->stride + 2 * x + (d & 1);
                child->S[i] = pg_synth_offset(ex, c, m[d][0], m[d][1]);
                child->V[i] = vv;
            }
        }
}

void pg_synth_jitter(const pg_synth_exemplar *ex, int scale, double r, uint64_t seed,
                     pg_synth_view *v) {
    if (r <= 0) return;
    const double hr = (double)(1 << scale) * r;
#pragma omp parallel for schedule(static) if (v->w * v->h >= 4096)
    for (int y = 0; y < v->h; y++)
        for (int x = 0; x < v->w; x++) {
            long gx = v->gx + x, gy = v->gy + y;
            double hx = pg_hash_texel(seed, scale, v->face, gx, gy, 0) * (2.0 / 4294967296.0) - 1;
            double hy = pg_hash_texel(seed, scale, v->face, gx, gy, 1) * (2.0 / 4294967296.0) - 1;
            int jx = (int)floor(hr * hx + 0.5), jy = (int)floor(hr * hy + 0.5);
            uint32_t *s = &v->S[y * v->stride + x];
            *s = pg_synth_offset(ex, *s, jx, jy);
        }
}

/* ---------------------------------- correction ---------------------------------- */

#define NCAND_MAX (9 * PG_SYNTH_MAX_K)
/* The correction helpers are forced inline into correct_batch so that its AVX2 clone
 * compiles them for AVX2 too. */
#define HOT static inline __attribute__((always_inline))
#define ND 4 /* diagonal neighbours */

static const int diag[ND][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, 1}};

/* Appearance vectors as 8 float lanes. With GCC or clang the lanes are a vector type
 * (one AVX register in the AVX2 clone of correct_batch, two SSE registers otherwise), so
 * the 8 int16 components are widened and converted in two instructions instead of 8
 * scalar conversions; elsewhere they are a plain array. Every lane does the same IEEE
 * operations in the same order as a scalar loop would (the build is ISO C, so nothing
 * is contracted into a fused multiply-add), hence the same bits on any path. */
#if defined(__GNUC__) || defined(__clang__)
typedef float lanes __attribute__((vector_size(4 * PG_SYNTH_MAX_DIMS)));
typedef int16_t lanes16 __attribute__((vector_size(2 * PG_SYNTH_MAX_DIMS)));
#define LANE(v, i) ((v)[i])
#define LANES_ADD(a, b) ((a) + (b))
#define LANES_SUB(a, b) ((a) - (b))
#define LANES_MUL(a, b) ((a) * (b))
#define LANES_SCALE(a, s) ((a) * (s))
/* (vectors travel through pointers: by value they would change the ABI of the
 * non-AVX clone) */
HOT void lanes_load(lanes *r, const int16_t *a) {
    lanes16 q;
    memcpy(&q, a, sizeof q);
    *r = __builtin_convertvector(q, lanes);
}
#else
typedef struct lanes {
    float v[PG_SYNTH_MAX_DIMS];
} lanes;
#define LANE(x, i) ((x).v[i])
#define LANES_ADD(a, b) lanes_op(a, b, 0)
#define LANES_SUB(a, b) lanes_op(a, b, 1)
#define LANES_MUL(a, b) lanes_op(a, b, 2)
#define LANES_SCALE(a, s) lanes_op(a, lanes_splat(s), 2)
HOT void lanes_load(lanes *r, const int16_t *a) {
    for (int i = 0; i < PG_SYNTH_MAX_DIMS; i++)
        r->v[i] = a[i];
}
HOT lanes lanes_splat(float s) {
    lanes r;
    for (int i = 0; i < PG_SYNTH_MAX_DIMS; i++)
        r.v[i] = s;
    return r;
}
HOT lanes lanes_op(lanes a, lanes b, int op) {
    for (int i = 0; i < PG_SYNTH_MAX_DIMS; i++)
        a.v[i] = op == 0 ? a.v[i] + b.v[i] : op == 1 ? a.v[i] - b.v[i] : a.v[i] * b.v[i];
    return a;
}
#endif

/* The sum of the lanes in a fixed tree order. */
static inline float lane_sum(const lanes *a) {
    return ((LANE(*a, 0) + LANE(*a, 1)) + (LANE(*a, 2) + LANE(*a, 3))) +
           ((LANE(*a, 4) + LANE(*a, 5)) + (LANE(*a, 6) + LANE(*a, 7)));
}

typedef struct corr_ctx {
    const pg_synth_exemplar *ex;
    const int16_t *A;
    const uint32_t *K;
    int kk, h, dims;
    float m2q;   /* metres -> quantized appearance units of component 1 */
    float kappa; /* jump penalty factor - 1 */
    bool offsets;
    float lambda; /* offset penalty */
    lanes mask;   /* 1 for components 2..dims, else 0 */
    float shape;  /* grid_shape weight; 0: off (pg_synth_grid_shape.h) */
    float tanq[PG_SYNTH_SHAPE_Q];
} corr_ctx;

static inline const int16_t *app_at(const corr_ctx *c, uint32_t q) {
    return c->A + pg_synth_texel(c->ex, q) * PG_SYNTH_MAX_DIMS;
}

/* The 3x3 neighbourhood of a texel as seen from the view: coordinates, offsets,
 * orientations. Index (dy + 1) * 3 + (dx + 1). */
typedef struct nbhd {
    uint32_t S[9];
    float V[9];
    uint8_t o[9];
} nbhd;

HOT void load_nbhd(const pg_synth_view *v, int x, int y, nbhd *n) {
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            ptrdiff_t i = (ptrdiff_t)(y + dy) * v->stride + (x + dx);
            int k = (dy + 1) * 3 + (dx + 1);
            n->S[k] = v->S[i];
            n->V[k] = v->V[i];
            n->o[k] = v->orient ? v->orient[i] : 0;
        }
}

/* Coordinate of the texel at e (in the view frame) moved by h * (ox, oy) in the view
 * frame: the offset is rotated into that texel's frame first. */
HOT uint32_t move_from(const corr_ctx *c, const nbhd *n, int ex, int ey, int ox, int oy) {
    int k = (ey + 1) * 3 + (ex + 1);
    if (!n->o[k]) return offs(c->ex, n->S[k], c->h * ox, c->h * oy);
    pg_synth_orient_apply(n->o[k], &ox, &oy);
    uint32_t q = offs(c->ex, n->S[k], c->h * ox, c->h * oy);
    return pg_synth_with_orient(q, pg_synth_orient(q) + n->o[k]); /* into the view's frame */
}

/* Target neighbourhood N_S: 4 diagonal vectors, each the mean of 3 predictions whose
 * exemplar coordinates were computed (and prefetched) in tq. */
HOT void target_nbhd(const corr_ctx *c, const nbhd *n, const uint32_t tq[ND][3], lanes ns[ND]) {
    for (int d = 0; d < ND; d++) {
        const int Dx = diag[d][0], Dy = diag[d][1];
        const int vk[3] = {(Dy + 1) * 3 + (Dx + 1), 3 + (Dx + 1), (Dy + 1) * 3 + 1};
        lanes acc = {0};
        for (int j = 0; j < 3; j++) {
            lanes a;
            lanes_load(&a, app_at(c, tq[d][j]));
            acc = LANES_ADD(acc, a);
            LANE(acc, 0) += n->V[vk[j]] * c->m2q;
        }
        ns[d] = LANES_SCALE(acc, 1.0f / 3.0f);
    }
}
typedef struct cand_list {
    uint32_t q[NCAND_MAX];
    float pen[NCAND_MAX];
    int n;
} cand_list;

HOT void add_cand(cand_list *l, uint32_t q, float pen) {
    for (int i = 0; i < l->n; i++)
        if (l->q[i] == q) {
            if (pen < l->pen[i]) l->pen[i] = pen;
            return;
        }
    l->q[l->n] = q;
    l->pen[l->n++] = pen;
}

HOT void gather_candidates(const corr_ctx *c, const uint32_t q0[9], cand_list *l) {
    l->n = 0;
    for (int i = 0; i < 9; i++) {
        int seen = 0; /* a repeated coherent candidate brings nothing new (same k entries) */
        for (int j = 0; j < i && !seen; j++)
            seen = q0[j] == q0[i];
        if (seen) continue;
        add_cand(l, q0[i], 1.0f);
        const uint32_t *kc = c->K ? c->K + pg_synth_texel(c->ex, q0[i]) * c->kk : NULL;
        /* a k-coherence match looks alike in its own frame: seen through q0's turn */
        for (int j = 0; j < c->kk; j++)
            add_cand(l, pg_kcoherence_candidate(q0[i], kc[j]), 1.0f + c->kappa);
    }
}
/* Distance of candidate q to the target (times its penalty pen), with its best height
 * offset in *hoff. Returns +inf as soon as the partial sum shows it cannot be < limit:
 * the lanes only grow, the height term is >= 0 and pen > 0, so the skip is exact, and
 * it saves the random reads of the remaining diagonals of hopeless candidates. */
HOT float cand_dist(const corr_ctx *c, const lanes ns[ND], const uint32_t dq[ND], float pen,
                    float limit, float *hoff) {
    /* 8-lane distances, component 1 and unused components masked out */
    float d1[ND], mean = 0;
    lanes acc = {0};
    for (int d = 0; d < ND; d++) {
        lanes a;
        lanes_load(&a, c->A + (size_t)dq[d] * PG_SYNTH_MAX_DIMS);
        lanes diff = LANES_SUB(ns[d], a);
        d1[d] = LANE(diff, 0);
        mean += d1[d];
        lanes t = LANES_MUL(diff, c->mask);
        acc = LANES_ADD(acc, LANES_MUL(t, t));
        if (d < ND - 1 && lane_sum(&acc) * pen >= limit) return INFINITY;
    }
    float rest = lane_sum(&acc);
    /* argmin over h of sum (d1 - h)^2 + lambda ND h^2 is mean(d1) / (1 + lambda) */
    mean = c->offsets ? mean * (1.0f / ND) / (1.0f + c->lambda) : 0.0f;
    float first = c->lambda * ND * mean * mean;
    for (int d = 0; d < ND; d++)
        first += (d1[d] - mean) * (d1[d] - mean);
    *hoff = mean;
    return (first + rest) * pen;
}

/* Each candidate's penalty times 1 + w s d (pg_synth_grid_shape.h); texels away from
 * the corners (s = 0) are left alone. */
HOT void shape_penalties(const corr_ctx *c, const pg_synth_view *v, int x, int y, cand_list *l) {
    pg_synth_shape_texel t;
    if (!pg_synth_shape_texel_at(c->tanq, v->face_r, v->gx + x, v->gy + y, &t)) return;
    const float ws = c->shape * t.s;
    for (int i = 0; i < l->n; i++)
        l->pen[i] *= pg_synth_shape_factor(c->tanq, &t, ws, c->ex->face_size, l->q[i]);
}

/* Texels are corrected in small batches, phase by phase, with prefetches issued one
 * phase ahead: the work is bound by the latency of random reads of appearance vectors
 * and k-coherence entries, and a batch keeps many of them in flight (removing the
 * prefetches costs ~1.5x). Texels of one parity class never read each other, so
 * batching changes no result. */
#define BATCH 8

static inline void prefetch_app(const corr_ctx *c, uint32_t q) {
    __builtin_prefetch(app_at(c, q));
}

typedef struct texel_work {
    nbhd n;
    uint32_t tq[ND][3]; /* coordinates of the 12 target predictions */
    uint32_t q0[9];     /* coherent candidates, incumbent first */
    lanes ns[ND];
    cand_list l;
    uint32_t dq[NCAND_MAX][ND]; /* texel indices of each candidate's diagonals */
} texel_work;

/* Phase 1: coordinates of the target predictions and coherent candidates, prefetched. */
HOT void texel_coords(const corr_ctx *c, texel_work *w) {
    static const int order[9][2] = {{0, 0},   {-1, 0}, {1, 0},  {0, -1}, {0, 1},
                                    {-1, -1}, {1, -1}, {-1, 1}, {1, 1}};
    for (int d = 0; d < ND; d++) {
        const int Dx = diag[d][0], Dy = diag[d][1];
        w->tq[d][0] = move_from(c, &w->n, Dx, Dy, 0, 0);
        w->tq[d][1] = move_from(c, &w->n, Dx, 0, 0, Dy);
        w->tq[d][2] = move_from(c, &w->n, 0, Dy, Dx, 0);
        for (int j = 0; j < 3; j++)
            prefetch_app(c, w->tq[d][j]);
    }
    for (int i = 0; i < 9; i++) {
        int ex = order[i][0], ey = order[i][1];
        w->q0[i] = move_from(c, &w->n, ex, ey, -ex, -ey); /* coherent: S[p+e] - h e */
        if (c->K) __builtin_prefetch(c->K + pg_synth_texel(c->ex, w->q0[i]) * c->kk);
    }
}
/* Phase 2 end: texel indices of every candidate's diagonal neighbours, prefetched. */
HOT void candidate_diagonals(const corr_ctx *c, texel_work *w) {
    for (int i = 0; i < w->l.n; i++)
        for (int d = 0; d < ND; d++) {
            uint32_t q = offs(c->ex, w->l.q[i], c->h * diag[d][0], c->h * diag[d][1]);
            w->dq[i][d] = (uint32_t)pg_synth_texel(c->ex, q);
            __builtin_prefetch(c->A + (size_t)w->dq[i][d] * PG_SYNTH_MAX_DIMS);
        }
}
HOT void choose(const corr_ctx *c, const texel_work *w, uint32_t *S, float *V) {
    uint32_t best = w->l.q[0];
    float best_h = 0, best_d = 0;
    for (int i = 0; i < w->l.n; i++) {
        float hq = 0,
              d = cand_dist(c, w->ns, w->dq[i], w->l.pen[i], i == 0 ? INFINITY : best_d, &hq);
        if (i == 0 || d < best_d) {
            best = w->l.q[i];
            best_d = d;
            best_h = hq;
        }
    }
    *S = best;
    *V = best_h / c->m2q;
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
static void
correct_batch(const corr_ctx *c, const pg_synth_view *v, int y, int x0, int cnt) {
    texel_work w[BATCH];
    for (int i = 0; i < cnt; i++) {
        load_nbhd(v, x0 + 2 * i, y, &w[i].n);
        texel_coords(c, &w[i]);
    }
    for (int i = 0; i < cnt; i++) {
        target_nbhd(c, &w[i].n, w[i].tq, w[i].ns);
        gather_candidates(c, w[i].q0, &w[i].l);
        if (c->shape > 0) shape_penalties(c, v, x0 + 2 * i, y, &w[i].l);
        candidate_diagonals(c, &w[i]);
    }
    for (int i = 0; i < cnt; i++) {
        ptrdiff_t at = (ptrdiff_t)y * v->stride + x0 + 2 * i;
        choose(c, &w[i], &v->S[at], &v->V[at]);
    }
}

void pg_synth_correct_subpass(const pg_synth_exemplar *ex, int scale, const pg_synth_params *p,
                              int parity, pg_synth_view *v) {
    if (scale < 0 || scale >= ex->levels) return;
    corr_ctx c = {.ex = ex,
                  .A = ex->app[scale],
                  .K = ex->k > 1 ? ex->kcoh[scale] : NULL,
                  .kk = ex->k - 1,
                  .h = 1 << scale,
                  .dims = ex->dims,
                  .m2q = ex->metres_to_app / ex->app_scale[scale],
                  .kappa = (float)p->kappa,
                  .offsets = p->height_offsets,
                  .lambda = (float)p->offset_penalty};
    for (int i = 0; i < PG_SYNTH_MAX_DIMS; i++)
        LANE(c.mask, i) = i >= 1 && i < ex->dims ? 1.0f : 0.0f;
    if (p->grid_shape > 0 && !ex->torus && v->face_r > 0) {
        c.shape = (float)p->grid_shape;
        pg_synth_shape_table(c.tanq);
    }
    const int px = parity & 1, py = parity >> 1;
#pragma omp parallel for schedule(dynamic, 4) if (v->w * v->h >= 16384)
    for (int y = 0; y < v->h; y++) {
        if ((int)((v->gy + y) & 1) != py) continue;
        int x0 = (int)((v->gx & 1) != px);
        for (int x = x0; x < v->w; x += 2 * BATCH) {
            int cnt = (v->w - x + 1) / 2;
            correct_batch(&c, v, y, x, cnt < BATCH ? cnt : BATCH);
        }
    }
}
