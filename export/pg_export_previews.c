/* pg_export_previews.c - preview images of a planet: equirectangular albedo and
 * shaded relief, and orthographic globe renders from four sides.
 *
 * Both work on a reduced copy of the planet, held as one contiguous cube buffer of
 * (R, G, B, height) so pg_cube_to_equirect and pg_cube_sample_grid can read it. The
 * faces are box-filtered by the largest integer factor that keeps as many texels as
 * the images need: a quarter of the equirect width (the equator crosses four faces),
 * and the globe size (a face texel then spans less than a pixel at the disc's
 * centre). A smaller cube is also a faster one: the samples stay in cache.
 *
 * The globe renders are a small CPU ray caster: an orthographic camera, intersected
 * with the ellipsoid (scaled to a sphere); the hit point's direction samples the cube.
 * Coverage uses 2 x 2 rays per pixel (a smooth limb); colour and height are sampled
 * once per pixel, at its centre. Shading is Lambert under a light from the upper left,
 * with the ellipsoid normal tilted by the exaggerated height gradient. The gradient is
 * taken between neighbouring pixels: their hit points and heights give two height
 * differences along two surface directions, which fix it in the tangent plane. So it is
 * the relief at the scale the render shows, and one cube sample a pixel suffices. The
 * relief is shaded, not displaced: at globe scale its silhouette is invisible anyway. */
#include "pg_huge.h"
#include "pg_export_internal.h"
#include "planetgen/pg_relief.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLOBE_DEFAULT_SIZE 512

typedef struct reduced {
    int64_t n;   /* texels per face edge */
    float *cube; /* 6*n*n*4: R, G, B, height (metres) */
} reduced;

static int equirect_width(const pg_export_opts *o, int64_t n) {
    return o->preview_width > 0 ? o->preview_width : (int)(4 * n < 2048 ? 4 * n : 2048);
}

static int globe_size(const pg_export_opts *o) {
    return o->globe_size > 0 ? o->globe_size : GLOBE_DEFAULT_SIZE;
}

/* The largest factor k dividing the face size that leaves at least `need` texels. */
static int64_t reduce_factor(int64_t n, int64_t need) {
    int64_t best = 1;
    for (int64_t k = 2; k <= n && n / k >= need; k++)
        if (n % k == 0) best = k;
    return best;
}

static pg_status reduce(const pg_planet *p, const pg_export_opts *o, reduced *r, pg_error *err) {
    int64_t need = (equirect_width(o, p->n) + 3) / 4, gs = globe_size(o);
    const int64_t k = reduce_factor(p->n, need > gs ? need : gs);
    r->n = p->n / k;
    size_t nn = (size_t)r->n * r->n;
    r->cube = pg_huge_calloc(6 * nn * 4, sizeof(float));
    if (!r->cube) return pg_error_set(err, PG_ERR_NOMEM, "cannot allocate the preview planet");
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
#pragma omp parallel for schedule(static)
        for (int64_t y = 0; y < r->n; y++)
            for (int64_t x = 0; x < r->n; x++) {
                double s[4] = {0, 0, 0, 0};
                for (int64_t b = 0; b < k; b++)
                    for (int64_t a = 0; a < k; a++) {
                        int64_t t = (y * k + b) * p->n + x * k + a;
                        for (int c = 0; c < 3; c++)
                            s[c] += p->albedo[f][3 * t + c];
                        s[3] += p->height[f][t];
                    }
                float *o = r->cube + 4 * ((size_t)f * nn + (size_t)y * r->n + x);
                for (int c = 0; c < 4; c++)
                    o[c] = (float)(s[c] / (double)(k * k));
            }
    }
    return PG_OK;
}

/* Write n PNGs at once: each encoding is single-threaded (zlib), so the images are
 * encoded in parallel, one per thread. The paths are taken first, in order, because
 * path_for need not be thread-safe. The first failure in image order is reported. */
static pg_status write_pngs(int n, const char *const *names, const pg_image *imgs,
                            pg_planet_path_fn path_for, void *user, int *nfiles, pg_error *err) {
    char paths[8][4096];
    for (int i = 0; i < n; i++) {
        const char *path = path_for(names[i], user);
        if (!path) return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", names[i]);
        snprintf(paths[i], sizeof paths[i], "%s", path);
        (*nfiles)++;
    }
    pg_status sk[8];
    pg_error e[8];
    memset(e, 0, sizeof e);
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < n; i++)
        sk[i] = pg_image_write_png(paths[i], &imgs[i], 8, &e[i]);
    for (int i = 0; i < n; i++)
        if (sk[i] != PG_OK) return pg_error_set(err, sk[i], "%s", e[i].msg);
    return PG_OK;
}

/* The equirectangular albedo and shaded relief into out[0] and out[1]. */
static pg_status equirect_previews(const pg_planet *p, const reduced *r, const pg_export_opts *o,
                                   pg_image *out, pg_error *err) {
    int w = equirect_width(o, p->n), h = w / 2;
    float *img4 = pg_huge_malloc((size_t)w * h * 4 * sizeof(float));
    pg_image *rgb = &out[0], *rel = &out[1];
    pg_status st = img4 ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "cannot allocate previews");
    if (st == PG_OK)
        st = pg_cube_to_equirect(p->projection, r->n, &p->ellipsoid, r->cube, 4, img4, w, h, err);
    if (st == PG_OK) st = pg_image_alloc(rgb, w, h, 3, err);
    if (st == PG_OK) st = pg_image_alloc(rel, w, h, 3, err);
    if (st == PG_OK) {
        float *elev = img4; /* compact the heights in place, after copying the colours */
        for (size_t i = 0; i < (size_t)w * h; i++) {
            memcpy(rgb->data + 3 * i, img4 + 4 * i, 3 * sizeof(float));
            elev[i] = img4[4 * i + 3];
        }
        pg_relief_shade(elev, w, h, p->sea_level, rel->data);
    }
    free(img4);
    return st;
}

typedef struct globe_view {
    const char *name;
    double view[3], up[3]; /* from the centre towards the camera; image up */
} globe_view;

typedef struct globe_ctx {
    const pg_planet *p;
    const reduced *r;
    pg_cube_grid g; /* the reduced cube's seam maps, built once */
    double exaggeration, a, b, ext;
    double view[3], up[3], right[3], light[3];
} globe_ctx;

/* What pass one leaves at a pixel: the surface point it shades (in units of the
 * equatorial radius), the sample there, and how many of its 2 x 2 rays hit. */
typedef struct globe_px {
    float pnt[3], rgb[3], h;
    int hits;
} globe_px;

/* The hit point of the ray through image-plane point (x, y); false on a miss. */
static bool hit_point(const globe_ctx *c, double x, double y, double pnt[3]) {
    double o[3], s = c->a / c->b; /* scale z so the ellipsoid becomes a sphere */
    for (int k = 0; k < 3; k++)
        o[k] = x * c->right[k] + y * c->up[k] + 3 * c->a * c->view[k];
    double os[3] = {o[0], o[1], o[2] * s}, ds[3] = {-c->view[0], -c->view[1], -c->view[2] * s};
    double A = pg_vec3_dot(ds, ds), B = 2 * pg_vec3_dot(os, ds),
           C = pg_vec3_dot(os, os) - c->a * c->a;
    double disc = B * B - 4 * A * C;
    if (disc < 0) return false;
    double t = (-B - sqrt(disc)) / (2 * A);
    for (int k = 0; k < 3; k++)
        pnt[k] = o[k] - t * c->view[k];
    return true;
}

/* Pass one at pixel (px, py): coverage from 2 x 2 rays, then the colour and the height
 * (the sea surface over the ocean) at the centre's hit point, or at the first hit ray's
 * when the centre misses. */
static void globe_sample(const globe_ctx *c, int size, int px, int py, globe_px *out) {
    double pnt[3], first[3];
    int hits = 0;
    for (int k = 0; k < 4; k++) {
        double x = (2 * (px + 0.25 + 0.5 * (k & 1)) / size - 1) * c->ext;
        double y = (1 - 2 * (py + 0.25 + 0.5 * (k >> 1)) / size) * c->ext;
        if (hit_point(c, x, y, pnt) && hits++ == 0) memcpy(first, pnt, sizeof pnt);
    }
    out->hits = hits;
    if (!hits) return;
    double cx = (2 * (px + 0.5) / size - 1) * c->ext, cy = (1 - 2 * (py + 0.5) / size) * c->ext;
    if (!hit_point(c, cx, cy, pnt)) memcpy(pnt, first, sizeof pnt);
    float v[4];
    pg_cube_sample_grid(&c->g, c->r->cube, 4, pnt, v);
    for (int k = 0; k < 3; k++)
        out->pnt[k] = (float)(pnt[k] / c->a), out->rgb[k] = v[k];
    out->h = v[3] > c->p->sea_level ? v[3] : (float)c->p->sea_level;
}

/* The difference across pixel q between its neighbours along one image axis (central
 * where both are on the globe, one-sided where one is): a surface step d (metres) and
 * the height change dh over it. False when neither neighbour is on the globe. */
static bool globe_step(const globe_ctx *c, const globe_px *q, const globe_px *lo,
                       const globe_px *hi, double d[3], double *dh) {
    const globe_px *a = lo && lo->hits ? lo : q, *b = hi && hi->hits ? hi : q;
    if (a == b) return false;
    for (int k = 0; k < 3; k++)
        d[k] = ((double)b->pnt[k] - a->pnt[k]) * c->a;
    *dh = (double)b->h - a->h;
    return true;
}

/* Pass two at pixel (px, py): the surface gradient g in the tangent plane from the two
 * steps (g . t_i = dh_i for their tangent parts t_i), the normal tilted by it, Lambert. */
static void globe_shade(const globe_ctx *c, const globe_px *buf, int size, int px, int py,
                        float out[3]) {
    const globe_px *q = &buf[(size_t)py * size + px];
    if (!q->hits) {
        out[0] = out[1] = out[2] = 0;
        return;
    }
    double pnt[3] = {q->pnt[0], q->pnt[1], q->pnt[2]};
    double ne[3] = {pnt[0], pnt[1], pnt[2] * (c->a * c->a) / (c->b * c->b)};
    pg_vec3_normalize(ne);
    const globe_px *W = px > 0 ? q - 1 : NULL, *E = px + 1 < size ? q + 1 : NULL;
    const globe_px *N = py > 0 ? q - size : NULL, *S = py + 1 < size ? q + size : NULL;
    double t[2][3] = {{0, 0, 0}, {0, 0, 0}}, dh[2] = {0, 0}, g[3] = {0, 0, 0};
    bool ok[2] = {globe_step(c, q, W, E, t[0], &dh[0]), globe_step(c, q, S, N, t[1], &dh[1])};
    for (int i = 0; i < 2; i++) { /* the tangent parts of the steps */
        double dn = pg_vec3_dot(t[i], ne);
        for (int k = 0; ok[i] && k < 3; k++)
            t[i][k] -= dn * ne[k];
    }
    if (ok[0] && ok[1]) { /* the Gram system of the two steps */
        double a11 = pg_vec3_dot(t[0], t[0]), a12 = pg_vec3_dot(t[0], t[1]),
               a22 = pg_vec3_dot(t[1], t[1]), det = a11 * a22 - a12 * a12;
        if (det > 1e-6 * a11 * a22) {
            double al = (a22 * dh[0] - a12 * dh[1]) / det, be = (a11 * dh[1] - a12 * dh[0]) / det;
            for (int k = 0; k < 3; k++)
                g[k] = al * t[0][k] + be * t[1][k];
        }
    } else {
        for (int i = 0; i < 2; i++) { /* one step: the gradient along it only */
            double l2 = pg_vec3_dot(t[i], t[i]);
            for (int k = 0; ok[i] && l2 > 0 && k < 3; k++)
                g[k] = dh[i] / l2 * t[i][k];
        }
    }
    double n[3];
    for (int k = 0; k < 3; k++)
        n[k] = ne[k] - c->exaggeration * g[k];
    pg_vec3_normalize(n);
    double lam = pg_vec3_dot(n, c->light);
    double shade = (0.15 + 0.85 * (lam > 0 ? lam : 0)) * q->hits / 4;
    for (int k = 0; k < 3; k++)
        out[k] = (float)(q->rgb[k] * shade);
}

static const globe_view globe_views[4] = {{"globe_north.png", {0, 0, 1}, {-1, 0, 0}},
                                          {"globe_south.png", {0, 0, -1}, {1, 0, 0}},
                                          {"globe_lon000.png", {1, 0, 0}, {0, 0, 1}},
                                          {"globe_lon180.png", {-1, 0, 0}, {0, 0, 1}}};

static void render_globe(globe_ctx *c, const globe_view *v, int size, globe_px *buf, float *rgb) {
    memcpy(c->view, v->view, sizeof c->view);
    memcpy(c->up, v->up, sizeof c->up);
    double fwd[3] = {-v->view[0], -v->view[1], -v->view[2]};
    pg_vec3_cross(fwd, c->up, c->right);
    for (int k = 0; k < 3; k++)
        c->light[k] = 0.55 * c->view[k] + 0.6 * c->up[k] - 0.6 * c->right[k];
    pg_vec3_normalize(c->light);
#pragma omp parallel for schedule(dynamic, 8)
    for (int py = 0; py < size; py++)
        for (int px = 0; px < size; px++)
            globe_sample(c, size, px, py, &buf[(size_t)py * size + px]);
#pragma omp parallel for schedule(dynamic, 8)
    for (int py = 0; py < size; py++)
        for (int px = 0; px < size; px++)
            globe_shade(c, buf, size, px, py, rgb + 3 * ((size_t)py * size + px));
}

#define NGLOBES 4

/* The four globe renders into out[0..3]. */
static pg_status globe_renders(const pg_planet *p, const reduced *r, const pg_export_opts *o,
                               pg_image *out, pg_error *err) {
    /* north: Greenwich at the bottom; south: at the top; equator: north up */
    int size = globe_size(o);
    globe_ctx c = {.p = p,
                   .r = r,
                   .exaggeration = o->exaggeration,
                   .a = p->ellipsoid.a,
                   .b = p->ellipsoid.a * (1 - p->ellipsoid.f)};
    c.ext = 1.04 * c.a;
    pg_status st = pg_cube_grid_init(&c.g, p->projection, (int)r->n, 1, err);
    globe_px *buf = st == PG_OK ? pg_huge_malloc((size_t)size * size * sizeof *buf) : NULL;
    if (st == PG_OK && !buf) st = pg_error_set(err, PG_ERR_NOMEM, "cannot allocate the globes");
    for (int v = 0; st == PG_OK && v < NGLOBES; v++) {
        st = pg_image_alloc(&out[v], size, size, 3, err);
        if (st == PG_OK) render_globe(&c, &globe_views[v], size, buf, out[v].data);
    }
    free(buf);
    return st;
}

pg_status pg_export_previews(const pg_planet *p, const pg_export_opts *o,
                             pg_planet_path_fn path_for, void *user, int *nfiles, pg_error *err) {
    reduced r;
    pg_status st = reduce(p, o, &r, err);
    if (st != PG_OK) return st;
    /* every image first, then all six encoded at once */
    pg_image img[2 + NGLOBES];
    memset(img, 0, sizeof img);
    const char *names[2 + NGLOBES] = {PG_EXPORT_ALBEDO_PREVIEW, PG_EXPORT_RELIEF_PREVIEW};
    for (int v = 0; v < NGLOBES; v++)
        names[2 + v] = globe_views[v].name;
    st = equirect_previews(p, &r, o, img, err);
    if (st == PG_OK) st = globe_renders(p, &r, o, img + 2, err);
    free(r.cube);
    if (st == PG_OK) st = write_pngs(2 + NGLOBES, names, img, path_for, user, nfiles, err);
    for (int i = 0; i < 2 + NGLOBES; i++)
        pg_image_free(&img[i]);
    return st;
}
