/* pg_planet_synth_deliver.c - delivery of the synthesized planet: the finest level
 * magnified to the delivered resolution (a cubic B-spline when the planet's faces are
 * finer than the exemplar's, the texel as it is otherwise), the delivered heights for
 * the final pit pass, and the albedo, heights and exemplar coordinates of the planet
 * (docs/generate.md, "Method": "Exemplar scale").
 *
 * Each delivered texel reads at most the 4 x 4 synthesized texels around it, across face
 * seams through the level's border; distributed, a process delivers its own tiles after
 * an exchange of width 2 (docs/mpi.md, "What is distributed, and how"). */
#include "pg_planet_synth_internal.h"
#include "pg_quantise.h"

#include <math.h>
#include <string.h>

/* Delivery at Nout = m N texels per face edge. One synthesized texel stands for one
 * exemplar texel of ground, so when the planet's faces are finer than the exemplar's
 * (m > 1) the synthesized albedo and height are magnified with a cubic B-spline (texel
 * centres aligned; the 4 x 4 taps read the level's one-texel border across face seams,
 * clamped to it). Why a B-spline and not an interpolating kernel: every tile edge of
 * the delivered planet is a synthesized-texel boundary, and an interpolating kernel
 * makes the delivered steps across such a boundary systematically larger than those
 * inside a synthesized texel, so tile edges would look like seams (default planet:
 * albedo seam ratio 1.155 bilinear, 1.19 Catmull-Rom, 1.04 B-spline; the B-spline's
 * smoothing is below the exemplar's own resolution). With m = 1 the synthesized texel
 * is delivered as it is. */
typedef struct texel_out {
    float rgb[3], h;
} texel_out;

/* Cubic B-spline weights of the taps n - 1 .. n + 2 around t = s - n, 0 <= t < 1. */
static void bspline3_weights(double t, double w[4]) {
    double u = 1 - t;
    w[0] = u * u * u / 6;
    w[1] = (3 * t * t * t - 6 * t * t + 4) / 6;
    w[2] = (3 * u * u * u - 6 * u * u + 4) / 6;
    w[3] = t * t * t / 6;
}

static void magnified_texel(const pg_ps_ctx *c, const pg_ps_level *L, int f, int64_t X, int64_t Y,
                            texel_out *o) {
    const int m = c->m, r = L->r;
    if (m == 1) {
        size_t i = pg_ps_at(L, f, (int)X, (int)Y), t = pg_synth_texel(c->ex, L->S[i]);
        for (int j = 0; j < 3; j++)
            o->rgb[j] = c->ex->albedo[t * 3 + j] * (1.0f / 255.0f);
        o->h = c->ex->height[t] + (L->V ? L->V[i] : 0.0f);
        return;
    }
    double sx = (X + 0.5) / m - 0.5, sy = (Y + 0.5) / m - 0.5;
    int x0 = (int)floor(sx), y0 = (int)floor(sy);
    double wx[4], wy[4], acc[4] = {0};
    bspline3_weights(sx - x0, wx);
    bspline3_weights(sy - y0, wy);
    for (int ky = 0; ky < 4; ky++)
        for (int kx = 0; kx < 4; kx++) {
            double w = wx[kx] * wy[ky];
            int x = x0 - 1 + kx, y = y0 - 1 + ky;
            x = x < -1 ? -1 : (x > r ? r : x);
            y = y < -1 ? -1 : (y > r ? r : y);
            size_t i = pg_ps_at(L, f, x, y);
            size_t t = pg_synth_texel(c->ex, L->S[i]);
            for (int j = 0; j < 3; j++)
                acc[j] += w * c->ex->albedo[t * 3 + j];
            acc[3] += w * (c->ex->height[t] + (L->V ? L->V[i] : 0.0f));
        }
    for (int j = 0; j < 3; j++)
        o->rgb[j] = (float)(acc[j] * (1.0 / 255.0));
    o->h = (float)acc[3];
}

/* The delivered texels [*x0, *x1) of row y of face f that lie in tile column tx, when
 * this process owns that tile (always without dist, or with all). */
static bool owned_span(const pg_ps_ctx *c, int f, int64_t y, int tx, bool all, int64_t *x0,
                       int64_t *x1) {
    const int64_t ts = c->Nout / c->T;
    *x0 = tx * ts, *x1 = *x0 + ts;
    return all || !c->p->dist || pg_ps_owns(c, f, tx, (int)(y / ts));
}

/* Row `row` (face row / n, texel row row % n) of the delivered planet: heights into h,
 * albedo into rgb, when not NULL. With all false, only the texels of this process's
 * tiles (all of them without dist); no other texel of h or rgb is touched. */
static void deliver_row(const pg_ps_ctx *c, const pg_ps_level *L, int64_t row, float *h, float *rgb,
                        bool all) {
    const int64_t n = c->Nout;
    const int f = (int)(row / n);
    for (int tx = 0; tx < c->T; tx++) {
        int64_t x0, x1;
        if (!owned_span(c, f, row % n, tx, all, &x0, &x1)) continue;
        for (int64_t x = x0; x < x1; x++) {
            texel_out o;
            magnified_texel(c, L, f, x, row % n, &o);
            if (h) h[x] = o.h;
            for (int k = 0; rgb && k < 3; k++)
                rgb[x * 3 + k] = o.rgb[k];
        }
    }
}

void pg_ps_finest_heights(const pg_ps_ctx *c, const pg_ps_level *L, float *H, bool all) {
#pragma omp parallel for schedule(static)
    for (int64_t row = 0; row < 6 * c->Nout; row++)
        deliver_row(c, L, row, H + (size_t)row * c->Nout, NULL, all);
}

/* The albedo as the planet stores it: 8 bits a channel, rounded as every image writer
 * rounds (pg_quantise.h). The planet in memory is then the planet on disk: a GeoTIFF
 * resampled from it equals one resampled from the PNG tiles that distributed ranks read
 * back, and `generate`'s own figures equal `inspect`'s on the saved planet. Exemplar
 * texels (k / 255) pass unchanged; the B-spline's and the sea ice's blends move. */
static void quantise_albedo(float *rgb) {
    for (int j = 0; j < 3; j++) {
        const double v = !(rgb[j] > 0) ? 0 : rgb[j] > 1 ? 1 : rgb[j];  /* NaN: 0 */
        rgb[j] = (float)pg_round_half_up(v * 255.0) * (1.0f / 255.0f); /* as magnified_texel */
    }
}

/* Albedo (magnified, under sea ice where ice is given; quantised as stored), the heights H, and per
 * delivered texel the exemplar coordinate of its synthesized texel (coords, types): this process's
 * tiles only. */
void pg_ps_render(const pg_ps_ctx *c, const pg_ps_level *L, const float *H, const pg_sea_ice *ice,
                  pg_planet *out, uint32_t *coords) {
    const int64_t n = c->Nout;
    const int r = L->r, m = c->m;
    const float sea = c->ex->sea_level;
    uint64_t ok = 0, ocean = 0, iced = 0;
    /* rows in small chunks: the sea ice's work lies on the polar faces, which a static
     * split by halves gave to one thread */
#pragma omp parallel for schedule(dynamic, 16) reduction(+ : ok, ocean, iced)
    for (int64_t row = 0; row < 6 * n; row++) {
        int f = (int)(row / n);
        int64_t y = row % n;
        deliver_row(c, L, row, NULL, out->albedo[f] + (size_t)y * n * 3, false);
        for (int tx = 0; tx < c->T; tx++) {
            int64_t x0, x1;
            if (!owned_span(c, f, y, tx, false, &x0, &x1)) continue;
            memcpy(out->height[f] + (size_t)y * n + x0, H + (size_t)row * n + x0,
                   (size_t)(x1 - x0) * sizeof *H);
            for (int64_t x = x0; x < x1; x++) {
                uint32_t q = L->S[pg_ps_at(L, f, (int)(x / m), (int)(y / m))];
                if (coords) coords[(size_t)row * n + x] = q;
                float *rgb = out->albedo[f] + ((size_t)y * n + (size_t)x) * 3;
                if (ice) {
                    const float h = H[(size_t)row * n + x];
                    ocean += h <= sea;
                    iced += pg_sea_ice_apply(ice, f, x, y, h, sea, rgb);
                }
                quantise_albedo(rgb);
                if (c->use_types)
                    ok += pg_ps_type_allowed_fast(
                        c, pg_ps_mask_at(c, r, f, (long)(x / m), (long)(y / m)), q);
            }
        }
    }
    double allowed = (double)ok; /* distributed: each process counted its tiles */
    if (c->use_types && c->p->dist && c->p->dist->sum)
        allowed = c->p->dist->sum(c->p->dist->user, allowed);
    c->info->allowed_fraction = c->use_types ? allowed / (6.0 * n * n) : 1.0;
    double sums[2] = {(double)ocean, (double)iced}; /* integers: exact in any order */
    if (ice && c->p->dist && c->p->dist->sum)
        for (int k = 0; k < 2; k++)
            sums[k] = c->p->dist->sum(c->p->dist->user, sums[k]);
    c->info->sea_ice_fraction = ice && sums[0] > 0 ? sums[1] / sums[0] : NAN;
}
