/* pg_types.h - terrain types (Gain et al. 2015 type constraints, EarthGen's four planet
 * kinds): classifying exemplar texels, presets and type maps that restrict which
 * types planet synthesis (pg_planet_synth.h) may place where. */
#ifndef PLANETGEN_PG_TYPES_H
#define PLANETGEN_PG_TYPES_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_synth.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pg_types_id {
    PG_TYPE_OCEAN,
    PG_TYPE_ICE,      /* ice and snow */
    PG_TYPE_DESERT,   /* desert and bare ground */
    PG_TYPE_GRASS,    /* grass and sparse vegetation */
    PG_TYPE_FOREST,   /* forest */
    PG_TYPE_MOUNTAIN, /* high ground that is not ice */
    PG_TYPE_COUNT
} pg_types_id;

#define PG_TYPES_ALL ((uint8_t)((1u << PG_TYPE_COUNT) - 1))

/* pg_types_exemplar's type for exemplar texels that no mask allows: inland water and
 * its rim (pg_types.c, "Inland water"). Never returned by pg_types_classify. Masks are
 * read through PG_TYPES_ALL, so even a mask with bit 6 set does not allow it. */
#define PG_TYPE_EXCLUDED ((int)PG_TYPE_COUNT)
/* Inland water: a texel above sea level whose every sRGB channel is at most this. */
#define PG_TYPES_LAKE_MAX 20
/* The rim excluded with inland water: the square of this many texels each way round a
 * lake texel, on its face, except ice. */
#define PG_TYPES_LAKE_RIM 2

/* "ocean", "ice", "desert", "grass", "forest", "mountain". */
const char *pg_types_name(int type);
/* The colour that names the type in a type map (sRGB 0..255). */
void pg_types_colour(int type, uint8_t rgb[3]);

/* The classification rule (documented in pg_types.c) of one exemplar texel from its
 * sRGB albedo and its height in metres. */
int pg_types_classify(const uint8_t rgb[3], float height_m, float sea_level);

/* Type of every texel of a prepared exemplar (nfaces*E*E bytes; caller frees):
 * pg_types_classify's, or PG_TYPE_EXCLUDED for inland water and for the texels other
 * than ice within PG_TYPES_LAKE_RIM of it (each axis) on its face. NULL when out of
 * memory. */
uint8_t *pg_types_exemplar(const pg_synth_exemplar *ex);

/* Allowed-type mask of a preset: "earth" (all), "desert", "snow", "grassland".
 * BADINPUT naming --preset for anything else. */
pg_status pg_types_preset(const char *name, uint8_t *mask, pg_error *err);

/* A type map: an equirectangular image whose pixels are type colours (or black =
 * any type). Loaded into a mask image (w x h bytes). BADINPUT if unreadable, not
 * 2:1, or with colours that name no type (they are listed). */
typedef struct pg_types_map {
    int width, height;
    uint8_t *mask;
} pg_types_map;
pg_status pg_types_map_load(const char *path, pg_types_map *m, pg_error *err);
void pg_types_map_free(pg_types_map *m);

#ifdef __cplusplus
}
#endif

#endif
