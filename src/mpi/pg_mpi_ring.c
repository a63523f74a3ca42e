/* pg_mpi_ring.c - a rank's cube tiles and the one-cell ring exchange around them, the
 * only point-to-point communication of the distributed pit removal (docs/mpi.md,
 * "Pit removal across ranks").
 *
 * The ring of a rank: the cells of other ranks that neighbour its tiles (8-connected,
 * across face seams through pg_pits_neighbours). Every rank derives, from the same
 * ownership function, both the cells it receives (its own ring, per owner) and those
 * it sends (the parts of the other ranks' rings it owns), each list sorted by cell id,
 * so sender and receiver agree on the order of every message without negotiation.
 * Preconditions: the tiles divide the face edge; the caller's array holds valid values
 * on its own tiles. Afterwards the ring holds the owners' values; no other cell is
 * read or written. */
#include "pg_mpi_comm.h"

#ifdef PG_HAVE_MPI

#include <stdlib.h>
#include <string.h>

static int log2_exact(uint32_t v) {
    int l = 0;
    while (l < 31 && (1u << l) < v)
        l++;
    return (1u << l) == v ? l : -1;
}

pg_status pg_mpi_tiling_init(pg_mpi_tiling *g, pg_pits_topo *topo, pg_mpi *m, int tiles, uint32_t n,
                             pg_error *err) {
    pg_status st = pg_pits_topo_cube(topo, n, err);
    if (!st && (tiles < 1 || n % (uint32_t)tiles))
        st = pg_error_set(err, PG_ERR_BADINPUT, "pits (MPI): %u texels do not split into %d tiles",
                          n, tiles);
    if (st) return st;
    const int nt = 6 * tiles * tiles, P = pg_mpi_size(m), me = pg_mpi_rank(m);
    *g = (pg_mpi_tiling){m,
                         topo,
                         tiles,
                         n,
                         n / (uint32_t)tiles,
                         -1,
                         -1,
                         pg_mpi_tile_first(nt, P, me),
                         pg_mpi_tile_first(nt, P, me + 1)};
    g->ln = log2_exact(n), g->lts = log2_exact(g->ts);
    if (g->lts < 0) g->ln = -1;
    return PG_OK;
}

/* Cells outside rank q's tiles that neighbour them: into recv[owner] when q is this
 * rank, into send[q] for those this rank owns. */
static void ring_of(const pg_mpi_tiling *g, int q, pg_mpi_idx *send, pg_mpi_idx *recv) {
    const int P = pg_mpi_size(g->m), me = pg_mpi_rank(g->m), nt = 6 * g->T * g->T;
    const int t0 = pg_mpi_tile_first(nt, P, q), t1 = pg_mpi_tile_first(nt, P, q + 1);
    uint32_t nb[8];
    for (int t = t0; t < t1; t++)
        for (uint32_t y = 0; y < g->ts; y++)
            for (uint32_t x = 0; x < g->ts; x++) {
                if (y > 0 && y + 1 < g->ts && x == 1) x = g->ts - 1; /* perimeter only */
                uint32_t id = pg_mpi_tile_cell(g, t, x, y);
                int k = pg_pits_neighbours(g->t, id, nb);
                for (int j = 0; j < k; j++) {
                    int o = pg_mpi_tile_owner(nt, P, pg_mpi_tile_of(g, nb[j]));
                    if (o == q) continue;
                    if (q == me && o != me) pg_mpi_idx_push(&recv[o], nb[j]);
                    if (q != me && o == me) pg_mpi_idx_push(&send[q], nb[j]);
                }
            }
}

pg_status pg_mpi_ring_exchange(const pg_mpi_tiling *g, void *arr, size_t elem, pg_error *err) {
    const int P = pg_mpi_size(g->m);
    const MPI_Comm comm = pg_mpi_comm_of(g->m);
    unsigned char *a = arr;
    pg_mpi_idx *send = calloc((size_t)P, sizeof *send), *recv = calloc((size_t)P, sizeof *recv);
    MPI_Request *req = malloc(2 * (size_t)P * sizeof *req);
    unsigned char **buf = calloc(2 * (size_t)P, sizeof *buf);
    int oom = !send || !recv || !req || !buf, nreq = 0;
    for (int q = 0; !oom && q < P; q++)
        ring_of(g, q, send, recv);
    for (int q = 0; !oom && q < P; q++) {
        pg_mpi_idx_unique(&send[q]);
        pg_mpi_idx_unique(&recv[q]);
        oom |= send[q].oom | recv[q].oom;
        buf[q] = malloc((send[q].n + 1) * elem);
        buf[P + q] = malloc((recv[q].n + 1) * elem);
        oom |= !buf[q] || !buf[P + q];
    }
    for (int q = 0; !oom && q < P; q++) {
        if (send[q].n) {
            for (size_t k = 0; k < send[q].n; k++)
                memcpy(buf[q] + k * elem, a + send[q].a[k] * elem, elem);
            MPI_Isend(buf[q], (int)(send[q].n * elem), MPI_BYTE, q, 11, comm, &req[nreq++]);
        }
        if (recv[q].n)
            MPI_Irecv(buf[P + q], (int)(recv[q].n * elem), MPI_BYTE, q, 11, comm, &req[nreq++]);
    }
    if (!oom) MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE);
    for (int q = 0; !oom && q < P; q++) {
        pg_mpi_note_pits_bytes(g->m, (double)(send[q].n * elem));
        for (size_t k = 0; k < recv[q].n; k++)
            memcpy(a + recv[q].a[k] * elem, buf[P + q] + k * elem, elem);
    }
    for (int q = 0; send && recv && buf && q < P; q++) {
        free(send[q].a), free(recv[q].a);
        free(buf[q]), free(buf[P + q]);
    }
    free(send), free(recv), free(req), free(buf);
    return oom ? pg_error_set(err, PG_ERR_NOMEM, "pits (MPI): out of memory (ring)") : PG_OK;
}

#endif
