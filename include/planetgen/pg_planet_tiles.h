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

/* Name of tile t's glTF file, "planet_F_TX_TY.glb" (written by pg_export_tiles_glb). */
void pg_planet_tile_glb_name(const pg_planet *p, int t, char glb[64]);

/* Write tiles [first, last) of p (only those texels are read). */
pg_status pg_planet_save_tiles(const pg_planet *p, int first, int last, pg_planet_path_fn path_for,
                               void *user, pg_error *err);

/* Write index.json for all 6 T^2 tiles. */
pg_status pg_planet_save_index(const pg_planet *p, pg_planet_path_fn path_for, void *user,
                               pg_error *err);
/* The same, listing each tile's .glb too when glb (pg_planet_tile_glb_name). */
pg_status pg_planet_save_index_glb(const pg_planet *p, bool glb, pg_planet_path_fn path_for,
                                   void *user, pg_error *err);

/* Is dir a tiled planet directory (index.json and no planet.json)? */
bool pg_planet_dir_is_tiled(const char *dir);

/* Load a tiled planet directory whole: index.json's parameters, every tile's albedo
 * and heights pasted into the six faces (no coordinate map). Missing or mis-sized tile
 * files are refused, naming them, before the planet is allocated. pg_planet_load
 * calls it for a directory that pg_planet_dir_is_tiled. */
pg_status pg_planet_load_tiles(const char *dir, pg_planet *p, pg_error *err);

/* Read every tile file in dir of the allocated planet p's grid into its faces (for a
 * process that holds only its own tiles, once all are written). */
pg_status pg_planet_load_tile_files(const char *dir, pg_planet *p, pg_error *err);

/* Check a tiled planet directory without loading it: index.json parses and every tile
 * file exists with the size it claims (headers only). The grid goes to *tiles and
 * *tile_size. BADINPUT names the first file missing or wrong. */
pg_status pg_planet_tiles_check(const char *dir, int *tiles, int *tile_size, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
