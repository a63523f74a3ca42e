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
 *   with T_PACK = PG_CLIMATE_ICE_C + 0.5 and T_OPEN = PG_CLIMATE_ICE_C + 3.5. On Earth the
 *   perennial Arctic pack lies at annual means of -15 to -20 deg C, the summer-minimum ice
 *   edge near -10 and the winter-maximum edge near 0 to -2; the picture is one moment, a
 *   pack with a marginal zone of floes, its edge (c = 1/2 at -8 deg C) between the
 *   seasons'. A margin spanning the seasons' whole range (8 K) spread floes and holes over
 *   a thousand kilometres of a world's gently cooling polar ocean. n_edge, a noise of
 *   about a thousand kilometres, makes the edge meander (A_EDGE = 1.33: about +-2 K, so
 *   water warmer than T_NONE = -4.5 deg C is always open).
 *   Floes and leads: the texel is ice where the floe noise n_floe (features of 4 to 32
 *   delivered texels, about 1/2 with standard deviation 0.13) lies below c, with a soft
 *   step of width W_STEP; so the covered share rises with c, the pack (C_MAX < 1) keeps a
 *   few holes, and the margin breaks into floes.
 *   Colour: the mean albedo of the exemplar's ice texels (the pg_types rule: its ice
 *   sheets' snow), times a tone of 0.89..1 from a noise of 64 to 128
 *   texels; thin ice is greyer: at the margin it keeps up to 35% of the water below it as
 *   c falls to 0, along the leads 70%. The leads are the edges of a Voronoi network of
 *   cells of about 96 texels (straight cracks that meet at angles), open only where the
 *   tone noise is above 0.55, so the network breaks into separate cracks.
 *   Where c is 0 the texel is not touched (bit for bit).
 *
 * NOISE. Every noise is a function of the texel's direction on the unit sphere, not of its
 * face coordinates: gradient noise (Perlin 2002) on the integer lattice of space, scaled
 * to the octave's wavelength, and a Voronoi network (Worley 1996) on the same kind of
 * lattice. So the ice crosses every seam and cube corner without a step, and nothing
 * lines up with the cube's texel grid: value noise on cube grids, interpolated
 * bilinearly, bent at every grid line and gave the margin square blobs of 4 texels. Every
 * lattice value is a hash of (seed, level, lattice point): the same for any thread count,
 * tiling or rank count. Nothing is stored but the warm-water table (pg_sea_ice_bytes), and
 * the octaves keep their wavelengths in delivered texels at every planet size. */
#include "planetgen/pg_planet_synth.h"

#include "planetgen/pg_climate.h"
#include "planetgen/pg_types.h"
#include "pg_hash.h"
#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define T_PACK (PG_CLIMATE_ICE_C + 0.5)
#define T_OPEN (PG_CLIMATE_ICE_C + 3.5)
#define A_EDGE 1.33
#define C_MAX 0.97
/* the warmest water the edge noise can still cover: u = -A_EDGE / 2 */
#define T_NONE (T_OPEN + A_EDGE / 2 * (T_OPEN - T_PACK))
#define W_STEP 0.2
#define THIN_KEEP 0.35
#define LEAD_KEEP 0.7
#define SALT 0x5eac1ce
/* the standard deviation of one octave of gradient_noise (measured over 4 M random points:
 * 0.270), and those the noises are given (noise()) */
#define GRAD_SD 0.27
#define SD_EDGE 0.15
#define SD_FLOES 0.13
#define SD_TONE 0.15
/* leads: where the Voronoi edges of a cell network lie within LEAD_W_TEX delivered texels */
#define LEAD_W_TEX 0.7

/* The noises' octaves: wavelengths in delivered texels (div: nout / div cells a face edge)
 * or in face edges (r cells a face edge), as the value noise on cube grids had them. */
static const struct {
    int div, r;
    double w;
} octaves[] = {
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
};
#define EDGE 0, 3
#define FLOES 3, 7
#define TONE 7, 9
/* leads: the edges of a Voronoi network of cells of LEAD_DIV delivered texels */
#define LEAD_DIV 96

/* Cells per unit length of the unit sphere for a wavelength of r cells a face edge: a face
 * edge spans a quarter circle. */
static double frequency(double r) {
    return r / (M_PI / 2);
}

static double octave_frequency(int i, int64_t nout) {
    return frequency(octaves[i].div ? (double)nout / octaves[i].div : octaves[i].r);
}

static double fade(double t) {
    return t * t * t * (t * (t * 6 - 15) + 10);
}

/* Gradient noise (Perlin 2002, "Improving noise", SIGGRAPH) at point p of the integer
 * lattice: each lattice point holds one of the 12 gradients (+-1, +-1, 0) and their
 * turns, drawn from pg_hash_texel(seed, level, lattice point, salt); the eight around p
 * are blended with the quintic fade, so the field is smooth across every cell face and
 * shows no grid. About -1..1, standard deviation GRAD_SD. */
static double gradient_noise(uint64_t seed, int level, int salt, const double p[3]) {
    double f[3], w[3], v[8];
    long c[3];
    for (int a = 0; a < 3; a++) {
        const double fl = floor(p[a]);
        c[a] = (long)fl, f[a] = p[a] - fl, w[a] = fade(f[a]);
    }
    for (int k = 0; k < 8; k++) {
        const int dx = k & 1, dy = k >> 1 & 1, dz = k >> 2;
        const uint32_t h = pg_hash_texel(seed, level, (int)(c[2] + dz), c[0] + dx, c[1] + dy, salt);
        const double x = f[0] - dx, y = f[1] - dy, z = f[2] - dz;
        const uint32_t g = h % 12; /* pair of axes g / 4, their signs g & 3 */
        const double g0 = g & 1 ? -1 : 1, g1 = g & 2 ? -1 : 1;
        v[k] = g < 4 ? g0 * x + g1 * y : g < 8 ? g0 * x + g1 * z : g0 * y + g1 * z;
    }
    const double x00 = v[0] + w[0] * (v[1] - v[0]), x10 = v[2] + w[0] * (v[3] - v[2]);
    const double x01 = v[4] + w[0] * (v[5] - v[4]), x11 = v[6] + w[0] * (v[7] - v[6]);
    const double y0 = x00 + w[1] * (x10 - x00), y1 = x01 + w[1] * (x11 - x01);
    return y0 + w[2] * (y1 - y0);
}

/* The weighted sum of octaves [i0, i1) at direction d, as a value about 1/2 with standard
 * deviation sd, clamped to 0..1: the spread of the mean of hashed vertex values that the
 * value noise on cube grids had, which set how wide the margin of floes is. */
static double noise(const pg_sea_ice *s, int i0, int i1, const double d[3], double sd) {
    double acc = 0, var = 0;
    for (int i = i0; i < i1; i++) {
        const double F = octave_frequency(i, s->nout), p[3] = {d[0] * F, d[1] * F, d[2] * F};
        acc += octaves[i].w * gradient_noise(s->seed, i, SALT + i, p);
        var += octaves[i].w * octaves[i].w;
    }
    const double n = 0.5 + sd * acc / (GRAD_SD * sqrt(var));
    return n < 0 ? 0 : n > 1 ? 1 : n;
}

/* The 27 cubes around a point, its own first, then those across a face, an edge and a
 * corner: the nearer cubes come first, so that the far ones can be skipped (lead_edge). */
static const int lead_order[27][3] = {
    {0, 0, 0},   {-1, 0, 0},  {1, 0, 0},   {0, -1, 0}, {0, 1, 0},   {0, 0, -1},   {0, 0, 1},
    {-1, -1, 0}, {1, -1, 0},  {-1, 1, 0},  {1, 1, 0},  {-1, 0, -1}, {1, 0, -1},   {-1, 0, 1},
    {1, 0, 1},   {0, -1, -1}, {0, 1, -1},  {0, -1, 1}, {0, 1, 1},   {-1, -1, -1}, {1, -1, -1},
    {-1, 1, -1}, {1, 1, -1},  {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1},  {1, 1, 1}};

/* How near direction d lies to an edge of the Voronoi network of cells of LEAD_DIV
 * delivered texels (one feature point per lattice cube, at a hashed place in it; Worley
 * 1996, "A cellular texture basis function", SIGGRAPH): 1 on the edge, falling to 0 at
 * LEAD_W_TEX texels from it. The edges are straight in the lattice and meet at angles, as
 * leads do. The search looks at the 27 cubes around p, which finds the nearest feature
 * point always and the second nearest nearly always; a rare miss leaves a short gap in an
 * edge, which on the ice is one more break between cracks. */
static double lead_edge(const pg_sea_ice *s, const double d[3]) {
    const double F = frequency((double)s->nout / LEAD_DIV);
    const double p[3] = {d[0] * F, d[1] * F, d[2] * F};
    const long c[3] = {(long)floor(p[0]), (long)floor(p[1]), (long)floor(p[2])};
    const double fr[3] = {p[0] - (double)c[0], p[1] - (double)c[1], p[2] - (double)c[2]};
    double f1 = INFINITY, f2 = INFINITY;
    double q1[3] = {0, 0, 0}, q2[3] = {0, 0, 0};
    for (int k = 0; k < 27; k++) {
        const int *o = lead_order[k];
        /* the least squared distance from p to any point of this cube: when it is not
         * below the second nearest so far, nothing in the cube can count */
        double lb = 0;
        for (int a = 0; a < 3; a++)
            lb += o[a] < 0 ? fr[a] * fr[a] : o[a] > 0 ? (1 - fr[a]) * (1 - fr[a]) : 0;
        if (lb >= f2) continue;
        const long x = c[0] + o[0], y = c[1] + o[1], z = c[2] + o[2];
        /* the feature point: 16 bits a coordinate from two hashes */
        const uint32_t h0 = pg_hash_texel(s->seed, 16, (int)z, x, y, SALT + 100);
        const uint32_t h1 = pg_hash_texel(s->seed, 16, (int)z, x, y, SALT + 101);
        const double q[3] = {(double)x + (h0 & 0xffff) * (1.0 / 65536.0),
                             (double)y + (h0 >> 16) * (1.0 / 65536.0),
                             (double)z + (h1 & 0xffff) * (1.0 / 65536.0)};
        double dd = 0;
        for (int a = 0; a < 3; a++)
            dd += (q[a] - p[a]) * (q[a] - p[a]);
        if (dd < f1) {
            f2 = f1, f1 = dd;
            memcpy(q2, q1, sizeof q1), memcpy(q1, q, sizeof q);
        } else if (dd < f2) {
            f2 = dd, memcpy(q2, q, sizeof q);
        }
    }
    /* The distance along the sphere from p to the bisector of its two nearest feature
     * points: the plane n.(x - mid) = 0, n = q2 - q1, cuts the sphere in a curve, and
     * walking on the sphere changes n.(x - mid) at the rate of n's part tangent to the
     * sphere at d, n_t = n - (n.d) d. Measured in space instead, a plane that grazes
     * the sphere gave a patch of thin ice tens of texels wide, not a crack. */
    double m = 0, nd = 0, nt2 = 0;
    for (int a = 0; a < 3; a++) {
        const double n = q2[a] - q1[a];
        m += n * (p[a] - 0.5 * (q1[a] + q2[a]));
        nd += n * d[a];
    }
    for (int a = 0; a < 3; a++) {
        const double nt = q2[a] - q1[a] - nd * d[a];
        nt2 += nt * nt;
    }
    if (!(nt2 > 1e-12)) return 0;                /* the plane touches the sphere here: no crack */
    const double dist = fabs(m) / sqrt(nt2) / F; /* on the unit sphere */
    const double texels = dist / (M_PI / 2) * (double)s->nout; /* in delivered texels */
    return texels >= LEAD_W_TEX ? 0 : 1 - texels / LEAD_W_TEX;
}

/* The unit direction of delivered texel (f, X, Y). */
static void texel_dir(const pg_sea_ice *s, int f, int64_t X, int64_t Y, double d[3]) {
    const double u = (2.0 * (double)X + 1.0) / (double)s->nout - 1.0;
    const double v = (2.0 * (double)Y + 1.0) / (double)s->nout - 1.0;
    pg_cube_to_dir(PG_CUBE_DEFAULT_PROJECTION, f, u, v, d);
    pg_vec3_normalize(d);
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
    (void)nout; /* the noises are computed where they are needed, not stored */
    return 6.0 * (double)world_n * (double)world_n * sizeof(float);
}

pg_status pg_sea_ice_init(pg_sea_ice *s, const pg_planet_world *w, const pg_synth_exemplar *ex,
                          const uint8_t *types, uint64_t seed, int64_t nout, pg_error *err) {
    memset(s, 0, sizeof *s);
    if (!w || w->n < 1 || !w->temperature_c || nout < 1)
        return pg_error_set(err, PG_ERR_BADINPUT, "sea ice: no macro world");
    s->world = w;
    s->nout = nout;
    s->seed = seed;
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
    return PG_OK;
}

void pg_sea_ice_free(pg_sea_ice *s) {
    free(s->warm_min);
    memset(s, 0, sizeof *s);
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

/* The cover target at delivered texel (f, X, Y); d gets the texel's direction wherever
 * the target can be above 0. */
static double cover(const pg_sea_ice *s, int f, int64_t X, int64_t Y, double d[3]) {
    const double k = (double)s->world->n / (double)s->nout;
    const double fx = (X + 0.5) * k - 0.5, fy = (Y + 0.5) * k - 0.5;
    if (!s->sample_all && surely_open(s, f, fx, fy)) return 0;
    const double t = temperature_at(s, f, fx, fy);
    if (!(t < T_NONE)) return 0; /* no edge noise reaches it (and no NaN goes on) */
    const double u = (T_OPEN - t) / (T_OPEN - T_PACK);
    texel_dir(s, f, X, Y, d);
    if (u - A_EDGE / 2 >= C_MAX) return C_MAX; /* the pack, whatever the edge noise */
    const double c = u + A_EDGE * (noise(s, EDGE, d, SD_EDGE) - 0.5);
    return c <= 0 ? 0 : c > C_MAX ? C_MAX : c;
}

double pg_sea_ice_cover(const pg_sea_ice *s, int f, int64_t X, int64_t Y) {
    double d[3];
    return cover(s, f, X, Y, d);
}

bool pg_sea_ice_apply(const pg_sea_ice *s, int f, int64_t X, int64_t Y, float height,
                      float sea_level, float rgb[3]) {
    if (height > sea_level) return false;
    double d[3];
    const double c = cover(s, f, X, Y, d);
    if (c <= 0) return false;
    double a = (c - noise(s, FLOES, d, SD_FLOES)) / W_STEP + 0.5;
    a = a < 0 ? 0 : a > 1 ? 1 : a;
    if (a <= 0) return false;
    const double nt = noise(s, TONE, d, SD_TONE), tone = 0.945 + 0.11 * (nt - 0.5);
    /* a lead is open where the tone noise is above 0.55, so the network breaks
     * into separate cracks instead of closing into cells */
    const double open = fmin(1.0, fmax(0.0, (nt - 0.55) * 8));
    const double lead = open > 0 ? open * lead_edge(s, d) : 0;
    /* thin ice shows the water: at the margin, and along the leads */
    const double keep = fmax(THIN_KEEP * (1 - c / C_MAX), LEAD_KEEP * lead);
    for (int j = 0; j < 3; j++) {
        double ice = (1 - keep) * fmin(1.0, s->ice_rgb[j] * tone) + keep * rgb[j];
        rgb[j] = (float)(rgb[j] + a * (ice - rgb[j]));
    }
    return a >= 0.5;
}
