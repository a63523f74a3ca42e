/* pg_inspect_seams.c - the seam statistics (see pg_inspect.h, docs/inspect.md "Seams").
 *
 * The idea: a seam is invisible when neighbours across it differ no more than
 * neighbours elsewhere. So we visit every 4-adjacent pair once per direction, sort it
 * into "straddles a tile edge", "straddles a face seam" or "inside a tile", and compare
 * the mean absolute differences. Face-seam pairs are found through pg_cube_wrap, the
 * same adjacency map the synthesis uses, so the statistic checks exactly the
 * neighbourhoods that synthesis stitched. Each face visits all four of its edges, so
 * every seam pair is counted twice (once from each side): the mean is unchanged.
 *
 * The same sums by the face across each seam give each of the 12 seams its own
 * figures, and the worst seam names where a failing pooled figure comes from.
 *
 * Sums run per face in parallel into per-face accumulators, then add up in face
 * order, so the result does not depend on the thread count. */
#include "planetgen/pg_inspect.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { KIND_INTERIOR, KIND_TILE, KIND_FACE, KIND_NEAR_FACE, KIND_COUNT };

/* The local control of a face-seam pair: the pairs across the seam's direction at
 * depths SEAM_NEAR_FROM .. SEAM_NEAR_FROM + SEAM_NEAR_COUNT inside the face (depth 0
 * is the edge texel), on both sides (each side visits its own). */
#define SEAM_NEAR_FROM 1
#define SEAM_NEAR_COUNT 8

typedef struct seam_acc {
    double sum[KIND_COUNT];
    uint64_t count[KIND_COUNT];
    /* the face-seam and near pairs again, by the face across the seam: one face's
     * accumulator holds its side of each of its four seams */
    double seam_sum[PG_CUBE_NFACES], near_sum[PG_CUBE_NFACES];
    uint64_t seam_count[PG_CUBE_NFACES], near_count[PG_CUBE_NFACES];
} seam_acc;

static double texel_delta(const float *a, const float *b, int ch) {
    double s = 0;
    for (int c = 0; c < ch; c++)
        s += fabs((double)a[c] - b[c]);
    return s / ch;
}

static void add(seam_acc *a, int kind, double d) {
    a->sum[kind] += d;
    a->count[kind]++;
}

/* Pairs inside face f: right and up neighbours, classified by tile boundaries. */
static void face_pairs(int64_t n, int S, const float *face, int ch, seam_acc *acc) {
    for (int64_t y = 0; y < n; y++) {
        for (int64_t x = 0; x < n; x++) {
            const float *p = face + (size_t)(y * n + x) * ch;
            if (x + 1 < n)
                add(acc, (x + 1) % S ? KIND_INTERIOR : KIND_TILE, texel_delta(p, p + ch, ch));
            if (y + 1 < n)
                add(acc, (y + 1) % S ? KIND_INTERIOR : KIND_TILE,
                    texel_delta(p, p + (size_t)n * ch, ch));
        }
    }
}

/* Pairs across the four edges of face f, through the seam map. */
static void seam_pairs(const pg_cube_grid *g, int f, const float *const faces[PG_CUBE_NFACES],
                       int ch, seam_acc *acc) {
    int64_t n = g->n;
    for (int64_t k = 0; k < n; k++) {
        int64_t in[4][2] = {{n - 1, k}, {0, k}, {k, n - 1}, {k, 0}};
        int64_t out[4][2] = {{n, k}, {-1, k}, {k, n}, {k, -1}};
        for (int e = 0; e < 4; e++) {
            int rot;
            int64_t id = pg_cube_wrap(g, f, out[e][0], out[e][1], &rot);
            int64_t nf = id / (n * n), rest = id % (n * n);
            const float *a = faces[f] + (size_t)(in[e][1] * n + in[e][0]) * ch;
            const float *b = faces[nf] + (size_t)rest * ch;
            const double dab = texel_delta(a, b, ch);
            add(acc, KIND_FACE, dab);
            acc->seam_sum[nf] += dab;
            acc->seam_count[nf]++;
            /* inward, one texel: minus the outward step */
            const ptrdiff_t step =
                -(ptrdiff_t)((out[e][1] - in[e][1]) * n + (out[e][0] - in[e][0]));
            for (int64_t d = SEAM_NEAR_FROM; d < SEAM_NEAR_FROM + SEAM_NEAR_COUNT && d + 1 < n;
                 d++) {
                const float *p = a + step * d * ch;
                const double dn = texel_delta(p, p + step * ch, ch);
                add(acc, KIND_NEAR_FACE, dn);
                acc->near_sum[nf] += dn;
                acc->near_count[nf]++;
            }
        }
    }
}

static double mean_of(double s, uint64_t c) {
    return c ? s / (double)c : NAN;
}

/* The seam with the largest ratio of its own against within (the mean of the pairs
 * inside faces): both sides' sums of each face pair, in face order. */
static void no_seam(pg_inspect_seam_stat *out) {
    out->worst_seam_ratio = out->worst_seam_ratio_local = NAN;
    out->worst_seam_faces[0] = out->worst_seam_faces[1] = -1;
}

static void worst_seam(const seam_acc acc[PG_CUBE_NFACES], double within,
                       pg_inspect_seam_stat *out) {
    no_seam(out);
    for (int a = 0; a < PG_CUBE_NFACES; a++)
        for (int b = a + 1; b < PG_CUBE_NFACES; b++) {
            const uint64_t c = acc[a].seam_count[b] + acc[b].seam_count[a];
            if (!c || !(within > 0)) continue;
            const double mean = (acc[a].seam_sum[b] + acc[b].seam_sum[a]) / (double)c;
            const double ratio = mean / within;
            if (!(ratio > out->worst_seam_ratio) && !isnan(out->worst_seam_ratio)) continue;
            const double near = mean_of(acc[a].near_sum[b] + acc[b].near_sum[a],
                                        acc[a].near_count[b] + acc[b].near_count[a]);
            out->worst_seam_ratio = ratio;
            out->worst_seam_ratio_local = near > 0 ? mean / near : NAN;
            out->worst_seam_faces[0] = a, out->worst_seam_faces[1] = b;
        }
}

pg_status pg_inspect_seam_field(int64_t n, int tile_size, const float *const faces[PG_CUBE_NFACES],
                                int ch, pg_inspect_seam_stat *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    no_seam(out); /* until the sums are in */
    if (n < 2 || tile_size < 1 || n % tile_size || ch < 1)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "seams: face size %lld is not a multiple of tile size %d", (long long)n,
                            tile_size);
    pg_cube_grid g;
    pg_status st =
        pg_cube_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, (int)(n / tile_size), tile_size, err);
    if (st != PG_OK) return st;
    seam_acc acc[PG_CUBE_NFACES];
    memset(acc, 0, sizeof acc);
#pragma omp parallel for schedule(dynamic, 1)
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        seam_acc local; /* accumulate privately: neighbouring acc[] share cache lines */
        memset(&local, 0, sizeof local);
        face_pairs(n, tile_size, faces[f], ch, &local);
        seam_pairs(&g, f, faces, ch, &local);
        acc[f] = local;
    }
    seam_acc t;
    memset(&t, 0, sizeof t);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int k = 0; k < KIND_COUNT; k++) {
            t.sum[k] += acc[f].sum[k];
            t.count[k] += acc[f].count[k];
        }
    out->seam_pairs = t.count[KIND_TILE] + t.count[KIND_FACE];
    out->interior_pairs = t.count[KIND_INTERIOR];
    out->seam_mean = mean_of(t.sum[KIND_TILE] + t.sum[KIND_FACE], out->seam_pairs);
    out->interior_mean = mean_of(t.sum[KIND_INTERIOR], out->interior_pairs);
    out->tile_edge_mean = mean_of(t.sum[KIND_TILE], t.count[KIND_TILE]);
    out->face_seam_mean = mean_of(t.sum[KIND_FACE], t.count[KIND_FACE]);
    out->ratio = out->interior_mean > 0 ? out->seam_mean / out->interior_mean : NAN;
    out->face_seam_pairs = t.count[KIND_FACE];
    out->within_face_mean = mean_of(t.sum[KIND_INTERIOR] + t.sum[KIND_TILE],
                                    t.count[KIND_INTERIOR] + t.count[KIND_TILE]);
    out->near_face_seam_mean = mean_of(t.sum[KIND_NEAR_FACE], t.count[KIND_NEAR_FACE]);
    out->face_seam_ratio =
        out->within_face_mean > 0 ? out->face_seam_mean / out->within_face_mean : NAN;
    out->face_seam_ratio_local =
        out->near_face_seam_mean > 0 ? out->face_seam_mean / out->near_face_seam_mean : NAN;
    out->tile_edge_ratio = out->interior_mean > 0 && t.count[KIND_TILE]
                               ? out->tile_edge_mean / out->interior_mean
                               : NAN;
    worst_seam(acc, out->within_face_mean, out);
    return PG_OK;
}

pg_status pg_inspect_seams_compute(const pg_planet *p, pg_inspect_seams *out, pg_error *err) {
    memset(out, 0, sizeof *out);
    no_seam(&out->height), no_seam(&out->albedo);
    const float *h[PG_CUBE_NFACES], *a[PG_CUBE_NFACES];
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        h[f] = p->height[f];
        a[f] = p->albedo[f];
    }
    pg_status st = pg_inspect_seam_field(p->n, p->tile_size, h, 1, &out->height, err);
    if (st == PG_OK) st = pg_inspect_seam_field(p->n, p->tile_size, a, 3, &out->albedo, err);
    out->ratio = fmax(out->height.ratio, out->albedo.ratio);
    out->face_seam_ratio = fmax(out->height.face_seam_ratio, out->albedo.face_seam_ratio);
    out->face_seam_ratio_local =
        fmax(out->height.face_seam_ratio_local, out->albedo.face_seam_ratio_local);
    out->tile_edge_ratio = fmax(out->height.tile_edge_ratio, out->albedo.tile_edge_ratio);
    const bool albedo = out->albedo.worst_seam_ratio > out->height.worst_seam_ratio ||
                        isnan(out->height.worst_seam_ratio);
    const pg_inspect_seam_stat *w = albedo ? &out->albedo : &out->height;
    out->worst_seam_ratio = w->worst_seam_ratio;
    out->worst_seam_ratio_local = w->worst_seam_ratio_local;
    out->worst_seam_faces[0] = w->worst_seam_faces[0];
    out->worst_seam_faces[1] = w->worst_seam_faces[1];
    snprintf(out->worst_seam_field, sizeof out->worst_seam_field, "%s",
             w->worst_seam_faces[0] < 0 ? ""
             : albedo                   ? "albedo"
                                        : "height");
    return st;
}
