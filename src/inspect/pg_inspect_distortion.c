/* pg_inspect_distortion.c - the content-blind distortion check (pg_inspect_distortion.h,
 * docs/inspect.md): the Jacobian of planet ground -> exemplar ground, read from the
 * planet's coordinate map, summarised over 26 caps at the cube's special points.
 *
 * THE JACOBIAN. The map sends each planet texel to the exemplar texel synthesis copied
 * into it. Where a patch was copied, the sources of a small window are an affine image
 * of the window, and the linear part J (ground km per ground km) says how the copy was
 * laid down: rotations and mirrors keep distances (singular values 1), a lat-lon layout
 * squeezes by 1/cos(latitude) east-west, a texel-for-texel copy onto a cube corner
 * inherits the corner texels' 60/120-degree rhombus shape. J is the least-squares
 * solution of b_k - mean(b) = J (a_k - mean(a)) over the window, where a_k are the
 * planet texel centres (pg_cube_to_dir, the planet's projection) in the tangent plane
 * at the window's centre and b_k their sources (pg_planet_source_dir) in the tangent
 * plane at the centre's source, both by the azimuthal equidistant (logarithm) map, in
 * km on the sphere of the ellipsoid's mean radius (2a + b) / 3. The singular values of
 * J do not depend on the orthonormal frames chosen in either plane (J -> R1 J R2), and
 * the log map is an isometry to first order at its centre, so over a window of a few
 * texels (1e-6 of the radius) the frames add no error worth naming.
 *
 * THE WINDOW is the 5x5 texels around the texel, clipped to its face, or the 3x3 where
 * the 5x5 is not coherent (it straddles a patch seam). Sources are whole exemplar
 * texels, so a faithful copy of a non-integer map (say from an exemplar cube of another
 * projection) is the true map rounded to texel centres; over a 3x3 window the rounding
 * tilts J by up to half a texel per step, which inflates the anisotropy (a >= 1 for any
 * noise): copying a gnomonic exemplar cube of 1170 onto the equi-angular N = 1024, the
 * mean anisotropy at a face centre is 1.33 on 3x3 windows, 1.18 on 5x5 (figure 1.61,
 * 1.28), and the ratio 1.07, 1.03. Integer maps (texel-for-texel copies on one grid)
 * are exact.
 *
 * COHERENCE. The rounding leaves each source off by at most half the texel's long
 * diagonal (0.71 texel on a square texel, 0.87 on a 60/120 rhombus); the fit absorbs
 * what the errors share (mean and gradient), and what is left stays below one texel: on
 * faithful rounded copies (equi-angular planet of 256 copying gnomonic exemplar cubes of
 * 200, 301, 400 and an equal-area one of 237) the largest residual over every texel is
 * 0.69-0.70 texel, and 1.03 only at 24 windows of face corners whose sources repeat
 * (degenerate anyway). A window straddling two patches copied from different places
 * leaves their offset, typically many texels. So a window is coherent when its largest
 * residual is at most one exemplar texel (PG_INSPECT_DISTORTION_RESIDUAL; the larger of
 * the exemplar grid's two spacings at the source) and J is not degenerate: degenerate
 * when, per window step, the sources move less than a quarter texel in some direction,
 * so that rounding may have made a 3x3 window's sources equal and J would measure
 * rounding, not geometry (PG_INSPECT_DISTORTION_MIN_STEP).
 *
 * MAGNIFICATION. A magnified planet holds one source per aligned m x m block; windows
 * of single texels would see repeats (J ~ 1/m, mostly degenerate). The map is scanned
 * for the largest such m, and everything works on the N/m block grid with block-centre
 * positions: exactly the planet synthesis saw.
 *
 * THE CAPS. A cap holds the texels (blocks) whose centre direction is within the cap
 * angle of the view's centre. To find them without visiting every texel, each face is
 * tiled into superblocks of 16 x 16 blocks with a bounding angle around their centre:
 * on the gnomonic and equi-angular grids lines of constant u or v are great circles, so
 * a superblock is a geodesic quadrilateral and the farthest of its texel centres from
 * any point of it is one of its corner texels; the bound takes the corners and edge
 * midpoints and adds 5% for the slightly curved lines of the equal-area grid. Only
 * superblocks whose bound meets the cap are visited texel by texel.
 *
 * DETERMINISM. Views run in parallel (OpenMP), each summed by one thread in a fixed
 * (face, row, column) order, so results do not depend on the thread count. */
#include "planetgen/pg_inspect_distortion.h"
#include "planetgen/pg_synth.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SUPER 16        /* blocks per superblock edge */
#define WINDOW_RADIUS 2 /* the 5x5 window; the fallback is radius 1 */

static const double PI = 3.14159265358979323846;

/* ---- the 26 views ---- */

typedef struct view_def {
    const char *name;
    pg_inspect_distortion_kind kind;
    double d[3]; /* not normalised */
} view_def;

static const view_def VIEWS[PG_INSPECT_DISTORTION_NVIEWS] = {
    {"north", PG_INSPECT_DISTORTION_POLE, {0, 0, 1}},
    {"south", PG_INSPECT_DISTORTION_POLE, {0, 0, -1}},
    {"equator_0", PG_INSPECT_DISTORTION_EQUATOR, {1, 0, 0}},
    {"equator_90e", PG_INSPECT_DISTORTION_EQUATOR, {0, 1, 0}},
    {"equator_180", PG_INSPECT_DISTORTION_EQUATOR, {-1, 0, 0}},
    {"equator_90w", PG_INSPECT_DISTORTION_EQUATOR, {0, -1, 0}},
    {"corner_n45e", PG_INSPECT_DISTORTION_CORNER, {1, 1, 1}},
    {"corner_n135e", PG_INSPECT_DISTORTION_CORNER, {-1, 1, 1}},
    {"corner_n135w", PG_INSPECT_DISTORTION_CORNER, {-1, -1, 1}},
    {"corner_n45w", PG_INSPECT_DISTORTION_CORNER, {1, -1, 1}},
    {"corner_s45e", PG_INSPECT_DISTORTION_CORNER, {1, 1, -1}},
    {"corner_s135e", PG_INSPECT_DISTORTION_CORNER, {-1, 1, -1}},
    {"corner_s135w", PG_INSPECT_DISTORTION_CORNER, {-1, -1, -1}},
    {"corner_s45w", PG_INSPECT_DISTORTION_CORNER, {1, -1, -1}},
    {"edge_n0", PG_INSPECT_DISTORTION_EDGE, {1, 0, 1}},
    {"edge_n90e", PG_INSPECT_DISTORTION_EDGE, {0, 1, 1}},
    {"edge_n180", PG_INSPECT_DISTORTION_EDGE, {-1, 0, 1}},
    {"edge_n90w", PG_INSPECT_DISTORTION_EDGE, {0, -1, 1}},
    {"edge_45e", PG_INSPECT_DISTORTION_EDGE, {1, 1, 0}},
    {"edge_135e", PG_INSPECT_DISTORTION_EDGE, {-1, 1, 0}},
    {"edge_135w", PG_INSPECT_DISTORTION_EDGE, {-1, -1, 0}},
    {"edge_45w", PG_INSPECT_DISTORTION_EDGE, {1, -1, 0}},
    {"edge_s0", PG_INSPECT_DISTORTION_EDGE, {1, 0, -1}},
    {"edge_s90e", PG_INSPECT_DISTORTION_EDGE, {0, 1, -1}},
    {"edge_s180", PG_INSPECT_DISTORTION_EDGE, {-1, 0, -1}},
    {"edge_s90w", PG_INSPECT_DISTORTION_EDGE, {0, -1, -1}},
};

/* ---- angles and tangent frames ---- */

/* The angle between a and b, well conditioned near 0 and pi. */
static double angle3(const double a[3], const double b[3]) {
    double c[3];
    pg_vec3_cross(a, b, c);
    return atan2(pg_vec3_length(c), pg_vec3_dot(a, b));
}

/* Orthonormal tangent frame (t1, t2) at unit p: t1 from the axis p leans on least. */
typedef struct tangent {
    double p[3], t1[3], t2[3];
} tangent;

static void tangent_init(tangent *t, const double p[3]) {
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (fabs(p[i]) < fabs(p[k])) k = i;
    double e[3] = {0, 0, 0};
    e[k] = 1;
    double c = pg_vec3_dot(e, p);
    for (int i = 0; i < 3; i++) {
        t->p[i] = p[i];
        t->t1[i] = e[i] - c * p[i];
    }
    pg_vec3_normalize(t->t1);
    pg_vec3_cross(p, t->t1, t->t2);
}

/* Azimuthal equidistant (log) map of unit q at t->p, scaled by radius r: the tangent
 * component w of q, |w| = sin(angle), stretched to length angle. Near p (angle < 0.01)
 * asin(s) / s = 1 + s^2/6 + 3 s^4/40 + O(s^6), exact to 1e-13, saves the atan2. */
static void tangent_log(const tangent *t, const double q[3], double r, double out[2]) {
    double c = pg_vec3_dot(t->p, q), w[3];
    for (int i = 0; i < 3; i++)
        w[i] = q[i] - c * t->p[i];
    double s2 = pg_vec3_dot(w, w), s = sqrt(s2);
    double k = c > 0 && s < 0.01 ? r * (1 + s2 / 6 + 0.075 * s2 * s2)
                                 : (s > 0 ? r * atan2(s, c) / s : 0.0);
    out[0] = k * pg_vec3_dot(w, t->t1);
    out[1] = k * pg_vec3_dot(w, t->t2);
}

/* ---- least squares and singular values ---- */

/* A least-squares linear fit y_k - ybar = J (x_k - xbar) + residual. */
typedef struct lsq {
    double J[2][2];
    double worst; /* largest residual length */
} lsq;

/* Returns false when the x_k do not span the plane. */
static bool fit_linear(int n, const double x[][2], const double y[][2], lsq *o) {
    double xm[2] = {0, 0}, ym[2] = {0, 0};
    for (int k = 0; k < n; k++)
        for (int i = 0; i < 2; i++) {
            xm[i] += x[k][i] / n;
            ym[i] += y[k][i] / n;
        }
    double sxx[2][2] = {{0, 0}, {0, 0}}, syx[2][2] = {{0, 0}, {0, 0}};
    for (int k = 0; k < n; k++)
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2; j++) {
                sxx[i][j] += (x[k][i] - xm[i]) * (x[k][j] - xm[j]);
                syx[i][j] += (y[k][i] - ym[i]) * (x[k][j] - xm[j]);
            }
    double det = sxx[0][0] * sxx[1][1] - sxx[0][1] * sxx[1][0];
    if (!(det > 1e-12 * (sxx[0][0] * sxx[1][1]))) return false;
    double inv[2][2] = {{sxx[1][1] / det, -sxx[0][1] / det}, {-sxx[1][0] / det, sxx[0][0] / det}};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            o->J[i][j] = syx[i][0] * inv[0][j] + syx[i][1] * inv[1][j];
    o->worst = 0;
    for (int k = 0; k < n; k++) {
        double dx0 = x[k][0] - xm[0], dx1 = x[k][1] - xm[1];
        double r0 = y[k][0] - ym[0] - (o->J[0][0] * dx0 + o->J[0][1] * dx1);
        double r1 = y[k][1] - ym[1] - (o->J[1][0] * dx0 + o->J[1][1] * dx1);
        o->worst = fmax(o->worst, sqrt(r0 * r0 + r1 * r1));
    }
    return true;
}

/* Singular values s1 >= s2 >= 0 of a 2x2 matrix, from its Frobenius norm and |det|. */
static void singular2(const double J[2][2], double *s1, double *s2) {
    double t = J[0][0] * J[0][0] + J[0][1] * J[0][1] + J[1][0] * J[1][0] + J[1][1] * J[1][1];
    double d = fabs(J[0][0] * J[1][1] - J[0][1] * J[1][0]);
    double disc = sqrt(fmax(0.0, t * t - 4 * d * d));
    *s1 = sqrt((t + disc) / 2);
    *s2 = *s1 > 0 ? d / *s1 : 0.0;
}

/* ---- the two grids ---- */

static double mean_radius_km(const pg_planet *p) {
    return p->ellipsoid.a * (1.0 - p->ellipsoid.f / 3.0) / 1000.0;
}

static void block_dir(const pg_planet *p, int64_t nb, int face, int64_t bx, int64_t by,
                      double d[3]) {
    pg_cube_to_dir(p->projection, face, (2.0 * bx + 1.0) / nb - 1.0, (2.0 * by + 1.0) / nb - 1.0,
                   d);
}

static uint32_t block_source(const pg_planet *p, int m, int face, int64_t bx, int64_t by) {
    return p->source.coords[face][(size_t)(by * m) * (size_t)p->n + (size_t)(bx * m)];
}

static void exemplar_dir(const pg_planet_source *s, int face, int u, int v, double d[3]) {
    double e = s->face_size;
    pg_cube_to_dir(s->projection, face, (2.0 * u + 1.0) / e - 1.0, (2.0 * v + 1.0) / e - 1.0, d);
}

/* Ground spacing (km) of the exemplar grid at source c along u or v (axis 0 / 1). */
static double exemplar_step(const pg_planet_source *s, uint32_t c, int axis, double r) {
    int f = pg_synth_face(c), u = pg_synth_u(c), v = pg_synth_v(c), e = s->face_size;
    int t = axis ? v : u, lo = t > 0 ? t - 1 : t, hi = t < e - 1 ? t + 1 : t;
    if (hi == lo) return r * PI / 2;
    double a[3], b[3];
    exemplar_dir(s, f, axis ? u : lo, axis ? lo : v, a);
    exemplar_dir(s, f, axis ? u : hi, axis ? hi : v, b);
    return r * angle3(a, b) / (hi - lo);
}

/* ---- one texel ---- */

/* The directions of the block centres and of their sources over a rectangle of one
 * face: computed once per cap, read by every window in it. */
typedef struct region {
    int face;
    int64_t x0, y0, x1, y1; /* blocks [x0, x1) x [y0, y1) */
    double *pd, *sd;        /* 3 doubles per block, row-major */
} region;

static void region_fill(const pg_planet *p, int m, region *g) {
    const int64_t nb = p->n / m, w = g->x1 - g->x0;
    for (int64_t y = g->y0; y < g->y1; y++)
        for (int64_t x = g->x0; x < g->x1; x++) {
            size_t i = (size_t)(3 * ((y - g->y0) * w + (x - g->x0)));
            block_dir(p, nb, g->face, x, y, g->pd + i);
            pg_planet_source_dir(p, g->face, x * m, y * m, g->sd + i);
        }
}

static size_t region_at(const region *g, int64_t x, int64_t y) {
    return (size_t)(3 * ((y - g->y0) * (g->x1 - g->x0) + (x - g->x0)));
}

#define WMAX ((2 * WINDOW_RADIUS + 1) * (2 * WINDOW_RADIUS + 1))

typedef struct window {
    int n;
    double a[WMAX][2]; /* planet offsets, km */
    double b[WMAX][2]; /* source offsets, km */
    double g[WMAX][2]; /* window step indices */
} window;

/* The window of radius rad around (bx, by), clipped to the region (which holds the
 * texel's window within the face). */
static void gather_window(const region *g, int64_t bx, int64_t by, int rad, double r, window *w) {
    size_t c = region_at(g, bx, by);
    tangent tp, ts;
    tangent_init(&tp, g->pd + c);
    tangent_init(&ts, g->sd + c);
    w->n = 0;
    for (int j = -rad; j <= rad; j++)
        for (int i = -rad; i <= rad; i++) {
            int64_t x = bx + i, y = by + j;
            if (x < g->x0 || y < g->y0 || x >= g->x1 || y >= g->y1) continue;
            size_t k = region_at(g, x, y);
            tangent_log(&tp, g->pd + k, r, w->a[w->n]);
            tangent_log(&ts, g->sd + k, r, w->b[w->n]);
            w->g[w->n][0] = i;
            w->g[w->n][1] = j;
            w->n++;
        }
}

/* Does the window hold at least PG_INSPECT_DISTORTION_MIN_SPAN distinct steps along
 * each axis? */
static bool window_span_ok(const window *w) {
    int lo[2] = {1 << 20, 1 << 20}, hi[2] = {-(1 << 20), -(1 << 20)};
    for (int k = 0; k < w->n; k++)
        for (int a = 0; a < 2; a++) {
            int v = (int)w->g[k][a];
            lo[a] = v < lo[a] ? v : lo[a];
            hi[a] = v > hi[a] ? v : hi[a];
        }
    return hi[0] - lo[0] + 1 >= PG_INSPECT_DISTORTION_MIN_SPAN &&
           hi[1] - lo[1] + 1 >= PG_INSPECT_DISTORTION_MIN_SPAN;
}

static void texel_nan(pg_inspect_distortion_texel *out, int points) {
    memset(out, 0, sizeof *out);
    out->points = points;
    out->s1 = out->s2 = out->scale = out->anisotropy = out->figure = NAN;
    out->residual = out->span = NAN;
    out->degenerate = true;
}

/* The measure over the window of radius rad; hu, hv: the exemplar grid's spacings (km)
 * at the texel's source. */
static void measure(const pg_planet *p, const region *g, int64_t bx, int64_t by, int rad, double hu,
                    double hv, pg_inspect_distortion_texel *out) {
    const double r = mean_radius_km(p);
    window w;
    gather_window(g, bx, by, rad, r, &w);
    lsq fj, fm;
    if (!fit_linear(w.n, (const double(*)[2])w.a, (const double(*)[2])w.b, &fj) ||
        !fit_linear(w.n, (const double(*)[2])w.g, (const double(*)[2])w.b, &fm))
        return texel_nan(out, w.n);
    double m1, m2;
    singular2(fm.J, &m1, &m2);
    memset(out, 0, sizeof *out);
    out->points = w.n;
    singular2(fj.J, &out->s1, &out->s2);
    out->scale = sqrt(out->s1 * out->s2);
    out->anisotropy = out->s2 > 0 ? out->s1 / out->s2 : INFINITY;
    out->figure = fmax(out->scale, 1.0 / out->scale) * out->anisotropy;
    out->residual = fj.worst / fmax(hu, hv);
    out->span = m2 / sqrt(hu * hv);
    out->mirrored = fj.J[0][0] * fj.J[1][1] - fj.J[0][1] * fj.J[1][0] < 0;
    out->degenerate = !(out->span >= PG_INSPECT_DISTORTION_MIN_STEP) || !(out->s2 > 0);
    /* a window only two texels wide fits any jump between its two columns (or rows)
     * as a linear map: it cannot tell a copy from a patch seam */
    out->coherent =
        !out->degenerate && out->residual <= PG_INSPECT_DISTORTION_RESIDUAL && window_span_ok(&w);
}

/* The wide window where it is coherent (less rounding noise), else the 3x3. */
static void measure_texel(const pg_planet *p, int m, const region *g, int64_t bx, int64_t by,
                          pg_inspect_distortion_texel *out) {
    const double r = mean_radius_km(p);
    uint32_t c = block_source(p, m, g->face, bx, by);
    double hu = exemplar_step(&p->source, c, 0, r), hv = exemplar_step(&p->source, c, 1, r);
    measure(p, g, bx, by, WINDOW_RADIUS, hu, hv, out);
    if (!out->coherent && WINDOW_RADIUS > 1) measure(p, g, bx, by, 1, hu, hv, out);
}

void pg_inspect_distortion_texel_at(const pg_planet *p, int m, int face, int64_t bx, int64_t by,
                                    pg_inspect_distortion_texel *out) {
    const int64_t nb = p->n / m;
    double pd[3 * WMAX], sd[3 * WMAX];
    region g = {face,
                bx > WINDOW_RADIUS ? bx - WINDOW_RADIUS : 0,
                by > WINDOW_RADIUS ? by - WINDOW_RADIUS : 0,
                bx + WINDOW_RADIUS + 1 < nb ? bx + WINDOW_RADIUS + 1 : nb,
                by + WINDOW_RADIUS + 1 < nb ? by + WINDOW_RADIUS + 1 : nb,
                pd,
                sd};
    region_fill(p, m, &g);
    measure_texel(p, m, &g, bx, by, out);
}

/* ---- the map: validity and magnification ---- */

static pg_status check_map(const pg_planet *p, pg_error *err) {
    const int64_t n = p->n;
    const int e = p->source.face_size;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t i = 0; i < n * n; i++) {
            uint32_t c = p->source.coords[f][i];
            if (pg_synth_face(c) < PG_CUBE_NFACES && pg_synth_u(c) < e && pg_synth_v(c) < e)
                continue;
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "coordinate map: texel (%s, %lld, %lld) points at (face %d, %d, "
                                "%d), outside the exemplar cube of %d texels per face edge",
                                pg_cube_face_name(f), (long long)(i % n), (long long)(i / n),
                                pg_synth_face(c), pg_synth_u(c), pg_synth_v(c), e);
        }
    return PG_OK;
}

static uint32_t coord_at(const pg_planet *p, int f, int64_t x, int64_t y) {
    return p->source.coords[f][(size_t)y * (size_t)p->n + (size_t)x] & ~PG_SYNTH_ORIENT_MASK;
}

/* Does every aligned m x m block hold one source? */
static bool blocks_constant(const pg_planet *p, int64_t m) {
    const int64_t n = p->n;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int64_t y = 0; y < n; y++)
            for (int64_t x = 0; x < n; x++)
                if (coord_at(p, f, x, y) != coord_at(p, f, x - x % m, y - y % m)) return false;
    return true;
}

int pg_inspect_distortion_magnification(const pg_planet *p) {
    if (!pg_planet_has_source(p)) return 1;
    int m = 1;
    while (p->n % (2 * m) == 0 && p->n / (2 * m) >= 2 && blocks_constant(p, 2 * m))
        m *= 2;
    return m;
}

/* ---- superblocks and caps ---- */

typedef struct superblock {
    double c[3];            /* direction of the centre */
    double rad;             /* bounding angle of its block centres around c */
    double cos_reach;       /* cos(cap + rad): a cap centred farther than that misses it */
    int64_t x0, y0, x1, y1; /* blocks [x0, x1) x [y0, y1) */
} superblock;

static void superblock_init(const pg_planet *p, int64_t nb, int f, int64_t sx, int64_t sy,
                            double cap, superblock *s) {
    s->x0 = sx * SUPER;
    s->y0 = sy * SUPER;
    s->x1 = s->x0 + SUPER < nb ? s->x0 + SUPER : nb;
    s->y1 = s->y0 + SUPER < nb ? s->y0 + SUPER : nb;
    double u0 = (2.0 * s->x0 + 1) / nb - 1, u1 = (2.0 * s->x1 - 1) / nb - 1;
    double v0 = (2.0 * s->y0 + 1) / nb - 1, v1 = (2.0 * s->y1 - 1) / nb - 1;
    pg_cube_to_dir(p->projection, f, (u0 + u1) / 2, (v0 + v1) / 2, s->c);
    double us[3] = {u0, (u0 + u1) / 2, u1}, vs[3] = {v0, (v0 + v1) / 2, v1}, d[3];
    s->rad = 0;
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            pg_cube_to_dir(p->projection, f, us[i], vs[j], d);
            s->rad = fmax(s->rad, angle3(s->c, d));
        }
    s->rad = s->rad * 1.05 + 1e-9;
    s->cos_reach = cap + s->rad < PI ? cos(cap + s->rad) : -1.0;
}

typedef struct view_acc {
    int64_t texels, coherent, degenerate;
    double sum_figure, sum_scale, sum_aniso;
} view_acc;

/* Bounding box [x0, x1) x [y0, y1) of the blocks of face f inside the cap; false if none. */
static bool cap_bbox(const pg_planet *p, int m, int f, const superblock *sb, int64_t ns,
                     const double c[3], double cap, region *g) {
    const int64_t nb = p->n / m;
    const double cos_cap = cos(cap);
    g->x0 = g->y0 = nb;
    g->x1 = g->y1 = 0;
    for (int64_t i = 0; i < ns * ns; i++) {
        const superblock *s = &sb[f * ns * ns + i];
        if (pg_vec3_dot(s->c, c) < s->cos_reach) continue;
        for (int64_t y = s->y0; y < s->y1; y++)
            for (int64_t x = s->x0; x < s->x1; x++) {
                double d[3];
                block_dir(p, nb, f, x, y, d);
                if (pg_vec3_dot(d, c) < cos_cap) continue;
                g->x0 = x < g->x0 ? x : g->x0;
                g->y0 = y < g->y0 ? y : g->y0;
                g->x1 = x + 1 > g->x1 ? x + 1 : g->x1;
                g->y1 = y + 1 > g->y1 ? y + 1 : g->y1;
            }
    }
    return g->x1 > g->x0;
}

/* Measure every block of the region's interior box [bx0, bx1) x [by0, by1) inside the cap. */
static void visit_region(const pg_planet *p, int m, const region *g, const int64_t box[4],
                         const double c[3], double cos_cap, view_acc *acc) {
    for (int64_t y = box[1]; y < box[3]; y++)
        for (int64_t x = box[0]; x < box[2]; x++) {
            if (pg_vec3_dot(g->pd + region_at(g, x, y), c) < cos_cap) continue;
            pg_inspect_distortion_texel t;
            measure_texel(p, m, g, x, y, &t);
            acc->texels++;
            acc->degenerate += t.degenerate;
            if (!t.coherent) continue;
            acc->coherent++;
            acc->sum_figure += t.figure;
            acc->sum_scale += t.scale;
            acc->sum_aniso += t.anisotropy;
        }
}

/* One face's part of a cap: its bounding box, widened by the window and clipped to the
 * face, gets its directions computed once. false when out of memory. */
static bool face_part(const pg_planet *p, int m, int f, const superblock *sb, int64_t ns,
                      const double c[3], double cap, view_acc *acc) {
    const int64_t nb = p->n / m, R = WINDOW_RADIUS;
    region g = {f, 0, 0, 0, 0, NULL, NULL};
    if (!cap_bbox(p, m, f, sb, ns, c, cap, &g)) return true;
    const int64_t box[4] = {g.x0, g.y0, g.x1, g.y1};
    g.x0 = g.x0 > R ? g.x0 - R : 0;
    g.y0 = g.y0 > R ? g.y0 - R : 0;
    g.x1 = g.x1 + R < nb ? g.x1 + R : nb;
    g.y1 = g.y1 + R < nb ? g.y1 + R : nb;
    size_t cnt = (size_t)((g.x1 - g.x0) * (g.y1 - g.y0)) * 3;
    g.pd = malloc(cnt * sizeof *g.pd);
    g.sd = malloc(cnt * sizeof *g.sd);
    bool ok = g.pd && g.sd;
    if (ok) {
        region_fill(p, m, &g);
        visit_region(p, m, &g, box, c, cos(cap), acc);
    }
    free(g.pd);
    free(g.sd);
    return ok;
}

static bool view_compute(const pg_planet *p, int m, const superblock *sb, int64_t ns, double cap,
                         pg_inspect_distortion_view *v) {
    view_acc acc = {0, 0, 0, 0, 0, 0};
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        if (!face_part(p, m, f, sb, ns, v->dir, cap, &acc)) return false;
    v->texels = acc.texels;
    v->coherent = acc.coherent;
    v->degenerate = acc.degenerate;
    v->share = acc.texels ? (double)acc.coherent / acc.texels : NAN;
    v->figure = acc.coherent ? acc.sum_figure / acc.coherent : NAN;
    v->mean_scale = acc.coherent ? acc.sum_scale / acc.coherent : NAN;
    v->mean_anisotropy = acc.coherent ? acc.sum_aniso / acc.coherent : NAN;
    return true;
}

/* ---- the report ---- */

static void init_out(pg_inspect_distortion *out) {
    memset(out, 0, sizeof *out);
    out->cap_deg = PG_INSPECT_DISTORTION_CAP_DEG;
    out->magnification = 1;
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++) {
        pg_inspect_distortion_view *v = &out->views[i];
        v->name = VIEWS[i].name;
        v->kind = VIEWS[i].kind;
        memcpy(v->dir, VIEWS[i].d, sizeof v->dir);
        pg_vec3_normalize(v->dir);
        v->share = v->figure = v->mean_scale = v->mean_anisotropy = NAN;
    }
    out->worst_figure = out->reference = out->ratio = out->share_ratio = NAN;
    out->worst = -1;
    out->worst_name = "none";
}

static bool is_reference(const pg_inspect_distortion_view *v) {
    return v->kind == PG_INSPECT_DISTORTION_EQUATOR || v->kind == PG_INSPECT_DISTORTION_EDGE;
}

/* The worst pole-or-corner view: the first without a figure (no coherent texel: nothing
 * there is a faithful copy of anything), else the largest figure. */
static void find_worst(pg_inspect_distortion *out) {
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++) {
        const pg_inspect_distortion_view *v = &out->views[i];
        if (is_reference(v)) continue;
        if (!isfinite(v->figure)) {
            out->worst = i;
            break;
        }
        if (out->worst < 0 || v->figure > out->views[out->worst].figure) out->worst = i;
    }
    out->worst_figure = out->views[out->worst].figure;
    out->worst_name = out->views[out->worst].name;
}

static void summarise(pg_inspect_distortion *out) {
    double ref = 0, share = 0, low_share = INFINITY;
    int nref = 0;
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++) {
        const pg_inspect_distortion_view *v = &out->views[i];
        if (is_reference(v)) {
            ref += v->figure;
            share += v->share;
            nref++;
        } else {
            low_share = fmin(low_share, v->share);
        }
    }
    find_worst(out);
    out->reference = ref / nref;
    out->share_ratio = low_share / (share / nref);
    out->ratio = out->worst_figure / out->reference;
    out->gate_pass = out->ratio <= PG_INSPECT_DISTORTION_GATE;
}

pg_status pg_inspect_distortion_compute(const pg_planet *p, pg_inspect_distortion *out,
                                        pg_error *err) {
    init_out(out);
    if (!pg_planet_has_source(p)) return PG_OK;
    pg_status st = check_map(p, err);
    if (st != PG_OK) return st;
    const int m = pg_inspect_distortion_magnification(p);
    const int64_t nb = p->n / m, ns = (nb + SUPER - 1) / SUPER;
    out->magnification = m;
    if (nb < 2)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "distortion: faces of %lld texels are too small for 3x3 windows",
                            (long long)p->n);
    superblock *sb = malloc((size_t)(PG_CUBE_NFACES * ns * ns) * sizeof *sb);
    if (!sb) return pg_error_set(err, PG_ERR_NOMEM, "distortion: out of memory");
    const double cap = out->cap_deg * PI / 180.0;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < PG_CUBE_NFACES * ns * ns; i++)
        superblock_init(p, nb, (int)(i / (ns * ns)), i % ns, (i / ns) % ns, cap, &sb[i]);
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : failed)
    for (int i = 0; i < PG_INSPECT_DISTORTION_NVIEWS; i++)
        failed += !view_compute(p, m, sb, ns, cap, &out->views[i]);
    free(sb);
    if (failed) return pg_error_set(err, PG_ERR_NOMEM, "distortion: out of memory");
    summarise(out);
    return PG_OK;
}
