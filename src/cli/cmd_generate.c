/* cmd_generate.c - `planetgen generate`: synthesize a whole planet by example on the cube
 * sphere (pg_planet_synth.h) and write the planet directory (pg_planet_save: per-face
 * albedo PNGs, height.exr, source.exr, planet.json), the export module's previews (equirect
 * albedo.png and relief.png, globe_*.png) and planet.glb (pg_export.h), and a JSON
 * report of parameters, stage timings and quality figures.
 *
 * Every input is validated before work: numbers and choices, the pyramid (S a multiple
 * of 2^(levels-1)), the guide and type map (readable, 2:1, known colours), the preset,
 * and the memory estimate against the available memory (refused with the estimate
 * unless --max-memory raises the limit). Outputs are staged and renamed at the end.
 * The distributed run's glue (docs/mpi.md) is in cmd_generate_mpi.c. */
#include "cmd_generate.h"
#include "pg_commands.h"

#include "pg_planet_synth_testing.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_export.h"
#include "planetgen/pg_inspect.h"
#include "planetgen/pg_json.h"
#include "planetgen/pg_mpi.h"
#include "planetgen/pg_planet_synth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GEN_LEVELS 6                       /* analysed levels of the exemplar (pg_synth default) */
#define GEN_SOURCE_BYTES 4e8               /* the loaded source images */
#define GEN_BYTES_PER_EXEMPLAR_TEXEL 200.0 /* preparing the exemplar cube, at its peak */
#define GEN_MAP_BYTES_PER_TEXEL 4.0        /* the coordinate map (source.exr) */
#define GEN_GUIDE_WEIGHT 0.8               /* --guide-weight's default */
/* layout world's: the plates' belts and coasts hold through the pyramid (at 0.8, a
 * quarter less of the high land lay in the belts, docs/generate.md) */
#define GEN_WORLD_GUIDE_WEIGHT 1.0

typedef struct gen_inputs {
    pg_guide guide;
    pg_types_map types;
    uint8_t mask;
    bool has_guide, has_types, has_world;
    gen_world world; /* layout world: the macro world, its guide and type map */
} gen_inputs;

/* layout world is the default, except that a guide alone asks for layout free */
static bool is_world(const gen_args *a) {
    return a->layout ? !strcmp(a->layout, "world") : !a->guide;
}

static int validate(pg_cli *cli, const gen_args *a) {
    long S = a->tile_size, need = 1L << (GEN_LEVELS - 1);
    if (S < 16 || S > 8192 || (S & (S - 1)))
        return pg_cli_usage_error(cli, "--tile-size %ld: must be a power of two in 16..8192", S);
    if (S % need)
        return pg_cli_usage_error(cli,
                                  "--tile-size %ld: does not divide into the %d-level pyramid "
                                  "(must be a multiple of 2^%d = %ld)",
                                  S, GEN_LEVELS, GEN_LEVELS - 1, need);
    if (a->keep_levels != PG_PLANET_KEEP_AUTO && a->keep_levels > GEN_LEVELS)
        return pg_cli_usage_error(cli, "--keep-levels %ld: must be in 0..%d", a->keep_levels,
                                  GEN_LEVELS);
    if (a->pit_skip > GEN_LEVELS)
        return pg_cli_usage_error(cli, "--pit-skip-levels %ld: must be in 0..%d", a->pit_skip,
                                  GEN_LEVELS);
    return 0;
}

static pg_status load_inputs(const gen_args *a, gen_inputs *in, pg_error *err) {
    memset(in, 0, sizeof *in);
    in->mask = PG_TYPES_ALL;
    pg_status st = a->preset ? pg_types_preset(a->preset, &in->mask, err) : PG_OK;
    if (!st && a->guide) {
        st = pg_guide_load(a->guide, &in->guide, err);
        in->has_guide = !st;
    }
    if (!st && a->types) {
        st = pg_types_map_load(a->types, &in->types, err);
        in->has_types = !st;
    }
    gen_world_init(&in->world); /* built once the exemplar is ready (build_world) */
    return st;
}

static void free_inputs(gen_inputs *in) {
    if (in->has_guide) pg_guide_free(&in->guide);
    if (in->has_types) pg_types_map_free(&in->types);
    gen_world_free(&in->world);
}

/* layout world: the macro world, and its elevation and climate as the guide and the
 * type map unless --guide or --types replace them */
static void set_world(const gen_args *a, const gen_inputs *in, pg_planet_synth_params *p) {
    p->layout = PG_LAYOUT_WORLD;
    if (a->guide_weight < 0) p->guide_alpha = GEN_WORLD_GUIDE_WEIGHT;
    p->world = &in->world.world; /* the guide and the types unless given (--guide, --types) */
}

static void set_params(const gen_args *a, const gen_inputs *in, pg_planet_synth_params *p) {
    pg_planet_synth_params_default(p);
    p->tiles = (int)a->tiles;
    p->tile_size = (int)a->tile_size;
    p->synth.seed = (uint64_t)a->seed;
    p->synth.jitter = a->jitter;
    p->synth.passes = (int)a->passes;
    p->synth.grid_shape = a->grid_shape;
    /* with a guide and no explicit layout, the sketch gives the arrangement */
    p->layout = is_world(a)                                ? PG_LAYOUT_WORLD
                : a->layout && !strcmp(a->layout, "earth") ? PG_LAYOUT_EARTH
                                                           : PG_LAYOUT_FREE;
    p->keep_levels = (int)a->keep_levels;
    p->guide = in->has_guide ? &in->guide : NULL;
    p->guide_alpha = a->guide_weight >= 0 ? a->guide_weight : GEN_GUIDE_WEIGHT;
    p->type_mask = in->mask;
    p->types = in->has_types ? &in->types : NULL;
    p->pits = strcmp(a->pits, "off") != 0;
    p->pit_skip_levels = (int)a->pit_skip;
    p->final_pits = strcmp(a->final_pits, "none") != 0;
    p->sea_ice = !a->no_sea_ice;
    if (p->final_pits) pg_pits_method_parse(a->final_pits, &p->final_method);
    if (in->has_world) set_world(a, in, p);
}

/* --face-size, or by default the planet's own face size (pg_planet_synth_face_size). */
static int gen_face_size(const gen_args *a) {
    return a->face_size ? (int)a->face_size
                        : pg_planet_synth_face_size((int)a->tiles, (int)a->tile_size);
}

/* The source images (Blue Marble, the 10800 x 5400 relief: about 0.4 GB) plus the
 * exemplar cube while it is prepared, about 200 B per exemplar texel at its peak
 * (E = 2048, 25 M exemplar texels: 5.1 GB peak RSS measured, cold). */
static double gen_exemplar_bytes(const gen_args *a) {
    double e = gen_face_size(a);
    return GEN_SOURCE_BYTES + GEN_BYTES_PER_EXEMPLAR_TEXEL * 6.0 * e * e;
}

/* Memory per rank of a distributed run (docs/mpi.md, "Memory per rank"): the constants
 * of the estimate, measured with `planetgen generate --json` (peak_private_dirty_bytes,
 * one process, and peak_private_bytes_per_rank under mpirun; layout free, default pits,
 * tiled, exemplar face 512 from a warm cache). Re-measure them here when the memory of
 * the synthesis or the pits changes. */
/* libraries, MPI and buffers of a rank: 46 MB private after loading the exemplar, in
 * every rank of 2 and 4 */
#define GEN_RANK_BASE_BYTES 50e6
/* per delivered texel: 19.1 B (N 512 -> 1024) and 20.1 B (N 1024 -> 2048) of peak
 * private memory per added texel in one process; under mpirun at 100 Mpx, 21.0 B (2
 * ranks) and 20.8 B (4 ranks) per owned texel above the base, the larger of the final
 * pass (H and the breach) and the delivery; rounded up */
#define GEN_RANK_BYTES_PER_TEXEL 24.0
/* rank 0 alone: the spill graph of the distributed fill while it solves it, about 55 B
 * per edge, and 11.4 S edges per tile of S^2 (140 426 for 96 tiles of 128^2) */
#define GEN_RANK0_BYTES_PER_EDGE 55.0
#define GEN_RANK0_EDGES_PER_TILE_EDGE 11.4
/* per synthesized texel of the pyramid (4/3 of the finest synthesized level): S and V
 * with the parent level, orientation and Gain-pit (pg_planet_synth_bytes's synthesis
 * phase, 15.5 B; counted, not measured: on these planets the delivery is the peak) */
#define GEN_RANK_BYTES_PER_SYNTH_TEXEL 16.0
/* the ring a rank reads around its tiles: 2 texels wide (the delivery's B-spline) */
#define GEN_RANK_RING_WIDTH 2

/* One rank's peak: its tiles' share of the delivered planet and of the synthesized
 * pyramid, the ring around them, its base, rank 0's spill graph, and the exemplar counted once per
 * machine (its cold preparation, the larger figure, shared by the ranks there that map its cache
 * file; --no-cache: every rank holds its own). */
static double gen_rank_bytes(const gen_args *a, const pg_planet_synth_params *p, const gen_mpi *g) {
    const int nt = 6 * p->tiles * p->tiles;
    const double owned =
        pg_mpi_tile_first(nt, g->size, g->rank + 1) - pg_mpi_tile_first(nt, g->size, g->rank);
    const double S = p->tile_size, face = gen_face_size(a);
    const double n = (double)p->tiles * S, nsyn = n > face ? face : n; /* synthesized edge */
    const double synth = 4.0 / 3.0 * owned / nt * 6.0 * nsyn * nsyn;
    const double ring = owned * 4.0 * (S + 2 * GEN_RANK_RING_WIDTH) * GEN_RANK_RING_WIDTH;
    const double sharers = a->no_cache ? 1 : g->node_size;
    const double graph = g->rank == 0 && (p->pits || p->pit_stats)
                             ? GEN_RANK0_BYTES_PER_EDGE * GEN_RANK0_EDGES_PER_TILE_EDGE * S * nt
                             : 0;
    /* every rank holds the sea ice's whole noise grids */
    const double ice = p->layout == PG_LAYOUT_WORLD && p->sea_ice
                           ? pg_sea_ice_bytes((int64_t)n, PG_SEA_ICE_WORLD_N)
                           : 0;
    return GEN_RANK_BASE_BYTES + GEN_RANK_BYTES_PER_TEXEL * (owned * S * S + ring) +
           GEN_RANK_BYTES_PER_SYNTH_TEXEL * synth + graph + gen_exemplar_bytes(a) / sharers + ice;
}

/* with_map: the single-file layout keeps the coordinate map, 4 bytes per texel held
 * from the end of the synthesis to the end of the run. A distributed run checks each
 * rank's share (gen_rank_bytes) against its limit (gen_check_memory_ranks). */
static int check_memory(pg_cli *cli, const gen_args *a, const pg_planet_synth_params *p, gen_mpi *g,
                        double *need_out) {
    char what[96];
    snprintf(what, sizeof what, "--tiles %ld --tile-size %ld", a->tiles, a->tile_size);
    if (g->mpi) {
        *need_out = gen_rank_bytes(a, p, g);
        return gen_check_memory_ranks(cli, g, what, *need_out, a->max_memory_gb);
    }
    double n = (double)p->tiles * p->tile_size;
    double need = pg_planet_synth_bytes(p->tiles, p->tile_size, p) + gen_exemplar_bytes(a) +
                  (!g->tiled ? GEN_MAP_BYTES_PER_TEXEL * 6.0 * n * n : 0);
    *need_out = need;
    return pg_cli_check_memory(cli, what, need, a->max_memory_gb);
}

static void exemplar_params(const gen_args *a, pg_exemplar_opts *eo, pg_synth_exemplar_params *ep) {
    pg_cli_exemplar_opts(&a->in, eo);
    pg_synth_exemplar_params_default(ep);
    ep->face_size = gen_face_size(a);
    ep->levels = GEN_LEVELS;
}

/* A warm cache: the exemplar found by the sources' fingerprint, without decoding them
 * (*ex NULL on a miss); *fp and *have_fp for recording a preparation. */
static pg_status lookup_exemplar(const gen_args *a, pg_synth_exemplar **ex, pg_synth_prep_info *pi,
                                 char *src_name, size_t name_size, uint64_t *fp, bool *have_fp,
                                 pg_error *err) {
    pg_exemplar_opts eo;
    pg_synth_exemplar_params ep;
    exemplar_params(a, &eo, &ep);
    *ex = NULL;
    *fp = 0;
    char an[512], hn[512];
    pg_error ferr = {0};
    *have_fp = !a->no_cache && pg_exemplar_fingerprint(&eo, fp, an, hn, sizeof an, &ferr) == 0;
    pg_status st = *have_fp ? pg_synth_lookup_exemplar(*fp, &ep, a->cache_dir, ex, pi, err) : PG_OK;
    if (!st && *ex) snprintf(src_name, name_size, "%s + %s", an, hn);
    return st;
}

pg_status gen_cached_exemplar(const gen_args *a, pg_synth_exemplar **ex, pg_synth_prep_info *pi,
                              char *src_name, size_t name_size, pg_error *err) {
    uint64_t fp;
    bool have_fp;
    return lookup_exemplar(a, ex, pi, src_name, name_size, &fp, &have_fp, err);
}

pg_status gen_prepare_exemplar(const gen_args *a, pg_synth_exemplar **ex, pg_synth_prep_info *pi,
                               char *src_name, size_t name_size, pg_error *err) {
    uint64_t fp;
    bool have_fp;
    pg_status st = lookup_exemplar(a, ex, pi, src_name, name_size, &fp, &have_fp, err);
    if (st || *ex) return st;
    pg_exemplar_opts eo;
    pg_synth_exemplar_params ep;
    exemplar_params(a, &eo, &ep);
    const char *cache = a->no_cache ? "" : a->cache_dir;
    pg_exemplar src;
    st = pg_exemplar_load(&eo, &src, err);
    if (st) return st;
    snprintf(src_name, name_size, "%s + %s", src.albedo_src, src.height_src);
    st = pg_synth_prepare_exemplar(src.albedo, src.elevation, src.width, src.height, src.sea_level,
                                   &ep, cache, ex, pi, err);
    pg_exemplar_free(&src);
    if (!st && have_fp && pi->cache_path[0]) pg_synth_remember_sources(fp, &ep, cache, *ex);
    return st;
}

/* ---- outputs ---- */

/* The synthesis coordinates (6 N^2, global texel ids) become the planet's coordinate
 * map (pg_planet.h; source.exr), orientation cleared; coords is freed. Faces are
 * copied last to first and the raw buffer shrunk behind each copy, so that the two
 * together hold little more than one copy. The tiled layout keeps no map: its tiles
 * are written one file each (pg_planet_save_tiles) and carry none. */
static pg_status adopt_coords(pg_planet *planet, int face_size, uint32_t *coords, pg_error *err) {
    pg_status st = pg_planet_source_alloc(planet, face_size, PG_CUBE_DEFAULT_PROJECTION, err);
    const size_t nn = (size_t)planet->n * (size_t)planet->n;
    for (int f = PG_CUBE_NFACES - 1; st == PG_OK && f >= 0; f--) {
        const uint32_t *src = coords + (size_t)f * nn;
        uint32_t *dst = planet->source.coords[f];
        for (size_t i = 0; i < nn; i++)
            dst[i] = pg_synth_with_orient(src[i], 0);
        uint32_t *shrunk = f > 0 ? realloc(coords, (size_t)f * nn * sizeof *coords) : NULL;
        if (shrunk) coords = shrunk; /* a failed shrink keeps the old block */
    }
    free(coords);
    return st;
}

const char *gen_path_for(const char *name, void *user) {
    path_ctx *pc = user;
    return pg_cli_output_path(pc->cli, pc->dir, name);
}

/* Previews (albedo.png, relief.png, globe_*.png) and the glTF globe through the export
 * module; height.exr is already in the planet directory. */
static pg_status write_exports(pg_cli *cli, const gen_args *a, const pg_planet *p,
                               const pg_planet_encoded *albedo_png, pg_error *err) {
    pg_export_opts o;
    pg_export_opts_default(&o);
    o.albedo_png = albedo_png; /* the face files' PNGs: planet.glb embeds the same bytes */
    o.exr = false;
    o.glb = !a->no_glb;
    o.geotiff = a->geotiff;
    o.preview_width = (int)a->preview_width;
    path_ctx pc = {cli, a->outdir}; /* pg_export_write checks the options and the relief */
    return pg_export_write(p, &o, gen_path_for, &pc, NULL, err);
}

static void report_depressions(pg_json *o, const char *key, const pg_pits_stats *s) {
    pg_json *d = pg_json_set_object(o, key);
    pg_json_set_number(d, "depressions", (double)s->depressions);
    pg_json_set_number(d, "depression_cells", (double)s->depression_cells);
    pg_json_set_number(d, "depression_area_m2", s->depression_area_m2);
    pg_json_set_number(d, "depression_volume_m3", s->depression_volume_m3);
    pg_json_set_number(d, "max_depth_m", s->max_depth_m);
}

/* What the exemplar decided: its face size, the magnification, the kept levels. */
typedef struct gen_scale {
    int face, mag, keep;
} gen_scale;

static void report(pg_cli *cli, const gen_args *a, const pg_planet_synth_params *p,
                   const pg_synth_prep_info *pi, const pg_planet_synth_info *si, double need,
                   const pg_inspect_seams *seams, const gen_scale *sc, const gen_world *w) {
    const int mag = sc->mag;
    double mpx = 6.0 * (double)a->tiles * a->tiles * a->tile_size * a->tile_size / 1e6;
    pg_cli_info(cli, "exemplar 6 x %d^2, %s in %.2f s\n", sc->face,
                pi->from_cache ? "loaded from cache" : "prepared", pi->seconds);
    if (!pi->from_cache)
        pg_cli_verbose(cli,
                       "         cube %.2f s, stack %.2f s, appearance %.2f s, k-coherence %.2f s, "
                       "cache write %.2f s\n",
                       pi->stage_seconds[0], pi->stage_seconds[1], pi->stage_seconds[2],
                       pi->stage_seconds[3], pi->stage_seconds[4]);
    /* Say how many texels were synthesized: a magnified planet delivers m^2 times more. */
    pg_cli_info(cli,
                "planet   6 x %ld^2 tiles of %ld^2 = %.1f Mpx; synthesized %.1f Mpx at the "
                "exemplar's scale, magnified %dx; %.2f s (%.2f Mpx/s synthesized)\n",
                a->tiles, a->tile_size, mpx, mpx / ((double)mag * mag), mag, si->synth_seconds,
                mpx / ((double)mag * mag) / si->synth_seconds);
    if (!isnan(si->land_agreement))
        pg_cli_info(cli, "layout   land/ocean agreement with the exemplar %.1f%%\n",
                    100 * si->land_agreement);
    if (p->type_mask != PG_TYPES_ALL || p->types)
        pg_cli_info(cli, "types    %.1f%% of texels of allowed types\n",
                    100 * si->allowed_fraction);
    if (!isnan(si->sea_ice_fraction))
        pg_cli_info(cli, "sea ice  %.1f%% of the ocean's texels\n", 100 * si->sea_ice_fraction);
    if (seams)
        pg_cli_info(cli, "seams    seam/interior |delta|: height %.3f, albedo %.3f (gate %.1f)\n",
                    seams->height.ratio, seams->albedo.ratio, PG_INSPECT_SEAM_GATE);
    if (p->pit_stats)
        pg_cli_info(cli, "pits     depressions %llu before the final pass, %llu after\n",
                    (unsigned long long)si->before.depressions,
                    (unsigned long long)si->after.depressions);
    pg_cli_verbose(cli, "method   Lefebvre & Hoppe 2005/2006 correction with Gain, Merry & "
                        "Marais 2015 height offsets and type constraints\n");
    if (p->synth.grid_shape > 0)
        pg_cli_verbose(cli,
                       "corners  candidates weighed by their grid's shape, weight %g "
                       "(docs/synthesis.md)\n",
                       p->synth.grid_shape);
    if (p->guide)
        pg_cli_verbose(cli,
                       "guide    Scott & Dodgson 2021 soft constraint, weight %.2f halving "
                       "per finer level\n",
                       p->guide_alpha);
    if (p->pits) { /* name what runs: the options the synthesis gives pg_pits */
        pg_pits_opts po;
        pg_planet_synth_pits_opts(p->pit_method, 0.0f, &po);
        pg_cli_verbose(cli, "pits     Gain-pit (Scott 2020 4.2.1): %s\n", pg_pits_citation(&po));
        pg_planet_synth_pits_opts(p->final_method, 0.0f, &po);
        if (p->final_pits) pg_cli_verbose(cli, "pits     final pass: %s\n", pg_pits_citation(&po));
    }
    pg_json *r = pg_cli_report(cli);
    if (w && !r) gen_world_report(cli, w, NULL);
    if (!r) return;
    pg_json *pp = pg_json_set_object(r, "parameters");
    pg_json_set_number(pp, "tiles", (double)a->tiles);
    pg_json_set_number(pp, "tile_size", (double)a->tile_size);
    pg_json_set_number(pp, "seed", (double)a->seed);
    pg_json_set_string(pp, "layout",
                       p->layout == PG_LAYOUT_EARTH   ? "earth"
                       : p->layout == PG_LAYOUT_WORLD ? "world"
                                                      : "free");
    if (p->layout == PG_LAYOUT_WORLD) {
        pg_json_set_number(pp, "plates", (double)a->plates);
        pg_json_set_number(pp, "land_fraction", a->land_fraction);
        pg_json_set_number(pp, "axial_tilt_deg", a->axial_tilt);
        pg_json_set_number(pp, "temperature_offset_K", a->temperature_offset);
        pg_json_set_bool(pp, "sea_ice", !a->no_sea_ice);
    }
    pg_json_set_bool(pp, "repair_ocean", !a->in.no_repair_ocean);
    pg_json_set_number(pp, "keep_levels", sc->keep);
    pg_json_set_number(pp, "exemplar_face_size", sc->face);
    pg_json_set_number(pp, "jitter", p->synth.jitter);
    pg_json_set_number(pp, "passes", p->synth.passes);
    pg_json_set_number(pp, "grid_shape", p->synth.grid_shape);
    pg_json_set_string(pp, "guide", a->guide ? a->guide : "");
    pg_json_set_number(pp, "guide_weight", p->guide_alpha);
    pg_json_set_string(pp, "types", a->types ? a->types : "");
    pg_json_set_string(pp, "preset", a->preset ? a->preset : "");
    pg_json_set_string(pp, "pits", a->pits);
    pg_json_set_number(pp, "pit_skip_levels", p->pit_skip_levels);
    pg_json_set_string(pp, "final_pits", a->final_pits);
    pg_json *res = pg_json_set_object(r, "results");
    if (w) gen_world_report(cli, w, res);
    pg_json_set_number(res, "megapixels", mpx);
    pg_json_set_number(res, "exemplar_prep_seconds", pi->seconds);
    pg_json_set_bool(res, "exemplar_from_cache", pi->from_cache);
    if (!pi->from_cache) { /* the preparation's own stages (pg_synth_prep_info) */
        static const char *const names[5] = {"cube", "stack", "appearance", "kcoherence",
                                             "cache_write"};
        pg_json *ps = pg_json_set_object(res, "exemplar_prep_stage_seconds");
        for (int i = 0; i < 5; i++)
            pg_json_set_number(ps, names[i], pi->stage_seconds[i]);
    }
    pg_json_set_number(res, "synth_seconds", si->synth_seconds);
    pg_json_set_number(res, "mpx_per_second", mpx / si->synth_seconds);
    pg_json_set_number(res, "magnification", mag);
    pg_json_set_number(res, "synthesized_mpx_per_second",
                       mpx / ((double)mag * mag) / si->synth_seconds);
    pg_json_set_number(res, "gain_pit_seconds", si->pits_seconds);
    pg_json_set_number(res, "gain_pit_cells_changed", (double)si->pit_cells_changed);
    pg_json_set_number(res, "final_pits_seconds", si->final_pits_seconds);
    pg_json_set_number(res, "depression_count_seconds", si->pit_stats_seconds);
    pg_json_set_number(res, "render_seconds", si->render_seconds);
    pg_json *lv = pg_json_set_array(res, "level_seconds");
    for (int i = 0; i < si->nlevels; i++)
        pg_json_push_number(lv, si->level_seconds[i]);
    pg_json_set_number(res, "memory_estimate_bytes", need);
    pg_json_set_number(res, "land_agreement", isnan(si->land_agreement) ? -1 : si->land_agreement);
    pg_json_set_number(res, "allowed_type_fraction", si->allowed_fraction);
    if (!isnan(si->sea_ice_fraction))
        pg_json_set_number(res, "sea_ice_fraction", si->sea_ice_fraction);
    if (seams) { /* not computed in a distributed run: they read the whole planet */
        pg_json_set_number(res, "seam_ratio_height", seams->height.ratio);
        pg_json_set_number(res, "seam_ratio_albedo", seams->albedo.ratio);
    }
    if (p->pit_stats) {
        report_depressions(res, "pits_before", &si->before);
        report_depressions(res, "pits_after", &si->after);
    }
}

/* planet.json's "generation" record */
static void record_generation(const gen_args *a, const pg_planet_synth_params *p,
                              pg_planet_generation *g) {
    memset(g, 0, sizeof *g);
    snprintf(g->layout, sizeof g->layout, "%s",
             p->layout == PG_LAYOUT_WORLD   ? "world"
             : p->layout == PG_LAYOUT_EARTH ? "earth"
                                            : "free");
    if (p->layout == PG_LAYOUT_WORLD) {
        g->plates = (int)a->plates;
        g->land_fraction = a->land_fraction;
        g->axial_tilt_deg = a->axial_tilt;
        g->temperature_offset_K = a->temperature_offset;
        g->sea_ice = !a->no_sea_ice;
    }
    g->jitter = a->jitter;
    g->passes = (int)a->passes;
    g->grid_shape = a->grid_shape;
}

static void on_progress(void *user, double frac) {
    pg_cli_progress(user, frac);
}

static int run(pg_cli *cli, const gen_args *a, gen_inputs *in, gen_mpi *g, int *hushed) {
    pg_planet_synth_params p;
    set_params(a, in, &p);
    /* distributed: depression counts only where the final pass needs the whole level */
    if (g->size > 1 && !(p.pits && p.final_pits)) p.pit_stats = false;
    double need;
    int rc = check_memory(cli, a, &p, g, &need);
    if (!rc) rc = gen_rank0_first_outdir(cli, a, g);
    if (rc) return rc;
    pg_synth_exemplar *ex = NULL;
    pg_synth_prep_info pi;
    char src_name[1100];
    pg_cli_stage_begin(cli, "prepare exemplar");
    /* paused while the ranks map the cached exemplar (gen_all_ranks_exemplar) */
    if ((rc = gen_all_ranks_exemplar(cli, a, g, hushed, &ex, &pi, src_name, sizeof src_name)))
        return rc;
    pg_cli_stage_end(cli); /* every rank maps it: the figures of this stage count it shared */
    pg_cli_memory_pause(cli, false);
    gen_loud(hushed);
    pg_error err = {0};
    if (is_world(a)) {
        /* the macro world takes the exemplar's hypsometry, so it comes after it */
        pg_cli_stage_begin(cli, "plates and climate");
        pg_status ws = gen_world_build(a, ex, &in->world, &err);
        pg_cli_stage_end(cli);
        if (ws) {
            pg_synth_exemplar_free(ex);
            return gen_fail_all(cli, g, &err);
        }
        in->has_world = true;
        set_world(a, in, &p);
    }
    pg_planet_synth_dist dist;
    if (g->mpi) {
        pg_mpi_synth_dist(g->mpi, (int)a->tiles, &dist);
        p.dist = &dist;
    }
    p.progress = on_progress;
    p.progress_user = cli;
    pg_planet planet;
    pg_planet_synth_info si;
    pg_cli_stage_begin(cli, "synthesize");
    uint32_t *coords = NULL; /* the single-file layout keeps the coordinate map */
    const pg_planet_synth_testing testing = {.independent_tiles = a->independent};
    pg_status st = pg_planet_synth_run_testing(ex, &p, &testing, &planet, g->tiled ? NULL : &coords,
                                               &si, &err);
    const gen_scale sc = {ex->face_size, pg_planet_synth_magnification(ex, &p),
                          pg_planet_synth_keep_levels(ex, &p)}; /* ex is freed next */
    pg_cli_stage_end(cli);
    /* The ranks of a machine unmap the shared exemplar together: a page that only one
     * rank still maps counts as that rank's private memory (docs/mpi.md). */
    if (g->mpi && !st) pg_cli_memory_pause(cli, true), pg_mpi_barrier(g->mpi);
    pg_synth_exemplar_free(ex);
    if (g->mpi && !st) pg_mpi_barrier(g->mpi), pg_cli_memory_pause(cli, false);
    if (!st && coords) {
        st = adopt_coords(&planet, sc.face, coords, &err);
        if (st) pg_planet_free(&planet);
    } else {
        free(coords);
    }
    if (st) return gen_fail_all(cli, g, &err);
    pg_inspect_seams seams = {0};
    /* the seam figures read the whole planet: not in a distributed run */
    if (!g->mpi && pg_inspect_seams_compute(&planet, &seams, &err)) {
        pg_planet_free(&planet);
        return pg_cli_fail(cli, &err);
    }
    record_generation(a, &p, &planet.generation);
    src_name[sizeof planet.exemplar - 1] = 0;
    memcpy(planet.exemplar, src_name, sizeof planet.exemplar);
    if (g->tiled) {
        /* The tiled layout records neither the coordinate map nor the closed-land share:
         * a distributed run cannot compute the share without gathering the level, and
         * the layout's files must be the same bytes for any rank count. */
        planet.closed_land_share_before_final = NAN;
        rc = gen_write_tiled(cli, a, g, &planet, in->has_world ? &in->world : NULL);
    } else {
        pg_cli_stage_begin(cli, "write planet");
        path_ctx pc = {cli, a->outdir};
        pg_planet_encoded enc = {0}; /* kept only for planet.glb */
        st = pg_planet_save_encoded(&planet, gen_path_for, &pc, a->no_glb ? NULL : &enc, &err);
        pg_cli_stage_end(cli);
        if (!st && in->has_world) st = gen_world_write(cli, a, &in->world, &err);
        if (!st) {
            pg_cli_stage_begin(cli, "write previews and globe");
            st = write_exports(cli, a, &planet, &enc, &err);
            pg_cli_stage_end(cli);
        }
        pg_planet_encoded_free(&enc);
        if (st) rc = pg_cli_fail(cli, &err);
    }
    pg_planet_free(&planet);
    if (rc) return rc;
    if (g->mpi) gen_report_mpi(cli, g, si.s_top);
    report(cli, a, &p, &pi, &si, need, g->mpi ? NULL : &seams, &sc,
           in->has_world ? &in->world : NULL);
    return pg_cli_finish(cli);
}

int pg_cmd_generate(pg_cli *cli, int argc, char **argv) {
    gen_args a = {.in = PG_CLI_EXEMPLAR_INIT,
                  .outdir = "planet",
                  .pits = "on",
                  .final_pits = "breach",
                  .tiles = 4,
                  .tile_size = 256,
                  .seed = 1,
                  .keep_levels = PG_PLANET_KEEP_AUTO,
                  .pit_skip = 1,
                  .passes = 2,
                  .face_size = 0, /* auto */
                  .jitter = 0.4,
                  .grid_shape = PG_PLANET_GRID_SHAPE,
                  .guide_weight = -1, /* auto: GEN_GUIDE_WEIGHT, or 1 for layout world */
                  .plates = 14,
                  .land_fraction = 0.29,
                  .axial_tilt = 23.4,
                  .temperature_offset = 0};
    const pg_opt opts[] = {
        {"--output", "-o", PG_OPT_STRING, &a.outdir, 0, 0, NULL, "DIR",
         "planet directory (default: planet)"},
        {"--tiles", NULL, PG_OPT_INT, &a.tiles, 1, 4096, NULL, "T", "tiles per face edge (4)"},
        {"--tile-size", NULL, PG_OPT_INT, &a.tile_size, 1, 1 << 20, NULL, "S",
         "texels per tile edge, a power of two, multiple of 32 (256)"},
        {"--seed", NULL, PG_OPT_INT, &a.seed, 0, 9007199254740992.0, NULL, "N", "random seed (1)"},
        {"--layout", NULL, PG_OPT_CHOICE, &a.layout, 0, 0, "world|earth|free", "L",
         "world: a new Earth-like planet from plate tectonics and climate, amplified by "
         "example; earth: Earth re-textured, continents where Earth has them; free: a new "
         "arrangement without plates or climate (default world, or free with --guide)"},
        {"--plates", NULL, PG_OPT_INT, &a.plates, PG_PLATES_MIN, PG_PLATES_MAX, NULL, "N",
         "layout world: tectonic plates (14)"},
        {"--land-fraction", NULL, PG_OPT_DOUBLE, &a.land_fraction, 0.05, 0.95, NULL, "F",
         "layout world: share of the surface above sea level (0.29)"},
        {"--axial-tilt", NULL, PG_OPT_DOUBLE, &a.axial_tilt, 0, 90, NULL, "DEG",
         "layout world: axial tilt in degrees (23.4)"},
        {"--temperature-offset", NULL, PG_OPT_DOUBLE, &a.temperature_offset, -40, 40, NULL, "K",
         "layout world: added to every temperature, ice age < 0 < hothouse (0)"},
        {"--no-sea-ice", NULL, PG_OPT_FLAG, &a.no_sea_ice, 0, 0, NULL, NULL,
         "layout world: leave the ocean of the ice climate open (no sea ice; docs/generate.md, "
         "\"Sea ice\")"},
        {"--keep-levels", NULL, PG_OPT_INT, &a.keep_levels, 0, 64, NULL, "K",
         "layout earth: coarsest levels kept without jitter (default: those at least 1/32 "
         "of a face apart: 2 for an exemplar face of 512, 1 for 1024 and up)"},
        {"--guide", NULL, PG_OPT_STRING, &a.guide, 0, 0, NULL, "PNG",
         "equirectangular grey elevation sketch, white high, black low (soft constraint)"},
        {"--guide-weight", NULL, PG_OPT_DOUBLE, &a.guide_weight, 0, 1, NULL, "A",
         "guide blend weight at the coarsest level, halving per finer level (0.8; 1 with "
         "--layout world)"},
        {"--types", NULL, PG_OPT_STRING, &a.types, 0, 0, NULL, "PNG",
         "equirectangular type map: ocean #0000ff ice #ffffff desert #ffff00 grass #00ff00 "
         "forest #008000 mountain #808080 any #000000"},
        {"--preset", NULL, PG_OPT_CHOICE, &a.preset, 0, 0, "earth|desert|snow|grassland", "P",
         "planet kind (allowed terrain types everywhere)"},
        {"--pits", NULL, PG_OPT_CHOICE, &a.pits, 0, 0, "on|off", "on|off",
         "pit removal inside the synthesis and after it (on)"},
        {"--pit-skip-levels", NULL, PG_OPT_INT, &a.pit_skip, 0, 64, NULL, "K",
         "finest levels without Gain-pit (1)"},
        {"--final-pits", NULL, PG_OPT_CHOICE, &a.final_pits, 0, 0, "breach|fill|hybrid|none", "M",
         "final pit removal (breach, with epsilon)"},
        {"--jitter", NULL, PG_OPT_DOUBLE, &a.jitter, 0, 1, NULL, "R", "jitter strength (0.4)"},
        {"--passes", NULL, PG_OPT_INT, &a.passes, 1, 16, NULL, "C",
         "correction passes per level (2)"},
        {"--grid-shape", NULL, PG_OPT_DOUBLE, &a.grid_shape, 0, 1000, NULL, "W",
         "near the cube's corners, prefer exemplar texels whose grid has the output's shape, "
         "weight W (25; 0 = off; docs/synthesis.md)"},
        {"--max-memory", NULL, PG_OPT_DOUBLE, &a.max_memory_gb, 0.001, 1e6, NULL, "GB",
         "memory limit instead of the available memory"},
        {"--preview-width", NULL, PG_OPT_INT, &a.preview_width, 16, 16384, NULL, "W",
         "width of the equirectangular previews (default 4 N, at most 2048)"},
        {"--no-glb", NULL, PG_OPT_FLAG, &a.no_glb, 0, 0, NULL, NULL,
         "do not write the glTF globe planet.glb (tiled: the .glb per tile)"},
        {"--geotiff", NULL, PG_OPT_FLAG, &a.geotiff, 0, 0, NULL, NULL,
         "also write the planet as georeferenced GeoTIFFs: height.tif, albedo.tif (tiled: "
         "per tile, with height.vrt and albedo.vrt; docs/export.md)"},
        {"--output-layout", NULL, PG_OPT_CHOICE, &a.output_layout, 0, 0, "planet|tiled", "L",
         "planet: face images, height.exr, previews, planet.glb; tiled: a PNG, an EXR and a "
         ".glb per tile plus index.json (default planet; tiled under mpirun, docs/mpi.md)"},
        PG_CLI_EXEMPLAR_OPTS(a.in),
        {"--face-size", NULL, PG_OPT_INT, &a.face_size, 512, 4096, NULL, "E",
         "exemplar cube face size (default: the planet's face size N, within 512..2048, so "
         "that nothing is magnified up to N = 2048)"},
        {"--cache-dir", NULL, PG_OPT_STRING, &a.cache_dir, 0, 0, NULL, "DIR",
         "exemplar cache (default $XDG_CACHE_HOME/planetgen)"},
        {"--no-cache", NULL, PG_OPT_FLAG, &a.no_cache, 0, 0, NULL, NULL,
         "neither read nor write the exemplar cache"},
        {"--independent-tiles", NULL, PG_OPT_FLAG, &a.independent, 0, 0, NULL, NULL,
         "diagnostic: synthesize tiles without their neighbours (shows seams)"},
        PG_OPT_END};
    const char *pos[1];
    int npos;
    int hushed = gen_hush(); /* under mpirun, one rank speaks about bad input */
    int rc = pg_cli_parse_or_help(
        cli, opts, argc, argv, pos, 0, &npos,
        "[-o DIR] [--tiles T] [--tile-size S] [--seed N] [OPTIONS]",
        "Synthesize a whole planet by example on the cube sphere (Lefebvre-Hoppe per tile,\n"
        "neighbouring edges as constraints, Gain-pit pit removal) and write the planet\n"
        "directory, equirectangular previews, globe renders and planet.glb to DIR.");
    gen_mpi g;
    if (rc < 0) rc = gen_mpi_start(cli, &a, &g);
    /* --json: the peak private memory between stage ends too (every rank reports it) */
    if (rc < 0 && cli->json_path) pg_cli_memory_watch(cli);
    if (rc >= 0) {
        gen_loud(&hushed);
        return rc;
    }
    if (!(rc = validate(cli, &a))) {
        gen_inputs in;
        pg_error err = {0};
        if (load_inputs(&a, &in, &err))
            rc = pg_cli_fail(cli, &err);
        else
            rc = run(cli, &a, &in, &g, &hushed);
        free_inputs(&in);
    }
    pg_mpi_finalize(g.mpi);
    gen_loud(&hushed); /* a no-op when run() already restored stderr */
    return rc;
}
