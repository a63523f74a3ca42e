/* cmd_grid.c - `planetgen grid`: describe a cube-sphere grid on a planet.
 *
 * Prints the tile and texel counts and the distortion of the chosen projection on
 * the chosen ellipsoid: texel area min/max and their ratio, the worst deviation of
 * a texel corner angle from 90 degrees, and the mean texel size. This is the place
 * to choose a projection and resolution before spending hours on synthesis. */
#include "pg_commands.h"

#include "planetgen/pg_cube.h"
#include "planetgen/pg_json.h"

#include <string.h>

typedef struct grid_args {
    const char *projection, *planet;
    long tiles, tile_size;
} grid_args;

static void report_json(pg_cli *cli, const grid_args *a, const pg_ellipsoid *e,
                        const pg_cube_grid *g, const pg_cube_distortion *d) {
    pg_json *r = pg_cli_report(cli);
    if (!r) return;
    pg_json *p = pg_json_set_object(r, "parameters");
    pg_json_set_string(p, "projection", pg_cube_projection_name(g->proj));
    pg_json_set_number(p, "tiles", (double)a->tiles);
    pg_json_set_number(p, "tile_size", (double)a->tile_size);
    pg_json_set_number(p, "radius_m", e->a);
    pg_json_set_number(p, "flattening", e->f);
    /* The distortion figures sit at the top level (the documented keys) and again
     * under "results" like every other command's figures. */
    pg_json *res = pg_json_set_object(r, "results");
    pg_json *objs[2] = {r, res};
    for (int i = 0; i < 2; i++) {
        pg_json_set_number(objs[i], "tile_count", (double)g->ntiles);
        pg_json_set_number(objs[i], "texel_count", 6.0 * (double)g->n * (double)g->n);
        pg_json_set_number(objs[i], "texel_area_min_m2", d->area_min_m2);
        pg_json_set_number(objs[i], "texel_area_max_m2", d->area_max_m2);
        pg_json_set_number(objs[i], "area_ratio", d->area_ratio);
        pg_json_set_number(objs[i], "max_angle_deviation_deg", d->max_angle_dev_deg);
        pg_json_set_number(objs[i], "mean_texel_km", d->mean_texel_km);
    }
}

static void print_summary(pg_cli *cli, const pg_ellipsoid *e, const pg_cube_grid *g,
                          const pg_cube_distortion *d) {
    double texels = 6.0 * (double)g->n * (double)g->n;
    pg_cli_info(cli, "projection  %s\n", pg_cube_projection_name(g->proj));
    pg_cli_info(cli, "planet      a = %.1f m, f = %.10g\n", e->a, e->f);
    pg_cli_info(cli, "tiles       6 x %d x %d = %lld tiles of %d x %d texels\n", g->tiles, g->tiles,
                (long long)g->ntiles, g->tile_size, g->tile_size);
    pg_cli_info(cli, "texels      6 x %lld x %lld = %.0f\n", (long long)g->n, (long long)g->n,
                texels);
    pg_cli_info(cli, "texel area  min %.6g m^2, max %.6g m^2, ratio %.4f\n", d->area_min_m2,
                d->area_max_m2, d->area_ratio);
    pg_cli_info(cli, "angles      max corner deviation from 90 deg: %.4f deg\n",
                d->max_angle_dev_deg);
    pg_cli_info(cli, "texel size  mean %.4f km\n", d->mean_texel_km);
}

/* Validate everything before any work: each message names its option. */
static pg_status validate(const grid_args *a, pg_cube_projection *p, pg_ellipsoid *e,
                          pg_error *err) {
    pg_status st = pg_cube_projection_parse(a->projection, "--projection", p, err);
    if (st != PG_OK) return st;
    if (a->tiles < 1)
        return pg_error_set(err, PG_ERR_BADINPUT, "--tiles: must be >= 1, got %ld", a->tiles);
    if (a->tile_size < 16 || a->tile_size > 8192 || (a->tile_size & (a->tile_size - 1)))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--tile-size: must be a power of two in 16..8192, got %ld",
                            a->tile_size);
    if (a->tiles * a->tile_size > (1L << 30))
        return pg_error_set(err, PG_ERR_BADINPUT, "--tiles: %ld x %ld texels per face is too many",
                            a->tiles, a->tile_size);
    return pg_ellipsoid_parse(a->planet, "--planet", e, err);
}

int pg_cmd_grid(pg_cli *cli, int argc, char **argv) {
    grid_args a = {"equi-angular", "sphere", 8, 256};
    const pg_opt opts[] = {{"--projection", NULL, PG_OPT_STRING, &a.projection, 0, 0, NULL, "P",
                            "gnomonic, equi-angular (default) or equal-area"},
                           {"--tiles", NULL, PG_OPT_INT, &a.tiles, 1, 65536, NULL, "T",
                            "tiles per face edge, >= 1 (default 8)"},
                           {"--tile-size", NULL, PG_OPT_INT, &a.tile_size, 16, 8192, NULL, "S",
                            "texels per tile edge, a power of two in 16..8192 (default 256)"},
                           {"--planet", NULL, PG_OPT_STRING, &a.planet, 0, 0, NULL, "E",
                            "sphere (R = 6371008.8 m, default), wgs84, or RADIUS_M,FLATTENING"},
                           PG_OPT_END};
    const char *pos[1];
    int npos;
    int rc = pg_cli_parse_or_help(cli, opts, argc, argv, pos, 0, &npos,
                                  "[--projection P] [--tiles T] [--tile-size S] [--planet E]",
                                  "Describe a cube-sphere grid: tile and texel counts, texel area "
                                  "min/max/ratio\non the ellipsoid, worst corner-angle deviation "
                                  "from 90 degrees, mean texel size.");
    if (rc >= 0) return rc;
    pg_error err = {0};
    pg_cube_projection p;
    pg_ellipsoid e;
    if (validate(&a, &p, &e, &err) != PG_OK) return pg_cli_fail(cli, &err);
    pg_cube_grid g;
    if (pg_cube_grid_init(&g, p, (int)a.tiles, (int)a.tile_size, &err) != PG_OK)
        return pg_cli_fail(cli, &err);
    pg_cube_distortion d;
    pg_cli_stage_begin(cli, "texel areas and angles");
    if (pg_cube_distortion_compute(p, g.n, &e, &d, &err) != PG_OK) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    print_summary(cli, &e, &g, &d);
    report_json(cli, &a, &e, &g, &d);
    return pg_cli_finish(cli);
}
