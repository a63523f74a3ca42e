/* pg_test_exemplar.c - the default exemplar for the tests that synthesize through the
 * library (pg_test.h): loaded and prepared once per test program, through the build's
 * exemplar cache. */
#include "pg_test.h"

#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_synth.h"

#include <stdio.h>
#include <stdlib.h>

pg_synth_exemplar *pg_test_default_exemplar(void) {
    pg_exemplar_opts eo;
    pg_exemplar_opts_default(&eo);
    pg_exemplar src;
    pg_error err = {0};
    if (pg_exemplar_load(&eo, &src, &err) != PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return NULL;
    }
    char dir[512];
    snprintf(dir, sizeof dir, "%s/synth-cache", getenv("PG_BUILD_DIR"));
    pg_synth_exemplar_params ep;
    pg_synth_exemplar_params_default(&ep);
    pg_synth_prep_info info;
    pg_synth_exemplar *ex = NULL;
    pg_status st = pg_synth_prepare_exemplar(src.albedo, src.elevation, src.width, src.height,
                                             src.sea_level, &ep, dir, &ex, &info, &err);
    pg_exemplar_free(&src);
    if (st) fprintf(stderr, "%s\n", err.msg);
    return st ? NULL : ex;
}
