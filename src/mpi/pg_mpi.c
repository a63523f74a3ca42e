/* pg_mpi.c - MPI-distributed planet synthesis: starting and stopping MPI, the
 * tile-edge exchange behind pg_planet_synth_dist and the synthesis's hooks. The header
 * (pg_mpi.h) gives the idea; docs/mpi.md ("What is distributed, and how") the design
 * and its limits.
 *
 * Layering (pg_mpi_comm.h says it whole): this file is the top of src/mpi. It calls
 * the communication layer (pg_mpi_comm.c: ownership, collectives) and, through the
 * hooks, the distributed pit removal (pg_mpi_pits_remove, pg_mpi_pits_stats); nothing
 * in src/mpi calls back into it.
 *
 * Exchange plans. For a level (scale) and a width w, the texels a rank q reads from
 * others are the rings of width w around q's tiles: inside a face, the texels
 * themselves; one texel beyond a face edge, the texel of the neighbouring face that
 * the synthesis's border copy reads there (pg_cube_wrap, exactly as the driver's
 * border map); further beyond a face edge nothing (the driver clamps reads to the
 * border). Every rank derives, from the same ownership function, both what it
 * receives (its own rings) and what it sends (the parts of the other ranks' rings it
 * owns), sorted by array index, so sender and receiver agree on the order of every
 * message without negotiation. Plans are cached for the current (scale, width).
 *
 * Correctness of the whole run (bit-identical to one process): a correction step
 * writes only owned texels and reads only its 3 x 3 neighbourhood, which the width-1
 * exchange made current; upsampling and jitter are per texel; the magnified delivery
 * reads at most two texels beyond a tile (width 2); the steps that read the whole
 * planet get the whole level first (allgather, width -1), and are deterministic, so
 * every rank computes the same values as a single process would. */
#include "pg_mpi_comm.h"
#include "pg_mpi_testing.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int pg_mpi_launcher_size(int *rank) {
    static const char *const sizes[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"};
    static const char *const ranks[] = {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"};
    if (rank) *rank = 0;
    for (int i = 0; i < 3; i++) {
        const char *s = getenv(sizes[i]);
        if (!s || atoi(s) < 1) continue;
        const char *r = getenv(ranks[i]);
        if (rank && r) *rank = atoi(r);
        return atoi(s);
    }
    return 1;
}

#ifdef PG_HAVE_MPI

#include <limits.h>
#include <mpi.h>
#include <unistd.h>

/* The exchange plan of the current (scale, width), per rank. A received texel is
 * written where this rank reads it: at its own index inside a face, and beyond a face
 * edge into the border texel that reads it (dst), so that no rank stores the edges of
 * faces it does not own (docs/mpi.md, "Memory per rank"). */
typedef struct pg_mpi_plan {
    int valid, scale, width, r;
    pg_mpi_idx *send, *recv; /* per rank: source indices, sorted, the messages' order */
    pg_mpi_idx *put;         /* per rank: (source, destination) pairs, sorted */
    uint32_t *buf;           /* 2 words per texel: all sends, then all receives */
} plan;

bool pg_mpi_built(void) {
    return true;
}

pg_status pg_mpi_init(pg_mpi **out, pg_error *err) {
    int provided = 0, inited = 0;
    MPI_Initialized(&inited);
    if (!inited && MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return pg_error_set(err, PG_ERR_RUNTIME, "MPI_Init failed");
    pg_mpi *m = calloc(1, sizeof *m);
    plan *pl = calloc(1, sizeof *pl);
    if (!m || !pl) {
        free(m), free(pl);
        return pg_error_set(err, PG_ERR_NOMEM, "MPI: out of memory");
    }
    m->pl = pl;
    m->comm = MPI_COMM_WORLD;
    MPI_Comm_rank(m->comm, &m->rank);
    MPI_Comm_size(m->comm, &m->size);
    MPI_Comm node;
    m->node_size = 1;
    if (MPI_Comm_split_type(m->comm, MPI_COMM_TYPE_SHARED, m->rank, MPI_INFO_NULL, &node) ==
        MPI_SUCCESS) {
        MPI_Comm_size(node, &m->node_size);
        MPI_Comm_rank(node, &m->node_rank);
        MPI_Comm_free(&node);
    }
    m->fail_rank = -1;
    const char *base = getenv(PG_MPI_TESTING_ID_BASE_ENV);
    if (base && sscanf(base, "%" SCNu64 ":%" SCNu64, &m->id_base, &m->id_stride) < 1)
        m->id_base = 0, m->id_stride = 0;
    *out = m;
    return PG_OK;
}

static void plan_free(plan *p, int size) {
    for (int q = 0; p->send && q < size; q++)
        free(p->send[q].a), free(p->recv[q].a), free(p->put[q].a);
    free(p->send);
    free(p->recv);
    free(p->put);
    free(p->buf);
    memset(p, 0, sizeof *p);
}

void pg_mpi_finalize(pg_mpi *m) {
    if (!m) return;
    plan_free(m->pl, m->size);
    free(m->pl);
    free(m);
    MPI_Finalize();
}

void pg_mpi_abort(pg_mpi *m, int code) {
    fflush(stdout);
    fflush(stderr);
    MPI_Abort(m ? m->comm : MPI_COMM_WORLD, code);
    _exit(code); /* MPI_Abort does not return; this keeps the compiler sure of it */
}

/* ---- ownership as the synthesis sees it ---- */

static int owner_of(const pg_mpi *m, int T, int f, int tx, int ty) {
    return pg_mpi_tile_owner(m->ntiles, m->size, f * T * T + ty * T + tx);
}

static bool owns_hook(void *user, int f, int tx, int ty) {
    const pg_mpi *m = user;
    return owner_of(m, m->tiles, f, tx, ty) == m->rank;
}

static size_t level_index(const pg_planet_level *L, int f, int x, int y) {
    return (size_t)f * L->face_stride + (size_t)(y + 1) * L->stride + (size_t)(x + 1);
}

/* The ring of width w around rank q's tiles, as (owner, index) pairs: into
 * recv[owner] when q is this rank, into send[q] for the texels this rank owns. */
static void plan_ring(const pg_mpi *m, const pg_cube_grid *g, const pg_planet_level *L, int q,
                      int w, plan *p) {
    const int T = L->T, ts = L->ts, r = L->r, me = m->rank;
    const int t0 = pg_mpi_tile_first(m->ntiles, m->size, q),
              t1 = pg_mpi_tile_first(m->ntiles, m->size, q + 1);
    for (int t = t0; t < t1; t++) {
        const int f = t / (T * T), x0 = t % T * ts, y0 = t / T % T * ts;
        for (int y = y0 - w; y < y0 + ts + w; y++)
            for (int x = x0 - w; x < x0 + ts + w; x++) {
                if (y >= y0 && y < y0 + ts && x == x0) x = x0 + ts; /* skip the interior */
                if (x >= x0 + ts + w) break;
                int sf = f, sx = x, sy = y; /* the source; (f, x, y) reads it */
                if (x < 0 || x >= r || y < 0 || y >= r) {
                    if (x < -1 || x > r || y < -1 || y > r) continue; /* clamped reads */
                    int rot;
                    int64_t id = pg_cube_wrap(g, f, x, y, &rot), per = (int64_t)r * r;
                    sf = (int)(id / per), sy = (int)(id % per / r), sx = (int)(id % r);
                }
                int o = owner_of(m, T, sf, sx / ts, sy / ts);
                size_t i = level_index(L, sf, sx, sy);
                if (q == me && o != me) {
                    pg_mpi_idx_push(&p->put[o], i);
                    pg_mpi_idx_push(&p->put[o], level_index(L, f, x, y));
                }
                if (q != me && o == me) pg_mpi_idx_push(&p->send[q], i);
            }
    }
}

static int cmp_pair(const void *a, const void *b) {
    const size_t *x = a, *y = b;
    if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
    return x[1] < y[1] ? -1 : x[1] > y[1];
}

/* Sort the (source, destination) pairs received from one rank, drop repeats, and list
 * the distinct sources (the message's order). */
static void plan_puts(pg_mpi_idx *put, pg_mpi_idx *recv) {
    size_t n = put->n / 2, k = 0;
    if (!n) return;
    qsort(put->a, n, 2 * sizeof *put->a, cmp_pair);
    for (size_t i = 0; i < n; i++) {
        if (k && !cmp_pair(&put->a[2 * i], &put->a[2 * (k - 1)])) continue;
        put->a[2 * k] = put->a[2 * i], put->a[2 * k + 1] = put->a[2 * i + 1];
        if (!recv->n || recv->a[recv->n - 1] != put->a[2 * k]) pg_mpi_idx_push(recv, put->a[2 * k]);
        k++;
    }
    put->n = 2 * k;
}

static pg_status plan_build(pg_mpi *m, const pg_planet_level *L, int w, pg_error *err) {
    plan *p = m->pl;
    if (p->valid && p->scale == L->scale && p->width == w && p->r == L->r) return PG_OK;
    plan_free(p, m->size);
    pg_cube_grid g;
    pg_status st = pg_cube_grid_init(&g, PG_CUBE_DEFAULT_PROJECTION, L->T, L->ts, err);
    if (st) return st;
    p->send = calloc((size_t)m->size, sizeof *p->send);
    p->recv = calloc((size_t)m->size, sizeof *p->recv);
    p->put = calloc((size_t)m->size, sizeof *p->put);
    if (!p->send || !p->recv || !p->put)
        return pg_error_set(err, PG_ERR_NOMEM, "MPI: out of memory (plan)");
    for (int q = 0; q < m->size; q++)
        plan_ring(m, &g, L, q, w, p);
    size_t words = 0;
    int oom = 0;
    for (int q = 0; q < m->size; q++) {
        pg_mpi_idx_unique(&p->send[q]);
        plan_puts(&p->put[q], &p->recv[q]);
        oom |= p->put[q].oom;
        words += 2 * (p->send[q].n + p->recv[q].n);
        oom |= p->send[q].oom | p->recv[q].oom;
        if (2 * p->send[q].n > INT_MAX || 2 * p->recv[q].n > INT_MAX) oom = 2;
    }
    if (oom == 2)
        return pg_error_set(err, PG_ERR_RUNTIME, "MPI: a tile-edge message exceeds 2^31 words");
    p->buf = malloc((words + 1) * sizeof *p->buf);
    if (oom || !p->buf) return pg_error_set(err, PG_ERR_NOMEM, "MPI: out of memory (plan)");
    p->valid = 1, p->scale = L->scale, p->width = w, p->r = L->r;
    return PG_OK;
}

static void pack(const pg_planet_level *L, const pg_mpi_idx *v, uint32_t *out) {
    for (size_t k = 0; k < v->n; k++) {
        out[2 * k] = L->S[v->a[k]];
        memcpy(&out[2 * k + 1], &L->V[v->a[k]], 4);
    }
}

/* Each received texel to every place that reads it (the pairs, sorted by source like
 * the message). */
static void unpack(const pg_planet_level *L, const pg_mpi_idx *put, const uint32_t *in) {
    size_t k = 0;
    for (size_t j = 0; j < put->n / 2; j++) {
        if (j && put->a[2 * j] != put->a[2 * j - 2]) k++;
        size_t d = put->a[2 * j + 1];
        L->S[d] = in[2 * k];
        memcpy(&L->V[d], &in[2 * k + 1], 4);
    }
}

/* Point-to-point exchange of the rings (width >= 0). */
static pg_status exchange_halo(pg_mpi *m, const pg_planet_level *L, int w, pg_error *err) {
    pg_status st = plan_build(m, L, w, err);
    if (st) return st;
    plan *p = m->pl;
    MPI_Request *req = malloc(2 * (size_t)m->size * sizeof *req);
    if (!req) return pg_error_set(err, PG_ERR_NOMEM, "MPI: out of memory");
    int nreq = 0;
    uint32_t *b = p->buf;
    size_t sent = 0;
    for (int q = 0; q < m->size; q++) {
        if (!p->send[q].n) continue;
        pack(L, &p->send[q], b);
        MPI_Isend(b, (int)(2 * p->send[q].n), MPI_UINT32_T, q, 7, m->comm, &req[nreq++]);
        b += 2 * p->send[q].n;
        sent += p->send[q].n;
        if (L->scale < PG_MPI_MAX_SCALES) m->stats.halo_messages[L->scale]++;
    }
    uint32_t *recv0 = b;
    for (int q = 0; q < m->size; q++) {
        if (!p->recv[q].n) continue;
        MPI_Irecv(b, (int)(2 * p->recv[q].n), MPI_UINT32_T, q, 7, m->comm, &req[nreq++]);
        b += 2 * p->recv[q].n;
    }
    int rc = MPI_Waitall(nreq, req, MPI_STATUSES_IGNORE);
    free(req);
    if (rc != MPI_SUCCESS)
        return pg_error_set(err, PG_ERR_RUNTIME, "MPI: tile-edge exchange failed");
    b = recv0;
    for (int q = 0; q < m->size; q++) {
        unpack(L, &p->put[q], b);
        b += 2 * p->recv[q].n;
    }
    if (L->scale < PG_MPI_MAX_SCALES) m->stats.halo_bytes[L->scale] += 8.0 * (double)sent;
    return PG_OK;
}

/* Every rank's tiles to every rank (width -1), for the whole-planet steps. */
static pg_status exchange_all(pg_mpi *m, const pg_planet_level *L, pg_error *err) {
    const int T = L->T, ts = L->ts, P = m->size;
    const size_t per_tile = 2 * (size_t)ts * ts;
    if (per_tile * (size_t)m->ntiles > INT_MAX)
        return pg_error_set(err, PG_ERR_RUNTIME,
                            "MPI: a %d^2 level is too large for one allgather (2^31 words); "
                            "use --pits off or more --pit-skip-levels (docs/mpi.md)",
                            L->r);
    int *counts = malloc(2 * (size_t)P * sizeof *counts);
    uint32_t *all = malloc((per_tile * (size_t)m->ntiles + 1) * sizeof *all);
    if (!counts || !all) {
        free(counts), free(all);
        return pg_error_set(err, PG_ERR_NOMEM, "MPI: out of memory (allgather of a level)");
    }
    int *displs = counts + P;
    for (int q = 0; q < P; q++) {
        int a = pg_mpi_tile_first(m->ntiles, P, q), b = pg_mpi_tile_first(m->ntiles, P, q + 1);
        counts[q] = (int)((size_t)(b - a) * per_tile);
        displs[q] = (int)((size_t)a * per_tile);
    }
    /* tile t's texels, row by row, at all + t * per_tile */
    for (int pass = 0; pass < 2; pass++) {
        for (int t = 0; t < m->ntiles; t++) {
            bool mine = pg_mpi_tile_owner(m->ntiles, P, t) == m->rank;
            if (mine != (pass == 0)) continue;
            const int f = t / (T * T), x0 = t % T * ts, y0 = t / T % T * ts;
            uint32_t *w = all + (size_t)t * per_tile;
            for (int y = 0; y < ts; y++) {
                size_t i = level_index(L, f, x0, y0 + y);
                for (int x = 0; x < ts; x++, w += 2) {
                    if (mine) {
                        w[0] = L->S[i + x];
                        memcpy(&w[1], &L->V[i + x], 4);
                    } else {
                        L->S[i + x] = w[0];
                        memcpy(&L->V[i + x], &w[1], 4);
                    }
                }
            }
        }
        if (pass == 0 && MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, all, counts, displs,
                                        MPI_UINT32_T, m->comm) != MPI_SUCCESS) {
            free(counts), free(all);
            return pg_error_set(err, PG_ERR_RUNTIME, "MPI: allgather of a level failed");
        }
    }
    if (L->scale < PG_MPI_MAX_SCALES)
        m->stats.gather_bytes[L->scale] += 4.0 * counts[m->rank] * (P - 1);
    free(counts);
    free(all);
    return PG_OK;
}

static pg_status exchange_hook(void *user, const pg_planet_level *L, int width, pg_error *err) {
    pg_mpi *m = user;
    if (m->rank == m->fail_rank && L->scale == m->fail_scale) {
        fprintf(stderr,
                "planetgen generate: rank %d: PG_MPI_TEST_FAIL_AT: simulated crash at scale %d\n",
                m->rank, L->scale);
        fflush(stderr);
        _exit(70);
    }
    double t0 = MPI_Wtime();
    pg_status st = width < 0 ? exchange_all(m, L, err) : exchange_halo(m, L, width, err);
    m->stats.seconds += MPI_Wtime() - t0;
    if (L->scale < PG_MPI_MAX_SCALES) m->stats.exchanges[L->scale]++;
    return st;
}

static pg_status pits_hook(void *user, uint32_t n, int tiles, float *h, const pg_pits_opts *o,
                           pg_error *err) {
    pg_mpi *m = user;
    pg_mpi_pits_info info;
    double t0 = MPI_Wtime();
    pg_status st = pg_mpi_pits_remove(m, tiles, n, h, o, &info, err);
    m->stats.pits_seconds += MPI_Wtime() - t0;
    return st;
}

static pg_status stats_hook(void *user, uint32_t n, int tiles, const float *h,
                            const pg_pits_opts *o, const pg_pits_area *area, pg_pits_stats *out,
                            pg_error *err) {
    pg_mpi *m = user;
    double t0 = MPI_Wtime();
    pg_status st = pg_mpi_pits_stats(m, tiles, n, h, o, area, out, err);
    m->stats.pits_seconds += MPI_Wtime() - t0;
    return st;
}

static double sum_hook(void *user, double v) {
    return pg_mpi_sum_double(user, v);
}

void pg_mpi_synth_dist(pg_mpi *m, int tiles, pg_planet_synth_dist *d) {
    m->tiles = tiles;
    m->ntiles = 6 * tiles * tiles;
    const char *fail = getenv(PG_MPI_TESTING_FAIL_AT_ENV);
    if (fail && sscanf(fail, "%d:%d", &m->fail_rank, &m->fail_scale) != 2) m->fail_rank = -1;
    d->user = m;
    d->owns = owns_hook;
    d->exchange = exchange_hook;
    d->pits = pits_hook;
    d->stats = stats_hook;
    d->sum = sum_hook;
    d->shared_exemplar = m->node_size > 1;
}

#else /* no MPI: the CLI refuses multi-rank launches before calling any of these */

bool pg_mpi_built(void) {
    return false;
}

pg_status pg_mpi_init(pg_mpi **out, pg_error *err) {
    *out = NULL;
    return pg_error_set(err, PG_ERR_RUNTIME, "this planetgen was built without MPI");
}

void pg_mpi_finalize(pg_mpi *m) {
    (void)m;
}

void pg_mpi_abort(pg_mpi *m, int code) {
    (void)m;
    exit(code);
}

void pg_mpi_synth_dist(pg_mpi *m, int tiles, pg_planet_synth_dist *d) {
    (void)m, (void)tiles;
    memset(d, 0, sizeof *d);
}

#endif
