/* pg_kcoherence_patchmatch.c - the k-coherence candidate table (Tong et al. 2002,
 * "Synthesis of bidirectional texture functions on arbitrary surfaces"; used by
 * Lefebvre & Hoppe 2005 section 3.4 with k = 2), built by PatchMatch (Barnes,
 * Shechtman, Finkelstein & Goldman 2009, "PatchMatch: a randomized correspondence
 * algorithm for structural image editing").
 *
 * For every exemplar texel t and level s we want the k-1 texels whose appearance vectors
 * (pg_appearance_pca.c) are nearest to t's, each at least min_separation * E away from
 * t and from each other (Zelinka & Garland 2002), so that a candidate is a genuine
 * alternative and not t's own neighbour. Texels on different faces count as far apart.
 *
 * PatchMatch exploits coherence: if t's match is m, t+o's match is likely m+o. Each
 * iteration scans a face in scanline order (reversed on odd iterations), trying for
 * every texel (1) propagation: the entries of the two already-visited neighbours,
 * shifted by one texel; (2) random search: samples around the current best in windows
 * shrinking 4x from E/2 down to 1 texel, plus one uniform sample from any face. Random numbers
 * are hashes of (seed, scale, face, x, y, iteration, step).
 *
 * At level s the appearance is blurred over 2^s texels, so matches are searched only on
 * a lattice of stride m = 2 (finest level) or 4 (coarser levels); the texels between take their
 * lattice point's entries moved by the same offset (a coherent extension, exact for a translation).
 *
 * Determinism: a face's scan reads and writes only that face's table (other data is
 * read-only), so faces run in parallel with identical results for any thread count. */
#include "pg_hash.h"
#include "pg_synth_internal.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

#define KMAX (PG_SYNTH_MAX_K - 1)

typedef struct pm_ctx {
    const pg_synth_exemplar *ex;
    int scale, kk, E, sep2;
    int m; /* lattice stride: matches are searched at every m-th texel only */
    uint64_t seed;
    uint32_t *table; /* kk entries per texel */
    int32_t *dist;   /* kk distances per texel */
} pm_ctx;

static int32_t app_dist(const pm_ctx *c, size_t ta, size_t tb) {
    const int16_t *a = c->ex->app[c->scale] + ta * PG_SYNTH_MAX_DIMS;
    const int16_t *b = c->ex->app[c->scale] + tb * PG_SYNTH_MAX_DIMS;
    int64_t d = 0;
    for (int i = 0; i < PG_SYNTH_MAX_DIMS; i++) {
        int32_t x = (int32_t)a[i] - b[i];
        d += (int64_t)x * x;
    }
    return d > INT_MAX ? INT_MAX : (int32_t)d;
}

static int too_close(const pm_ctx *c, uint32_t a, uint32_t b) {
    if (pg_synth_face(a) != pg_synth_face(b)) return 0;
    int du = pg_synth_u(a) - pg_synth_u(b), dv = pg_synth_v(a) - pg_synth_v(b);
    if (c->ex->torus) { /* wrapped distance */
        du = abs(du);
        dv = abs(dv);
        if (du > c->E / 2) du = c->E - du;
        if (dv > c->E / 2) dv = c->E - dv;
    }
    return du * du + dv * dv < c->sep2;
}

/* Offer candidate m to texel t's sorted list (coord self). */
static void offer(const pm_ctx *c, uint32_t self, size_t t, uint32_t m0) {
    const uint32_t m = m0 & ~PG_SYNTH_ORIENT_MASK; /* the table holds exemplar texels */
    if (too_close(c, self, m)) return;
    uint32_t *e = c->table + t * c->kk;
    int32_t *d = c->dist + t * c->kk;
    for (int i = 0; i < c->kk; i++)
        if (e[i] == m) return;
    int32_t dm = app_dist(c, t, pg_synth_texel(c->ex, m));
    int slot = c->kk - 1; /* replace the worst, or a near-duplicate that is worse */
    for (int i = 0; i < c->kk; i++)
        if (too_close(c, e[i], m)) {
            slot = i;
            break;
        }
    if (dm >= d[slot]) return;
    e[slot] = m;
    d[slot] = dm;
    for (int i = slot; i > 0 && d[i] < d[i - 1]; i--) { /* keep sorted */
        int32_t td = d[i];
        d[i] = d[i - 1];
        d[i - 1] = td;
        uint32_t te = e[i];
        e[i] = e[i - 1];
        e[i - 1] = te;
    }
}

static uint32_t random_coord(const pm_ctx *c, int face, int x, int y, int salt) {
    uint32_t h1 = pg_hash_texel(c->seed, c->scale, face, x, y, salt);
    uint32_t h2 = pg_hash_texel(c->seed, c->scale, face, x, y, salt + 1);
    int f = (int)(h1 % (uint32_t)c->ex->nfaces);
    return pg_synth_pack(f, (int)((h1 >> 8) % (uint32_t)c->E), (int)(h2 % (uint32_t)c->E));
}

/* The work is bound by the latency of the candidates' appearance vectors, read at
 * random: each texel's candidates are prefetched while the texel before it is visited
 * (prefetches change no result). */
static void prefetch_app(const pm_ctx *c, uint32_t m) {
    __builtin_prefetch(c->ex->app[c->scale] +
                       pg_synth_texel(c->ex, m & ~PG_SYNTH_ORIENT_MASK) * PG_SYNTH_MAX_DIMS);
}

#define INIT_DRAWS (4 * KMAX)

static void init_face(pm_ctx *c, int face) {
    const int E = c->E, m = c->m, draws = 4 * c->kk;
    uint32_t next[INIT_DRAWS];
    for (int a = 0; a < draws; a++)
        next[a] = random_coord(c, face, 0, 0, a * 2);
    for (int y = 0; y < E; y += m)
        for (int x = 0; x < E; x += m) {
            size_t t = ((size_t)face * E + y) * E + x;
            uint32_t self = pg_synth_pack(face, x, y), cur[INIT_DRAWS];
            memcpy(cur, next, sizeof(uint32_t) * (size_t)draws);
            int nx = x + m < E ? x + m : 0, ny = x + m < E ? y : y + m;
            for (int a = 0; ny < E && a < draws; a++) {
                next[a] = random_coord(c, face, nx, ny, a * 2);
                prefetch_app(c, next[a]);
            }
            for (int i = 0; i < c->kk; i++) {
                c->table[t * c->kk + i] = self; /* sentinel: infinitely bad until replaced */
                c->dist[t * c->kk + i] = INT_MAX;
            }
            for (int a = 0; a < draws; a++)
                offer(c, self, t, cur[a]);
        }
}

/* The most windows a search has: one per factor 4 from E/2 down to 1 (log4(E/2) + 1,
 * 8 at E = 8192); 16 holds faces up to 2^30. */
#define SEARCH_MAX 16

/* The random search of one visit, drawn before it: the offsets of its windows (shrinking
 * 4x from E/2, each applied to the best as it stands when its turn comes) and its one
 * candidate anywhere. The draws are hashes of the texel, not of the best, so the plan
 * serves both the prefetch ahead of the visit and the visit itself. */
typedef struct search_plan {
    int n;
    int du[SEARCH_MAX], dv[SEARCH_MAX];
    uint32_t anywhere;
} search_plan;

static void plan_search(const pm_ctx *c, int face, int x, int y, int it, search_plan *p) {
    int salt = 1000 + it * 100;
    p->n = 0;
    for (int r = c->E / 2; r >= 1; r /= 4, salt += 2) {
        uint32_t h = pg_hash_texel(c->seed, c->scale, face, x, y, salt);
        p->du[p->n] = (int)(h & 0xffff) % (2 * r + 1) - r;
        p->dv[p->n++] = (int)(h >> 16) % (2 * r + 1) - r;
    }
    p->anywhere = random_coord(c, face, x, y, salt);
}

/* Prefetch the search's candidates around b. */
static void prefetch_search(const pm_ctx *c, const search_plan *p, uint32_t b) {
    for (int i = 0; i < p->n; i++)
        prefetch_app(c, pg_synth_offset(c->ex, b, p->du[i], p->dv[i]));
}

/* The entries of (x, y)'s visited lattice neighbour n (0: along x, 1: along y) in the scan
 * direction dir, at (*nx, *ny); NULL off the edge of a face that is no torus. */
static const uint32_t *lattice_neighbour(const pm_ctx *c, int face, int x, int y, int n, int dir,
                                         int *nx, int *ny) {
    const int E = c->E, m = c->m;
    *nx = x - (n == 0 ? dir * m : 0), *ny = y - (n == 1 ? dir * m : 0);
    if (!c->ex->torus && (*nx < 0 || *ny < 0 || *nx >= E || *ny >= E)) return NULL;
    *nx &= E - 1;
    *ny &= E - 1;
    return c->table + (((size_t)face * E + *ny) * E + *nx) * c->kk;
}

/* Prefetch what visiting (x, y) will read: its neighbours' entries moved to it, and
 * its random search around its best as it stands (the propagation may still improve
 * that best; then those prefetches are wasted, never wrong). */
static void prefetch_visit(const pm_ctx *c, int face, int x, int y, int dir, const search_plan *p) {
    const int E = c->E;
    for (int n = 0; n < 2; n++) {
        int nx, ny;
        const uint32_t *ne = lattice_neighbour(c, face, x, y, n, dir, &nx, &ny);
        for (int i = 0; ne && i < c->kk; i++)
            prefetch_app(c, pg_synth_offset(c->ex, ne[i], x - nx, y - ny));
    }
    prefetch_search(c, p, c->table[(((size_t)face * E + y) * E + x) * c->kk]);
    prefetch_app(c, p->anywhere);
}

/* One PatchMatch step at lattice texel (x, y): propagation from its two visited lattice
 * neighbours, then the random search around its best, each candidate offered in turn. */
static void visit(pm_ctx *c, int face, int x, int y, int dir, const search_plan *p) {
    const int E = c->E;
    size_t t = ((size_t)face * E + y) * E + x;
    uint32_t self = pg_synth_pack(face, x, y), best = c->table[t * c->kk];
    /* propagation from the visited lattice neighbours (x - dir m, y), (x, y - dir m) */
    for (int n = 0; n < 2; n++) {
        int nx, ny;
        const uint32_t *ne = lattice_neighbour(c, face, x, y, n, dir, &nx, &ny);
        for (int i = 0; ne && i < c->kk; i++) {
            if (ne[i] == pg_synth_pack(face, nx, ny)) continue; /* still the sentinel */
            offer(c, self, t, pg_synth_offset(c->ex, ne[i], x - nx, y - ny));
        }
    }
    /* When the propagation moved the best, the search prefetched ahead of the visit
     * was around the old one: fetch the windows around the new best all at once, so
     * that their misses overlap instead of following one another. */
    if (c->table[t * c->kk] != best) prefetch_search(c, p, c->table[t * c->kk]);
    /* random search around the current best (re-read after each offer), windows
     * shrinking 4x, then one anywhere */
    for (int i = 0; i < p->n; i++)
        offer(c, self, t, pg_synth_offset(c->ex, c->table[t * c->kk], p->du[i], p->dv[i]));
    offer(c, self, t, p->anywhere);
}

/* Visit the face's lattice texels in scan order (reversed on odd iterations), each
 * prefetched while the one before it is visited. */
static void scan_face(pm_ctx *c, int face, int it) {
    const int E = c->E, m = c->m, last = E - m, dir = it % 2 == 0 ? 1 : -1;
    int x = dir > 0 ? 0 : last, y = x;
    search_plan plan[2];
    plan_search(c, face, x, y, it, &plan[0]);
    for (int i = 0;; i ^= 1) {
        int nx, ny; /* the next lattice texel of the scan */
        if (dir > 0) {
            nx = x + m < E ? x + m : 0;
            ny = x + m < E ? y : y + m;
        } else {
            nx = x >= m ? x - m : last;
            ny = x >= m ? y : y - m;
        }
        const int more = ny >= 0 && ny < E;
        if (more) plan_search(c, face, nx, ny, it, &plan[i ^ 1]);
        visit(c, face, x, y, dir, &plan[i]);
        if (!more) break;
        prefetch_visit(c, face, nx, ny, dir, &plan[i ^ 1]);
        x = nx;
        y = ny;
    }
}

/* Texels between lattice points take their lattice point's entries, moved coherently. A
 * move that crosses an exemplar seam keeps that seam's turn in the entry, the one kind of
 * entry with an orientation; pg_kcoherence_candidate composes it with the coordinate's. */
static void fill_from_lattice(pm_ctx *c, int face) {
    const int E = c->E, m = c->m;
    for (int y = 0; y < E; y++)
        for (int x = 0; x < E; x++) {
            int lx = x - x % m, ly = y - y % m;
            if (lx == x && ly == y) continue;
            size_t t = ((size_t)face * E + y) * E + x, l = ((size_t)face * E + ly) * E + lx;
            for (int i = 0; i < c->kk; i++) {
                c->table[t * c->kk + i] =
                    pg_synth_offset(c->ex, c->table[l * c->kk + i], x - lx, y - ly);
                c->dist[t * c->kk + i] = c->dist[l * c->kk + i];
            }
        }
}

pg_status pg_kcoherence_build(pg_synth_exemplar *ex, int scale, uint64_t seed, int iters,
                              double min_separation, int32_t *dist, pg_error *err) {
    pm_ctx c = {.ex = ex, .scale = scale, .kk = ex->k - 1, .E = ex->face_size, .seed = seed};
    /* coarser levels are smoother (blurred over h = 2^scale): search a sparser lattice */
    c.m = scale == 0 ? 2 : 4;
    if (c.m > c.E / 8) c.m = 1;
    if (c.kk <= 0) return PG_OK;
    int sep = (int)(min_separation * ex->face_size + 0.999);
    c.sep2 = sep * sep;
    size_t n = (size_t)ex->nfaces * ex->face_size * ex->face_size;
    c.table = ex->kcoh[scale];
    c.dist = dist;
#pragma omp parallel for schedule(dynamic, 1)
    for (int face = 0; face < ex->nfaces; face++) {
        init_face(&c, face);
        for (int it = 0; it < iters; it++)
            scan_face(&c, face, it);
        fill_from_lattice(&c, face);
    }
    /* a texel still holding the sentinel (tiny exemplars only) gets any far texel */
    for (size_t t = 0; t < n * c.kk; t++)
        if (c.dist[t] == INT_MAX) {
            size_t tex = t / c.kk;
            int face = (int)(tex / ((size_t)c.E * c.E));
            int rem = (int)(tex % ((size_t)c.E * c.E));
            c.table[t] =
                ~PG_SYNTH_ORIENT_MASK &
                pg_synth_offset(ex, pg_synth_pack(face, rem % c.E, rem / c.E), c.E / 2, c.E / 2);
        }
    (void)err;
    return PG_OK;
}
