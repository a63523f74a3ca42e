/* cmd_inspect.c - `planetgen inspect OUTDIR`: the realism report of a planet
 * (pg_realism.h, docs/inspect.md) in one table and one JSON report, the planet next to
 * Earth's own figures, plus the views of the texture comparison and rivers.png.
 *
 * The planet directory is checked before anything is computed, so a wrong path fails
 * in a second with the missing file named. Earth's side comes from a cache beside the
 * synthesis exemplar's (computed and written on first use). */
#include "pg_commands.h"

#include "pg_planet_meta.h"
#include "planetgen/pg_json.h"
#include "planetgen/pg_realism.h"
#include "planetgen/pg_relief.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct inspect_args {
    pg_cli_exemplar in;
    const char *planet_dir, *views_dir, *cache_dir;
    long view_size;
    double max_memory_gb;
    bool no_cache;
} inspect_args;

typedef struct inspect_figures {
    pg_realism planet, earth;
    bool earth_cached;
    pg_inspect_distortion dist;
    pg_cube_distortion grid;
    pg_inspect_poles poles;
    float *acc;                    /* drainage accumulation, km^2 */
    double mountain_belt_fraction; /* NaN without the macro world (world.exr) */
} inspect_figures;

/* Largest view size: 18 views of 16 bytes per pixel plus the supersampled buffers take
 * ~1.5 GB at 2048 px; 4096 would take four times that. */
#define INSPECT_MAX_VIEW 2048
/* The texture comparison is reported, not gated: 256 px (the metric's minimum, five
 * octaves) keeps it to about a second; --view-size asks for more. */
#define INSPECT_DEFAULT_VIEW 256
/* rivers.png: an equirectangular preview this wide (or 4 N if smaller). */
#define INSPECT_RIVERS_WIDTH 2048

static int check_view_size(pg_cli *cli, long n) {
    if (n < 1 || (n & (n - 1)))
        return pg_cli_usage_error(cli, "--view-size: must be a positive power of two, got %ld", n);
    long need = (long)PG_LPIPS_MIN_LEVEL << (PG_LPIPS_OCTAVES - 1);
    if (n < need)
        return pg_cli_usage_error(cli,
                                  "--view-size: must be %ld..%d (the metric's %d octaves need "
                                  "%d px at the coarsest), got %ld",
                                  need, INSPECT_MAX_VIEW, PG_LPIPS_OCTAVES, PG_LPIPS_MIN_LEVEL, n);
    if (n > INSPECT_MAX_VIEW)
        return pg_cli_usage_error(cli, "--view-size: must be %ld..%d (memory), got %ld", need,
                                  INSPECT_MAX_VIEW, n);
    return 0;
}

static pg_status load_exemplar(const inspect_args *a, pg_exemplar *ex, pg_error *err) {
    pg_exemplar_opts o;
    pg_cli_exemplar_opts(&a->in, &o);
    return pg_exemplar_load(&o, ex, err);
}

/* Peak memory: the exemplar pair (pg_cli_exemplar_bytes); per texel the planet with
 * its map (20 B), Earth's planet and map when its side is not cached (20 B), the
 * fidelity's full-resolution exemplar cube and detail buffers (48 B), drainage and
 * the filled heights (33 B) and the depression count (48 B), with margin: 200 B;
 * 512 B per view pixel. A planet.json that cannot be read passes here; loading the
 * planet then names the problem. */
static int check_memory(pg_cli *cli, const inspect_args *a) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", a->planet_dir, PG_PLANET_META_NAME);
    pg_planet_meta meta;
    pg_error err = {0};
    if (pg_planet_meta_read(path, &meta, &err) != PG_OK) return 0;
    pg_exemplar_opts o;
    pg_cli_exemplar_opts(&a->in, &o);
    double n = (double)meta.tiles * meta.tile_size, v = (double)a->view_size;
    double need = pg_cli_exemplar_bytes(&o) + 150e6 + 6 * n * n * 200 + v * v * 512;
    return pg_cli_check_memory(cli, a->planet_dir, need, a->max_memory_gb);
}

/* ---- figures ---- */

typedef struct progress_ctx {
    pg_cli *cli;
    const char *side;
    char name[96];
} progress_ctx;

static void on_stage(void *user, int stage, bool begin) {
    progress_ctx *c = user;
    if (begin) {
        snprintf(c->name, sizeof c->name, "%s%s", c->side, pg_realism_stage_name(stage));
        pg_cli_stage_begin(c->cli, c->name);
    } else {
        pg_cli_stage_end(c->cli);
    }
}

static pg_status compute_figures(pg_cli *cli, const inspect_args *a, const pg_planet *p,
                                 const pg_exemplar *ex, pg_inspect_views *v, inspect_figures *fig,
                                 pg_error *err) {
    progress_ctx pc = {cli, "Earth: ", ""};
    pg_inspect_fid_exemplar *fx = NULL;
    pg_status st = pg_realism_earth_cached(p, ex, a->no_cache ? "" : a->cache_dir, on_stage, &pc,
                                           &fig->earth, &fx, &fig->earth_cached, err);
    if (st != PG_OK) return st;
    pc.side = "";
    st = pg_realism_planet(p, ex, fx, &fig->earth, on_stage, &pc, &fig->planet, &fig->acc,
                           &fig->dist, err);
    pg_inspect_fid_exemplar_free(fx);
    char world[4200];
    snprintf(world, sizeof world, "%s/world.exr", a->planet_dir);
    if (st == PG_OK) st = pg_inspect_mountain_belts(p, world, &fig->mountain_belt_fraction, err);
    if (st != PG_OK) return st;
    st = pg_cube_distortion_compute(p->projection, p->n, &p->ellipsoid, &fig->grid, err);
    if (st != PG_OK) return st;
    pg_cli_stage_begin(cli, "render views");
    st = pg_inspect_render_views_nofloor(p, ex, (int)a->view_size, v, err);
    pg_cli_stage_end(cli);
    if (st != PG_OK) return st;
    pg_cli_stage_begin(cli, "texture comparison (LPIPS-style)");
    pg_lpips_params lp;
    pg_lpips_params_default(&lp);
    st = pg_inspect_pole_scores(v, &lp, &fig->poles, err);
    pg_cli_stage_end(cli);
    return st;
}

/* ---- outputs ---- */

static pg_status write_png(pg_cli *cli, const char *dir, const char *name, const pg_image *img,
                           pg_error *err) {
    const char *path = pg_cli_output_path(cli, dir, name);
    if (!path) return pg_error_set(err, PG_ERR_NOMEM, "%s/%s: out of memory", dir, name);
    return pg_image_write_png(path, img, 8, err);
}

/* Every view as VIEW_SOURCE.png, and poles.png: planet north | exemplar north | planet
 * south | exemplar south (exemplar = the equirect rendering). */
static pg_status write_views(pg_cli *cli, const char *dir, const pg_inspect_views *v,
                             pg_error *err) {
    pg_status st = PG_OK;
    for (int s = 0; s < PG_INSPECT_NSRC && st == PG_OK; s++)
        for (int k = 0; k < PG_VIEWS_COUNT && st == PG_OK && v->v[s][k].size > 0; k++) {
            char name[96];
            snprintf(name, sizeof name, "%s_%s.png", pg_views_centre_get(k)->name,
                     pg_inspect_source_name(s));
            pg_image img = pg_view_rgb_image(&v->v[s][k]);
            st = write_png(cli, dir, name, &img, err);
        }
    if (st != PG_OK) return st;
    const pg_view *row[4] = {
        &v->v[PG_INSPECT_SRC_PLANET][PG_VIEW_NORTH], &v->v[PG_INSPECT_SRC_EXRECT][PG_VIEW_NORTH],
        &v->v[PG_INSPECT_SRC_PLANET][PG_VIEW_SOUTH], &v->v[PG_INSPECT_SRC_EXRECT][PG_VIEW_SOUTH]};
    pg_image m;
    st = pg_views_montage(row, 4, 8, &m, err);
    if (st != PG_OK) return st;
    st = write_png(cli, dir, "poles.png", &m, err);
    pg_image_free(&m);
    return st;
}

/* rivers.png: the rivers (accumulation >= the river threshold) over shaded relief. */
static pg_status write_rivers(pg_cli *cli, const char *dir, const pg_planet *p, const float *acc,
                              pg_error *err) {
    int w = (int)(4 * p->n < INSPECT_RIVERS_WIDTH ? 4 * p->n : INSPECT_RIVERS_WIDTH), h = w / 2;
    pg_image img;
    pg_status st = pg_image_alloc(&img, w, h, 3, err);
    if (st != PG_OK) return st;
    float *hf = pg_inspect_height_field(p), *eq = malloc((size_t)w * h * sizeof *eq);
    if (!hf || !eq) st = pg_error_set(err, PG_ERR_NOMEM, "rivers.png: out of memory");
    if (st == PG_OK)
        st = pg_cube_to_equirect(p->projection, p->n, &p->ellipsoid, hf, 1, eq, w, h, err);
    if (st == PG_OK) {
        pg_relief_shade(eq, w, h, p->sea_level, img.data);
        pg_drainage_opts o;
        pg_drainage_opts_default(&o);
        pg_drainage_terrain t = pg_planet_drainage_terrain(p);
        st = pg_drainage_draw_rivers(&t, acc, o.river_threshold_km2, img.data, w, h, err);
    }
    if (st == PG_OK) st = write_png(cli, dir, "rivers.png", &img, err);
    free(hf), free(eq);
    pg_image_free(&img);
    return st;
}

/* ---- the table ---- */

static const char *verdict(double v, double gate, int lower_is_better) {
    if (!isfinite(v)) return "FAIL (no value)";
    return (lower_is_better ? v <= gate : v >= gate) ? "PASS" : "FAIL";
}

static void row(pg_cli *cli, const char *name, double planet, double earth, const char *fmt_note) {
    pg_cli_info(cli, "  %-26s %10.4g %10.4g  %s\n", name, planet, earth, fmt_note ? fmt_note : "");
}

static void gated(pg_cli *cli, const char *name, double planet, double earth, double gate,
                  int lower) {
    char note[64];
    snprintf(note, sizeof note, "%s %.2f: %s", lower ? "<=" : ">=", gate,
             verdict(planet, gate, lower));
    row(cli, name, planet, earth, note);
}

static void print_geometry(pg_cli *cli, const pg_realism *P, const pg_realism *E) {
    char note[160];
    pg_cli_info(cli, "geometry of what was copied (coordinate map):\n");
    gated(cli, "pole_distortion_ratio", P->pole_distortion_ratio, E->pole_distortion_ratio,
          PG_INSPECT_DISTORTION_GATE, 1);
    snprintf(note, sizeof note, "worst view %s: %.3f against %.3f", P->distortion_worst_view,
             P->distortion_worst_figure, P->distortion_reference);
    row(cli, "distortion_share_ratio", P->distortion_share_ratio, E->distortion_share_ratio, note);
    gated(cli, "face_seam_ratio", P->seams.face_seam_ratio, E->seams.face_seam_ratio,
          PG_INSPECT_FACE_SEAM_GATE, 1);
    row(cli, "face_seam_ratio_local", P->seams.face_seam_ratio_local,
        E->seams.face_seam_ratio_local, "each seam against the ground beside it");
    if (P->seams.worst_seam_faces[0] >= 0) {
        snprintf(note, sizeof note, "worst seam %s/%s (%s), against its own ground %.3f",
                 pg_cube_face_name(P->seams.worst_seam_faces[0]),
                 pg_cube_face_name(P->seams.worst_seam_faces[1]), P->seams.worst_seam_field,
                 P->seams.worst_seam_ratio_local);
        row(cli, "face_seam_worst_ratio", P->seams.worst_seam_ratio, E->seams.worst_seam_ratio,
            note);
    }
    gated(cli, "face_seam_coherence", P->coherence.face_seam_coherence,
          E->coherence.face_seam_coherence, PG_INSPECT_FACE_COHERENCE_GATE, 0);
    row(cli, "tile_edge_ratio", P->seams.tile_edge_ratio, E->seams.tile_edge_ratio, NULL);
    row(cli, "earth_copy_fraction", P->copy.earth_copy_fraction, E->copy.earth_copy_fraction,
        "sources within 500 km of their texel, less the shuffled-longitude share");
    gated(cli, "fidelity_ratio", P->fidelity.ratio, E->fidelity.ratio, PG_INSPECT_FIDELITY_GATE, 1);
    gated(cli, "completeness_ratio", P->fidelity.completeness_ratio, E->fidelity.completeness_ratio,
          PG_INSPECT_FIDELITY_GATE, 1);
    snprintf(note, sizeof note, "(structure %.3f, detail %.3f)",
             P->fidelity.structure_completeness_ratio, P->fidelity.detail_completeness_ratio);
    pg_cli_info(cli, "  %-26s %s\n", "", note);
}

/* How unequal the shelf is along the coasts: the 90th over the 10th percentile of its
 * width (docs/inspect.md, "Earth-likeness"). */
static double shelf_spread(const pg_earthlike *e) {
    return e->shelf_width_p90_km / e->shelf_width_p10_km;
}

static void print_earthlike(pg_cli *cli, const pg_realism *P, const pg_realism *E, double belts) {
    const pg_earthlike *p = &P->earthlike, *e = &E->earthlike;
    char note[160];
    pg_cli_info(cli, "Earth-likeness (area-weighted):\n");
    row(cli, "land_fraction", p->land_fraction, e->land_fraction, NULL);
    row(cli, "landmasses >= 1e4 km2", (double)p->landmasses_1e4, (double)e->landmasses_1e4, NULL);
    row(cli, "landmasses_1e6", (double)p->landmasses_1e6, (double)e->landmasses_1e6, NULL);
    row(cli, "largest_landmass_share", p->largest_landmass_share, e->largest_landmass_share, NULL);
    row(cli, "rank_size_slope", p->rank_size_slope, e->rank_size_slope, NULL);
    snprintf(note, sizeof note, "Earth's land heights: std %.0f m", e->land_std_m);
    row(cli, "hypsometry_w1_land_m", P->hypsometry_w1_land_m, E->hypsometry_w1_land_m, note);
    snprintf(note, sizeof note, "Earth's ocean heights: std %.0f m", e->ocean_std_m);
    row(cli, "hypsometry_w1_ocean_m", P->hypsometry_w1_ocean_m, E->hypsometry_w1_ocean_m, note);
    row(cli, "ice_equator_fraction", p->ice_equator_fraction, e->ice_equator_fraction,
        "ice share of all area within 20 deg of the equator");
    row(cli, "ice_polar_fraction", p->ice_polar_fraction, e->ice_polar_fraction,
        "ice share of land poleward of 66 deg");
    row(cli, "desert_band_ratio", p->desert_band_ratio, e->desert_band_ratio,
        "desert share of land at 15-35 deg / within 10 deg");
    snprintf(note, sizeof note, "shelf width at the coasts, median %.0f km (Earth %.0f)",
             p->shelf_width_p50_km, e->shelf_width_p50_km);
    row(cli, "shelf_width_spread", shelf_spread(p), shelf_spread(e), note);
    row(cli, "mountain_belt_fraction", belts, NAN,
        "share of non-ice land above 2000 m within 500 km of a convergent boundary");
    row(cli, "zonal correlation", P->zonal_correlation, E->zonal_correlation,
        "terrain-type fractions per 10-deg band, against Earth's");
    snprintf(note, sizeof note, "agreement with Earth at the same place %.3f, chance %.3f",
             P->novelty.agreement, P->novelty.chance);
    row(cli, "novelty", P->novelty.novelty, E->novelty.novelty, note);
}

static void print_water(pg_cli *cli, const pg_realism *P, const pg_realism *E) {
    const pg_drainage_stats *p = &P->drainage, *e = &E->drainage;
    char note[160];
    pg_cli_info(cli, "drainage (D8 on the pit-free heights):\n");
    snprintf(note, sizeof note, "L ~ A^h over %llu basins >= 1e4 km2 (r2 %.2f); rivers 0.5-0.6",
             (unsigned long long)p->hack_basins, p->hack_r2);
    row(cli, "hack_exponent", p->hack_exponent, e->hack_exponent, note);
    row(cli, "drainage density /km", p->drainage_density_per_km, e->drainage_density_per_km,
        "river length / land area, rivers >= 1e4 km2");
    row(cli, "largest basin share", p->largest_basin_land_share, e->largest_basin_land_share, NULL);
    row(cli, "closed land before final", P->closed_land_share_before_final,
        E->closed_land_share_before_final, "land draining into closed basins");
    row(cli, "depressions", (double)P->depressions.depressions, (double)E->depressions.depressions,
        "of the heights as given");
}

static void print_table(pg_cli *cli, const pg_planet *p, const inspect_figures *f, int size) {
    const pg_inspect_poles *q = &f->poles;
    pg_cli_info(cli,
                "planet       %s, 6 x %d x %d tiles of %d^2 (%lld^2 per face), seed %llu; %s\n",
                pg_cube_projection_name(p->projection), p->tiles, p->tiles, p->tile_size,
                (long long)p->n, (unsigned long long)p->seed,
                pg_planet_has_source(p) ? "with its coordinate map"
                                        : "no coordinate map (copy figures are NaN)");
    pg_cli_info(cli, "Earth        the exemplar on a cube of the same geometry (%s)\n",
                f->earth_cached ? "cached" : "computed and cached");
    pg_cli_info(cli, "  %-26s %10s %10s  %s\n", "figure", "planet", "Earth", "gate");
    print_geometry(cli, &f->planet, &f->earth);
    print_earthlike(cli, &f->planet, &f->earth, f->mountain_belt_fraction);
    print_water(cli, &f->planet, &f->earth);
    pg_cli_info(cli,
                "texture comparison with Earth at the same place (LPIPS-style, fixed Gabor "
                "features, no gate), %d px views:\n",
                size);
    for (int k = 0; k < PG_VIEWS_COUNT; k++)
        pg_cli_info(cli, "  %-12s %9.4f\n", pg_views_centre_get(k)->name,
                    q->d[PG_INSPECT_SRC_PLANET][k].distance);
    pg_cli_info(cli, "  pole/equator north %.3f, south %.3f (no floor added)\n", q->raw_north,
                q->raw_south);
}

/* ---- JSON ---- */

/* The documented keys (docs/inspect.md), for one side. */
static void json_keys(pg_json *o, const pg_realism *r) {
    const pg_earthlike *e = &r->earthlike;
    pg_json_set_number(o, "pole_distortion_ratio", r->pole_distortion_ratio);
    pg_json_set_number(o, "face_seam_ratio", r->seams.face_seam_ratio);
    pg_json_set_number(o, "face_seam_ratio_local", r->seams.face_seam_ratio_local);
    pg_json_set_number(o, "face_seam_coherence", r->coherence.face_seam_coherence);
    pg_json_set_number(o, "tile_edge_ratio", r->seams.tile_edge_ratio);
    pg_json_set_number(o, "seam_ratio", r->seams.ratio);
    pg_json_set_number(o, "fidelity_ratio", r->fidelity.ratio);
    pg_json_set_number(o, "completeness_ratio", r->fidelity.completeness_ratio);
    pg_json_set_number(o, "earth_copy_fraction", r->copy.earth_copy_fraction);
    pg_json_set_number(o, "land_fraction", e->land_fraction);
    pg_json_set_number(o, "landmasses_1e6", (double)e->landmasses_1e6);
    pg_json_set_number(o, "largest_landmass_share", e->largest_landmass_share);
    pg_json_set_number(o, "hypsometry_w1_m", r->hypsometry_w1_m);
    pg_json_set_number(o, "hypsometry_w1_land_m", r->hypsometry_w1_land_m);
    pg_json_set_number(o, "hypsometry_w1_ocean_m", r->hypsometry_w1_ocean_m);
    pg_json_set_number(o, "ice_equator_fraction", e->ice_equator_fraction);
    pg_json_set_number(o, "ice_polar_fraction", e->ice_polar_fraction);
    pg_json_set_number(o, "desert_band_ratio", e->desert_band_ratio);
    pg_json_set_number(o, "shelf_width_p10_km", e->shelf_width_p10_km);
    pg_json_set_number(o, "shelf_width_p50_km", e->shelf_width_p50_km);
    pg_json_set_number(o, "shelf_width_p90_km", e->shelf_width_p90_km);
    pg_json_set_number(o, "shelf_width_spread", shelf_spread(e));
    pg_json_set_number(o, "novelty", r->novelty.novelty);
    pg_json_set_number(o, "hack_exponent", r->drainage.hack_exponent);
    pg_json_set_number(o, "depressions", (double)r->depressions.depressions);
}

static void json_zonal(pg_json *o, const pg_earthlike *e) {
    pg_json *z = pg_json_set_object(o, "zonal");
    pg_json *lat = pg_json_set_array(z, "band_south_deg");
    for (int b = 0; b < PG_EARTHLIKE_BANDS; b++)
        pg_json_push_number(lat, -90 + 10 * b);
    for (int t = 0; t < PG_TYPE_COUNT; t++) {
        pg_json *a = pg_json_set_array(z, pg_types_name(t));
        for (int b = 0; b < PG_EARTHLIKE_BANDS; b++)
            pg_json_push_number(a, e->zonal[b][t]);
    }
}

/* Everything behind the keys, for one side. */
static void json_details(pg_json *o, const pg_realism *r) {
    const pg_earthlike *e = &r->earthlike;
    pg_json *d = pg_json_set_object(o, "distortion");
    pg_json_set_number(d, "share_ratio", r->distortion_share_ratio);
    pg_json_set_number(d, "reference", r->distortion_reference);
    pg_json_set_number(d, "worst_figure", r->distortion_worst_figure);
    pg_json_set_string(d, "worst_view", r->distortion_worst_view);
    d = pg_json_set_object(o, "seams");
    pg_json_set_number(d, "face_seam_ratio_height", r->seams.height.face_seam_ratio);
    pg_json_set_number(d, "face_seam_ratio_albedo", r->seams.albedo.face_seam_ratio);
    pg_json_set_number(d, "face_seam_ratio_local_height", r->seams.height.face_seam_ratio_local);
    pg_json_set_number(d, "face_seam_ratio_local_albedo", r->seams.albedo.face_seam_ratio_local);
    pg_json_set_number(d, "worst_seam_ratio", r->seams.worst_seam_ratio);
    pg_json_set_number(d, "worst_seam_ratio_local", r->seams.worst_seam_ratio_local);
    if (r->seams.worst_seam_faces[0] >= 0) {
        char faces[16];
        snprintf(faces, sizeof faces, "%s/%s", pg_cube_face_name(r->seams.worst_seam_faces[0]),
                 pg_cube_face_name(r->seams.worst_seam_faces[1]));
        pg_json_set_string(d, "worst_seam", faces);
        pg_json_set_string(d, "worst_seam_field", r->seams.worst_seam_field);
    }
    pg_json_set_number(d, "tile_edge_ratio_height", r->seams.height.tile_edge_ratio);
    pg_json_set_number(d, "tile_edge_ratio_albedo", r->seams.albedo.tile_edge_ratio);
    pg_json_set_number(d, "coherent_share_face_seams", r->coherence.seam_share);
    pg_json_set_number(d, "coherent_share_inside_faces", r->coherence.interior_share);
    d = pg_json_set_object(o, "copy");
    pg_json_set_number(d, "near_share", r->copy.near_share);
    pg_json_set_number(d, "shuffled_share", r->copy.shuffled_share);
    d = pg_json_set_object(o, "fidelity");
    pg_json_set_number(d, "fidelity", r->fidelity.fidelity);
    pg_json_set_number(d, "loo", r->fidelity.loo);
    pg_json_set_number(d, "random_ratio", r->fidelity.random_ratio);
    pg_json_set_number(d, "completeness", r->fidelity.completeness);
    pg_json_set_number(d, "structure_completeness_ratio", r->fidelity.structure_completeness_ratio);
    pg_json_set_number(d, "detail_completeness_ratio", r->fidelity.detail_completeness_ratio);
    pg_json_set_number(d, "analysis_face_size", r->fidelity.analysis_size);
    d = pg_json_set_object(o, "earthlike");
    pg_json_set_number(d, "landmasses_1e4", (double)e->landmasses_1e4);
    pg_json_set_number(d, "largest_landmass_km2", e->largest_landmass_km2);
    pg_json_set_number(d, "rank_size_slope", e->rank_size_slope);
    pg_json_set_number(d, "shelf_coast_texels", (double)e->shelf_coast_texels);
    pg_json_set_number(d, "shelf_closed_texels", (double)e->shelf_closed_texels);
    pg_json_set_number(d, "land_mean_m", e->land_mean_m);
    pg_json_set_number(d, "land_std_m", e->land_std_m);
    pg_json_set_number(d, "ocean_mean_m", e->ocean_mean_m);
    pg_json_set_number(d, "ocean_std_m", e->ocean_std_m);
    pg_json_set_number(d, "zonal_correlation", r->zonal_correlation);
    pg_json_set_number(d, "novelty_agreement", r->novelty.agreement);
    pg_json_set_number(d, "novelty_chance", r->novelty.chance);
    pg_json_set_number(d, "novelty_kappa", r->novelty.kappa);
    json_zonal(d, e);
    d = pg_json_set_object(o, "drainage");
    pg_json_set_number(d, "hack_basins", (double)r->drainage.hack_basins);
    pg_json_set_number(d, "hack_r2", r->drainage.hack_r2);
    pg_json_set_number(d, "drainage_density_per_km", r->drainage.drainage_density_per_km);
    pg_json_set_number(d, "largest_basin_land_share", r->drainage.largest_basin_land_share);
    pg_json_set_number(d, "closed_land_share_before_final", r->closed_land_share_before_final);
    pg_json_set_number(d, "depression_cells", (double)r->depressions.depression_cells);
    pg_json_set_number(d, "depression_area_m2", r->depressions.depression_area_m2);
    pg_json *s = pg_json_set_object(o, "seconds");
    for (int k = 0; k < PG_REALISM_NSTAGES; k++)
        pg_json_set_number(s, pg_realism_stage_name(k), r->seconds[k]);
}

static void json_views(pg_json *res, const inspect_figures *f) {
    pg_json *views = pg_json_set_array(res, "distortion_views");
    for (int k = 0; k < PG_INSPECT_DISTORTION_NVIEWS; k++) {
        const pg_inspect_distortion_view *v = &f->dist.views[k];
        pg_json *o = pg_json_push_object(views);
        pg_json_set_string(o, "name", v->name ? v->name : "");
        pg_json_set_number(o, "figure", v->figure);
        pg_json_set_number(o, "scale", v->mean_scale);
        pg_json_set_number(o, "anisotropy", v->mean_anisotropy);
        pg_json_set_number(o, "coherent_share", v->share);
    }
    const pg_inspect_poles *q = &f->poles;
    pg_json *t = pg_json_set_object(res, "texture");
    /* no JND floor: without a gate, the raw ratios say what was measured */
    pg_json_set_number(t, "pole_equator_ratio", fmax(q->raw_north, q->raw_south));
    pg_json_set_number(t, "ratio_north", q->raw_north);
    pg_json_set_number(t, "ratio_south", q->raw_south);
    for (int k = 0; k < PG_VIEWS_COUNT; k++) {
        pg_json *v = pg_json_set_object(t, pg_views_centre_get(k)->name);
        pg_json_set_number(v, "distance", q->d[PG_INSPECT_SRC_PLANET][k].distance);
    }
    pg_json *g = pg_json_set_object(res, "grid");
    pg_json_set_number(g, "texel_area_ratio", f->grid.area_ratio);
    pg_json_set_number(g, "max_angle_deviation_deg", f->grid.max_angle_dev_deg);
    pg_json_set_number(g, "mean_texel_km", f->grid.mean_texel_km);
}

static void report_json(pg_cli *cli, const inspect_args *a, const pg_planet *p,
                        const pg_exemplar *ex, const inspect_figures *f) {
    pg_json *r = pg_cli_report(cli);
    if (!r) return;
    pg_json *in = pg_json_set_object(r, "inputs");
    pg_json_set_string(in, "planet", a->planet_dir);
    pg_json_set_string(in, "planet_exemplar", p->exemplar);
    pg_json_set_string(in, "exemplar_albedo", ex->albedo_src);
    pg_json_set_string(in, "exemplar_height", ex->height_src);
    pg_json_set_bool(in, "coordinate_map", pg_planet_has_source(p));
    pg_json_set_bool(in, "earth_from_cache", f->earth_cached);
    pg_json *par = pg_json_set_object(r, "parameters");
    pg_json_set_number(par, "view_size", (double)a->view_size);
    pg_json_set_string(par, "views_dir", a->views_dir);
    json_keys(r, &f->planet);
    pg_json_set_number(r, "mountain_belt_fraction", f->mountain_belt_fraction);
    json_keys(pg_json_set_object(r, "earth"), &f->earth);
    pg_json *g = pg_json_set_object(r, "gates");
    pg_json_set_number(g, "pole_distortion_ratio", PG_INSPECT_DISTORTION_GATE);
    pg_json_set_number(g, "face_seam_ratio", PG_INSPECT_FACE_SEAM_GATE);
    pg_json_set_number(g, "face_seam_coherence", PG_INSPECT_FACE_COHERENCE_GATE);
    pg_json_set_number(g, "fidelity_ratio", PG_INSPECT_FIDELITY_GATE);
    pg_json_set_number(g, "completeness_ratio", PG_INSPECT_FIDELITY_GATE);
    pg_json *res = pg_json_set_object(r, "results");
    json_details(pg_json_set_object(res, "planet"), &f->planet);
    json_details(pg_json_set_object(res, "earth"), &f->earth);
    json_views(res, f);
}

/* ---- the command ---- */

static int run(pg_cli *cli, inspect_args *a) {
    pg_error err = {0};
    pg_planet p;
    pg_cli_stage_begin(cli, "load planet");
    if (pg_planet_load(a->planet_dir, &p, &err) != PG_OK) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    pg_exemplar ex;
    pg_cli_stage_begin(cli, "load exemplar");
    if (load_exemplar(a, &ex, &err) != PG_OK) {
        pg_planet_free(&p);
        return pg_cli_fail(cli, &err);
    }
    pg_cli_stage_end(cli);
    inspect_figures *fig = calloc(1, sizeof *fig);
    pg_inspect_views v;
    memset(&v, 0, sizeof v);
    pg_status st = fig ? compute_figures(cli, a, &p, &ex, &v, fig, &err)
                       : pg_error_set(&err, PG_ERR_NOMEM, "inspect: out of memory");
    if (st == PG_OK) {
        pg_cli_stage_begin(cli, "write views and rivers.png");
        st = pg_cli_prepare_outdir(cli, a->views_dir, &err);
        if (st == PG_OK) st = write_views(cli, a->views_dir, &v, &err);
        if (st == PG_OK) st = write_rivers(cli, a->views_dir, &p, fig->acc, &err);
        pg_cli_stage_end(cli);
    }
    if (st == PG_OK) {
        print_table(cli, &p, fig, (int)a->view_size);
        report_json(cli, a, &p, &ex, fig);
    }
    if (fig) free(fig->acc);
    free(fig);
    pg_inspect_views_free(&v);
    pg_exemplar_free(&ex);
    pg_planet_free(&p);
    return st == PG_OK ? pg_cli_finish(cli) : pg_cli_fail(cli, &err);
}

int pg_cmd_inspect(pg_cli *cli, int argc, char **argv) {
    inspect_args a = {PG_CLI_EXEMPLAR_INIT, NULL, NULL, NULL, INSPECT_DEFAULT_VIEW, 0, false};
    const pg_opt opts[] = {
        {"--view-size", NULL, PG_OPT_INT, &a.view_size, (double)LONG_MIN, (double)LONG_MAX, NULL,
         "N", "texture-comparison views are N x N px, N a power of two in 256..2048 (default 256)"},
        {"--views", "-o", PG_OPT_STRING, &a.views_dir, 0, 0, NULL, "DIR",
         "where to write the view PNGs and rivers.png (default OUTDIR/inspect)"},
        {"--cache-dir", NULL, PG_OPT_STRING, &a.cache_dir, 0, 0, NULL, "DIR",
         "where Earth's figures are cached (default $XDG_CACHE_HOME/planetgen)"},
        {"--no-cache", NULL, PG_OPT_FLAG, &a.no_cache, 0, 0, NULL, NULL,
         "compute Earth's figures afresh; neither read nor write the cache"},
        PG_CLI_EXEMPLAR_OPTS(a.in),
        PG_CLI_MAX_MEMORY_OPT(a.max_memory_gb),
        PG_OPT_END};
    const char *pos[1];
    int npos;
    int rc = pg_cli_parse_or_help(
        cli, opts, argc, argv, pos, 1, &npos, "OUTDIR [--json F] [--view-size N] [-o DIR]",
        "Report the realism figures of a planet directory next to Earth's own\n"
        "(the exemplar on a cube of the same geometry): the distortion and seams\n"
        "of what was copied (from the planet's coordinate map), copy detection,\n"
        "neighbourhood fidelity and completeness, Earth-likeness statistics\n"
        "(land, landmasses, hypsometry, zonal climate, novelty), the drainage\n"
        "network and depressions, and an LPIPS-style texture comparison; write\n"
        "the texture views and rivers.png. docs/inspect.md explains each figure.");
    if (rc >= 0) return rc;
    if (npos != 1) return pg_cli_usage_error(cli, "expected one planet directory (OUTDIR)");
    a.planet_dir = pos[0];
    if ((rc = check_view_size(cli, a.view_size))) return rc;
    if ((rc = check_memory(cli, &a))) return rc;
    char views[4096];
    if (!a.views_dir) {
        snprintf(views, sizeof views, "%s/inspect", a.planet_dir);
        a.views_dir = views;
    }
    return run(cli, &a);
}
