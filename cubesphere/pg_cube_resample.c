/* pg_cube_resample.c - equirectangular images <-> cube faces, bilinear.
 *
 * Equirect -> cube: every cube texel's direction (or samples x samples directions
 * inside it) becomes a geodetic lat/lon on the planet's ellipsoid and is sampled
 * bilinearly; longitude wraps. Near a pole the last pixel row is half a pixel from
 * the pole, where every longitude meets, so we continue the image to a pole value
 * (the mean of the polar row) instead of clamping: the result is single-valued and
 * continuous at the pole, with no pinch artefacts.
 *
 * Cube -> equirect: every pixel's direction is sampled bilinearly on the face grid;
 * the four taps may fall one texel past an edge and are wrapped across the seam
 * with pg_cube_wrap, so there are no seams in the output.
 *
 * Parallel over rows with OpenMP; each output value depends only on its own inputs,
 * so results are identical for any thread count. */
#include "pg_cube_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double DEG = 180.0 / 3.14159265358979323846;

typedef struct equirect {
    const float *img;
    int w, h, ch;
    const double *pole; /* 2*ch: north mean, south mean */
} equirect;

static pg_status check_image(int w, int h, int ch, const char *what, pg_error *err) {
    if (w < 2 || h < 2 || ch < 1)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: bad image size %dx%d with %d channels", what,
                            w, h, ch);
    return PG_OK;
}

/* Horizontal linear interpolation in row j at pixel coordinate fx, with wrap. */
static void row_lerp(const equirect *E, int j, double fx, double *out) {
    double fl = floor(fx);
    double t = fx - fl;
    long i0 = ((long)fl % E->w + E->w) % E->w, i1 = (i0 + 1) % E->w;
    const float *a = E->img + ((size_t)j * E->w + i0) * E->ch;
    const float *b = E->img + ((size_t)j * E->w + i1) * E->ch;
    for (int c = 0; c < E->ch; c++)
        out[c] = (1 - t) * a[c] + t * b[c];
}

static void equirect_sample(const equirect *E, double lat, double lon, double *out, double *tmp) {
    double fx = (lon + 180) / 360 * E->w - 0.5;
    double fy = (90 - lat) / 180 * E->h - 0.5;
    if (fy < 0 || fy > E->h - 1) { /* polar cap: blend the edge row with the pole value */
        int north = fy < 0;
        int j = north ? 0 : E->h - 1;
        double t = north ? -fy * 2 : (fy - (E->h - 1)) * 2;
        t = t > 1 ? 1 : t;
        const double *p = E->pole + (north ? 0 : E->ch);
        row_lerp(E, j, fx, out);
        for (int c = 0; c < E->ch; c++)
            out[c] = (1 - t) * out[c] + t * p[c];
        return;
    }
    int j0 = (int)floor(fy);
    j0 = j0 > E->h - 2 ? E->h - 2 : j0;
    double t = fy - j0;
    row_lerp(E, j0, fx, out);
    row_lerp(E, j0 + 1, fx, tmp);
    for (int c = 0; c < E->ch; c++)
        out[c] = (1 - t) * out[c] + t * tmp[c];
}

static void pole_means(const float *img, int w, int h, int ch, double *pole) {
    for (int c = 0; c < 2 * ch; c++)
        pole[c] = 0;
    for (int i = 0; i < w; i++) {
        for (int c = 0; c < ch; c++) {
            pole[c] += img[(size_t)i * ch + c];
            pole[ch + c] += img[((size_t)(h - 1) * w + i) * ch + c];
        }
    }
    for (int c = 0; c < 2 * ch; c++)
        pole[c] /= w;
}

/* Directions -> lat/lon; on a sphere geocentric = geodetic, so no adapter call. */
static void dirs_to_latlon(const pg_ellipsoid *ell, size_t m, const double *d, double *lat,
                           double *lon) {
    if (ell && ell->f != 0) {
        pg_geo_dirs_to_latlon(ell, m, d, lat, lon);
        return;
    }
    for (size_t i = 0; i < m; i++) {
        const double *v = d + 3 * i;
        lat[i] = atan2(v[2], hypot(v[0], v[1])) * DEG;
        lon[i] = atan2(v[1], v[0]) * DEG;
    }
}

static void latlon_to_dirs(const pg_ellipsoid *ell, size_t m, const double *lat, const double *lon,
                           double *d) {
    if (ell && ell->f != 0) {
        pg_geo_latlons_to_dirs(ell, m, lat, lon, d);
        return;
    }
    for (size_t i = 0; i < m; i++) {
        double cl = cos(lat[i] / DEG);
        d[3 * i] = cl * cos(lon[i] / DEG);
        d[3 * i + 1] = cl * sin(lon[i] / DEG);
        d[3 * i + 2] = sin(lat[i] / DEG);
    }
}

/* One cube row: directions of all taps, then lat/lon in one batch, then sampling. */
static int cube_row(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell, const equirect *E,
                    int samples, int face, int64_t y, float *dst) {
    size_t taps = (size_t)samples * samples, m = (size_t)n * taps;
    double *d = malloc(m * 3 * sizeof *d), *lat = malloc(m * 2 * sizeof *lat);
    double *acc = malloc(3 * (size_t)E->ch * sizeof *acc);
    if (!d || !lat || !acc) {
        free(d), free(lat), free(acc);
        return -1;
    }
    double *lon = lat + m, *val = acc + E->ch, *tmp = val + E->ch;
    for (int64_t x = 0; x < n; x++) {
        for (size_t k = 0; k < taps; k++) {
            double sx = ((double)(k % samples) + 0.5) / samples;
            double sy = ((double)(k / samples) + 0.5) / samples;
            double u = 2 * ((double)x + sx) / (double)n - 1,
                   v = 2 * ((double)y + sy) / (double)n - 1;
            pg_cube_to_dir(p, face, u, v, d + 3 * ((size_t)x * taps + k));
        }
    }
    dirs_to_latlon(ell, m, d, lat, lon);
    for (int64_t x = 0; x < n; x++) {
        for (int c = 0; c < E->ch; c++)
            acc[c] = 0;
        for (size_t k = 0; k < taps; k++) {
            size_t i = (size_t)x * taps + k;
            equirect_sample(E, lat[i], lon[i], val, tmp);
            for (int c = 0; c < E->ch; c++)
                acc[c] += val[c];
        }
        for (int c = 0; c < E->ch; c++)
            dst[(size_t)x * E->ch + c] = (float)(acc[c] / taps);
    }
    free(d), free(lat), free(acc);
    return 0;
}

pg_status pg_cube_from_equirect(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                const float *img, int w, int h, int ch, int samples, float *cube,
                                pg_error *err) {
    return pg_cube_from_equirect_rows(p, n, ell, img, w, h, ch, samples, 0, PG_CUBE_NFACES * n,
                                      cube, err);
}

pg_status pg_cube_from_equirect_rows(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                     const float *img, int w, int h, int ch, int samples,
                                     int64_t row0, int64_t row1, float *cube, pg_error *err) {
    pg_status st = check_image(w, h, ch, "equirect", err);
    if (st != PG_OK) return st;
    if (n < 1 || samples < 1 || samples > 16)
        return pg_error_set(err, PG_ERR_BADINPUT, "resample: bad face size %lld or samples %d",
                            (long long)n, samples);
    if (row0 < 0 || row1 > PG_CUBE_NFACES * n || row0 > row1)
        return pg_error_set(err, PG_ERR_BADINPUT, "resample: bad rows [%lld, %lld)",
                            (long long)row0, (long long)row1);
    double *pole = malloc(2 * (size_t)ch * sizeof *pole);
    if (!pole) return pg_error_set(err, PG_ERR_NOMEM, "resample: out of memory");
    pole_means(img, w, h, ch, pole);
    equirect E = {img, w, h, ch, pole};
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(| : failed)
    for (int64_t r = row0; r < row1; r++) {
        int face = (int)(r / n);
        failed |= cube_row(p, n, ell, &E, samples, face, r % n, cube + (size_t)r * n * ch);
    }
    free(pole);
    if (failed) return pg_error_set(err, PG_ERR_NOMEM, "resample: out of memory");
    return PG_OK;
}

/* Bilinear on the face grid; taps past an edge are wrapped across the seam. Next
 * to a cube vertex one tap can lie past both edges, where no texel exists (three
 * faces meet); that tap is extrapolated from the other three (a + b - c, exact for
 * a plane), which keeps the interpolation second-order there. */
static void face_sample_g(const pg_cube_grid *g, const float *const faces[PG_CUBE_NFACES], int ch,
                          int face, double fx, double fy, float *out) {
    const int64_t nn = g->n * g->n;
    double x0 = floor(fx), y0 = floor(fy), tx = fx - x0, ty = fy - y0;
    const float *tap[4];
    int past = -1;
    const int64_t ix = (int64_t)x0, iy = (int64_t)y0;
    if (ix >= 0 && iy >= 0 && ix + 1 < g->n && iy + 1 < g->n) { /* inside the face */
        const float *t0 = faces[face] + (size_t)(iy * g->n + ix) * ch;
        tap[0] = t0, tap[1] = t0 + ch, tap[2] = t0 + (size_t)g->n * ch, tap[3] = tap[2] + ch;
    } else {
        for (int k = 0; k < 4; k++) {
            int64_t x = ix + (k & 1), y = iy + (k >> 1);
            if ((x < 0 || x >= g->n) && (y < 0 || y >= g->n)) past = k;
            int64_t id = pg_cube_wrap(g, face, x, y, NULL);
            tap[k] = faces[id / nn] + (size_t)(id % nn) * ch;
        }
    }
    for (int c = 0; c < ch; c++) {
        double t[4];
        for (int k = 0; k < 4; k++)
            t[k] = tap[k][c];
        if (past >= 0) t[past] = t[past ^ 1] + t[past ^ 2] - t[past ^ 3];
        double a = t[0] + tx * (t[1] - t[0]), b = t[2] + tx * (t[3] - t[2]);
        out[c] = (float)(a + ty * (b - a));
    }
}

void pg_cube_locate(const pg_cube_grid *g, const double dir[3], int *face, double *fx, double *fy) {
    double u, v;
    pg_cube_from_dir(g->proj, dir, face, &u, &v);
    *fx = (u + 1) / 2 * (double)g->n - 0.5, *fy = (v + 1) / 2 * (double)g->n - 0.5;
}

static void cube_sample_g(const pg_cube_grid *g, const float *const faces[PG_CUBE_NFACES], int ch,
                          const double dir[3], float *out) {
    int face;
    double fx, fy;
    pg_cube_locate(g, dir, &face, &fx, &fy);
    face_sample_g(g, faces, ch, face, fx, fy, out);
}

/* The faces of a contiguous cube buffer. */
static void split_faces(const float *cube, int64_t n, int ch, const float *faces[PG_CUBE_NFACES]) {
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        faces[f] = cube + (size_t)f * (size_t)(n * n) * ch;
}

void pg_cube_sample_grid(const pg_cube_grid *g, const float *cube, int ch, const double dir[3],
                         float *out) {
    const float *faces[PG_CUBE_NFACES];
    split_faces(cube, g->n, ch, faces);
    cube_sample_g(g, faces, ch, dir, out);
}

void pg_cube_sample_face(const pg_cube_grid *g, const float *cube, int ch, int face, double fx,
                         double fy, float *out) {
    const float *faces[PG_CUBE_NFACES];
    split_faces(cube, g->n, ch, faces);
    face_sample_g(g, faces, ch, face, fx, fy, out);
}

void pg_cube_sample_grid_init(pg_cube_grid *g, pg_cube_projection p, int64_t n) {
    pg_cube_grid_init_faces(g, p, n);
}

void pg_cube_sample(pg_cube_projection p, int64_t n, const float *cube, int ch, const double dir[3],
                    float *out) {
    pg_cube_grid g;
    pg_cube_grid_init_faces(&g, p, n);
    const float *faces[PG_CUBE_NFACES];
    split_faces(cube, n, ch, faces);
    cube_sample_g(&g, faces, ch, dir, out);
}

/* Pixels [x0, x0 + rw) of row j of a w x h equirectangular grid. */
static int equirect_row(const pg_cube_grid *g, const pg_ellipsoid *ell,
                        const float *const faces[PG_CUBE_NFACES], int ch, int w, int h, int x0,
                        int rw, int j, float *dst) {
    double *lat = malloc((size_t)rw * 5 * sizeof *lat);
    if (!lat) return -1;
    double *lon = lat + rw, *d = lon + rw;
    for (int i = 0; i < rw; i++) {
        lat[i] = 90 - (j + 0.5) * 180.0 / h;
        lon[i] = -180 + (x0 + i + 0.5) * 360.0 / w;
    }
    latlon_to_dirs(ell, (size_t)rw, lat, lon, d);
    for (int i = 0; i < rw; i++)
        cube_sample_g(g, faces, ch, d + 3 * i, dst + (size_t)i * ch);
    free(lat);
    return 0;
}

pg_status pg_cube_faces_to_equirect(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                    const float *const faces[PG_CUBE_NFACES], int ch, int w, int h,
                                    int x0, int y0, int rw, int rh, float *img, pg_error *err) {
    pg_status st = check_image(w, h, ch, "equirect", err);
    if (st != PG_OK) return st;
    if (n < 2)
        return pg_error_set(err, PG_ERR_BADINPUT, "resample: bad face size %lld", (long long)n);
    if (x0 < 0 || y0 < 0 || rw < 1 || rh < 1 || x0 > w - rw || y0 > h - rh)
        return pg_error_set(err, PG_ERR_BADINPUT, "resample: region %dx%d+%d+%d outside %dx%d", rw,
                            rh, x0, y0, w, h);
    pg_cube_grid g;
    pg_cube_grid_init_faces(&g, p, n);
    int failed = 0;
#pragma omp parallel for schedule(dynamic, 4) reduction(| : failed)
    for (int j = 0; j < rh; j++)
        failed |= equirect_row(&g, ell, faces, ch, w, h, x0, rw, y0 + j, img + (size_t)j * rw * ch);
    if (failed) return pg_error_set(err, PG_ERR_NOMEM, "resample: out of memory");
    return PG_OK;
}

pg_status pg_cube_to_equirect(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                              const float *cube, int ch, float *img, int w, int h, pg_error *err) {
    const float *faces[PG_CUBE_NFACES];
    split_faces(cube, n, ch, faces);
    return pg_cube_faces_to_equirect(p, n, ell, faces, ch, w, h, 0, 0, w, h, img, err);
}
