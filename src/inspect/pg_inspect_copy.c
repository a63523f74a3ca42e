/* pg_inspect_copy.c - copy detection and face seam coherence from the coordinate map
 * (pg_inspect_copy.h; docs/inspect.md, "Copy detection" and "Face seams").
 *
 * Earth copy fraction. Directions are unit vectors from the planet's centre: a
 * texel's own from the planet's projection, its source's from the exemplar cube's
 * (as pg_planet_source_dir). The gnomonic and equi-angular projections are separable
 * (pg_cube.h: the cube-plane point is n + A(u) e_u + A(v) e_v), so A at every texel
 * centre is tabulated once, read off pg_cube_to_dir on face +X (n = x, e_u = y,
 * e_v = z: A(u) = d_y / d_x), and a direction costs a normalisation; the equal-area
 * projection, which is not separable, goes through pg_cube_to_dir. On a sphere of
 * radius R two directions are within distance r along a great circle exactly when
 * their dot product is at least cos(r / R), so the test costs one dot product and no
 * trigonometry. R is the ellipsoid's mean radius (2a + b) / 3 (IUGG R1). The baseline
 * keeps the source's z (its geocentric latitude) and turns it to the longitude
 * lambda = 2 pi h / 2^32 - pi, h a hash of (seed, texel id) (pg_synth_hash):
 * s' = (rho cos lambda, rho sin lambda, z) with rho = sqrt(1 - z^2), a point uniformly
 * distributed along the source's parallel.
 *
 * Coherence. Two sources a != b are coherent when b is one of a's 8 neighbours on the
 * exemplar cube: on the same face when |du|, |dv| <= 1, and across the exemplar's face
 * seams by its cube topology (pg_pits_topo_cube of E, 8 neighbours per texel, 7 at
 * the cube's corners). Pairs inside a face are (x, y)-(x+1, y) and (x, y)-(x, y+1);
 * a pair across a seam is an edge texel and its partner one step outside the face,
 * wrapped onto the neighbouring face by the grid's edge transforms (pg_cube_wrap).
 * Each of the 12 seams is visited once, from the lower-numbered of its two faces (two
 * cube faces share at most one edge), so there are 12 N seam pairs.
 *
 * Precondition: every coordinate of the map lies in the exemplar cube (face 0..5, u and
 * v below E); a map that breaks it is refused (BADINPUT), never indexed. Both measures
 * count integers per row and add them up: integer sums do not depend on the order, so
 * the results are the same for any thread count. */
#include "planetgen/pg_inspect_copy.h"
#include "planetgen/pg_inspect_distortion.h"

#include "planetgen/pg_pits.h"
#include "planetgen/pg_synth.h"

#include "pg_vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define COPY_HASH_SALT 0x636f7079 /* "copy": the baseline's own hash stream */

/* Every coordinate of the map on a face of the exemplar cube and inside it. */
static pg_status check_map(const pg_planet *p, pg_error *err) {
    const size_t nn = (size_t)p->n * (size_t)p->n;
    const int e = p->source.face_size;
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        const uint32_t *c = p->source.coords[f];
        size_t bad = 0;
#pragma omp parallel for reduction(+ : bad) schedule(static)
        for (size_t i = 0; i < nn; i++)
            bad += pg_synth_face(c[i]) >= PG_CUBE_NFACES || pg_synth_u(c[i]) >= e ||
                   pg_synth_v(c[i]) >= e;
        if (bad)
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "coordinate map: %zu texels of face %s point outside the "
                                "exemplar cube of 6 x %d^2",
                                bad, pg_cube_face_name(f), e);
    }
    return PG_OK;
}

/* ---- earth copy fraction ---- */

/* Mean radius (2a + b) / 3 of the planet's ellipsoid. */
static double mean_radius(const pg_ellipsoid *e) {
    return e->a * (1.0 - e->f / 3.0);
}

/* The source direction s turned to a hashed longitude on its own parallel. */
static void shuffled_dir(const double s[3], uint32_t h, double out[3]) {
    const double lambda = 2.0 * M_PI * ((double)h / 4294967296.0) - M_PI;
    const double z = s[2] > 1 ? 1 : (s[2] < -1 ? -1 : s[2]), rho = sqrt(1.0 - z * z);
    out[0] = rho * cos(lambda);
    out[1] = rho * sin(lambda);
    out[2] = z;
}

/* Texel-centre directions of a cube of `size` texels per face edge. */
typedef struct dir_table {
    pg_cube_projection proj;
    int size;
    double *a; /* A((2i + 1) / size - 1), i = 0..size-1; NULL: not separable */
} dir_table;

static pg_status dir_table_init(dir_table *t, pg_cube_projection proj, int size, pg_error *err) {
    t->proj = proj;
    t->size = size;
    t->a = NULL;
    if (proj == PG_CUBE_EQUALAREA) return PG_OK;
    if (!(t->a = malloc((size_t)size * sizeof *t->a)))
        return pg_error_set(err, PG_ERR_NOMEM, "copy detection: out of memory");
    for (int i = 0; i < size; i++) {
        double d[3];
        pg_cube_to_dir(proj, PG_CUBE_FACE_PX, (2.0 * i + 1.0) / size - 1.0, 0.0, d);
        t->a[i] = d[1] / d[0];
    }
    return PG_OK;
}

static void dir_at(const dir_table *t, int face, int i, int j, double d[3]) {
    if (!t->a) {
        pg_cube_to_dir(t->proj, face, (2.0 * i + 1.0) / t->size - 1.0,
                       (2.0 * j + 1.0) / t->size - 1.0, d);
        return;
    }
    int n[3], eu[3], ev[3];
    pg_cube_face_frame(face, n, eu, ev);
    const double a = t->a[i], b = t->a[j];
    for (int k = 0; k < 3; k++)
        d[k] = n[k] + a * eu[k] + b * ev[k];
    pg_vec3_scale(d, 1.0 / pg_vec3_length(d), d); /* by the reciprocal: rounds unlike normalize */
}

typedef struct copy_ctx {
    const pg_planet *p;
    dir_table own, src;
    double cos_r;
} copy_ctx;

/* Texels of row y of face f whose source is near (counts[0]) and whose shuffled
 * source is near (counts[1]). */
static void copy_row(const copy_ctx *c, int f, int64_t y, uint64_t counts[2]) {
    const pg_planet *p = c->p;
    const uint32_t *row = p->source.coords[f] + (size_t)y * (size_t)p->n;
    for (int64_t x = 0; x < p->n; x++) {
        double d[3], s[3], t[3];
        dir_at(&c->own, f, (int)x, (int)y, d);
        dir_at(&c->src, pg_synth_face(row[x]), pg_synth_u(row[x]), pg_synth_v(row[x]), s);
        shuffled_dir(s, pg_synth_hash(p->seed, 0, f, (long)x, (long)y, COPY_HASH_SALT), t);
        counts[0] += pg_vec3_dot(d, s) >= c->cos_r;
        counts[1] += pg_vec3_dot(d, t) >= c->cos_r;
    }
}

/* counts[0], counts[1] of copy_row over every row of the planet. */
static void copy_count(const copy_ctx *c, uint64_t counts[2]) {
    const int64_t n = c->p->n, rows = PG_CUBE_NFACES * n;
    uint64_t near = 0, shuffled = 0;
#pragma omp parallel for reduction(+ : near, shuffled) schedule(dynamic, 16)
    for (int64_t r = 0; r < rows; r++) {
        uint64_t k[2] = {0, 0};
        copy_row(c, (int)(r / n), r % n, k);
        near += k[0];
        shuffled += k[1];
    }
    counts[0] = near;
    counts[1] = shuffled;
}

static void copy_nan(pg_inspect_copy_stat *out) {
    memset(out, 0, sizeof *out);
    out->near_share = out->shuffled_share = out->earth_copy_fraction = NAN;
}

pg_status pg_inspect_copy_fraction(const pg_planet *p, pg_inspect_copy_stat *out, pg_error *err) {
    copy_nan(out);
    if (!pg_planet_has_source(p)) return PG_OK;
    pg_status st = check_map(p, err);
    if (st != PG_OK) return st;
    copy_ctx c = {p, {0}, {0}, cos(PG_INSPECT_COPY_RADIUS_M / mean_radius(&p->ellipsoid))};
    st = dir_table_init(&c.own, p->projection, (int)p->n, err);
    if (st == PG_OK) st = dir_table_init(&c.src, p->source.projection, p->source.face_size, err);
    uint64_t counts[2] = {0, 0};
    if (st == PG_OK) copy_count(&c, counts);
    free(c.own.a);
    free(c.src.a);
    if (st != PG_OK) return st;
    const uint64_t near = counts[0], shuffled = counts[1];
    const int64_t n = p->n, rows = PG_CUBE_NFACES * n;
    const double total = (double)rows * (double)n;
    out->texels = (uint64_t)rows * (uint64_t)n;
    out->near_share = (double)near / total;
    out->shuffled_share = (double)shuffled / total;
    out->earth_copy_fraction = out->near_share - out->shuffled_share;
    return PG_OK;
}

/* ---- face seam coherence ---- */

/* Are packed sources a and b two distinct 8-neighbours on the exemplar cube t? */
static bool coherent(const pg_pits_topo *t, uint32_t a, uint32_t b) {
    if (a == b) return false;
    const int fa = pg_synth_face(a), ua = pg_synth_u(a), va = pg_synth_v(a);
    const int fb = pg_synth_face(b), ub = pg_synth_u(b), vb = pg_synth_v(b);
    if (fa == fb && abs(ua - ub) <= 1 && abs(va - vb) <= 1) return true;
    const int e = (int)t->w;
    if (ua > 0 && ua < e - 1 && va > 0 && va < e - 1) return false; /* all on its face */
    const uint32_t ea = (uint32_t)e * (uint32_t)e;
    uint32_t nb[8], idb = (uint32_t)fb * ea + (uint32_t)vb * (uint32_t)e + (uint32_t)ub;
    const int k =
        pg_pits_neighbours_slow(t, (uint32_t)fa * ea + (uint32_t)va * e + (uint32_t)ua, nb);
    for (int i = 0; i < k; i++)
        if (nb[i] == idb) return true;
    return false;
}

/* Coherent pairs among the 4-adjacent pairs inside face f starting on row y that cross
 * a block boundary of the magnification m (pairs inside an m x m block share one source
 * and say nothing; every seam pair crosses blocks). */
static uint64_t interior_row(const pg_planet *p, const pg_pits_topo *t, int m, int f, int64_t y) {
    const int64_t n = p->n;
    const uint32_t *row = p->source.coords[f] + (size_t)y * (size_t)n;
    uint64_t c = 0;
    for (int64_t x = 0; x < n; x++) {
        if (x + 1 < n && (x + 1) % m == 0) c += coherent(t, row[x], row[x + 1]);
        if (y + 1 < n && (y + 1) % m == 0) c += coherent(t, row[x], row[x + n]);
    }
    return c;
}

/* Texel i (0..n-1) along edge e of a face, and the offset that steps across it. */
static void edge_texel(int e, int64_t n, int64_t i, int64_t *x, int64_t *y, int *dx, int *dy) {
    pg_cube_dir_offset((pg_cube_dir)e, dx, dy);
    *x = *dx > 0 ? n - 1 : (*dx < 0 ? 0 : i);
    *y = *dy > 0 ? n - 1 : (*dy < 0 ? 0 : i);
}

/* Coherent pairs across edge e of face f (n pairs). */
static uint64_t seam_pairs(const pg_planet *p, const pg_cube_grid *g, const pg_pits_topo *t, int f,
                           int e) {
    const int64_t n = p->n;
    uint64_t c = 0;
    for (int64_t i = 0; i < n; i++) {
        int64_t x, y;
        int dx, dy;
        edge_texel(e, n, i, &x, &y, &dx, &dy);
        const int64_t id = pg_cube_wrap(g, f, x + dx, y + dy, NULL), nn = n * n;
        const uint32_t a = p->source.coords[f][y * n + x];
        c += coherent(t, a, p->source.coords[id / nn][id % nn]);
    }
    return c;
}

static void coherence_nan(pg_inspect_coherence_stat *out) {
    memset(out, 0, sizeof *out);
    out->seam_share = out->interior_share = out->face_seam_coherence = NAN;
}

pg_status pg_inspect_copy_coherence(const pg_planet *p, pg_inspect_coherence_stat *out,
                                    pg_error *err) {
    coherence_nan(out);
    if (!pg_planet_has_source(p)) return PG_OK;
    pg_status st = check_map(p, err);
    pg_pits_topo t;
    pg_cube_grid g;
    if (st == PG_OK) st = pg_pits_topo_cube(&t, (uint32_t)p->source.face_size, err);
    if (st == PG_OK) st = pg_cube_grid_init(&g, p->projection, (int)p->n, 1, err);
    if (st != PG_OK) return st;
    const int64_t n = p->n, rows = PG_CUBE_NFACES * n;
    const int m = pg_inspect_distortion_magnification(p);
    uint64_t inner = 0, seam = 0, seam_count = 0;
#pragma omp parallel for reduction(+ : inner) schedule(dynamic, 16)
    for (int64_t r = 0; r < rows; r++)
        inner += interior_row(p, &t, m, (int)(r / n), r % n);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int e = PG_CUBE_XP; e <= PG_CUBE_YM; e++)
            if (g.nbr_face[f][e] > f) {
                seam += seam_pairs(p, &g, &t, f, e);
                seam_count += (uint64_t)n;
            }
    /* per face, n rows of n / m - 1 block-crossing pairs, each way */
    out->interior_pairs = (uint64_t)PG_CUBE_NFACES * 2 * (uint64_t)n * (uint64_t)(n / m - 1);
    out->seam_pairs = seam_count; /* 12 n: each seam once */
    out->interior_share = out->interior_pairs ? (double)inner / (double)out->interior_pairs : NAN;
    out->seam_share = (double)seam / (double)out->seam_pairs;
    out->face_seam_coherence =
        out->interior_share > 0 ? out->seam_share / out->interior_share : NAN;
    return PG_OK;
}
