/* pg_planet_sea_ice.c - sea ice on the delivered planet of layout world: the ocean of an
 * ice climate is covered with pack ice, and its edge is a marginal zone of floes and
 * leads (docs/generate.md, "Sea ice").
 *
 * WHY IT IS NOT SYNTHESIZED. Blue Marble, the default exemplar, is a cloud- and
 * sea-ice-free composite: its Arctic Ocean is open water. The type rule lets the sea of
 * an ice climate take "ice or ocean" (pg_planet_world.c), but the exemplar's only ice is
 * the land ice of Antarctica and Greenland, kilometres above the sea, so the synthesis
 * always copies open water there. Sea ice is a cover on the ocean's surface, a metre or
 * a few thick, not relief: this pass changes the albedo of ocean texels only and leaves
 * every height (the sea floor) as synthesized.
 *
 * THE MODEL, per delivered ocean texel (height <= sea level), with T the world's annual
 * mean temperature sampled bilinearly on the cube (as the type constraints sample it):
 *   cover c = clamp((T_OPEN - T) / (T_OPEN - T_PACK) + A_EDGE (n_edge - 1/2), 0, C_MAX)
 *   with T_PACK = PG_CLIMATE_ICE_C - 2 and T_OPEN = PG_CLIMATE_ICE_C + 6 (the tundra
 *   margin of the type rule). On Earth the perennial Arctic pack lies at annual means of
 *   -15 to -20 deg C, the summer-minimum ice edge near -10 and the winter-maximum edge
 *   near 0 to -2; the picture lies between the seasons. n_edge, a noise of about a
 *   thousand kilometres, makes the edge meander (A_EDGE = 0.5: about +-2 K, so water warmer than
 *   T_NONE = -2 deg C is always open).
 *   Floes and leads: the texel is ice where the floe noise n_floe (features of 4 to 32
 *   delivered texels) lies below c, with a soft step of width W_STEP; so the covered
 *   share rises with c, the pack (C_MAX < 1) keeps a few leads, and the margin breaks
 *   into floes.
 *   Colour: the mean albedo of the exemplar's ice texels (the pg_types rule: its ice
 *   sheets' snow), times a tone of 0.89..1 from a noise of 64 to 128
 *   texels; thin ice is greyer: at the margin it keeps up to 35% of the water below it as
 *   c falls to 0, along the leads (the contour n = 1/2 of a noise of 16 to 32 texels, open where
 *   the tone noise is above its middle) 70%.
 *   Where c is 0 the texel is not touched (bit for bit).
 *
 * NOISE. Value noise on the cube's grid lines: a grid of r texels per face edge has
 * (r + 1)^2 vertices a face, and each vertex is a point of the integer lattice of the
 * cube's surface, P = r (1,1,1) + r n + (2i - r) e_u + (2j - r) e_v with the face frame
 * (pg_cube_face_frame), the same point for every face that shares it. The vertex holds
 * pg_synth_hash(seed, log2 r, P) / 2^32, and a delivered texel takes the value of its
 * grid square, interpolated bilinearly between the square's four vertices. A seam's vertices are
 * shared, so the ice crosses every seam and cube corner without a step (sampling a texel-centred
 * grid across a corner extrapolates a missing texel, which each face does its own way), and every
 * value is a hash of (seed, level, lattice point): the same for any thread count, tiling or rank
 * count. The grids are at most SEA_ICE_MAX_R a face edge: 2.3 MB for a planet of 1024 a
 * face edge, at most 51 MB (pg_sea_ice_bytes). Above faces of 2048 the capped octaves
 * stretch: at 16384 every floe octave is 32 delivered texels, not 4 to 32. */
#include "planetgen/pg_planet_synth.h"

#include "planetgen/pg_climate.h"
#include "planetgen/pg_types.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define T_PACK (PG_CLIMATE_ICE_C - 2.0)
#define T_OPEN (PG_CLIMATE_ICE_C + 6.0)
#define A_EDGE 0.5
#define C_MAX 0.97
/* the warmest water the edge noise can still cover: u = -A_EDGE / 2 */
#define T_NONE (T_OPEN + A_EDGE / 2 * (T_OPEN - T_PACK))
#define W_STEP 0.2
#define THIN_KEEP 0.35
#define LEAD_W 0.01
#define LEAD_KEEP 0.7
#define SEA_ICE_MAX_R 512
#define SALT 0x5eac1ce

/* the noises' octaves: grid texels per face edge, as a divisor of the delivered face
 * (0: a fixed r) */
static const struct {
    int div, r;
    double w;
} octaves[PG_SEA_ICE_OCTAVES] = {
    /* edge: a thousand kilometres and finer on an Earth-sized face */
    {0, 8, 0.5},
    {0, 16, 0.3},
    {0, 32, 0.2},
    /* floes */
    {4, 0, 0.15},
    {8, 0, 0.35},
    {16, 0, 0.3},
    {32, 0, 0.2},
    /* tone */
    {64, 0, 0.6},
    {128, 0, 0.4},
    /* leads: the contour n = 1/2 of a noise of 16 to 32 texels */
    {16, 0, 0.6},
    {32, 0, 0.4},
};

static int octave_r(int i, int64_t nout) {
    int64_t r = octaves[i].div ? nout / octaves[i].div : octaves[i].r;
    if (r > SEA_ICE_MAX_R) r = SEA_ICE_MAX_R;
    if (r > nout) r = nout;
    return r < 2 ? 2 : (int)r;
}

static int log2i(int r) {
    int l = 0;
    while ((1 << (l + 1)) <= r)
        l++;
    return l;
}

/* The exemplar's ice colour: the mean sRGB of its finest texels of type ice (types[t],
 * or pg_types_classify without types), summed in integers (the same for any thread
 * count); a plain snow white without an exemplar or when it has no ice. */
static void ice_colour(const pg_synth_exemplar *ex, const uint8_t *types, float rgb[3]) {
    const int64_t n = ex ? (int64_t)ex->nfaces * ex->face_size * ex->face_size : 0;
    uint64_t s0 = 0, s1 = 0, s2 = 0, cnt = 0;
#pragma omp parallel for schedule(static) reduction(+ : s0, s1, s2, cnt)
    for (int64_t t = 0; t < n; t++) {
        const uint8_t *a = ex->albedo + 3 * t;
        const int type = types ? types[t] : pg_types_classify(a, ex->height[t], ex->sea_level);
        if (type != PG_TYPE_ICE) continue;
        s0 += a[0], s1 += a[1], s2 += a[2], cnt++;
    }
    if (!cnt) {
        rgb[0] = 0.92f, rgb[1] = 0.94f, rgb[2] = 0.96f;
        return;
    }
    rgb[0] = (float)((double)s0 / (255.0 * (double)cnt));
    rgb[1] = (float)((double)s1 / (255.0 * (double)cnt));
    rgb[2] = (float)((double)s2 / (255.0 * (double)cnt));
}

double pg_sea_ice_bytes(int64_t nout, int64_t world_n) {
    double b = 6.0 * (double)world_n * (double)world_n * sizeof(float);
    for (int i = 0; i < PG_SEA_ICE_OCTAVES; i++)
        b += 6.0 * (octave_r(i, nout) + 1) * (octave_r(i, nout) + 1) * sizeof(float);
    return b;
}

pg_status pg_sea_ice_init(pg_sea_ice *s, const pg_planet_world *w, const pg_synth_exemplar *ex,
                          const uint8_t *types, uint64_t seed, int64_t nout, pg_error *err) {
    memset(s, 0, sizeof *s);
    if (!w || w->n < 1 || !w->temperature_c || nout < 1)
        return pg_error_set(err, PG_ERR_BADINPUT, "sea ice: no macro world");
    s->world = w;
    s->nout = nout;
    pg_cube_sample_grid_init(&s->wgrid, PG_CUBE_DEFAULT_PROJECTION, w->n);
    ice_colour(ex, types, s->ice_rgb);
    const int64_t wn = w->n;
    s->warm_min = malloc((size_t)(6 * wn * wn) * sizeof(float));
    if (!s->warm_min) {
        pg_sea_ice_free(s);
        return pg_error_set(err, PG_ERR_NOMEM, "sea ice: out of memory");
    }
#pragma omp parallel for schedule(static)
    for (int64_t k = 0; k < 6 * wn * wn; k++) {
        const int64_t x = k % wn, y = k / wn % wn;
        const float *t = w->temperature_c + k;
        float m = t[0];
        if (x + 1 < wn && y + 1 < wn) {
            m = fminf(fminf(m, t[1]), fminf(t[wn], t[wn + 1]));
        }
        s->warm_min[k] = m;
    }
    for (int i = 0; i < PG_SEA_ICE_OCTAVES; i++) {
        const int r = octave_r(i, nout), lr = log2i(r), v = r + 1;
        s->r[i] = r;
        s->noise[i] = malloc((size_t)6 * v * v * sizeof(float));
        if (!s->noise[i]) {
            pg_sea_ice_free(s);
            return pg_error_set(err, PG_ERR_NOMEM, "sea ice: out of memory");
        }
        float *g = s->noise[i];
#pragma omp parallel for schedule(static)
        for (int64_t k = 0; k < (int64_t)6 * v * v; k++) {
            const int f = (int)(k / ((int64_t)v * v)), vi = (int)(k % v), vj = (int)(k / v % v);
            int n[3], eu[3], ev[3];
            long P[3];
            pg_cube_face_frame(f, n, eu, ev);
            for (int a = 0; a < 3; a++)
                P[a] = (long)r + (long)r * n[a] + (long)(2 * vi - r) * eu[a] +
                       (long)(2 * vj - r) * ev[a];
            g[k] = (float)(pg_synth_hash(seed, lr, (int)P[2], P[0], P[1], SALT + i) *
                           (1.0 / 4294967296.0));
        }
    }
    return PG_OK;
}

void pg_sea_ice_free(pg_sea_ice *s) {
    for (int i = 0; i < PG_SEA_ICE_OCTAVES; i++)
        free(s->noise[i]);
    free(s->warm_min);
    memset(s, 0, sizeof *s);
}

/* Where a delivered texel's centre lies on a grid of r texels a face edge: the square
 * *i (0..r-1) and the weight *t of its far vertex. Linear: eased weights flatten the
 * field across every grid line, and the face seams are grid lines, so the seams would
 * come out smoother than the ground beside them. */
static void grid_pos(int64_t X, int64_t nout, int r, int *i, double *t) {
    const double g = ((double)X + 0.5) * r / (double)nout;
    int k = (int)g;
    if (k > r - 1) k = r - 1;
    *i = k, *t = g - k;
}

/* The weighted mean of octaves [i0, i1) at delivered texel (f, X, Y). */
static double noise(const pg_sea_ice *s, int i0, int i1, int f, int64_t X, int64_t Y) {
    double acc = 0, wsum = 0;
    for (int i = i0; i < i1; i++) {
        const int r = s->r[i], v = r + 1;
        int x, y;
        double tx, ty;
        grid_pos(X, s->nout, r, &x, &tx);
        grid_pos(Y, s->nout, r, &y, &ty);
        const float *q = s->noise[i] + ((size_t)f * v + (size_t)y) * v + (size_t)x;
        const double a = q[0] + tx * (q[1] - q[0]), b = q[v] + tx * (q[v + 1] - q[v]);
        acc += octaves[i].w * (a + ty * (b - a));
        wsum += octaves[i].w;
    }
    return acc / wsum;
}

/* The world's temperature at world point (fx, fy) of face f. */
static double temperature_at(const pg_sea_ice *s, int f, double fx, double fy) {
    float t;
    pg_cube_sample_face(&s->wgrid, s->world->temperature_c, 1, f, fx, fy, &t);
    return t;
}

double pg_sea_ice_temperature(const pg_sea_ice *s, int f, int64_t X, int64_t Y) {
    const double k = (double)s->world->n / (double)s->nout;
    return temperature_at(s, f, (X + 0.5) * k - 0.5, (Y + 0.5) * k - 0.5);
}

/* Whether the bilinear temperature at world point (fx, fy) of face f is surely warm
 * enough for open water: inside the face its four taps are a convex combination, so
 * their minimum (warm_min, with a margin for rounding) bounds it. Most of the ocean is
 * decided by this one lookup, without the sample. */
static bool surely_open(const pg_sea_ice *s, int f, double fx, double fy) {
    const int64_t n = s->world->n, ix = (int64_t)floor(fx), iy = (int64_t)floor(fy);
    if (ix < 0 || iy < 0 || ix + 1 >= n || iy + 1 >= n) return false;
    return s->warm_min[((size_t)f * (size_t)n + (size_t)iy) * (size_t)n + (size_t)ix] >=
           T_NONE + 1e-3;
}

double pg_sea_ice_cover(const pg_sea_ice *s, int f, int64_t X, int64_t Y) {
    const double k = (double)s->world->n / (double)s->nout;
    const double fx = (X + 0.5) * k - 0.5, fy = (Y + 0.5) * k - 0.5;
    if (!s->sample_all && surely_open(s, f, fx, fy)) return 0;
    const double t = temperature_at(s, f, fx, fy);
    if (!(t < T_NONE)) return 0; /* no edge noise reaches it (and no NaN goes on) */
    const double u = (T_OPEN - t) / (T_OPEN - T_PACK);
    const double c = u + A_EDGE * (noise(s, 0, 3, f, X, Y) - 0.5);
    return c <= 0 ? 0 : c > C_MAX ? C_MAX : c;
}

bool pg_sea_ice_apply(const pg_sea_ice *s, int f, int64_t X, int64_t Y, float height,
                      float sea_level, float rgb[3]) {
    if (height > sea_level) return false;
    const double c = pg_sea_ice_cover(s, f, X, Y);
    if (c <= 0) return false;
    double a = (c - noise(s, 3, 7, f, X, Y)) / W_STEP + 0.5;
    a = a < 0 ? 0 : a > 1 ? 1 : a;
    if (a <= 0) return false;
    const double nt = noise(s, 7, 9, f, X, Y), tone = 0.945 + 0.11 * (nt - 0.5);
    /* a lead is open where the tone noise is above its middle, so the contour breaks
     * into separate cracks instead of closing into loops */
    const double open = fmin(1.0, fmax(0.0, (nt - 0.5) * 8));
    const double lead = open * (1 - fmin(1.0, fabs(noise(s, 9, 11, f, X, Y) - 0.5) / LEAD_W));
    /* thin ice shows the water: at the margin, and along the leads */
    const double keep = fmax(THIN_KEEP * (1 - c / C_MAX), LEAD_KEEP * lead);
    for (int j = 0; j < 3; j++) {
        double ice = (1 - keep) * fmin(1.0, s->ice_rgb[j] * tone) + keep * rgb[j];
        rgb[j] = (float)(rgb[j] + a * (ice - rgb[j]));
    }
    return a >= 0.5;
}
