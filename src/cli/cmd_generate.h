/* cmd_generate.h - what the two files of `planetgen generate` share: cmd_generate.c (the
 * options, the inputs, the run and its report) and cmd_generate_mpi.c (the distributed
 * run's glue: rank roles, quiet ranks, collective failures, the tiled output and the MPI
 * figures; docs/mpi.md). Not for other commands. */
#ifndef CMD_GENERATE_H
#define CMD_GENERATE_H

#include "pg_cli.h"

#include "planetgen/pg_mpi.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_synth.h"
#include "planetgen/pg_climate.h"
#include "planetgen/pg_planet_synth.h"
#include "planetgen/pg_plates.h"

#include <stdbool.h>
#include <stddef.h>

typedef struct gen_args {
    const char *outdir, *layout, *guide, *types, *preset, *pits, *final_pits, *cache_dir;
    const char *output_layout; /* planet | tiled; NULL: planet, tiled when distributed */
    pg_cli_exemplar in;
    long tiles, tile_size, seed, keep_levels, pit_skip, passes, face_size, preview_width;
    double jitter, guide_weight, max_memory_gb;
    double grid_shape;                                    /* synth.grid_shape (pg_synth.h) */
    long plates;                                          /* layout world */
    double land_fraction, axial_tilt, temperature_offset; /* layout world */
    bool no_cache, independent, no_glb, no_sea_ice;
    bool geotiff; /* also the GIS rasters (pg_export.h) */
} gen_args;

/* A distributed run (mpirun -np P, P > 1, docs/mpi.md): NULL mpi in one process. */
typedef struct gen_mpi {
    pg_mpi *mpi;
    int rank, size;
    int node_size, node_rank; /* the ranks on this rank's machine, and its number there */
    int tiles;                /* --tiles */
    bool tiled;
    double need; /* this rank's memory estimate (gen_check_memory_ranks) */
} gen_mpi;

/* The output namer handed to the writers: staged paths in dir (gen_path_for). */
typedef struct path_ctx {
    pg_cli *cli;
    const char *dir;
} path_ctx;

/* ---- cmd_generate.c ---- */

/* Load the exemplar sources and prepare (or load from the cache) the exemplar cube. */
pg_status gen_prepare_exemplar(const gen_args *a, pg_synth_exemplar **ex, pg_synth_prep_info *pi,
                               char *src_name, size_t name_size, pg_error *err);
/* The exemplar from the cache only (*ex NULL on a miss). */
pg_status gen_cached_exemplar(const gen_args *a, pg_synth_exemplar **ex, pg_synth_prep_info *pi,
                              char *src_name, size_t name_size, pg_error *err);
/* The staged path of output `name` in the path_ctx `user`. */
const char *gen_path_for(const char *name, void *user);

/* ---- cmd_generate_world.c ---- */

/* Layout world's macro world. */
typedef struct gen_world {
    pg_plates_world plates;
    pg_climate climate;
    float *detail;         /* the fields on a finer cube (pg_plates_detail), 3 planes */
    pg_planet_world world; /* views into detail: what the synthesis follows */
    pg_plates_stats stats; /* of the plates' world */
} gen_world;

void gen_world_init(gen_world *w);
void gen_world_free(gen_world *w);
/* Plates and climate from the options (seed, plates, land fraction, tilt, offset). */
pg_status gen_world_build(const gen_args *a, const pg_synth_exemplar *ex, gen_world *w,
                          pg_error *err);
/* The plates' own figures: a line of the report, and "world" in res (may be NULL). */
struct pg_json;
void gen_world_report(pg_cli *cli, const gen_world *w, struct pg_json *res);
/* plates.png, climate.png and world.exr into the planet directory. */
pg_status gen_world_write(pg_cli *cli, const gen_args *a, const gen_world *w, pg_error *err);

/* ---- cmd_generate_mpi.c ---- */

int gen_fail_all(pg_cli *cli, const gen_mpi *g, const pg_error *err);
/* The memory check of a distributed run: each rank's estimate `need` against its limit
 * (pg_cli_memory_limit: --max-memory, or the available memory over the ranks on its
 * machine); rank 0 names the rank that is furthest over in one line. Collective; every
 * rank returns the same code. */
int gen_check_memory_ranks(pg_cli *cli, gen_mpi *g, const char *what, double need,
                           double max_memory_gb);
int gen_hush(void);
void gen_loud(int *saved);
int gen_rank0_first_outdir(pg_cli *cli, const gen_args *a, gen_mpi *g);
int gen_all_ranks_exemplar(pg_cli *cli, const gen_args *a, gen_mpi *g, int *hushed,
                           pg_synth_exemplar **ex, pg_synth_prep_info *pi, char *src_name,
                           size_t name_size);
void gen_report_mpi(pg_cli *cli, gen_mpi *g, int s_top);
int gen_write_tiled(pg_cli *cli, const gen_args *a, gen_mpi *g, pg_planet *planet,
                    const gen_world *world);
int gen_mpi_start(pg_cli *cli, const gen_args *a, gen_mpi *g);

#endif
