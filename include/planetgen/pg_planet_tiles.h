/* pg_planet_tiles.h - the tiled layout of a planet directory (docs/mpi.md): one albedo
 * PNG and one height EXR per tile plus an index, for planets too large for one .glb
 * and for distributed runs, where each process writes only its own tiles.
 *
 * Files, for tile (tx, ty) of face F (F = +X -X +Y -Y +Z -Z; tile_size S):
 *   albedo_F_TX_TY.png  8-bit sRGB RGB, S x S
 *   height_F_TX_TY.exr  float32 metres, one channel Y, S x S
 * covering face texels x in [TX S, TX S + S), y in [TY S, TY S + S), with PNG/EXR row
 * 0 at the tile's +v edge (the same orientation as the planet layout's face images).
 *   index.json          the planet's parameters (as planet.json) and the list of
 *                       tiles with their files. Written last: a tiled directory is
 *                       complete exactly when index.json exists. */
#ifndef PLANETGEN_PG_PLANET_TILES_H
#define PLANETGEN_PG_PLANET_TILES_H

#include "planetgen/pg_planet.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PG_PLANET_INDEX_NAME "index.json"

/* File names of tile t (face-major: t = f T^2 + ty T + tx). */
void pg_planet_tile_names(const pg_planet *p, int t, char albedo[64], char height[64]);

/* Write tiles [first, last) of p (only those texels are read). */
pg_status pg_planet_save_tiles(const pg_planet *p, int first, int last, pg_planet_path_fn path_for,
                               void *user, pg_error *err);

/* Write index.json for all 6 T^2 tiles. */
pg_status pg_planet_save_index(const pg_planet *p, pg_planet_path_fn path_for, void *user,
                               pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
