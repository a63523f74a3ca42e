/* pg_drainage_planet.c - the drainage measures of a whole planet (pg_drainage.h): D8
 * (pg_drainage_d8_ocallaghan1984.c) and true texel areas on the ellipsoid
 * (pg_drainage_cube.c) make the receiver graph of the 6 x n x n texels (global texel
 * ids, so ids < 2^31 for n <= 18918); the graph core (pg_drainage.c) measures it.
 * The accumulation handed out for the preview is zeroed on the sea, where it would only
 * show where rivers end. */
#include "pg_huge.h"
#include "planetgen/pg_drainage.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The per-cell arrays of a planet's graph. */
typedef struct planet_graph {
    int32_t *receiver;
    float *area, *length;
    uint8_t *flags;
} planet_graph;

static void graph_free(planet_graph *g) {
    free(g->receiver), free(g->area), free(g->length), free(g->flags);
}

static pg_status graph_build(const float *const faces[PG_CUBE_NFACES], int64_t n,
                             pg_cube_projection p, const pg_ellipsoid *ell, float sea,
                             planet_graph *g, pg_error *err) {
    size_t nc = (size_t)6 * (size_t)n * (size_t)n;
    memset(g, 0, sizeof *g);
    if (n < 2 || n > 18918)
        return pg_error_set(err, PG_ERR_BADINPUT, "drainage: face size %lld outside 2..18918",
                            (long long)n);
    g->receiver = pg_huge_malloc(nc * sizeof *g->receiver);
    g->area = pg_huge_malloc(nc * sizeof *g->area);
    g->length = pg_huge_malloc(nc * sizeof *g->length);
    g->flags = pg_huge_malloc(nc);
    pg_status s = PG_OK;
    if (!g->receiver || !g->area || !g->length || !g->flags)
        s = pg_error_set(err, PG_ERR_NOMEM, "drainage: out of memory for %zu texels", nc);
    if (!s) s = pg_drainage_cube_d8(faces, n, p, ell, sea, g->receiver, g->length, g->flags, err);
    if (!s) s = pg_drainage_cube_areas(p, n, ell, g->area, err);
    if (s) graph_free(g);
    return s;
}

static pg_status graph_run(const planet_graph *pg, int64_t n, const pg_drainage_opts *o,
                           pg_drainage_stats *st, float *acc, pg_error *err) {
    pg_drainage_graph g = {(uint64_t)6 * (uint64_t)n * (uint64_t)n, pg->receiver, pg->area,
                           pg->length, pg->flags};
    return pg_drainage_compute(&g, o, acc, st, err);
}

pg_status pg_drainage_planet(const pg_drainage_terrain *p, const pg_drainage_opts *o,
                             pg_drainage_stats *st, float **acc_out, pg_error *err) {
    if (acc_out) *acc_out = NULL;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        if (!p->height[f])
            return pg_error_set(err, PG_ERR_BADINPUT, "drainage: planet has no heights");
    const float *faces[PG_CUBE_NFACES];
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        faces[f] = p->height[f];
    planet_graph g;
    pg_status s = graph_build(faces, p->n, p->projection, &p->ellipsoid, p->sea_level, &g, err);
    if (s) return s;
    size_t nc = (size_t)6 * (size_t)p->n * (size_t)p->n;
    float *acc = NULL;
    if (acc_out && !(acc = pg_huge_malloc(nc * sizeof *acc)))
        s = pg_error_set(err, PG_ERR_NOMEM, "drainage: out of memory for the accumulation");
    if (!s) s = graph_run(&g, p->n, o, st, acc, err);
    if (!s && acc)
        for (size_t i = 0; i < nc; i++)
            if (!(g.flags[i] & PG_DRAINAGE_LAND)) acc[i] = 0.0f;
    graph_free(&g);
    if (s) free(acc), acc = NULL;
    if (acc_out) *acc_out = acc;
    return s;
}

/* Mark every land cell whose flow ends in a pit with PG_DRAINAGE_CLOSED: walk down to
 * a cell already decided or a root, then mark the path. Each cell is walked at most
 * twice (once to decide, once to mark), so O(n) without a topological order. */
#define PG_DRAINAGE_DECIDED 4u
#define PG_DRAINAGE_CLOSED 8u

static void mark_closed(const int32_t *recv, uint8_t *flags, int64_t nc) {
    for (int64_t i = 0; i < nc; i++) {
        if ((flags[i] & PG_DRAINAGE_DECIDED) || !(flags[i] & PG_DRAINAGE_LAND)) continue;
        int64_t j = i;
        while (!(flags[j] & PG_DRAINAGE_DECIDED) && recv[j] >= 0 &&
               (flags[recv[j]] & PG_DRAINAGE_LAND))
            j = recv[j];
        /* j is decided, a pit (a land root) or a mouth (its receiver is sea) */
        uint8_t closed = (flags[j] & PG_DRAINAGE_DECIDED) ? flags[j] & PG_DRAINAGE_CLOSED
                         : recv[j] < 0                    ? PG_DRAINAGE_CLOSED
                                                          : 0;
        for (int64_t k = i;; k = recv[k]) {
            flags[k] |= PG_DRAINAGE_DECIDED | closed;
            if (k == j) break;
        }
    }
}

pg_status pg_drainage_closed_land_share(const float *heights, int64_t n, pg_cube_projection p,
                                        const pg_ellipsoid *ell, float sea_level, double *share,
                                        pg_error *err) {
    *share = NAN;
    if (n < 2 || n > 18918)
        return pg_error_set(err, PG_ERR_BADINPUT, "drainage: face size %lld outside 2..18918",
                            (long long)n);
    const int64_t nc = 6 * n * n;
    const float *faces[PG_CUBE_NFACES];
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        faces[f] = heights + (size_t)f * (size_t)n * (size_t)n;
    int32_t *recv = pg_huge_malloc((size_t)nc * sizeof *recv);
    uint8_t *flags = pg_huge_malloc((size_t)nc);
    float *area = NULL;
    pg_status s = PG_OK;
    if (!recv || !flags)
        s = pg_error_set(err, PG_ERR_NOMEM, "drainage: out of memory for %lld texels",
                         (long long)nc);
    if (!s) s = pg_drainage_cube_d8(faces, n, p, ell, sea_level, recv, NULL, flags, err);
    if (!s && !(area = pg_huge_malloc((size_t)nc * sizeof *area)))
        s = pg_error_set(err, PG_ERR_NOMEM, "drainage: out of memory for texel areas");
    if (!s) s = pg_drainage_cube_areas(p, n, ell, area, err);
    if (!s) {
        mark_closed(recv, flags, nc);
        double land = 0, closed = 0;
        for (int64_t i = 0; i < nc; i++) {
            if (flags[i] & PG_DRAINAGE_LAND) land += area[i];
            if (flags[i] & PG_DRAINAGE_CLOSED) closed += area[i];
        }
        *share = land > 0 ? closed / land : NAN;
    }
    free(recv), free(flags), free(area);
    return s;
}
