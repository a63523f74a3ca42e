/* pg_planet_synth_testing.h - test-only options of the planet synthesis driver
 * (pg_planet_synth.h). Library-internal: tests and the CLI's hidden test flags use it
 * to show what the driver's guarantees rest on; no planet worth keeping needs it. */
#ifndef PG_PLANET_SYNTH_TESTING_H
#define PG_PLANET_SYNTH_TESTING_H

#include "planetgen/pg_planet_synth.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pg_planet_synth_testing {
    /* Tiles see no neighbours (the halo is their own edge continued), to show that
     * seams then appear (the CLI's --independent-tiles). */
    bool independent_tiles;
} pg_planet_synth_testing;

/* pg_planet_synth_run with test-only options (t NULL: none, the same as
 * pg_planet_synth_run). */
pg_status pg_planet_synth_run_testing(const pg_synth_exemplar *ex, const pg_planet_synth_params *p,
                                      const pg_planet_synth_testing *t, pg_planet *out,
                                      uint32_t **coords_out, pg_planet_synth_info *info,
                                      pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
