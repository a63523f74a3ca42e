/* cmd_inspect.c - `planetgen inspect OUTDIR`: every realism figure of a planet in one
 * table and one JSON report, and the views it was judged on as PNGs.
 *
 * The figures: the LPIPS-style pole check (pg_inspect.h: pole and equator distances of
 * the planet against the exemplar, their ratio and the gate), the seam statistic of
 * issue 5, depressions (pg_pits), neighbourhood fidelity against the exemplar with its
 * leave-one-out and random baselines (pg_inspect_fidelity_compute), and the
 * projection's distortion table. The
 * planet directory is checked before anything is computed, so a wrong path fails in a
 * second with the missing file named. */
#include "pg_commands.h"

#include "pg_planet_meta.h"
#include "planetgen/pg_inspect.h"
#include "planetgen/pg_json.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct inspect_args {
    pg_cli_exemplar in;
    const char *planet_dir, *views_dir;
    long view_size;
    double max_memory_gb;
} inspect_args;

typedef struct inspect_figures {
    pg_inspect_seams seams;
    pg_pits_stats pits;
    pg_cube_distortion dist;
    pg_inspect_poles poles;
    pg_inspect_fidelity fid;
} inspect_figures;

/* Largest view size: 18 views of 16 bytes per pixel plus the supersampled buffers take
 * ~1.5 GB at 2048 px; 4096 would take four times that. */
#define INSPECT_MAX_VIEW 2048

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

/* Peak memory: the exemplar pair (pg_cli_exemplar_bytes), the planet with its
 * depression count (48 B per texel, as pits --stats) and the 18 views with their
 * supersampled buffers, 512 B per view pixel. Measured on 6 x 1024^2 texels: 0.57 GB
 * at 512 px views, 0.94 GB at 1024 px; estimated 1.24 and 1.64 GB. A planet.json
 * that cannot be read passes here; loading the planet then names the problem. */
static int check_memory(pg_cli *cli, const inspect_args *a) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", a->planet_dir, PG_PLANET_META_NAME);
    pg_planet_meta meta;
    pg_error err = {0};
    if (pg_planet_meta_read(path, &meta, &err) != PG_OK) return 0;
    pg_exemplar_opts o;
    pg_cli_exemplar_opts(&a->in, &o);
    double n = (double)meta.tiles * meta.tile_size, v = (double)a->view_size;
    double need = pg_cli_exemplar_bytes(&o) + 150e6 + 6 * n * n * 48 + v * v * 512;
    return pg_cli_check_memory(cli, a->planet_dir, need, a->max_memory_gb);
}

/* ---- figures ---- */

static pg_status compute_figures(pg_cli *cli, const pg_planet *p, const pg_exemplar *ex, int size,
                                 pg_inspect_views *v, inspect_figures *fig, pg_error *err) {
    pg_cli_stage_begin(cli, "seams");
    pg_status st = pg_inspect_seams_compute(p, &fig->seams, err);
    pg_cli_stage_end(cli);
    if (st != PG_OK) return st;
    pg_cli_stage_begin(cli, "depressions");
    st = pg_inspect_depressions(p, &fig->pits, err);
    pg_cli_stage_end(cli);
    if (st != PG_OK) return st;
    pg_cli_stage_begin(cli, "distortion");
    st = pg_cube_distortion_compute(p->projection, p->n, &p->ellipsoid, &fig->dist, err);
    pg_cli_stage_end(cli);
    if (st != PG_OK) return st;
    pg_cli_stage_begin(cli, "neighbourhood fidelity");
    st = pg_inspect_fidelity_compute(p, ex, &fig->fid, err);
    pg_cli_stage_end(cli);
    if (st != PG_OK) return st;
    pg_cli_stage_begin(cli, "render views");
    st = pg_inspect_render_views(p, ex, size, v, err);
    pg_cli_stage_end(cli);
    if (st != PG_OK) return st;
    pg_cli_stage_begin(cli, "LPIPS-style distances");
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
    pg_status st = pg_cli_prepare_outdir(cli, dir, err);
    for (int s = 0; s < PG_INSPECT_NSRC && st == PG_OK; s++)
        for (int k = 0; k < PG_VIEWS_COUNT && st == PG_OK; k++) {
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
    if (st == PG_OK) st = write_png(cli, dir, "poles.png", &m, err);
    if (st == PG_OK) pg_image_free(&m);
    return st;
}

static void print_table(pg_cli *cli, const pg_planet *p, const inspect_figures *f, int size,
                        double sigma_deg) {
    const pg_inspect_poles *q = &f->poles;
    pg_cli_info(cli, "planet       %s, 6 x %d x %d tiles of %d^2 (%lld^2 per face)\n",
                pg_cube_projection_name(p->projection), p->tiles, p->tiles, p->tile_size,
                (long long)p->n);
    pg_cli_info(cli, "views        %d px, %.0f deg field, prefilter sigma %.3f deg\n", size,
                PG_VIEWS_DEFAULT_FOV_DEG, sigma_deg);
    pg_cli_info(cli, "LPIPS-style distance to the exemplar (fixed Gabor features, NOT learned "
                     "LPIPS):\n");
    pg_cli_info(cli, "  %-12s %9s %14s %14s\n", "view", "planet", "exemplar cube",
                "planet-vs-cube");
    for (int k = 0; k < PG_VIEWS_COUNT; k++)
        pg_cli_info(cli, "  %-12s %9.4f %14.4f %14.4f\n", pg_views_centre_get(k)->name,
                    q->d[PG_INSPECT_SRC_PLANET][k].distance,
                    q->d[PG_INSPECT_SRC_EXCUBE][k].distance, q->d_vs_cube[k].distance);
    pg_cli_info(
        cli, "pole/equator north %.3f, south %.3f (raw %.3f, %.3f) -> %.3f: %s (gate %.2f)\n",
        q->ratio_north, q->ratio_south, q->raw_north, q->raw_south, q->pole_equator_ratio,
        q->pole_equator_ratio <= PG_INSPECT_POLE_GATE ? "PASS" : "FAIL", PG_INSPECT_POLE_GATE);
    pg_cli_info(cli, "seams        height %.3f, albedo %.3f -> %.3f: %s (gate %.2f)\n",
                f->seams.height.ratio, f->seams.albedo.ratio, f->seams.ratio,
                f->seams.ratio <= PG_INSPECT_SEAM_GATE ? "PASS" : "FAIL", PG_INSPECT_SEAM_GATE);
    pg_cli_info(cli, "depressions  %llu (%llu cells, deepest %.1f m)\n",
                (unsigned long long)f->pits.depressions,
                (unsigned long long)f->pits.depression_cells, f->pits.max_depth_m);
    const pg_inspect_fidelity *fd = &f->fid;
    pg_cli_info(cli,
                "fidelity     %.3f = %.3f x leave-one-out %.3f (random texels %.3f = %.2f x); "
                "Lab RMS to the nearest exemplar 5x5 at %d^2 per face\n",
                fd->fidelity, fd->ratio, fd->loo, fd->random, fd->random_ratio, fd->analysis_size);
    pg_cli_info(
        cli, "completeness %.3f = %.3f x leave-one-out (exemplar 5x5 to the nearest planet 5x5)\n",
        fd->completeness, fd->completeness_ratio);
    pg_cli_info(cli,
                "distortion   texel area ratio %.4f, max angle deviation %.3f deg, mean "
                "texel %.3f km\n",
                f->dist.area_ratio, f->dist.max_angle_dev_deg, f->dist.mean_texel_km);
}

static void json_seam(pg_json *o, const char *key, const pg_inspect_seam_stat *s) {
    pg_json *j = pg_json_set_object(o, key);
    pg_json_set_number(j, "ratio", s->ratio);
    pg_json_set_number(j, "seam_mean", s->seam_mean);
    pg_json_set_number(j, "interior_mean", s->interior_mean);
    pg_json_set_number(j, "tile_edge_mean", s->tile_edge_mean);
    pg_json_set_number(j, "face_seam_mean", s->face_seam_mean);
    pg_json_set_number(j, "seam_pairs", (double)s->seam_pairs);
    pg_json_set_number(j, "interior_pairs", (double)s->interior_pairs);
}

static void json_views(pg_json *res, const pg_inspect_poles *q) {
    pg_json *views = pg_json_set_object(res, "views");
    for (int k = 0; k < PG_VIEWS_COUNT; k++) {
        const pg_views_centre *c = pg_views_centre_get(k);
        pg_json *v = pg_json_set_object(views, c->name);
        pg_json_set_number(v, "lat_deg", c->lat_deg);
        pg_json_set_number(v, "lon_deg", c->lon_deg);
        pg_json_set_number(v, "distance", q->d[PG_INSPECT_SRC_PLANET][k].distance);
        pg_json_set_number(v, "exemplar_cube_distance", q->d[PG_INSPECT_SRC_EXCUBE][k].distance);
        pg_json_set_number(v, "distance_vs_exemplar_cube", q->d_vs_cube[k].distance);
        pg_json *layers = pg_json_set_array(v, "layers");
        for (int l = 0; l < q->d[PG_INSPECT_SRC_PLANET][k].layers; l++)
            pg_json_push_number(layers, q->d[PG_INSPECT_SRC_PLANET][k].layer[l]);
    }
}

static void json_fidelity(pg_json *top, pg_json *res, const pg_inspect_fidelity *fd) {
    pg_json_set_number(top, "neighbourhood_fidelity_ratio", fd->ratio);
    pg_json_set_number(res, "neighbourhood_fidelity", fd->fidelity);
    pg_json_set_number(res, "neighbourhood_fidelity_loo", fd->loo);
    pg_json_set_number(res, "neighbourhood_fidelity_ratio", fd->ratio);
    pg_json_set_number(res, "neighbourhood_fidelity_random", fd->random);
    pg_json_set_number(res, "neighbourhood_fidelity_random_ratio", fd->random_ratio);
    pg_json_set_number(res, "neighbourhood_completeness", fd->completeness);
    pg_json_set_number(res, "neighbourhood_completeness_ratio", fd->completeness_ratio);
    pg_json *d = pg_json_set_object(res, "neighbourhood_fidelity_details");
    pg_json_set_string(d, "measure",
                       "mean over hashed planet texels of the RMS difference per texel and "
                       "channel (Lab, height scaled to the Lab std) of the 5x5 neighbourhood "
                       "to the nearest exemplar 5x5 neighbourhood (exact search)");
    pg_json_set_number(d, "analysis_face_size", fd->analysis_size);
    pg_json_set_number(d, "planet_texels_per_analysis_texel", fd->magnification);
    pg_json_set_number(d, "queries", fd->queries);
    pg_json_set_number(d, "random_queries", fd->random_queries);
    pg_json_set_number(d, "database", fd->database);
    pg_json_set_number(d, "height_lab_per_m", fd->height_scale);
}

static void report_json(pg_cli *cli, const inspect_args *a, const pg_planet *p,
                        const pg_exemplar *ex, const inspect_figures *f, double sigma_deg) {
    pg_json *r = pg_cli_report(cli);
    if (!r) return;
    const pg_inspect_poles *q = &f->poles;
    pg_json *in = pg_json_set_object(r, "inputs");
    pg_json_set_string(in, "planet", a->planet_dir);
    pg_json_set_string(in, "planet_exemplar", p->exemplar);
    pg_json_set_string(in, "exemplar_albedo", ex->albedo_src);
    pg_json_set_string(in, "exemplar_height", ex->height_src);
    pg_json *par = pg_json_set_object(r, "parameters");
    pg_json_set_number(par, "view_size", (double)a->view_size);
    pg_json_set_number(par, "fov_deg", PG_VIEWS_DEFAULT_FOV_DEG);
    pg_json_set_number(par, "prefilter_sigma_deg", sigma_deg);
    pg_json_set_number(par, "jnd", PG_INSPECT_JND);
    pg_json_set_string(par, "metric",
                       "LPIPS-style: fixed complex Gabor energies, not learned LPIPS");
    pg_json_set_string(par, "views_dir", a->views_dir);
    /* the documented keys at the top level, everything under "results" */
    pg_json_set_number(r, "pole_equator_ratio", q->pole_equator_ratio);
    pg_json_set_number(r, "seam_ratio", f->seams.ratio);
    pg_json_set_number(r, "depressions", (double)f->pits.depressions);
    pg_json *res = pg_json_set_object(r, "results");
    pg_json_set_number(res, "pole_equator_ratio", q->pole_equator_ratio);
    pg_json_set_number(res, "pole_gate", PG_INSPECT_POLE_GATE);
    pg_json_set_bool(res, "pole_gate_pass", q->pole_equator_ratio <= PG_INSPECT_POLE_GATE);
    pg_json_set_number(res, "ratio_north", q->ratio_north);
    pg_json_set_number(res, "ratio_south", q->ratio_south);
    pg_json_set_number(res, "raw_ratio_north", q->raw_north);
    pg_json_set_number(res, "raw_ratio_south", q->raw_south);
    pg_json_set_number(res, "pole_north_distance",
                       q->d[PG_INSPECT_SRC_PLANET][PG_VIEW_NORTH].distance);
    pg_json_set_number(res, "pole_south_distance",
                       q->d[PG_INSPECT_SRC_PLANET][PG_VIEW_SOUTH].distance);
    pg_json_set_number(res, "equator_mean_distance", q->equator_mean);
    pg_json_set_number(res, "exemplar_cube_pole_equator_ratio", q->floor_ratio);
    json_views(res, q);
    pg_json_set_number(res, "seam_ratio", f->seams.ratio);
    json_seam(res, "seam_height", &f->seams.height);
    json_seam(res, "seam_albedo", &f->seams.albedo);
    pg_json *d = pg_json_set_object(res, "depressions");
    pg_json_set_number(d, "count", (double)f->pits.depressions);
    pg_json_set_number(d, "cells", (double)f->pits.depression_cells);
    pg_json_set_number(d, "area_m2", f->pits.depression_area_m2);
    pg_json_set_number(d, "volume_m3", f->pits.depression_volume_m3);
    pg_json_set_number(d, "max_depth_m", f->pits.max_depth_m);
    json_fidelity(r, res, &f->fid);
    pg_json *dist = pg_json_set_object(res, "distortion");
    pg_json_set_string(dist, "projection", pg_cube_projection_name(p->projection));
    pg_json_set_number(dist, "texel_area_min_m2", f->dist.area_min_m2);
    pg_json_set_number(dist, "texel_area_max_m2", f->dist.area_max_m2);
    pg_json_set_number(dist, "area_ratio", f->dist.area_ratio);
    pg_json_set_number(dist, "max_angle_deviation_deg", f->dist.max_angle_dev_deg);
    pg_json_set_number(dist, "mean_texel_km", f->dist.mean_texel_km);
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
    inspect_figures fig;
    memset(&fig, 0, sizeof fig);
    pg_inspect_views v;
    pg_status st = compute_figures(cli, &p, &ex, (int)a->view_size, &v, &fig, &err);
    if (st == PG_OK) {
        pg_cli_stage_begin(cli, "write views");
        st = write_views(cli, a->views_dir, &v, &err);
        pg_cli_stage_end(cli);
    }
    if (st == PG_OK) {
        print_table(cli, &p, &fig, (int)a->view_size, v.sigma_deg);
        report_json(cli, a, &p, &ex, &fig, v.sigma_deg);
    }
    pg_inspect_views_free(&v);
    pg_exemplar_free(&ex);
    pg_planet_free(&p);
    return st == PG_OK ? pg_cli_finish(cli) : pg_cli_fail(cli, &err);
}

int pg_cmd_inspect(pg_cli *cli, int argc, char **argv) {
    inspect_args a = {PG_CLI_EXEMPLAR_INIT, NULL, NULL, PG_VIEWS_DEFAULT_SIZE, 0};
    const pg_opt opts[] = {{"--view-size", NULL, PG_OPT_INT, &a.view_size, (double)LONG_MIN,
                            (double)LONG_MAX, NULL, "N",
                            "views are N x N px, N a power of two in 256..2048 (default 512)"},
                           {"--views", "-o", PG_OPT_STRING, &a.views_dir, 0, 0, NULL, "DIR",
                            "where to write the view PNGs (default OUTDIR/inspect)"},
                           PG_CLI_EXEMPLAR_OPTS(a.in),
                           PG_CLI_MAX_MEMORY_OPT(a.max_memory_gb),
                           PG_OPT_END};
    const char *pos[1];
    int npos;
    int rc = pg_cli_parse_or_help(
        cli, opts, argc, argv, pos, 1, &npos, "OUTDIR [--json F] [--view-size N] [-o DIR]",
        "Report the realism figures of a planet directory: LPIPS-style pole\n"
        "and equator distances to the exemplar (fixed Gabor features, not\n"
        "learned LPIPS) and their ratio, the seam statistic, depressions,\n"
        "neighbourhood fidelity to the exemplar (with leave-one-out and\n"
        "random baselines) and the projection's distortion; write the six\n"
        "views of the planet and of the exemplar (cube and equirect) as PNGs.");
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
