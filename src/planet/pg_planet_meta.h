/* pg_planet_meta.h - reading planet.json (C API over the nlohmann/json adapter). */
#ifndef PG_PLANET_META_H
#define PG_PLANET_META_H

#include "planetgen/pg_geo.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pg_planet_meta {
    int format_version;
    pg_ellipsoid ellipsoid;
    char projection[32];
    int tiles, tile_size;
    uint64_t seed;
    double sea_level;
    char exemplar[512];
    /* optional "source" object: the coordinate map's file (a plain name inside the
     * planet directory), exemplar face size and projection name; has_source false
     * when planet.json has none */
    bool has_source;
    char source_file[256];
    int source_face_size;
    char source_projection[32];
    double closed_land_share_before_final; /* NaN when absent */
} pg_planet_meta;

/* Parse and validate planet.json; every problem names the file and the key. */
pg_status pg_planet_meta_read(const char *path, pg_planet_meta *m, pg_error *err);

/* Allocate the planet that meta describes (faces zeroed) and set its parameters;
 * `file` names the JSON file in errors (pg_planet.c). */
struct pg_planet;
pg_status pg_planet_alloc_meta(const pg_planet_meta *meta, const char *file, struct pg_planet *p,
                               pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
