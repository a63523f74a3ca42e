/* cmd_generate_world.c - `planetgen generate --layout world`: the macro world that the
 * synthesis amplifies by example (docs/generate.md, "Layout world"). Plates (pg_plates.h,
 * after Cortial et al. 2019) give the elevation, the climate model (pg_climate.h) its
 * temperature and precipitation; the synthesis samples them as its guide and type
 * constraints at every level (pg_planet_world_level). The macro fields are written into
 * the planet directory: plates.png, climate.png and world.exr (one part per cube face,
 * channels elevation_m, temperature_c, precipitation_mm, convergent_km). */
#include "cmd_generate.h"

#include "planetgen/pg_exr.h"
#include "planetgen/pg_json.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GEN_WORLD_N 64     /* macro texels per face edge (about 140 km) */
#define GEN_WORLD_DETAIL 4 /* the synthesis' controls on a cube this many times finer */
#define GEN_WORLD_PREVIEW_WIDTH 1024
#define GEN_WORLD_QUANTILES 1001 /* the exemplar's hypsometry, per mille */

void gen_world_init(gen_world *w) {
    memset(w, 0, sizeof *w);
    pg_plates_world_init(&w->plates);
    pg_climate_init(&w->climate);
}

void gen_world_free(gen_world *w) {
    pg_plates_world_free(&w->plates);
    pg_climate_free(&w->climate);
    free(w->detail);
    w->detail = NULL;
}

/* An ice sheet's rank offset: land whose first-guess climate is an ice climate stands
 * higher the colder it is, up to GEN_WORLD_ICE_SHEET_M at 20 K below the ice line (Earth's
 * sheets: 2-3 km over their interiors, thinning to the margins). */
#define GEN_WORLD_ICE_SHEET_M 3000.0
static pg_status ice_sheets(const gen_args *a, const pg_plates_world *pw, float *off,
                            pg_error *err) {
    pg_climate_params cp;
    pg_climate_params_default(&cp);
    cp.axial_tilt_deg = a->axial_tilt;
    cp.temperature_offset_K = a->temperature_offset;
    pg_climate cl;
    pg_climate_init(&cl);
    pg_status st = pg_climate_compute(&cp, pw->proj, pw->n, pw->elevation_m, &cl, err);
    for (int64_t t = 0; !st && t < 6 * pw->n * pw->n; t++) {
        double below = PG_CLIMATE_ICE_C - cl.temperature_c[t];
        off[t] = pw->elevation_m[t] > 0 && below > 0
                     ? (float)(GEN_WORLD_ICE_SHEET_M * fmin(1.0, below / 20.0))
                     : 0.0f;
    }
    pg_climate_free(&cl);
    return st;
}

/* The plates' heights take the exemplar's hypsometry (pg_plates_match_hypsometry), ice
 * sheets ranked by their surface. */
static pg_status match_exemplar(const gen_args *a, const pg_synth_exemplar *ex, pg_plates_world *pw,
                                pg_error *err) {
    float *q = malloc(2 * GEN_WORLD_QUANTILES * sizeof *q);
    float *off = malloc((size_t)6 * pw->n * pw->n * sizeof *off);
    pg_status st =
        q && off ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "layout world: out of memory");
    if (!st)
        st = pg_planet_world_exemplar_hypsometry(ex, GEN_WORLD_N, GEN_WORLD_QUANTILES, q,
                                                 q + GEN_WORLD_QUANTILES, err);
    if (!st) st = ice_sheets(a, pw, off, err);
    pg_plates_hypsometry h = {GEN_WORLD_QUANTILES, q, q + GEN_WORLD_QUANTILES, off};
    if (!st) st = pg_plates_match_hypsometry(pw, &h, err);
    free(q);
    free(off);
    return st;
}

/* The macro fields with warped contours on a finer cube (pg_plates_detail), as the
 * world the synthesis follows; plates.png, climate.png and world.exr keep the macro
 * grid. */
static pg_status detail_world(const gen_args *a, gen_world *w, pg_error *err) {
    const int64_t n = w->plates.n, m = GEN_WORLD_DETAIL * n, nn = 6 * n * n, mm = 6 * m * m;
    float *in = malloc((size_t)nn * 3 * sizeof *in), *out = malloc((size_t)mm * 3 * sizeof *out);
    w->detail = malloc((size_t)mm * 3 * sizeof *w->detail);
    if (!in || !out || !w->detail) {
        free(in), free(out);
        return pg_error_set(err, PG_ERR_NOMEM, "layout world: out of memory");
    }
    for (int64_t i = 0; i < nn; i++) {
        in[3 * i] = w->plates.elevation_m[i];
        in[3 * i + 1] = w->climate.temperature_c[i];
        in[3 * i + 2] = w->climate.precipitation_mm[i];
    }
    pg_status st = pg_plates_detail((uint64_t)a->seed, w->plates.proj, n, in, 3, m, out, err);
    for (int64_t i = 0; !st && i < mm; i++)
        for (int c = 0; c < 3; c++)
            w->detail[c * mm + i] = out[3 * i + c];
    free(in), free(out);
    w->world = (pg_planet_world){m, w->detail, w->detail + mm, w->detail + 2 * mm};
    return st;
}

pg_status gen_world_build(const gen_args *a, const pg_synth_exemplar *ex, gen_world *w,
                          pg_error *err) {
    pg_plates_params pp;
    pg_plates_params_default(&pp);
    pp.seed = (uint64_t)a->seed;
    pp.n = GEN_WORLD_N;
    pp.plates = (int)a->plates;
    pp.land_fraction = a->land_fraction;
    pg_status st = pg_plates_generate(&pp, &w->plates, err);
    if (!st) st = match_exemplar(a, ex, &w->plates, err);
    if (!st) st = pg_plates_stats_compute(&w->plates, &w->stats, err);
    pg_climate_params cp;
    pg_climate_params_default(&cp);
    cp.axial_tilt_deg = a->axial_tilt;
    cp.temperature_offset_K = a->temperature_offset;
    if (!st)
        st = pg_climate_compute(&cp, w->plates.proj, w->plates.n, w->plates.elevation_m,
                                &w->climate, err);
    if (!st) st = detail_world(a, w, err);
    return st;
}

static pg_status write_exr(const char *path, const gen_world *w, pg_error *err) {
    const int64_t n = w->plates.n;
    const size_t nn = (size_t)n * n;
    const float *src[4] = {w->plates.elevation_m, w->climate.temperature_c,
                           w->climate.precipitation_mm, w->plates.convergent_km};
    const char *channels[4] = {"elevation_m", "temperature_c", "precipitation_mm", "convergent_km"};
    pg_image parts[PG_CUBE_NFACES];
    const char *names[PG_CUBE_NFACES];
    memset(parts, 0, sizeof parts);
    pg_status st = PG_OK;
    /* Cube fields are stored bottom-up (row 0 = the face's -v edge); like every face image
     * of the planet directory (height.exr, albedo_+X.png, source.exr), each part puts
     * row 0 at the +v edge, so the files line up texel for texel. */
    for (int f = 0; f < PG_CUBE_NFACES && !st; f++) {
        names[f] = pg_cube_face_name(f);
        st = pg_image_alloc(&parts[f], (int)n, (int)n, 4, err);
        for (int64_t y = 0; !st && y < n; y++)
            for (int64_t x = 0; x < n; x++) {
                size_t i = (size_t)(n - 1 - y) * n + x, j = (size_t)f * nn + (size_t)y * n + x;
                for (int k = 0; k < 4; k++)
                    parts[f].data[i * 4 + k] = src[k][j];
            }
    }
    if (!st) st = pg_exr_write_parts(path, PG_CUBE_NFACES, names, parts, channels, err);
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        pg_image_free(&parts[f]);
    return st;
}

void gen_world_report(pg_cli *cli, const gen_world *w, pg_json *res) {
    const pg_plates_stats *s = &w->stats;
    pg_cli_info(cli,
                "world    plates: land %.3f, largest landmass %.2f of land, %d landmasses >= "
                "1e6 km2, high land in belts %.2f\n",
                s->land_fraction, s->largest_land_share, s->landmasses_1e6km2,
                s->mountain_belt_share);
    if (!res) return;
    pg_json *o = pg_json_set_object(res, "world");
    pg_json_set_number(o, "land_fraction", s->land_fraction);
    pg_json_set_number(o, "largest_landmass_share", s->largest_land_share);
    pg_json_set_number(o, "landmasses_1e6", s->landmasses_1e6km2);
    pg_json_set_number(o, "mountain_belt_share", s->mountain_belt_share);
    pg_json_set_number(o, "high_land_fraction", s->high_land_fraction);
}

/* plates.png, climate.png and world.exr: the two maps rendered (each render is parallel
 * inside), then the three files encoded at once, since each encoder is single-threaded.
 * The first failure in that order is reported. */
pg_status gen_world_write(pg_cli *cli, const gen_args *a, const gen_world *w, pg_error *err) {
    pg_image img[2] = {{0}, {0}};
    pg_status st = pg_plates_render_plates(&w->plates, GEN_WORLD_PREVIEW_WIDTH, &img[0], err);
    if (!st)
        st = pg_climate_render_preview(&w->climate, w->plates.elevation_m, GEN_WORLD_PREVIEW_WIDTH,
                                       &img[1], err);
    const char *names[3] = {"plates.png", "climate.png", "world.exr"}, *paths[3] = {0};
    for (int k = 0; !st && k < 3; k++)
        if (!(paths[k] = pg_cli_output_path(cli, a->outdir, names[k])))
            st = pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", names[k]);
    if (!st) {
        pg_status sk[3];
        pg_error e[3];
        memset(e, 0, sizeof e);
#pragma omp parallel for schedule(dynamic, 1)
        for (int k = 0; k < 3; k++)
            sk[k] = k < 2 ? pg_image_write_png(paths[k], &img[k], 8, &e[k])
                          : write_exr(paths[k], w, &e[k]);
        for (int k = 0; !st && k < 3; k++)
            if (sk[k]) st = pg_error_set(err, sk[k], "%s", e[k].msg);
    }
    pg_image_free(&img[0]);
    pg_image_free(&img[1]);
    return st;
}
