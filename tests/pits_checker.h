/* pits_checker.h - the pit tests' INDEPENDENT drainage checker and reference fill.
 *
 * Shares no code with src/pg_pits_*: it has its own neighbour rules (the flat grid,
 * and the cube's across-seam neighbours built from 3D geometry with only the face
 * frames of pg_cube.h), its own sink rule, and
 * decides drainage by a plain search backwards from the sinks: a cell drains if a
 * neighbour drains and lies strictly below it (or not above, for non-strict), or
 * the neighbour is a sink (entering an outlet is always allowed). */
#ifndef PITS_CHECKER_H
#define PITS_CHECKER_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "planetgen/pg_cube.h"

/* A neighbour table: nb[i*8 + j] for j < cnt[i]. */
typedef struct chk_graph {
    size_t n;
    uint32_t *nb;
    uint8_t *cnt;
} chk_graph;

static inline void chk_graph_free(chk_graph *g) {
    free(g->nb);
    free(g->cnt);
}

static inline chk_graph chk_grid_graph(int w, int h) {
    chk_graph g = {(size_t)w * h, malloc(sizeof(uint32_t) * 8 * (size_t)w * h),
                   calloc((size_t)w * h, 1)};
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int X = x + dx, Y = y + dy;
                    if ((dx || dy) && X >= 0 && Y >= 0 && X < w && Y < h)
                        g.nb[i * 8 + g.cnt[i]++] = (uint32_t)(Y * w + X);
                }
        }
    return g;
}

/* Independent neighbours: a step off the face is taken in 3D (half-texel units,
 * the face plane extended) and projected centrally back onto the cube. */
static inline chk_graph geometric_cube_graph(int N) {
    size_t n = 6 * (size_t)N * N;
    chk_graph g = {n, malloc(sizeof(uint32_t) * 8 * n), calloc(n, 1)};
    for (int f = 0; f < 6; f++) {
        int fn[3], fu[3], fv[3];
        pg_cube_face_frame(f, fn, fu, fv);
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                size_t id = ((size_t)f * N + y) * N + x;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int X = x + dx, Y = y + dy;
                        int ox = X < 0 || X >= N, oy = Y < 0 || Y >= N;
                        if ((!dx && !dy) || (ox && oy)) continue;
                        double a = 2 * X + 1 - N, b = 2 * Y + 1 - N, p[3];
                        for (int i = 0; i < 3; i++)
                            p[i] = N * fn[i] + a * fu[i] + b * fv[i];
                        int ax = 0;
                        for (int i = 1; i < 3; i++)
                            if (fabs(p[i]) > fabs(p[ax])) ax = i;
                        double s = N / fabs(p[ax]);
                        int g2 = -1, gx = 0, gy = 0;
                        for (int k = 0; k < 6; k++) {
                            int kn[3], ku[3], kv[3];
                            pg_cube_face_frame(k, kn, ku, kv);
                            if (kn[ax] * p[ax] <= 0) continue;
                            double u = s * (p[0] * ku[0] + p[1] * ku[1] + p[2] * ku[2]);
                            double v = s * (p[0] * kv[0] + p[1] * kv[1] + p[2] * kv[2]);
                            g2 = k;
                            gx = (int)floor((u + N) / 2);
                            gy = (int)floor((v + N) / 2);
                        }
                        g.nb[id * 8 + g.cnt[id]++] = (uint32_t)(((size_t)g2 * N + gy) * N + gx);
                    }
            }
    }
    return g;
}

/* Sinks: h <= sea (if has_sea), lakes, border cells (if edges, grid w x h), else the
 * lowest cell (smallest index on ties). Caller frees. */
static inline uint8_t *chk_sinks(const float *h, size_t n, int has_sea, double sea,
                                 const uint8_t *lakes, int edges, int w, int hh) {
    uint8_t *s = calloc(n, 1);
    size_t cnt = 0;
    for (size_t i = 0; i < n; i++) {
        int x = (int)(i % (size_t)(w ? w : 1)), y = (int)(i / (size_t)(w ? w : 1));
        int border = edges && (x == 0 || y == 0 || x == w - 1 || y == hh - 1);
        s[i] = (has_sea && h[i] <= sea) || (lakes && lakes[i]) || border;
        cnt += s[i];
    }
    if (!cnt) {
        size_t lo = 0;
        for (size_t i = 1; i < n; i++)
            if (h[i] < h[lo]) lo = i;
        s[lo] = 1;
    }
    return s;
}

/* Number of non-sink cells WITHOUT a descending path to a sink (0 = pit-free). */
static inline size_t chk_undrained(const chk_graph *g, const float *h, const uint8_t *sink,
                                   int strict) {
    uint8_t *ok = calloc(g->n, 1);
    uint32_t *q = malloc(sizeof(uint32_t) * g->n);
    size_t head = 0, tail = 0, bad = 0;
    for (size_t i = 0; i < g->n; i++)
        if (sink[i]) {
            ok[i] = 1;
            q[tail++] = (uint32_t)i;
        }
    while (head < tail) {
        uint32_t d = q[head++];
        for (int j = 0; j < g->cnt[d]; j++) {
            uint32_t c = g->nb[(size_t)d * 8 + j];
            if (ok[c]) continue;
            if (sink[d] || (strict ? h[d] < h[c] : h[d] <= h[c])) {
                ok[c] = 1;
                q[tail++] = c;
            }
        }
    }
    for (size_t i = 0; i < g->n; i++)
        bad += !ok[i];
    free(ok);
    free(q);
    return bad;
}

/* The minimal fill by brute force (Planchon & Darboux 2002 style iteration):
 * W = -inf on sinks (outlets take water at any height), +inf elsewhere; repeat
 * W(c) = max(h(c), min over nbrs W(n)) until nothing changes; with eps, the min is
 * raised by one ulp first (their epsilon: the minimal surface with strict descent). */
static inline float *chk_minimal_fill_eps(const chk_graph *g, const float *h, const uint8_t *sink,
                                          int eps) {
    float *W = malloc(sizeof(float) * g->n);
    for (size_t i = 0; i < g->n; i++)
        W[i] = sink[i] ? -INFINITY : INFINITY; /* outlets */
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t c = 0; c < g->n; c++) {
            if (sink[c]) continue;
            float m = INFINITY;
            for (int j = 0; j < g->cnt[c]; j++)
                m = fminf(m, W[g->nb[c * 8 + j]]);
            float v = fmaxf(h[c], eps ? nextafterf(m, INFINITY) : m);
            if (v < W[c]) {
                W[c] = v;
                changed = 1;
            }
        }
    }
    for (size_t i = 0; i < g->n; i++)
        if (sink[i]) W[i] = h[i];
    return W;
}

static inline float *chk_minimal_fill(const chk_graph *g, const float *h, const uint8_t *sink) {
    return chk_minimal_fill_eps(g, h, sink, 0);
}

#endif
