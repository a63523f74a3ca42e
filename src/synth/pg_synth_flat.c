/* pg_synth_flat.c - synthesis of a flat N x N region, coarse to fine, and rendering.
 *
 * The driver owns two level buffers with a one-texel border. Levels run from the
 * coarsest scale s_top = log2(min(N, E)) (N >> s_top texels a side, one per exemplar
 * spacing h = 2^s_top) down to 0. The coarsest level starts at block centres of a
 * toroidal exemplar (so jitter 0 reproduces the exemplar exactly) or at hashed random
 * positions of the exemplar cube. Each level: upsample, jitter, then, if the level is
 * analysed, `passes` correction passes of 4 sub-passes.
 *
 * The region's outside is a coherent continuation: before each sub-pass the border
 * texels are set to their nearest edge texel's coordinate moved by h times the offset,
 * with its V. Corrections are run tile by tile (tile_size) through the same view API the
 * planet uses; since sub-passes are order-independent (pg_synth_lefebvre_hoppe.c) any
 * tiling and any thread count give identical bytes. */
#include "pg_hash.h"
#include "pg_synth_internal.h"

#include <stdlib.h>
#include <string.h>

static int ilog2(long v) {
    int l = 0;
    while ((1L << (l + 1)) <= v)
        l++;
    return l;
}

double pg_synth_flat_bytes(int n) {
    double a = (double)(n + 2) * (n + 2), b = (double)(n / 2 + 2) * (n / 2 + 2);
    return (a + b) * (sizeof(uint32_t) + sizeof(float));
}

typedef struct level_buf {
    uint32_t *S;
    float *V;
    int res;
    ptrdiff_t stride;
} level_buf;

static pg_synth_view interior(const level_buf *b) {
    pg_synth_view v = {.S = b->S + b->stride + 1,
                       .V = b->V + b->stride + 1,
                       .stride = b->stride,
                       .w = b->res,
                       .h = b->res};
    return v;
}

static void fill_border(const pg_synth_exemplar *ex, int scale, level_buf *b) {
    const int r = b->res, h = 1 << scale;
    uint32_t *S = b->S + b->stride + 1;
    float *V = b->V + b->stride + 1;
    for (int i = -1; i <= r; i++) {
        int pts[4][2] = {{i, -1}, {i, r}, {-1, i}, {r, i}};
        for (int k = 0; k < 4; k++) {
            int x = pts[k][0], y = pts[k][1];
            int cx = x < 0 ? 0 : (x >= r ? r - 1 : x), cy = y < 0 ? 0 : (y >= r ? r - 1 : y);
            ptrdiff_t c = (ptrdiff_t)cy * b->stride + cx, t = (ptrdiff_t)y * b->stride + x;
            S[t] = pg_synth_offset(ex, S[c], h * (x - cx), h * (y - cy));
            V[t] = V[c];
        }
    }
}

static void init_top(const pg_synth_exemplar *ex, int s_top, uint64_t seed, level_buf *b) {
    const int E = ex->face_size, h = 1 << s_top;
    pg_synth_view v = interior(b);
    for (int y = 0; y < b->res; y++)
        for (int x = 0; x < b->res; x++) {
            uint32_t c;
            if (ex->torus) {
                c = pg_synth_pack(0, (h * x + h / 2) & (E - 1), (h * y + h / 2) & (E - 1));
            } else {
                uint32_t a = pg_hash_texel(seed, 99, 0, x, y, 7);
                uint32_t bb = pg_hash_texel(seed, 99, 0, x, y, 8);
                c = pg_synth_pack((int)(a % (uint32_t)ex->nfaces), (int)((a >> 3) % (uint32_t)E),
                                  (int)(bb % (uint32_t)E));
            }
            v.S[y * v.stride + x] = c;
            v.V[y * v.stride + x] = 0;
        }
}

static void correct_level(const pg_synth_exemplar *ex, int scale, const pg_synth_params *p,
                          level_buf *b, pg_synth_pass_hook hook, void *user) {
    const int r = b->res;
    const int ts = p->tile_size > 0 && p->tile_size < r ? p->tile_size : r;
    const int nt = (r + ts - 1) / ts;
    pg_synth_view all = interior(b);
    for (int pass = 0; pass < p->passes; pass++) {
        for (int sp = 0; sp < 4; sp++) {
            fill_border(ex, scale, b);
            if (nt == 1) {
                pg_synth_correct_subpass(ex, scale, p, pg_synth_subpass_order[sp], &all);
                continue;
            }
#pragma omp parallel for schedule(dynamic, 1)
            for (int t = 0; t < nt * nt; t++) {
                int tx = (t % nt) * ts, ty = (t / nt) * ts;
                pg_synth_view v = all;
                v.S += (ptrdiff_t)ty * all.stride + tx;
                v.V += (ptrdiff_t)ty * all.stride + tx;
                v.w = tx + ts <= r ? ts : r - tx;
                v.h = ty + ts <= r ? ts : r - ty;
                v.gx = tx;
                v.gy = ty;
                pg_synth_correct_subpass(ex, scale, p, pg_synth_subpass_order[sp], &v);
            }
        }
        if (hook) hook(user, ex, scale, pass, b->S, b->V, r, b->stride);
    }
}

static pg_status check(const pg_synth_exemplar *ex, int n, const pg_synth_params *p,
                       pg_error *err) {
    if (n < 1 || (n & (n - 1)) != 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "--size %d: must be a power of two", n);
    for (int s = 0; s < PG_SYNTH_MAX_LEVELS + 8; s++) {
        double r = pg_synth_jitter_for(p, s);
        if (!(r >= 0 && r <= 1))
            return pg_error_set(err, PG_ERR_BADINPUT, "--jitter %g: must be in [0, 1]", r);
    }
    if (p->passes < 0 || p->passes > 16)
        return pg_error_set(err, PG_ERR_BADINPUT, "--passes %d: must be in 0..16", p->passes);
    if (!(p->kappa >= 0 && p->kappa <= 100))
        return pg_error_set(err, PG_ERR_BADINPUT, "--kappa %g: must be in [0, 100]", p->kappa);
    if (!(p->offset_penalty >= 0 && p->offset_penalty <= 1e6))
        return pg_error_set(err, PG_ERR_BADINPUT, "--offset-penalty %g: must be >= 0",
                            p->offset_penalty);
    if (!ex) return pg_error_set(err, PG_ERR_BADINPUT, "synthesis: no exemplar");
    return PG_OK;
}

pg_status pg_synth_flat(const pg_synth_exemplar *ex, int n, const pg_synth_params *p,
                        pg_synth_pass_hook hook, void *hook_user, pg_synth_result *out,
                        pg_error *err) {
    memset(out, 0, sizeof *out);
    pg_status st = check(ex, n, p, err);
    if (st) return st;
    /* start at the coarsest analysed level: LH2005 initialise it with random samples */
    int s_top = ilog2(n < ex->face_size ? n : ex->face_size);
    if (s_top > ex->levels - 1) s_top = ex->levels - 1;
    size_t cap_a = (size_t)(n + 2) * (n + 2), cap_b = (size_t)(n / 2 + 2) * (n / 2 + 2);
    level_buf a = {malloc(cap_a * 4), malloc(cap_a * 4), 0, 0};
    level_buf b = {malloc(cap_b * 4), malloc(cap_b * 4), 0, 0};
    if (!a.S || !a.V || !b.S || !b.V) {
        free(a.S), free(a.V), free(b.S), free(b.V);
        return pg_error_set(err, PG_ERR_NOMEM, "synthesis: out of memory for %d x %d", n, n);
    }
    /* the finest level must land in buffer a: start in a or b by parity of s_top */
    level_buf *cur = (s_top % 2 == 0) ? &a : &b, *nxt = (cur == &a) ? &b : &a;
    cur->res = n >> s_top;
    cur->stride = cur->res + 2;
    double t0 = pg_synth_now();
    init_top(ex, s_top, p->seed, cur);
    pg_synth_view v = interior(cur);
    pg_synth_jitter(ex, s_top, pg_synth_jitter_for(p, s_top), p->seed, &v);
    correct_level(ex, s_top, p, cur, hook, hook_user);
    out->level_seconds[out->nlevels_run++] = pg_synth_now() - t0;
    for (int s = s_top - 1; s >= 0; s--) {
        t0 = pg_synth_now();
        nxt->res = cur->res * 2;
        nxt->stride = nxt->res + 2;
        pg_synth_view pv = interior(cur), cv = interior(nxt);
        pg_synth_upsample(ex, s, &pv, &cv);
        pg_synth_jitter(ex, s, pg_synth_jitter_for(p, s), p->seed, &cv);
        correct_level(ex, s, p, nxt, hook, hook_user);
        level_buf *t = cur;
        cur = nxt;
        nxt = t;
        out->level_seconds[out->nlevels_run++] = pg_synth_now() - t0;
    }
    /* compact the finest level (in a) into row-major N x N, in place */
    for (int y = 0; y < n; y++) {
        memmove(a.S + (size_t)y * n, a.S + (size_t)(y + 1) * a.stride + 1, (size_t)n * 4);
        memmove(a.V + (size_t)y * n, a.V + (size_t)(y + 1) * a.stride + 1, (size_t)n * 4);
    }
    free(b.S), free(b.V);
    out->size = n;
    out->coords = a.S;
    out->offset = a.V;
    return PG_OK;
}

void pg_synth_result_free(pg_synth_result *r) {
    free(r->coords);
    free(r->offset);
    memset(r, 0, sizeof *r);
}

void pg_synth_render(const pg_synth_exemplar *ex, const uint32_t *coords, const float *offset,
                     size_t count, uint8_t *albedo_rgb, float *height_m) {
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < count; i++) {
        size_t t = pg_synth_texel(ex, coords[i]);
        if (albedo_rgb) memcpy(albedo_rgb + i * 3, ex->albedo + t * 3, 3);
        if (height_m) height_m[i] = ex->height[t] + (offset ? offset[i] : 0.0f);
    }
}

void pg_synth_coords_rgb(const pg_synth_exemplar *ex, const uint32_t *coords, size_t count,
                         uint8_t *rgb) {
    const float inv = 255.0f / (float)(ex->face_size - 1);
    for (size_t i = 0; i < count; i++) {
        uint32_t c = coords[i];
        rgb[i * 3 + 0] = (uint8_t)(pg_synth_u(c) * inv + 0.5f);
        rgb[i * 3 + 1] = (uint8_t)(pg_synth_v(c) * inv + 0.5f);
        rgb[i * 3 + 2] = (uint8_t)(ex->nfaces > 1 ? 40 + pg_synth_face(c) * 43 : 128);
    }
}
