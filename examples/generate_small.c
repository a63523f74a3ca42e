/* generate_small.c - a small planet through libplanetgen's public API alone: load the
 * default exemplar (Debian's marble-qt-data: Blue Marble and Marble's relief), prepare
 * it for synthesis, synthesize a planet of 6 x 2^2 tiles of 64^2 texels, save it as a
 * planet directory (albedo_*.png, height.exr, planet.json; `planetgen export` and
 * `planetgen inspect` read it) and print one summary line.
 *
 * Build against an installed planetgen (examples/README.md):
 *     cc generate_small.c $(pkg-config --cflags --libs planetgen) -o generate_small
 * usage: generate_small OUT_DIR [CACHE_DIR]
 * The prepared exemplar is cached in CACHE_DIR (default: planetgen's own cache), so a
 * second run skips the preparation. */
#define _POSIX_C_SOURCE 200809L /* mkdir */

#include <planetgen/planetgen.h>

#include <errno.h>
#include <stdio.h>
#include <sys/stat.h>

/* Print the error and return the CLI's exit code for it (pg_common.h). */
static int fail(const char *what, const pg_error *err) {
    fprintf(stderr, "generate_small: %s: %s\n", what, err->msg);
    return pg_status_exit_code(err->status);
}

/* Share of texels above sea level, and the height range, over the whole cube. */
static void summarize(const pg_planet *p, double *land, float *lo, float *hi) {
    size_t nn = (size_t)p->n * (size_t)p->n, above = 0;
    *lo = *hi = p->height[0][0];
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (size_t i = 0; i < nn; i++) {
            float h = p->height[f][i];
            above += h > p->sea_level;
            *lo = h < *lo ? h : *lo;
            *hi = h > *hi ? h : *hi;
        }
    *land = (double)above / (double)(PG_CUBE_NFACES * nn);
}

int main(int argc, char **argv) {
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: generate_small OUT_DIR [CACHE_DIR]\n");
        return 2;
    }
    char cache[1024];
    if (argc == 3)
        snprintf(cache, sizeof cache, "%s", argv[2]);
    else
        pg_synth_default_cache_dir(cache, sizeof cache);
    if (mkdir(argv[1], 0777) != 0 && errno != EEXIST) {
        perror(argv[1]);
        return 1;
    }

    /* The planet's parameters first: the exemplar is prepared at the face size the
     * planet needs (pg_planet_synth_face_size). */
    pg_planet_synth_params params;
    pg_planet_synth_params_default(&params);
    params.tiles = 2;
    params.tile_size = 64;
    params.synth.seed = 1;

    pg_error err = {0};
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo); /* NULL paths: the Marble maps */
    pg_exemplar src = {0};
    if (pg_exemplar_load(&eo, &src, &err) != PG_OK) return fail("exemplar", &err);

    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    ep.face_size = pg_planet_synth_face_size(params.tiles, params.tile_size);
    pg_synth_exemplar *ex = NULL;
    pg_synth_prep_info prep;
    pg_status st = pg_synth_prepare_exemplar(src.albedo, src.elevation, src.width, src.height,
                                             src.sea_level, &ep, cache, &ex, &prep, &err);
    pg_exemplar_free(&src); /* the prepared exemplar keeps what synthesis needs */
    if (st != PG_OK) return fail("prepare exemplar", &err);

    pg_planet planet = {0};
    st = pg_planet_synth_run(ex, &params, &planet, NULL, NULL, &err);
    pg_synth_exemplar_free(ex);
    if (st == PG_OK) st = pg_planet_save_dir(&planet, argv[1], &err);
    if (st != PG_OK) {
        pg_planet_free(&planet);
        return fail("planet", &err);
    }

    double land;
    float lo, hi;
    summarize(&planet, &land, &lo, &hi);
    printf("planetgen %s: planet 6 x %d^2 x %d^2 (n = %lld) in %s: land %.3f, heights %.0f to "
           "%.0f m, sea level %.0f m\n",
           pg_version(), planet.tiles, planet.tile_size, (long long)planet.n, argv[1], land,
           (double)lo, (double)hi, (double)planet.sea_level);
    pg_planet_free(&planet);
    return 0;
}
