/* cmd_synth.c - `planetgen synth`: synthesize an N x N flat terrain from the exemplar
 * with the Lefebvre-Hoppe engine (pg_synth.h) and write albedo.png, height.exr and
 * coords.png (a debug colouring of the exemplar coordinates).
 *
 * Every input is validated before any work or output: N a power of two whose
 * estimated peak memory fits in the available memory or --max-memory (the estimate is
 * shown when it does not), jitter in [0, 1], a numeric seed. The exemplar is
 * prepared through the on-disk cache, so only the first run pays the analysis. */
#include "pg_commands.h"

#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_json.h"
#include "planetgen/pg_synth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct synth_args {
    pg_cli_exemplar in;
    const char *outdir, *cache_dir;
    long size, seed, passes, tile_size, face_size, levels;
    double jitter, kappa, offset_penalty, height_weight, max_memory_gb;
    bool no_offsets, no_cache;
} synth_args;

/* Bytes per output texel beyond the synthesis buffers: albedo, height, coords, and the
 * float image the PNG writer takes. */
#define OUTPUT_BYTES_PER_TEXEL (3 + 4 + 3 + 12)

static int validate(pg_cli *cli, const synth_args *a) {
    if (a->size < 16 || (a->size & (a->size - 1)) != 0)
        return pg_cli_usage_error(cli, "--size %ld: must be a power of two >= 16", a->size);
    /* pg_synth_flat_bytes takes an int; beyond 2^20 its n^2 (S + V, the level and its
     * parent: 8 B x 1.25) is computed here in doubles */
    double n2 = (double)a->size * a->size;
    double need = (a->size > (1L << 20) ? n2 * 8 * 1.25 : pg_synth_flat_bytes((int)a->size)) +
                  n2 * OUTPUT_BYTES_PER_TEXEL;
    /* the exemplar's share: loading the pair; the prepared cube is smaller and replaces it */
    pg_exemplar_opts eo;
    pg_cli_exemplar_opts(&a->in, &eo);
    need += pg_cli_exemplar_bytes(&eo);
    char what[64];
    snprintf(what, sizeof what, "--size %ld", a->size);
    int rc = pg_cli_check_memory(cli, what, need, a->max_memory_gb);
    if (rc) return rc;
    if (a->face_size < 16 || (a->face_size & (a->face_size - 1)) != 0)
        return pg_cli_usage_error(cli, "--face-size %ld: must be a power of two >= 16",
                                  a->face_size);
    return 0;
}

/* Exemplar faces store row 0 at the south (-v) edge; images put row 0 on top. Flip so
 * copied patches appear north-up, as in the exemplar. */
static void flip_rows(void *data, int n, size_t texel_bytes) {
    size_t row = (size_t)n * texel_bytes;
    unsigned char *d = data, tmp[4096];
    for (int y = 0; y < n / 2; y++)
        for (size_t off = 0; off < row; off += sizeof tmp) {
            size_t len = row - off < sizeof tmp ? row - off : sizeof tmp;
            unsigned char *a = d + (size_t)y * row + off, *b = d + (size_t)(n - 1 - y) * row + off;
            memcpy(tmp, a, len);
            memcpy(a, b, len);
            memcpy(b, tmp, len);
        }
}

static pg_status write_outputs(pg_cli *cli, const synth_args *a, const pg_synth_exemplar *ex,
                               const pg_synth_result *r, pg_error *err) {
    const int n = r->size;
    size_t count = (size_t)n * n;
    uint8_t *rgb = malloc(count * 3), *crgb = malloc(count * 3);
    pg_image img = {0}, hgt = {.width = n, .height = n, .channels = 1};
    hgt.data = malloc(count * sizeof(float));
    pg_status st = PG_OK;
    if (!rgb || !crgb || !hgt.data || pg_image_alloc(&img, n, n, 3, err) != PG_OK)
        st = pg_error_set(err, PG_ERR_NOMEM, "synth: out of memory for outputs");
    if (!st) {
        pg_synth_render(ex, r->coords, r->offset, count, rgb, hgt.data);
        pg_synth_coords_rgb(ex, r->coords, count, crgb);
        flip_rows(rgb, n, 3);
        flip_rows(crgb, n, 3);
        flip_rows(hgt.data, n, 4);
        for (size_t i = 0; i < count * 3; i++)
            img.data[i] = rgb[i] * (1.0f / 255.0f);
        const char *p = pg_cli_output_path(cli, a->outdir, "albedo.png");
        st = pg_image_write_png(p, &img, 8, err);
    }
    if (!st) {
        const char *p = pg_cli_output_path(cli, a->outdir, "height.exr");
        st = pg_image_write_exr(p, &hgt, NULL, err);
    }
    if (!st) {
        for (size_t i = 0; i < count * 3; i++)
            img.data[i] = crgb[i] * (1.0f / 255.0f);
        const char *p = pg_cli_output_path(cli, a->outdir, "coords.png");
        st = pg_image_write_png(p, &img, 8, err);
    }
    free(rgb);
    free(crgb);
    free(hgt.data);
    pg_image_free(&img);
    return st;
}

static void report(pg_cli *cli, const synth_args *a, const pg_synth_prep_info *pi, double synth_s) {
    double mpx = (double)a->size * a->size / 1e6;
    pg_cli_info(cli, "exemplar %s in %.2f s%s%s\n",
                pi->from_cache ? "loaded from cache" : "prepared", pi->seconds,
                pi->cache_path[0] ? ": " : "", pi->cache_path);
    pg_cli_info(cli, "synth    %ld x %ld in %.2f s (%.2f Mpx/s)\n", a->size, a->size, synth_s,
                mpx / synth_s);
    pg_json *r = pg_cli_report(cli);
    if (!r) return;
    pg_json *p = pg_json_set_object(r, "parameters");
    pg_json_set_number(p, "size", (double)a->size);
    pg_json_set_number(p, "seed", (double)a->seed);
    pg_json_set_number(p, "jitter", a->jitter);
    pg_json_set_number(p, "passes", (double)a->passes);
    pg_json_set_number(p, "kappa", a->kappa);
    pg_json *res = pg_json_set_object(r, "results");
    pg_json_set_number(res, "exemplar_prep_seconds", pi->seconds);
    pg_json_set_bool(res, "exemplar_from_cache", pi->from_cache);
    pg_json_set_number(res, "synth_seconds", synth_s);
    pg_json_set_number(res, "mpx_per_second", mpx / synth_s);
}

static pg_status load_and_prepare(const synth_args *a, pg_synth_exemplar **ex,
                                  pg_synth_prep_info *pi, pg_error *err) {
    pg_exemplar_opts eo;
    pg_cli_exemplar_opts(&a->in, &eo);
    pg_exemplar src;
    pg_status st = pg_exemplar_load(&eo, &src, err);
    if (st) return st;
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    ep.face_size = (int)a->face_size;
    ep.levels = (int)a->levels;
    ep.height_weight = a->height_weight;
    st = pg_synth_prepare_exemplar(src.albedo, src.elevation, src.width, src.height, src.sea_level,
                                   &ep, a->cache_dir, ex, pi, err);
    pg_exemplar_free(&src);
    return st;
}

/* For `planetgen exemplar --prepare`: prepare the synthesis exemplar through the cache
 * and report the cold preparation time and the cached load time. When the cache was
 * empty, the cold figure is this run's and the cached one is a second, timed load;
 * otherwise the cold figure is the one stored in the cache file. Failures (e.g. a
 * constant exemplar) are reported, not fatal: the command's own job is done. */
void pg_synth_cli_report_prep(pg_cli *cli, const pg_exemplar *src) {
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    pg_synth_exemplar *ex = NULL;
    pg_synth_prep_info pi, pc;
    pg_error err = {0};
    pg_cli_stage_begin(cli, "prepare synthesis exemplar");
    pg_status st = pg_synth_prepare_exemplar(src->albedo, src->elevation, src->width, src->height,
                                             src->sea_level, &ep, NULL, &ex, &pi, &err);
    pg_cli_stage_end(cli);
    if (st) {
        pg_cli_info(cli, "synth    exemplar preparation failed: %s\n", err.msg);
        return;
    }
    double cold = pi.from_cache ? ex->cold_seconds : pi.seconds, cached = pi.seconds;
    pg_synth_exemplar_free(ex);
    if (!pi.from_cache && pi.cache_path[0] &&
        pg_synth_prepare_exemplar(src->albedo, src->elevation, src->width, src->height,
                                  src->sea_level, &ep, NULL, &ex, &pc, &err) == PG_OK) {
        cached = pc.seconds;
        pg_synth_exemplar_free(ex);
    }
    pg_cli_info(cli,
                "synth    exemplar cube 6 x %d^2, %d levels: prepared cold in %.2f s, "
                "cached load %.2f s (%s)\n",
                ep.face_size, ep.levels, cold, cached,
                pi.cache_path[0] ? pi.cache_path : "cache not writable");
    pg_json *r = pg_cli_report(cli);
    if (!r) return;
    pg_json *o = pg_json_set_object(r, "synth_exemplar_prep");
    pg_json_set_number(o, "cold_seconds", cold);
    pg_json_set_number(o, "cached_seconds", cached);
    pg_json_set_string(o, "cache_path", pi.cache_path);
}

int pg_cmd_synth(pg_cli *cli, int argc, char **argv) {
    synth_args a = {
        PG_CLI_EXEMPLAR_INIT, "out", NULL, 0, 1, 2, 0, 512, 6, 0.4, 0.1, 1.0, 1.0, 0, false, false};
    const pg_opt opts[] = {
        {"--size", NULL, PG_OPT_INT, &a.size, 1, 1e12, NULL, "N",
         "output is N x N texels, N a power of two (required)"},
        {"--seed", NULL, PG_OPT_INT, &a.seed, 0, 9007199254740992.0, NULL, "S",
         "random seed (default 1)"},
        {"--output", "-o", PG_OPT_STRING, &a.outdir, 0, 0, NULL, "DIR",
         "output directory (default: out)"},
        {"--jitter", NULL, PG_OPT_DOUBLE, &a.jitter, 0, 1, NULL, "R",
         "jitter strength r_l for every level, in [0, 1] (default 0.4)"},
        {"--passes", NULL, PG_OPT_INT, &a.passes, 0, 16, NULL, "C",
         "correction passes per level (default 2)"},
        {"--kappa", NULL, PG_OPT_DOUBLE, &a.kappa, 0, 100, NULL, "K",
         "jump penalty for k-coherence candidates (default 0.1)"},
        {"--offset-penalty", NULL, PG_OPT_DOUBLE, &a.offset_penalty, 0, 1e6, NULL, "L",
         "cost lambda of a height offset h: lambda*4*h^2 (0 = Gain et al.; default 1)"},
        {"--no-offsets", NULL, PG_OPT_FLAG, &a.no_offsets, 0, 0, NULL, NULL,
         "disable Gain et al. height offsets"},
        {"--tile-size", NULL, PG_OPT_INT, &a.tile_size, 0, 1 << 20, NULL, "T",
         "correct in T x T tiles (0: whole levels; the result is identical)"},
        PG_CLI_EXEMPLAR_OPTS(a.in),
        {"--face-size", NULL, PG_OPT_INT, &a.face_size, 16, 8192, NULL, "E",
         "exemplar cube face size (default 512)"},
        {"--levels", NULL, PG_OPT_INT, &a.levels, 1, 10, NULL, "L",
         "analysed (corrected) levels (default 6)"},
        {"--height-weight", NULL, PG_OPT_DOUBLE, &a.height_weight, 0, 1000, NULL, "W",
         "height weight w_h relative to the albedo in appearance space (default 1)"},
        {"--cache-dir", NULL, PG_OPT_STRING, &a.cache_dir, 0, 0, NULL, "DIR",
         "exemplar cache (default $XDG_CACHE_HOME/planetgen or ~/.cache/planetgen)"},
        {"--no-cache", NULL, PG_OPT_FLAG, &a.no_cache, 0, 0, NULL, NULL,
         "neither read nor write the exemplar cache"},
        PG_CLI_MAX_MEMORY_OPT(a.max_memory_gb),
        PG_OPT_END};
    const char *pos[1];
    int npos;
    int rc = pg_cli_parse_or_help(cli, opts, argc, argv, pos, 0, &npos,
                                  "--size N [--seed S] [-o DIR] [OPTIONS]",
                                  "Synthesize an N x N flat terrain by example (Lefebvre-Hoppe "
                                  "with Gain et al.\nheight offsets) and write albedo.png, "
                                  "height.exr (metres) and coords.png to DIR.");
    if (rc >= 0) return rc;
    if (a.size == 0) return pg_cli_usage_error(cli, "--size is required");
    if ((rc = validate(cli, &a))) return rc;
    pg_error err = {0};
    pg_synth_exemplar *ex = NULL;
    pg_synth_prep_info pi;
    pg_cli_stage_begin(cli, "prepare exemplar");
    if (load_and_prepare(&a, &ex, &pi, &err) != PG_OK) return pg_cli_fail(cli, &err);
    pg_cli_stage_end(cli);
    pg_synth_params sp;
    pg_synth_params_default(&sp);
    sp.seed = (uint64_t)a.seed;
    sp.jitter = a.jitter;
    sp.passes = (int)a.passes;
    sp.kappa = a.kappa;
    sp.height_offsets = !a.no_offsets;
    sp.offset_penalty = a.offset_penalty;
    sp.tile_size = (int)a.tile_size;
    pg_synth_result r;
    pg_cli_stage_begin(cli, "synthesize");
    double t0 = pg_synth_now();
    pg_status st = pg_synth_flat(ex, (int)a.size, &sp, NULL, NULL, &r, &err);
    double synth_s = pg_synth_now() - t0;
    pg_cli_stage_end(cli);
    if (!st) {
        pg_cli_stage_begin(cli, "write outputs");
        st = pg_cli_prepare_outdir(cli, a.outdir, &err);
        if (!st) st = write_outputs(cli, &a, ex, &r, &err);
        pg_cli_stage_end(cli);
        pg_synth_result_free(&r);
    }
    if (st) {
        pg_synth_exemplar_free(ex);
        return pg_cli_fail(cli, &err);
    }
    report(cli, &a, &pi, synth_s);
    pg_synth_exemplar_free(ex);
    return pg_cli_finish(cli);
}
