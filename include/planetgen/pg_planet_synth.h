/* pg_planet_synth.h - whole-planet synthesis by example on the cube sphere
 * (docs/generate.md, "Method"), steered by terrain types (pg_types.h) and an elevation
 * guide (pg_guide.h).
 *
 * THE DRIVER (pg_planet_synth_run) runs the Lefebvre-Hoppe engine of pg_synth.h
 * level-synchronously over all 6 T^2 tiles of the planet: at every level and every
 * correction sub-pass, each tile is corrected through a view whose one-texel halo is
 * its neighbours' current edge texels (across tile edges and, through the adjacency
 * map of pg_cube.h, across face seams, with the seam rotation in the view's orient).
 * Sub-passes are order-independent (see pg_synth_lefebvre_hoppe.c), so all tiles are
 * corrected in parallel and the output is bit-identical for any tile size and any
 * thread count. Randomness is a hash of (seed, level, face, x, y).
 *
 * CONTROL
 *  - layout earth: the coarsest level starts from the exemplar cube at the same
 *    direction, and jitter starts only below the top keep_levels levels; layout free:
 *    the coarsest level starts from hashed random exemplar texels.
 *  - guide: a grey elevation sketch resampled onto every level is blended into the
 *    reconstructed heights after every correction pass, R <- w G + (1 - w) R, with w
 *    halving at each finer level (Scott & Dodgson 2021 §4.2, exponential weighting).
 *  - types: every exemplar texel is classified (pg_types_exemplar: pg_types_classify,
 *    with inland water and its rim excluded from every mask); an allowed-type
 *    mask per output texel (a type map or a preset) rejects disallowed candidates
 *    after each sub-pass: a disallowed texel takes the first allowed coherent
 *    candidate of its neighbours, else a hashed draw among the valid exemplar texels.
 *
 * PITS (Gain-pit, Scott 2020 §4.2.1): after each correction pass at every level but the
 * finest pit_skip_levels, the planet's heights R = E_s(S) + V are made pit-free
 * globally on the cube sphere (pg_pits) and V += R' - R. A final pass on the
 * delivered heights removes the rest. */
#ifndef PLANETGEN_PG_PLANET_SYNTH_H
#define PLANETGEN_PG_PLANET_SYNTH_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_guide.h"
#include "planetgen/pg_pits.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_synth.h"
#include "planetgen/pg_types.h"

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------- the driver ---------------------------------- */

typedef enum pg_planet_layout { PG_LAYOUT_EARTH, PG_LAYOUT_FREE, PG_LAYOUT_WORLD } pg_planet_layout;

/* ----------------------------------- layout world ----------------------------------- */

/* The macro world that layout world amplifies (pg_plates.h, pg_climate.h): cube fields
 * of 6*n*n floats in the default projection, caller-owned. The coarsest level starts
 * from exemplar texels whose features (height, temperature, precipitation) match the
 * world's (texture-by-numbers, Hertzmann et al. 2001), the elevation is the guide and the
 * climate the type constraints, sampled on the cube at each level (pg_planet_world_level)
 * unless the params give a guide or a type map of their own. */
typedef struct pg_planet_world {
    int64_t n;
    const float *elevation_m;      /* relative to sea level */
    const float *temperature_c;    /* annual mean */
    const float *precipitation_mm; /* annual */
} pg_planet_world;

/* The world's elevation as an equirectangular guide of width x width/2 (pg_guide_free). */
pg_status pg_planet_world_guide(const pg_planet_world *w, int width, pg_guide *out, pg_error *err);

/* The world's climate as a type map of width x width/2 (pg_types_map_free): no ice where
 * it is warm, no desert where it is wet, no forest or grass where it is ice. */
pg_status pg_planet_world_types(const pg_planet_world *w, int width, pg_types_map *out,
                                pg_error *err);

/* The guide and the type constraints of layout world as the synthesis uses them: the
 * elevation (guide, metres) and the climate rule's allowed types (mask, as a type map's
 * pixel) at the texels of a level of r texels a face edge, for the global rows [row0,
 * row1) (row f r + y is face f's row y), sampled on the cube itself with no
 * equirectangular step. Either output may be NULL; each holds (row1 - row0) r values. */
pg_status pg_planet_world_level(const pg_planet_world *w, int64_t r, int64_t row0, int64_t row1,
                                float *guide, uint8_t *mask, pg_error *err);
/* The same with the annual mean temperature as well (temp, whole degrees C, rounded and
 * clamped to the int8 range; may be NULL): the climate constraint's target (docs/generate.md,
 * "Method": "Climate constraint"). */
pg_status pg_planet_world_level_climate(const pg_planet_world *w, int64_t r, int64_t row0,
                                        int64_t row1, float *guide, uint8_t *mask, int8_t *temp,
                                        pg_error *err);
/* The climate rule's allowed types at the world's own texel i. */
uint8_t pg_planet_world_mask_at(const pg_planet_world *w, size_t i);

/* The exemplar's own macro climate, the features layout world matches against: its
 * heights averaged to n texels a face edge (n divides the face size; relative to its sea
 * level) through the same climate model with Earth's parameters. out is initialised
 * here (pg_climate_free). */
struct pg_climate;
pg_status pg_planet_world_exemplar_climate(const pg_synth_exemplar *ex, int64_t n,
                                           struct pg_climate *out, pg_error *err);

/* The exemplar's hypsometry at the macro world's scale: its heights averaged to n texels
 * a face edge (as above), area-weighted, as nq quantiles of the land (> 0 m) into land_m
 * and of the ocean (<= 0 m) into ocean_m, ascending (caller-owned, nq each; nq >= 2), for
 * pg_plates_match_hypsometry. */
pg_status pg_planet_world_exemplar_hypsometry(const pg_synth_exemplar *ex, int64_t n, int nq,
                                              float *land_m, float *ocean_m, pg_error *err);

/* Sea ice (pg_planet_sea_ice.c; docs/generate.md, "Sea ice"): the ocean of the world's ice
 * climate covered with pack ice, its edge broken into floes, as an albedo cover that
 * leaves the heights alone. The exemplar lends the ice colour: the mean of its finest
 * texels of type ice, read from types (pg_types_exemplar's array, which the synthesis
 * already holds) or, with types NULL, classified here; ex may be NULL: snow white.
 * Caller-owned context, freed by pg_sea_ice_free. Every value is a hash of (seed, level,
 * lattice point): the same for any thread count, tiling or rank count. */
typedef struct pg_sea_ice {
    const pg_planet_world *world;
    int64_t nout; /* delivered texels per face edge */
    uint64_t seed;
    float ice_rgb[3];
    pg_cube_grid wgrid;
    float *warm_min; /* per world texel, the least temperature of its 2 x 2 block */
    bool sample_all; /* testing: sample every texel, without the warm_min shortcut */
} pg_sea_ice;

pg_status pg_sea_ice_init(pg_sea_ice *s, const pg_planet_world *w, const pg_synth_exemplar *ex,
                          const uint8_t *types, uint64_t seed, int64_t nout, pg_error *err);
void pg_sea_ice_free(pg_sea_ice *s);
/* The bytes pg_sea_ice_init allocates for a planet of nout texels a face edge and a
 * world of world_n (one float a world texel; the noises are computed, not stored). */
double pg_sea_ice_bytes(int64_t nout, int64_t world_n);
/* The world size pg_planet_synth_bytes assumes before the world exists: generate's
 * warped detail world, 4 x 64 texels a face edge (docs/generate.md, "Warped detail"). */
#define PG_SEA_ICE_WORLD_N 256
/* The world's annual mean temperature at delivered texel (f, X, Y). */
double pg_sea_ice_temperature(const pg_sea_ice *s, int f, int64_t X, int64_t Y);
/* The ice cover target there, 0 (open water) .. just under 1 (pack with leads). */
double pg_sea_ice_cover(const pg_sea_ice *s, int f, int64_t X, int64_t Y);
/* Cover the delivered texel's sRGB albedo rgb (0..1) with sea ice when it is ocean
 * (height <= sea_level) in an ice climate; rgb is untouched where the cover is 0.
 * Returns whether the texel is mostly ice. */
bool pg_sea_ice_apply(const pg_sea_ice *s, int f, int64_t X, int64_t Y, float height,
                      float sea_level, float rgb[3]);

#define PG_PLANET_KEEP_AUTO (-1)     /* keep_levels by ground scale */
#define PG_PLANET_FACE_MIN 512       /* smallest exemplar face with 6 analysed levels */
#define PG_PLANET_FACE_AUTO_MAX 2048 /* largest exemplar face chosen automatically */
/* The planet's synth.grid_shape by default: near the cube's corners, candidates whose
 * exemplar grid has the output texel's shape (docs/synthesis.md, "Grid shape at the
 * cube's corners"). */
#define PG_PLANET_GRID_SHAPE 25.0

/* DISTRIBUTION HOOKS (docs/mpi.md, "What is distributed, and how"; filled by pg_mpi.h,
 * NULL in a single process). A level of the synthesis, as the hooks see it: face f's
 * texel (x, y), x and y in -1..r (the one-texel border holds the neighbouring faces'
 * edges), is element f * face_stride + (y + 1) * stride + x + 1 of S and V. Tiles are
 * ts x ts texels at this level, T x T per face. */
typedef struct pg_planet_level {
    int scale, r, ts, T;
    size_t stride, face_stride;
    uint32_t *S;
    float *V;
} pg_planet_level;

/* With dist set, this process corrects, upsamples, jitters and delivers only the
 * tiles `owns` accepts, and calls `exchange` whenever it is about to read texels of
 * other tiles: width 1 before every correction step (the neighbours' current edges),
 * width 2 before the magnified delivery, and width -1 (every texel of the level)
 * before the whole-planet steps it does not distribute (Gain-pit, the land/ocean
 * agreement, the final pit removal and depression counts; docs/mpi.md). After
 * exchange(width >= 0), every texel within `width` of an owned tile (through face
 * seams for the first ring) holds its owner's current value; the others are stale and
 * never read. A sub-pass reads only its 3 x 3 neighbourhood, so the owned texels come
 * out bit-identical to a single-process run. */
typedef struct pg_planet_synth_dist {
    void *user;
    bool (*owns)(void *user, int face, int tx, int ty);
    pg_status (*exchange)(void *user, const pg_planet_level *L, int width, pg_error *err);
    /* Optional. Pit removal on a cube level of n texels per face edge in tiles x tiles
     * tiles (pg_pits cube ids): only the owned tiles of h need be valid and only they
     * come out right, bit-identical to pg_pits_remove (pg_mpi_pits_remove). When set,
     * Gain-pit (at levels the tiles divide) and the final pass run through it and the
     * level is not gathered for them. */
    pg_status (*pits)(void *user, uint32_t n, int tiles, float *h, const pg_pits_opts *o,
                      pg_error *err);
    /* Optional, with pits: the depression statistics of such a level
     * (pg_mpi_pits_stats); every process gets the totals. */
    pg_status (*stats)(void *user, uint32_t n, int tiles, const float *h, const pg_pits_opts *o,
                       const pg_pits_area *area, pg_pits_stats *out, pg_error *err);
    /* Optional: the sum of v over the processes (the land/ocean agreement's count). */
    double (*sum)(void *user, double v);
    /* Other processes on this machine map the same exemplar cache file: its levels are
     * read in place, never copied into private memory, so the machine holds one copy
     * (docs/mpi.md, "Memory per rank"). */
    bool shared_exemplar;
} pg_planet_synth_dist;

typedef struct pg_planet_synth_params {
    int tiles, tile_size;        /* T, S; S must be a multiple of 2^(levels-1) */
    pg_synth_params synth;       /* seed, jitter, passes, ... (tile_size ignored) */
    pg_planet_layout layout;     /* default earth (world needs `world` set; the CLI's default) */
    int keep_levels;             /* layout earth: top levels without jitter; default
                                    PG_PLANET_KEEP_AUTO (pg_planet_synth_keep_levels) */
    const pg_guide *guide;       /* NULL: none */
    double guide_alpha;          /* blend weight at the coarsest level; default 0.8 */
    uint8_t type_mask;           /* allowed types everywhere (preset); default all */
    const pg_types_map *types;   /* NULL: type_mask everywhere */
    bool pits;                   /* Gain-pit and the final pass; default true */
    int pit_skip_levels;         /* finest levels without Gain-pit; default 1 */
    pg_pits_method pit_method;   /* inside the synthesis; default breach */
    bool final_pits;             /* default true */
    pg_pits_method final_method; /* default breach (with epsilon) */
    bool pit_stats;              /* count depressions before and after the final pass */
    void (*progress)(void *user, double frac); /* optional */
    void *progress_user;

    /* distribution (docs/mpi.md): NULL, this process synthesizes every tile */
    const pg_planet_synth_dist *dist;

    /* layout world: the macro world (required there, NULL otherwise); with guide or types
     * NULL, the guide or the type constraints come from it */
    const pg_planet_world *world;
    /* layout world: cover the ocean of the ice climate with sea ice (pg_sea_ice_apply;
     * default true) */
    bool sea_ice;
} pg_planet_synth_params;

void pg_planet_synth_params_default(pg_planet_synth_params *p);

typedef struct pg_planet_synth_info {
    int s_top, nlevels;
    double level_seconds[PG_SYNTH_MAX_LEVELS + 8];
    double synth_seconds, pits_seconds, render_seconds;
    /* the final pass; in one process with pit_stats, the depression counts are taken by
     * its own floods (pg_pits_remove_counted) and their time is in here */
    double final_pits_seconds;
    double pit_stats_seconds;    /* counting apart from the final pass (pit_stats): the
                                    closed-land share, and distributed, the counts */
    uint64_t pit_cells_changed;  /* summed over the Gain-pit passes */
    pg_pits_stats before, after; /* depressions before/after the final pass (pit_stats) */
    double land_agreement;       /* layout earth: land/ocean match with the exemplar at
                                    the coarsest kept level (NaN otherwise) */
    double allowed_fraction;     /* texels of the finest level with an allowed type */
    double sea_ice_fraction;     /* layout world with sea_ice: the share of the delivered
                                    ocean texels mostly under sea ice (NaN otherwise) */
    double peak_bytes_estimate;
} pg_planet_synth_info;

/* The options Gain-pit (method p->pit_method) and the final pass (p->final_method) run
 * with on an exemplar of this sea level: breach or hybrid along the descent tree with
 * epsilon, the ocean a sink (docs/generate.md, "Method"). */
void pg_planet_synth_pits_opts(pg_pits_method m, float sea_level, pg_pits_opts *o);

/* Bytes the driver needs beyond the prepared exemplar for a planet of T x S. */
double pg_planet_synth_bytes(int tiles, int tile_size, const pg_planet_synth_params *p);

/* Check the parameters against the exemplar (BADINPUT naming the option). */
pg_status pg_planet_synth_check(const pg_synth_exemplar *ex, const pg_planet_synth_params *p,
                                pg_error *err);

/* Magnification m from synthesized to delivered texels: one synthesized texel is one
 * exemplar texel of ground, so a planet whose faces are at least twice as fine as the
 * exemplar cube's is synthesized at N / m (m the largest power of two keeping
 * N / m >= the exemplar's face size and whole pyramids per tile) and magnified (cubic
 * B-spline) at delivery. With the exemplar face from pg_planet_synth_face_size, only
 * planets with faces beyond 2048 are magnified. */
int pg_planet_synth_magnification(const pg_synth_exemplar *ex, const pg_planet_synth_params *p);

/* Levels layout earth keeps without jitter: keep_levels, or for PG_PLANET_KEEP_AUTO
 * those whose spacing is at least 1/32 of a face (E = 512: 2, 1024: 1), at least 1. */
int pg_planet_synth_keep_levels(const pg_synth_exemplar *ex, const pg_planet_synth_params *p);

/* The exemplar face size for a planet of T x S: N = T S rounded up to a power of two,
 * within [PG_PLANET_FACE_MIN, PG_PLANET_FACE_AUTO_MAX], so that planets up to faces of
 * 2048 are synthesized texel for texel (magnification 1). */
int pg_planet_synth_face_size(int tiles, int tile_size);

/* Synthesize a planet: out is allocated (pg_planet_alloc, default projection, WGS84)
 * and filled with albedo and heights. Optionally returns the finest exemplar coordinates
 * (6*N*N, global texel ids; caller frees) for tests; when magnified, each delivered texel
 * gets the coordinate of its synthesized texel. */
pg_status pg_planet_synth_run(const pg_synth_exemplar *ex, const pg_planet_synth_params *p,
                              pg_planet *out, uint32_t **coords_out, pg_planet_synth_info *info,
                              pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
