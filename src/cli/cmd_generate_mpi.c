/* cmd_generate_mpi.c - the glue of a distributed `planetgen generate` (mpirun -np P,
 * docs/mpi.md): starting MPI and refusing what a distributed run cannot do, quiet ranks
 * while every rank checks the same inputs, rank 0 first where a directory or the cache
 * is created, a failure in one rank stopping the job, the tiled output, and the figures
 * of the run (bytes communicated, memory per rank). In one process every function
 * here does what the single-process run needs and no more (g->mpi is NULL). */
#include "cmd_generate.h"

#include "planetgen/pg_export.h"

#include "planetgen/pg_json.h"
#include "planetgen/pg_planet_tiles.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A runtime failure in one rank of a distributed run: its line and clean-up, then the
 * whole job stops (MPI_Abort; the other ranks' signal watchers remove their staged
 * files), so no rank waits forever for a dead peer. */
int gen_fail_all(pg_cli *cli, const gen_mpi *g, const pg_error *err) {
    int rc = pg_cli_fail(cli, err);
    if (g->mpi) pg_mpi_abort(g->mpi, rc);
    return rc;
}

/* Ranks other than 0 keep quiet while every rank checks the same inputs, so that a bad
 * input gives one line, not one per rank: their stderr goes to /dev/null until
 * gen_loud. */
int gen_hush(void) {
    int rank = 0;
    if (pg_mpi_launcher_size(&rank) <= 1 || rank == 0) return -1;
    fflush(stderr);
    int saved = dup(2);
    FILE *null = fopen("/dev/null", "w");
    if (null) {
        dup2(fileno(null), 2);
        fclose(null);
    }
    return saved;
}

void gen_loud(int *saved) {
    if (*saved < 0) return;
    fflush(stderr);
    dup2(*saved, 2);
    close(*saved);
    *saved = -1;
}

int gen_check_memory_ranks(pg_cli *cli, gen_mpi *g, const char *what, double need,
                           double max_memory_gb) {
    const double have = pg_cli_memory_limit(max_memory_gb, g->node_size);
    g->need = need;
    if (!g->mpi) return pg_cli_check_memory_shared(cli, what, need, have, max_memory_gb, 1);
    const int P = g->size;
    double *v = g->rank == 0 ? calloc(3 * (size_t)P, sizeof *v) : NULL, scratch[3];
    pg_mpi_gather_double(g->mpi, need, v ? v : scratch);
    pg_mpi_gather_double(g->mpi, have, v ? v + P : scratch);
    pg_mpi_gather_double(g->mpi, g->node_size, v ? v + 2 * P : scratch);
    int rc = 0;
    if (g->rank == 0) {
        int w = 0; /* the rank furthest over its limit (or nearest to it) */
        for (int q = 1; v && q < P; q++)
            if (v[q] * v[P + w] > v[w] * v[P + q]) w = q;
        char what_rank[256];
        snprintf(what_rank, sizeof what_rank, "mpirun -np %d, rank %d (%d of %d tiles): %s", P, w,
                 pg_mpi_tile_first(6 * g->tiles * g->tiles, P, w + 1) -
                     pg_mpi_tile_first(6 * g->tiles * g->tiles, P, w),
                 6 * g->tiles * g->tiles, what);
        rc =
            v ? pg_cli_check_memory_shared(cli, what_rank, v[w], v[P + w], max_memory_gb,
                                           (int)v[2 * P + w])
              : pg_cli_check_memory_shared(cli, what_rank, need, have, max_memory_gb, g->node_size);
    }
    free(v);
    return pg_mpi_max_int(g->mpi, rc);
}

/* Rank 0 first, then the others: the output directory and the exemplar cache are
 * created once and found by the other ranks. Returns the agreed exit code of rank 0's
 * attempt (0: go on). */
int gen_rank0_first_outdir(pg_cli *cli, const gen_args *a, gen_mpi *g) {
    pg_error err = {0};
    int rc = 0;
    if (g->rank == 0 && pg_cli_prepare_outdir(cli, a->outdir, &err) != PG_OK)
        rc = pg_cli_fail(cli, &err);
    rc = pg_mpi_max_int(g->mpi, rc);
    if (!rc && g->rank != 0 && pg_cli_prepare_outdir(cli, a->outdir, &err) != PG_OK)
        rc = gen_fail_all(cli, g, &err);
    return rc;
}

/* One exemplar per machine: the first rank of each machine prepares it (or maps it from
 * the cache), then the others map the cache file it wrote, so a cold cache is prepared
 * once per machine, not once per rank, and every rank maps the same file (the cache is
 * written under a temporary name and renamed, so concurrent writers on a shared file
 * system are safe). Without the cache (--no-cache) every rank prepares its own at once.
 * Bad input fails on every rank alike and rank 0 says so; any other failure is said by
 * the rank that met it. */
int gen_all_ranks_exemplar(pg_cli *cli, const gen_args *a, gen_mpi *g, int *hushed,
                           pg_synth_exemplar **ex, pg_synth_prep_info *pi, char *src_name,
                           size_t name_size) {
    pg_error err = {0};
    int rc = 0;
    const bool first = a->no_cache || g->node_rank == 0;
    *ex = NULL;
    /* The memory samples (pg_cli_memory_pause): a first rank's preparation counts, its
     * mapping of the cache file does not until the others map it too (the stage's end
     * samples it shared); the others only map it. */
    pg_cli_smaps_figures before;
    pg_cli_memory_peaks(cli, &before, NULL);
    for (int round = 0; round < 2 && !rc; round++) {
        if (round == !first && gen_prepare_exemplar(a, ex, pi, src_name, name_size, &err)) {
            if (err.status != PG_ERR_BADINPUT) gen_loud(hushed);
            rc = pg_cli_fail(cli, &err);
        }
        if (g->mpi) pg_cli_memory_pause(cli, true);
        if (g->mpi && round == !first && *ex && pi->from_cache)
            pg_cli_memory_peaks(cli, NULL, &before);
        /* A first rank that prepared the exemplar maps the cache file it wrote instead,
         * the file the other ranks of its machine are about to map. */
        if (round == 0 && first && !rc && *ex && !pi->from_cache && g->node_size > 1 &&
            !a->no_cache) {
            pg_synth_exemplar *mapped = NULL;
            pg_synth_prep_info mpi_info;
            char name[1100];
            pg_error merr = {0};
            if (!gen_cached_exemplar(a, &mapped, &mpi_info, name, sizeof name, &merr) && mapped) {
                pg_synth_exemplar_free(*ex);
                *ex = mapped; /* the same arrays; pi still says it was prepared */
            }
        }
        /* the first ranks are done; then also lines the ranks up before the synthesis */
        rc = pg_mpi_max_int(g->mpi, rc);
    }
    if (rc && !err.status) pg_synth_exemplar_free(*ex), *ex = NULL;
    return rc;
}

/* Each rank's memory, gathered on rank 0 into the report's "mpi" object: peak RSS, the
 * peaks of private, shared and private dirty memory (smaps_rollup, pg_cli_smaps), the
 * estimate it was checked with (gen_check_memory_ranks), and private and shared
 * memory at the end of every stage (rank 0's stage names; -1 where a rank has no such
 * stage). RSS counts the exemplar's pages in every rank that reads them; private memory
 * does not count pages that other ranks map too. Collective. */
static void report_memory(pg_cli *cli, gen_mpi *g, pg_json *o) {
    const int P = g->size;
    double *v = calloc((size_t)P, sizeof *v), scratch[1];
    double *out = v ? v : scratch; /* only rank 0 reads the gathered values */
    pg_cli_sample_memory(cli);
    pthread_mutex_lock(&cli->lock);
    const double mine[5] = {pg_cli_peak_rss_bytes(), cli->private_peak, cli->shared_peak,
                            cli->private_dirty_peak, g->need};
    pthread_mutex_unlock(&cli->lock);
    static const char *const keys[5] = {
        "peak_rss_bytes_per_rank", "peak_private_bytes_per_rank", "peak_shared_bytes_per_rank",
        "peak_private_dirty_bytes_per_rank", "memory_estimate_bytes_per_rank"};
    double rss_max = 0, priv_max = 0;
    for (int k = 0; k < 5; k++) {
        pg_mpi_gather_double(g->mpi, mine[k], out);
        pg_json *a = o ? pg_json_set_array(o, keys[k]) : NULL;
        for (int q = 0; a && v && q < P; q++)
            pg_json_push_number(a, v[q]);
        for (int q = 0; v && g->rank == 0 && q < P; q++) {
            if (k == 0 && v[q] > rss_max) rss_max = v[q];
            if (k == 1 && v[q] > priv_max) priv_max = v[q];
        }
    }
    pg_json *st = o ? pg_json_set_array(o, "stages_per_rank") : NULL;
    const int ns = pg_mpi_max_int(g->mpi, cli->nstages);
    for (int i = 0; i < ns; i++) {
        pg_json *s = st ? pg_json_push_object(st) : NULL;
        if (s) pg_json_set_string(s, "name", i < cli->nstages ? cli->stages[i].name : "");
        for (int k = 0; k < 2; k++) {
            double x = i >= cli->nstages ? -1
                       : k               ? cli->stages[i].shared_bytes
                                         : cli->stages[i].private_bytes;
            pg_mpi_gather_double(g->mpi, x, out);
            pg_json *a = s ? pg_json_set_array(s, k ? "shared_bytes" : "private_bytes") : NULL;
            for (int q = 0; a && v && q < P; q++)
                pg_json_push_number(a, v[q]);
        }
    }
    if (g->rank == 0)
        pg_cli_info(cli, "memory   per rank: peak RSS up to %.0f MB, peak private up to %.0f MB\n",
                    rss_max / 1e6, priv_max / 1e6);
    free(v);
}

/* Figures of a distributed run: bytes sent per level (all ranks), memory per rank.
 * Collective: every rank calls it; rank 0 prints and reports. */
void gen_report_mpi(pg_cli *cli, gen_mpi *g, int s_top) {
    const pg_mpi_stats *ms = pg_mpi_stats_get(g->mpi);
    double halo[PG_MPI_MAX_SCALES], gath[PG_MPI_MAX_SCALES], total = 0;
    for (int s = 0; s < PG_MPI_MAX_SCALES; s++) {
        halo[s] = pg_mpi_sum_double(g->mpi, ms->halo_bytes[s]);
        gath[s] = pg_mpi_sum_double(g->mpi, ms->gather_bytes[s]);
        total += halo[s] + gath[s];
    }
    double xsec = pg_mpi_sum_double(g->mpi, ms->seconds) / g->size;
    double pbytes = pg_mpi_sum_double(g->mpi, ms->pits_bytes);
    double psec = pg_mpi_sum_double(g->mpi, ms->pits_seconds) / g->size;
    total += pbytes;
    pg_json *r = g->rank == 0 ? pg_cli_report(cli) : NULL;
    pg_json *o = r ? pg_json_set_object(r, "mpi") : NULL;
    if (g->rank == 0)
        pg_cli_info(cli,
                    "mpi      %d ranks; %.2f MB communicated (tile edges, level allgathers, "
                    "%.2f MB by the distributed pits); %.2f s per rank in exchanges, %.2f s in "
                    "the pits\n",
                    g->size, total / 1e6, pbytes / 1e6, xsec, psec);
    if (o) {
        pg_json_set_number(o, "ranks", g->size);
        pg_json_set_number(o, "exchange_seconds_mean", xsec);
        pg_json_set_number(o, "pits_seconds_mean", psec);
        pg_json_set_number(o, "pits_bytes", pbytes);
        pg_json *h = pg_json_set_array(o, "halo_bytes_per_scale");
        pg_json *ga = pg_json_set_array(o, "allgather_bytes_per_scale");
        for (int s = 0; s <= s_top && s < PG_MPI_MAX_SCALES; s++) {
            pg_json_push_number(h, halo[s]);
            pg_json_push_number(ga, gath[s]);
        }
    }
    report_memory(cli, g, o);
}

/* --geotiff with the tiled layout: the GeoTIFF tiles and their VRTs, from rank 0. In a
 * distributed run rank 0 holds only its own tiles' rows, so it commits the rest of the
 * planet and reads the others' tiles from the files they committed: the one step that
 * holds the whole planet in one rank (docs/mpi.md, "What is not distributed"). */
static pg_status write_geotiff_tiles(pg_cli *cli, const gen_args *a, gen_mpi *g, pg_planet *planet,
                                     pg_error *err) {
    if (g->mpi &&
        (pg_planet_open_all_rows(planet, err) || pg_planet_load_tile_files(a->outdir, planet, err)))
        return err->status;
    pg_export_opts o;
    pg_export_opts_default(&o);
    o.glb = o.exr = o.previews = false;
    o.geotiff = o.geotiff_tiled = true;
    path_ctx pc = {cli, a->outdir};
    pg_cli_stage_begin(cli, "write GeoTIFF tiles");
    pg_status st = pg_export_write(planet, &o, gen_path_for, &pc, NULL, err);
    pg_cli_stage_end(cli);
    return st;
}

/* The glTF file of each of this process's tiles (docs/export.md, "Tiled planets"), once
 * every tile's files are in place: the texels around a tile that another rank holds are
 * read from its committed height EXR. */
static pg_status write_tile_glbs(pg_cli *cli, const gen_args *a, gen_mpi *g, pg_planet *planet,
                                 pg_error *err) {
    const int n = 6 * planet->tiles * planet->tiles;
    pg_export_opts o;
    pg_export_opts_default(&o);
    path_ctx pc = {cli, a->outdir};
    pg_cli_stage_begin(cli, "write tile glTF");
    pg_status st = pg_export_tiles_glb(planet, pg_mpi_tile_first(n, g->size, g->rank),
                                       pg_mpi_tile_first(n, g->size, g->rank + 1),
                                       g->mpi ? a->outdir : NULL, &o, gen_path_for, &pc, NULL, err);
    pg_cli_stage_end(cli);
    return st;
}

/* The tiled layout: this process's tiles (all of them in one process) and, from rank 0,
 * the macro world's files (layout world), then, once every rank has renamed its files
 * into place, each rank's tile .glb files (unless --no-glb), the GeoTIFFs (--geotiff) and
 * index.json from rank 0 - the mark that the directory is complete. */
int gen_write_tiled(pg_cli *cli, const gen_args *a, gen_mpi *g, pg_planet *planet,
                    const gen_world *world) {
    const int n = 6 * planet->tiles * planet->tiles;
    path_ctx pc = {cli, a->outdir};
    pg_error err = {0};
    pg_cli_stage_begin(cli, "write tiles");
    pg_status st =
        pg_planet_save_tiles(planet, pg_mpi_tile_first(n, g->size, g->rank),
                             pg_mpi_tile_first(n, g->size, g->rank + 1), gen_path_for, &pc, &err);
    if (!st && world && g->rank == 0) st = gen_world_write(cli, a, world, &err);
    pg_cli_stage_end(cli);
    if (st) return gen_fail_all(cli, g, &err);
    if (g->mpi) {
        pg_mpi_barrier(g->mpi); /* every rank has written all its tiles */
        if (pg_cli_commit(cli, &err)) return gen_fail_all(cli, g, &err);
        pg_mpi_barrier(g->mpi); /* every tile is in place */
    }
    if (!a->no_glb) {
        if (write_tile_glbs(cli, a, g, planet, &err)) return gen_fail_all(cli, g, &err);
        if (g->mpi) {
            pg_mpi_barrier(g->mpi); /* every rank has written its tiles' .glb */
            if (pg_cli_commit(cli, &err)) return gen_fail_all(cli, g, &err);
            pg_mpi_barrier(g->mpi);
        }
    }
    if (g->rank == 0 && a->geotiff && write_geotiff_tiles(cli, a, g, planet, &err))
        return gen_fail_all(cli, g, &err);
    if (g->rank == 0 && pg_planet_save_index_glb(planet, !a->no_glb, gen_path_for, &pc, &err))
        return gen_fail_all(cli, g, &err);
    return 0;
}

/* Under a launcher with P > 1 ranks: refuse a build without MPI, start MPI, refuse
 * more ranks than tiles and the single-file layout. Returns -1 to go on, else the
 * exit code (MPI already finalized). */
int gen_mpi_start(pg_cli *cli, const gen_args *a, gen_mpi *g) {
    int lrank = 0, P = pg_mpi_launcher_size(&lrank);
    memset(g, 0, sizeof *g);
    g->size = g->node_size = 1;
    g->tiles = (int)a->tiles;
    g->tiled = a->output_layout && !strcmp(a->output_layout, "tiled");
    if (P <= 1) return -1;
    if (!pg_mpi_built()) {
        if (lrank != 0) return 2;
        return pg_cli_usage_error(cli,
                                  "launched by mpirun with %d ranks, but this planetgen was built "
                                  "without MPI (rebuild with cmake -DPG_MPI=ON, or run it "
                                  "without mpirun)",
                                  P);
    }
    pg_error err = {0};
    if (pg_mpi_init(&g->mpi, &err)) return pg_cli_fail(cli, &err);
    g->rank = pg_mpi_rank(g->mpi);
    g->size = pg_mpi_size(g->mpi);
    g->node_size = pg_mpi_node_size(g->mpi);
    g->node_rank = pg_mpi_node_rank(g->mpi);
    g->tiled = true;
    int rc = -1;
    long ntiles = 6 * a->tiles * a->tiles;
    if (g->size > ntiles)
        rc = g->rank ? 2
                     : pg_cli_usage_error(cli,
                                          "mpirun -np %d: more ranks than the %ld tiles of the "
                                          "planet (6 x --tiles %ld^2); use at most %ld ranks or "
                                          "more --tiles",
                                          g->size, ntiles, a->tiles, ntiles);
    else if (a->output_layout && strcmp(a->output_layout, "tiled"))
        rc = g->rank ? 2
                     : pg_cli_usage_error(cli,
                                          "--output-layout %s: a distributed run writes each "
                                          "rank's tiles (--output-layout tiled); the planet "
                                          "layout needs the whole planet in one process",
                                          a->output_layout);
    if (rc >= 0) {
        pg_mpi_finalize(g->mpi);
        g->mpi = NULL;
        return rc;
    }
    if (g->rank != 0) { /* rank 0 speaks for the job */
        cli->quiet = true;
        pg_json_free(pg_cli_report(cli));
        cli->report = NULL;
    }
    return -1;
}
