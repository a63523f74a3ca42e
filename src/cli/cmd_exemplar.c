/* cmd_exemplar.c - `planetgen exemplar`: load the exemplar pair, report its geometry
 * and statistics, and write equirectangular previews (albedo.png, relief.png).
 *
 * This is the first stage of every planet, run alone: it shows the user exactly
 * what planetgen understood of their inputs (sizes, the grey -> metres calibration,
 * sea level, land fraction) before any synthesis is spent on them. */
#include "pg_commands.h"

#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_json.h"
#include "planetgen/pg_relief.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct exemplar_args {
    pg_cli_exemplar in;
    const char *outdir;
    double max_mpx, max_memory_gb;
    long grid_width;
    bool prepare; /* also prepare the synthesis exemplar and time it (cmd_synth.c) */
} exemplar_args;

static void report_json(pg_cli *cli, const exemplar_args *a, const pg_exemplar *ex,
                        const pg_exemplar_stats *s) {
    pg_json *r = pg_cli_report(cli);
    if (!r) return;
    pg_json *in = pg_json_set_object(r, "inputs");
    pg_json_set_string(in, "albedo", ex->albedo_src);
    pg_json_set_string(in, "height", ex->height_src);
    pg_json *p = pg_json_set_object(r, "parameters");
    pg_json_set_string(p, "outdir", a->outdir);
    pg_json_set_number(p, "grid_width", ex->width);
    pg_json_set_number(p, "height_scale", a->in.height_scale);
    pg_json_set_number(p, "height_offset", a->in.height_offset);
    pg_json_set_bool(p, "repair_ocean", !a->in.no_repair_ocean);
    pg_json_set_number(p, "sea_level_m", ex->sea_level);
    pg_json *res = pg_json_set_object(r, "results");
    pg_json_set_number(res, "albedo_width", ex->albedo_w);
    pg_json_set_number(res, "albedo_height", ex->albedo_h);
    pg_json_set_number(res, "height_width", ex->height_w);
    pg_json_set_number(res, "height_height", ex->height_h);
    pg_json_set_number(res, "height_min_m", s->height_min);
    pg_json_set_number(res, "height_max_m", s->height_max);
    pg_json_set_number(res, "height_mean_m", s->height_mean);
    pg_json_set_number(res, "land_fraction", s->land_fraction);
    if (ex->height_is_grey) {
        pg_json_set_number(res, "sea_level_grey", ex->calib.sea_grey);
        pg_json_set_number(res, "water_mask_agreement", ex->calib.mask_agreement);
    }
}

static void print_summary(pg_cli *cli, const pg_exemplar *ex, const pg_exemplar_stats *s) {
    pg_cli_info(cli, "albedo   %s\n         %d x %d\n", ex->albedo_src, ex->albedo_w, ex->albedo_h);
    pg_cli_info(cli, "height   %s\n         %d x %d%s\n", ex->height_src, ex->height_w,
                ex->height_h, ex->height_is_grey ? " (grey ramp, calibrated to metres)" : "");
    pg_cli_info(cli, "grid     %d x %d equirectangular, %.1f km per pixel at the equator\n",
                ex->width, ex->height, 40075.017 / ex->width);
    pg_cli_info(cli, "albedo   R %.3f..%.3f  G %.3f..%.3f  B %.3f..%.3f (sRGB 0..1)\n",
                s->albedo_min[0], s->albedo_max[0], s->albedo_min[1], s->albedo_max[1],
                s->albedo_min[2], s->albedo_max[2]);
    pg_cli_info(cli, "height   %.0f .. %.0f m, mean %.0f m\n", s->height_min, s->height_max,
                s->height_mean);
    if (ex->height_is_grey)
        pg_cli_info(cli,
                    "calib    sea level at grey %.1f; grey %.0f -> %.0f m, grey %.0f -> %.0f m; "
                    "water mask agreement %.1f%%\n",
                    ex->calib.sea_grey, ex->calib.grey[0], ex->calib.metres[0],
                    ex->calib.grey[ex->calib.nknots - 1], ex->calib.metres[ex->calib.nknots - 1],
                    100 * ex->calib.mask_agreement);
    for (int k = 0; ex->height_is_grey && k < ex->calib.nknots; k++)
        pg_cli_verbose(cli, "knot     grey %6.1f -> %7.0f m\n", ex->calib.grey[k],
                       ex->calib.metres[k]);
    pg_cli_info(cli, "sea      %.1f m; land fraction %.1f%% (area-weighted)\n", ex->sea_level,
                100 * s->land_fraction);
    if (ex->notes[0]) pg_cli_info(cli, "note     %s\n", ex->notes);
}

static pg_status write_previews(pg_cli *cli, const char *dir, const pg_exemplar *ex,
                                pg_error *err) {
    pg_image img = {.width = ex->width, .height = ex->height, .channels = 3, .data = ex->albedo};
    const char *p = pg_cli_output_path(cli, dir, "albedo.png");
    pg_status st =
        p ? pg_image_write_png(p, &img, 8, err) : pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    if (st != PG_OK) return st;
    pg_image rel;
    st = pg_image_alloc(&rel, ex->width, ex->height, 3, err);
    if (st != PG_OK) return st;
    pg_relief_shade(ex->elevation, ex->width, ex->height, ex->sea_level, rel.data);
    p = pg_cli_output_path(cli, dir, "relief.png");
    st = p ? pg_image_write_png(p, &rel, 8, err) : pg_error_set(err, PG_ERR_NOMEM, "no memory");
    pg_image_free(&rel);
    return st;
}

int pg_cmd_exemplar(pg_cli *cli, int argc, char **argv) {
    exemplar_args a = {PG_CLI_EXEMPLAR_INIT, "out", 0, 0, 0, false};
    const pg_opt opts[] = {PG_CLI_EXEMPLAR_OPTS(a.in),
                           {"--output", "-o", PG_OPT_STRING, &a.outdir, 0, 0, NULL, "DIR",
                            "output directory (default: out)"},
                           {"--max-pixels", NULL, PG_OPT_DOUBLE, &a.max_mpx, 1, 1e5, NULL, "MPX",
                            "refuse input images above this many megapixels (default 2147)"},
                           {"--grid-width", NULL, PG_OPT_INT, &a.grid_width, 16, 86400, NULL, "W",
                            "common grid width, height W/2 (default: the coarser input's)"},
                           {"--prepare", NULL, PG_OPT_FLAG, &a.prepare, 0, 0, NULL, NULL,
                            "prepare the synthesis exemplar cube; report cold and cached times"},
                           PG_CLI_MAX_MEMORY_OPT(a.max_memory_gb),
                           PG_OPT_END};
    const char *pos[1];
    int npos;
    int rc = pg_cli_parse_or_help(cli, opts, argc, argv, pos, 0, &npos,
                                  "[--albedo F] [--height F] [-o DIR] [OPTIONS]",
                                  "Load a global albedo/height exemplar, print its geometry and "
                                  "statistics,\nand write equirectangular previews albedo.png "
                                  "and relief.png (shaded) to DIR.");
    if (rc >= 0) return rc;
    pg_exemplar_opts eo;
    pg_cli_exemplar_opts(&a.in, &eo);
    eo.grid_width = (int)a.grid_width;
    eo.max_pixels = a.max_mpx > 0 ? (uint64_t)(a.max_mpx * 1e6) : 0;
    /* --prepare adds the exemplar cube, far smaller than the loaded pair it is made of */
    char what[2048];
    snprintf(what, sizeof what, "exemplar %s + %s", eo.albedo_path ? eo.albedo_path : "Blue Marble",
             eo.height_path ? eo.height_path : "Marble relief");
    if ((rc = pg_cli_check_memory(cli, what, pg_cli_exemplar_bytes(&eo), a.max_memory_gb)))
        return rc;
    pg_error err = {0};
    pg_exemplar ex;
    /* The output dir is checked first (and removed again if we fail), so an
     * unwritable -o is reported before any work is spent. */
    if (pg_cli_prepare_outdir(cli, a.outdir, &err) != PG_OK) return pg_cli_fail(cli, &err);
    pg_cli_stage_begin(cli, "load exemplar");
    if (pg_exemplar_load(&eo, &ex, &err) != PG_OK) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    pg_exemplar_stats s;
    pg_exemplar_compute_stats(&ex, &s);
    pg_cli_stage_begin(cli, "write previews");
    pg_status st = write_previews(cli, a.outdir, &ex, &err);
    if (st != PG_OK) {
        pg_exemplar_free(&ex);
        return pg_cli_fail(cli, &err);
    }
    pg_cli_stage_end(cli);
    print_summary(cli, &ex, &s);
    if (a.prepare) pg_synth_cli_report_prep(cli, &ex);
    report_json(cli, &a, &ex, &s);
    pg_exemplar_free(&ex);
    return pg_cli_finish(cli);
}
