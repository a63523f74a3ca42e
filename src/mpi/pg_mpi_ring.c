/* pg_mpi_ring.c - a rank's cube tiles in tile-local arrays and the one-cell ring
 * exchange around them, the only point-to-point communication of the distributed pit
 * removal (docs/mpi.md, "Pit removal across ranks").
 *
 * The ring of a rank: the cells of other ranks that neighbour its tiles (8-connected,
 * across face seams through pg_cube_wrap, 7 neighbours at the cube corners as in
 * pg_pits_topo_cube). Neighbourhood is symmetric, so the cells a rank sends to rank q
 * are its own cells with a neighbour in q's tiles, and those it receives from q are its
 * ring cells in q's tiles: both lists come from the rank's own tile perimeters, each
 * sorted by cube id, so sender and receiver agree on the order of every message
 * without negotiation, and no rank walks another rank's tiles. The plan is made once
 * per tiling. Every array of the distributed pits is local (pg_mpi_comm.h): a rank's
 * memory follows its tiles and their perimeters, never the planet. */
#include "pg_mpi_comm.h"

#ifdef PG_HAVE_MPI

#include "pg_pits_barnes2016_core.h"

#include <stdlib.h>
#include <string.h>

static int log2_exact(uint32_t v) {
    int l = 0;
    while (l < 31 && (1u << l) < v)
        l++;
    return (1u << l) == v ? l : -1;
}

/* The neighbours of a cube id (64-bit; pg_pits_neighbours_slow's rule, raster order). */
static int cube_neighbours(const pg_mpi_tiling *g, uint64_t id, uint64_t out[8]) {
    const int64_t n = g->n;
    const uint64_t per = (uint64_t)n * (uint64_t)n, f = id / per, r = id % per;
    const int64_t x = (int64_t)(r % (uint64_t)n), y = (int64_t)(r / (uint64_t)n);
    int k = 0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            if (!dx && !dy) continue;
            int64_t nx = x + dx, ny = y + dy;
            int outx = nx < 0 || nx >= n, outy = ny < 0 || ny >= n;
            if (!outx && !outy)
                out[k++] = f * per + (uint64_t)ny * (uint64_t)n + (uint64_t)nx;
            else if (!(outx && outy))
                out[k++] = (uint64_t)pg_cube_wrap(&g->cube, (int)f, nx, ny, NULL);
        }
    return k;
}

uint32_t pg_mpi_local_of(const pg_mpi_tiling *g, uint64_t id) {
    int t = pg_mpi_tile_of(g, id);
    if (t >= g->t0 && t < g->t1) {
        uint64_t per = (uint64_t)g->n * g->n, r = id % per, x = r % g->n, y = r / g->n;
        return (uint32_t)(t - g->t0) * g->ts * g->ts + (uint32_t)(y % g->ts) * g->ts +
               (uint32_t)(x % g->ts);
    }
    size_t k = pits_sorted_index_u64(g->ring, g->nring, id);
    return k < g->nring && g->ring[k] == id ? g->nown + (uint32_t)k : UINT32_MAX;
}

/* The local topology's border rule: a border cell's neighbours as local ids. */
static int local_border(const void *ctx, uint32_t l, uint32_t out[8]) {
    const pg_mpi_tiling *g = ctx;
    uint64_t nb[8];
    int k = cube_neighbours(g, pg_mpi_cube_id(g, l), nb);
    for (int j = 0; j < k; j++)
        out[j] = pg_mpi_local_of(g, nb[j]);
    return k;
}

/* Every perimeter cell of this rank's tiles with a neighbour in another rank's tile:
 * the neighbour into the ring list, the cell (cube id) into send[owner]. */
static int ring_plan(pg_mpi_tiling *g) {
    const int P = pg_mpi_size(g->m), me = pg_mpi_rank(g->m), nt = 6 * g->T * g->T;
    size_t nr = 0, cap = 0;
    uint64_t *ring = NULL, nb[8];
    int oom = 0;
    for (int t = g->t0; !oom && t < g->t1; t++)
        for (uint32_t y = 0; !oom && y < g->ts; y++)
            for (uint32_t x = 0; !oom && x < g->ts; x++) {
                if (y > 0 && y + 1 < g->ts && x == 1) x = g->ts - 1; /* perimeter only */
                uint64_t id = pg_mpi_tile_cell(g, t, x, y);
                int k = cube_neighbours(g, id, nb);
                for (int j = 0; j < k; j++) {
                    int o = pg_mpi_tile_owner(nt, P, pg_mpi_tile_of(g, nb[j]));
                    if (o == me) continue;
                    pg_mpi_idx_push(&g->send[o], (size_t)id);
                    if (nr == cap) {
                        uint64_t *r = realloc(ring, (cap = cap ? 2 * cap : 1024) * sizeof *r);
                        if (!r) {
                            oom = 1;
                            break;
                        }
                        ring = r;
                    }
                    ring[nr++] = nb[j];
                }
            }
    if (!oom) nr = pits_sort_unique_u64(ring, nr);
    g->ring = ring, g->nring = (uint32_t)nr;
    if (oom || (uint64_t)g->nown + nr >= UINT32_MAX - 2) return oom ? 1 : 2;
    for (int q = 0; q < P; q++) { /* cube ids to local ids, both in cube-id order */
        pg_mpi_idx_unique(&g->send[q]);
        oom |= g->send[q].oom;
        for (size_t k = 0; k < g->send[q].n; k++)
            g->send[q].a[k] = pg_mpi_local_of(g, g->send[q].a[k]);
    }
    for (size_t k = 0; k < nr; k++)
        pg_mpi_idx_push(&g->recv[pg_mpi_tile_owner(nt, P, pg_mpi_tile_of(g, ring[k]))],
                        g->nown + k);
    for (int q = 0; q < P; q++)
        oom |= g->recv[q].oom;
    return oom;
}

pg_status pg_mpi_tiling_init(pg_mpi_tiling *g, pg_mpi *m, int tiles, uint32_t n, pg_error *err) {
    memset(g, 0, sizeof *g);
    if (n < 2 || tiles < 1 || n % (uint32_t)tiles)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits (MPI): %u texels do not split into %d tiles", n, tiles);
    if ((uint64_t)6 * (uint64_t)tiles * (uint64_t)tiles > INT32_MAX / 2)
        return pg_error_set(err, PG_ERR_BADINPUT, "pits (MPI): %d tiles per face edge: too many",
                            tiles);
    const int nt = 6 * tiles * tiles, P = pg_mpi_size(m), me = pg_mpi_rank(m);
    g->m = m, g->T = tiles, g->n = n, g->ts = n / (uint32_t)tiles;
    g->t0 = pg_mpi_tile_first(nt, P, me), g->t1 = pg_mpi_tile_first(nt, P, me + 1);
    g->ln = log2_exact(n), g->lts = log2_exact(g->ts);
    if (g->lts < 0) g->ln = -1;
    g->base = m ? m->id_base : 0;
    g->stride = m && m->id_stride ? m->id_stride : 1;
    uint64_t own = (uint64_t)(g->t1 - g->t0) * g->ts * g->ts;
    if (own >= UINT32_MAX - 2)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits (MPI): rank %d owns %llu cells, above the 2^32-3 local ids of "
                            "one rank: use more ranks",
                            me, (unsigned long long)own);
    g->nown = (uint32_t)own;
    pg_status st = pg_cube_grid_init(&g->cube, PG_CUBE_EQUIANGULAR, (int)n, 1, err);
    if (st) return st;
    g->send = calloc((size_t)P, sizeof *g->send), g->recv = calloc((size_t)P, sizeof *g->recv);
    int bad = !g->send || !g->recv ? 1 : ring_plan(g);
    if (bad == 2) {
        pg_mpi_tiling_free(g);
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "pits (MPI): rank %d holds %llu cells with its ring, above the "
                            "2^32-3 local ids of one rank: use more ranks",
                            me, (unsigned long long)own + g->nring);
    }
    g->nloc = (size_t)g->nown + g->nring;
    if (!bad)
        st = pg_pits_topo_blocks(&g->t, g->ts, (uint32_t)(g->t1 - g->t0), g->nring, local_border, g,
                                 err);
    if (bad || st) {
        pg_mpi_tiling_free(g);
        return st ? st : pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (ring plan)");
    }
    return PG_OK;
}

void pg_mpi_tiling_free(pg_mpi_tiling *g) {
    const int P = pg_mpi_size(g->m);
    for (int q = 0; q < P; q++) {
        if (g->send) free(g->send[q].a);
        if (g->recv) free(g->recv[q].a);
    }
    free(g->send), free(g->recv), free(g->ring);
    g->send = g->recv = NULL, g->ring = NULL;
}

void pg_mpi_tiling_load(const pg_mpi_tiling *g, const float *planet, float *local) {
    for (int t = g->t0; t < g->t1; t++)
        for (uint32_t y = 0; y < g->ts; y++)
            memcpy(local + ((size_t)(t - g->t0) * g->ts + y) * g->ts,
                   planet + pg_mpi_tile_cell(g, t, 0, y), g->ts * sizeof *local);
}

void pg_mpi_tiling_store(const pg_mpi_tiling *g, const float *local, float *planet) {
    for (int t = g->t0; t < g->t1; t++)
        for (uint32_t y = 0; y < g->ts; y++)
            memcpy(planet + pg_mpi_tile_cell(g, t, 0, y),
                   local + ((size_t)(t - g->t0) * g->ts + y) * g->ts, g->ts * sizeof *local);
}

typedef struct copy_ctx {
    const unsigned char *a;
    size_t elem;
} copy_ctx;

static void pack_copy(const void *ctx, uint32_t l, void *out) {
    const copy_ctx *c = ctx;
    memcpy(out, c->a + (size_t)l * c->elem, c->elem);
}

pg_status pg_mpi_ring_exchange_packed(const pg_mpi_tiling *g, size_t elem, pg_mpi_pack_fn pack,
                                      const void *ctx, void *ring_out, pg_error *err) {
    const int P = pg_mpi_size(g->m);
    const MPI_Comm comm = pg_mpi_comm_of(g->m);
    unsigned char *out = ring_out;
    MPI_Request *req = malloc(2 * (size_t)P * sizeof *req);
    unsigned char **buf = calloc(2 * (size_t)P, sizeof *buf);
    int oom = !req || !buf, nreq = 0;
    for (int q = 0; !oom && q < P; q++) {
        oom |= g->send[q].n * elem > INT32_MAX || g->recv[q].n * elem > INT32_MAX;
        buf[q] = malloc((g->send[q].n + 1) * elem);
        buf[P + q] = malloc((g->recv[q].n + 1) * elem);
        oom |= !buf[q] || !buf[P + q];
    }
    for (int q = 0; !oom && q < P; q++) {
        if (g->send[q].n) {
            for (size_t k = 0; k < g->send[q].n; k++)
                pack(ctx, (uint32_t)g->send[q].a[k], buf[q] + k * elem);
            MPI_Isend(buf[q], (int)(g->send[q].n * elem), MPI_BYTE, q, 11, comm, &req[nreq++]);
        }
        if (g->recv[q].n)
            MPI_Irecv(buf[P + q], (int)(g->recv[q].n * elem), MPI_BYTE, q, 11, comm, &req[nreq++]);
    }
    if (!oom) MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE);
    for (int q = 0; !oom && q < P; q++) {
        pg_mpi_note_pits_bytes(g->m, (double)(g->send[q].n * elem));
        for (size_t k = 0; k < g->recv[q].n; k++)
            memcpy(out + (g->recv[q].a[k] - g->nown) * elem, buf[P + q] + k * elem, elem);
    }
    for (int q = 0; buf && q < 2 * P; q++)
        free(buf[q]);
    free(req), free(buf);
    return oom ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (ring)") : PG_OK;
}

pg_status pg_mpi_ring_exchange(const pg_mpi_tiling *g, void *arr, size_t elem, pg_error *err) {
    copy_ctx c = {arr, elem};
    return pg_mpi_ring_exchange_packed(g, elem, pack_copy, &c,
                                       (unsigned char *)arr + (size_t)g->nown * elem, err);
}

#endif
