/* pg_mpi_comm.c - the bottom of the MPI module: tile ownership, the pg_mpi handle's
 * accessors, the collectives the CLI and the pit algorithms use, gathers to rank 0 and
 * sorted index lists. Calls nothing else in src/mpi (the layering: pg_mpi_comm.h). */
#include "pg_mpi_comm.h"
#include "pg_pits_internal.h"
#include "pg_array.h"

#include <stdlib.h>

int pg_mpi_tile_first(int ntiles, int nranks, int rank) {
    return (int)((int64_t)rank * ntiles / nranks);
}

int pg_mpi_tile_owner(int ntiles, int nranks, int t) {
    /* the largest q with first(q) <= t */
    int q = (int)(((int64_t)t * nranks + nranks - 1) / ntiles);
    if (q >= nranks) q = nranks - 1;
    while (q > 0 && pg_mpi_tile_first(ntiles, nranks, q) > t)
        q--;
    while (q + 1 < nranks && pg_mpi_tile_first(ntiles, nranks, q + 1) <= t)
        q++;
    return q;
}

void pg_mpi_idx_push(pg_mpi_idx *v, size_t i) {
    if (PG_ARRAY_RESERVE(v->a, &v->cap, v->n + 1, NULL) != PG_OK)
        v->oom = 1;
    else
        v->a[v->n++] = i;
}

static int cmp_size(const void *a, const void *b) {
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return x < y ? -1 : x > y;
}

void pg_mpi_idx_unique(pg_mpi_idx *v) {
    if (!v->n) return;
    qsort(v->a, v->n, sizeof *v->a, cmp_size);
    size_t k = 1;
    for (size_t i = 1; i < v->n; i++)
        if (v->a[i] != v->a[k - 1]) v->a[k++] = v->a[i];
    v->n = k;
}

#ifdef PG_HAVE_MPI

#include <limits.h>

MPI_Comm pg_mpi_comm_of(const pg_mpi *m) {
    return m ? m->comm : MPI_COMM_WORLD;
}

int pg_mpi_rank(const pg_mpi *m) {
    return m ? m->rank : 0;
}

int pg_mpi_size(const pg_mpi *m) {
    return m ? m->size : 1;
}

int pg_mpi_node_size(const pg_mpi *m) {
    return m ? m->node_size : 1;
}

int pg_mpi_node_rank(const pg_mpi *m) {
    return m ? m->node_rank : 0;
}

void pg_mpi_barrier(pg_mpi *m) {
    if (m) MPI_Barrier(m->comm);
}

int pg_mpi_max_int(pg_mpi *m, int v) {
    int r = v;
    if (m) MPI_Allreduce(&v, &r, 1, MPI_INT, MPI_MAX, m->comm);
    return r;
}

void pg_mpi_gather_double(pg_mpi *m, double v, double *out) {
    if (!m) {
        out[0] = v;
        return;
    }
    MPI_Gather(&v, 1, MPI_DOUBLE, out, 1, MPI_DOUBLE, 0, m->comm);
}

double pg_mpi_sum_double(pg_mpi *m, double v) {
    double r = v;
    if (m) MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_SUM, m->comm);
    return r;
}

void pg_mpi_note_pits_bytes(pg_mpi *m, double bytes) {
    if (m) m->stats.pits_bytes += bytes;
}

const pg_mpi_stats *pg_mpi_stats_get(const pg_mpi *m) {
    return &m->stats;
}

void *pg_mpi_gather_root(pg_mpi *m, const void *mine, size_t words, MPI_Datatype type,
                         size_t word_bytes, size_t *total, int *bad) {
    const int P = pg_mpi_size(m), me = pg_mpi_rank(m);
    const MPI_Comm comm = pg_mpi_comm_of(m);
    int cnt = words > INT_MAX ? -1 : (int)words;
    int *counts = me == 0 ? calloc(2 * (size_t)P, sizeof *counts) : NULL;
    MPI_Gather(&cnt, 1, MPI_INT, counts, 1, MPI_INT, 0, comm);
    long long sum = 0;
    void *all = NULL;
    if (me == 0) {
        for (int q = 0; counts && q < P; q++) {
            if (counts[q] < 0) *bad = 1;
            counts[P + q] = (int)sum;
            sum += counts[q];
        }
        if (!counts || sum > INT_MAX) *bad = 1;
        all = *bad ? NULL : malloc(((size_t)sum + 1) * word_bytes);
        if (!all) *bad = 1;
    }
    MPI_Bcast(bad, 1, MPI_INT, 0, comm);
    if (!*bad) MPI_Gatherv(mine, cnt, type, all, counts, counts ? counts + P : NULL, type, 0, comm);
    if (!*bad && me != 0) pg_mpi_note_pits_bytes(m, (double)word_bytes * cnt);
    free(counts);
    *total = (size_t)sum;
    return all;
}

#else /* no MPI: one process */

int pg_mpi_rank(const pg_mpi *m) {
    (void)m;
    return 0;
}

int pg_mpi_size(const pg_mpi *m) {
    (void)m;
    return 1;
}

int pg_mpi_node_size(const pg_mpi *m) {
    (void)m;
    return 1;
}

int pg_mpi_node_rank(const pg_mpi *m) {
    (void)m;
    return 0;
}

void pg_mpi_barrier(pg_mpi *m) {
    (void)m;
}

int pg_mpi_max_int(pg_mpi *m, int v) {
    (void)m;
    return v;
}

void pg_mpi_gather_double(pg_mpi *m, double v, double *out) {
    (void)m;
    out[0] = v;
}

double pg_mpi_sum_double(pg_mpi *m, double v) {
    (void)m;
    return v;
}

void pg_mpi_note_pits_bytes(pg_mpi *m, double bytes) {
    (void)m, (void)bytes;
}

static const pg_mpi_stats no_stats;
const pg_mpi_stats *pg_mpi_stats_get(const pg_mpi *m) {
    (void)m;
    return &no_stats;
}

#endif
