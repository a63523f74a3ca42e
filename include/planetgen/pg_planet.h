/* pg_planet.h - a synthesized planet in memory and on disk.
 *
 * In memory: six N x N faces (N = tiles * tile_size) in the cube-sphere frames of
 * pg_cube.h (row y = 0 is the face's -v edge), albedo as RGB floats 0..1 (sRGB
 * encoded) and heights in metres. Everything that generate, pits, export and
 * inspect share goes through this one type.
 *
 * On disk, a planet directory holds:
 *   planet.json         metadata: format version, radius, flattening, projection,
 *                       tiles, tile_size, seed, sea_level_m, exemplar, faces
 *   albedo_+X.png ...   per-face albedo, 8-bit sRGB, N x N; PNG row 0 is the
 *                       face's +v edge (north up on the equatorial faces)
 *   height.exr          float32 heights in metres, one part per face, parts named
 *                       "+X", "-X", "+Y", "-Y", "+Z", "-Z", same orientation as PNGs
 *   source.exr          optional: the synthesis coordinate map (pg_planet_source), one
 *                       part per face, channels face, u, v (exemplar-cube texel) as
 *                       32-bit unsigned integers, same orientation as PNGs
 * Files are written under temporary names and renamed by the caller (the CLI's
 * pg_cli_output_path), so a directory is either complete or absent. */
#ifndef PLANETGEN_PG_PLANET_H
#define PLANETGEN_PG_PLANET_H

#include "planetgen/pg_cube.h"
#include "planetgen/pg_drainage.h"
#include "planetgen/pg_exemplar.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PG_PLANET_FORMAT_VERSION 1

/* Where each texel came from (docs/inspect.md, "Copy detection"): the exemplar-cube
 * texel that synthesis copied into it. The exemplar cube has face_size texels per
 * face edge, the given projection and the planet's own face frames (pg_cube.h); its
 * texel (face, u, v) has its centre at grid coordinates ((2u+1)/E - 1, (2v+1)/E - 1).
 * coords[f] is NULL when the planet has no map (made by pg_planet_from_exemplar, or
 * by an older planetgen): the measures that need it then report NaN. */
typedef struct pg_planet_source {
    int face_size;                    /* E, exemplar texels per face edge (0: no map) */
    pg_cube_projection projection;    /* of the exemplar cube */
    uint32_t *coords[PG_CUBE_NFACES]; /* n*n, pg_synth_pack(face, u, v), orientation 0 */
} pg_planet_source;

/* How the planet was made, as planet.json's "generation" records it (docs/generate.md,
 * "Outputs"): the layout, and for layout world the macro world's parameters. An empty
 * layout (as pg_planet_alloc leaves it) writes no record. */
typedef struct pg_planet_generation {
    char layout[16]; /* "world", "earth" or "free" */
    int plates;      /* layout world: the others leave 0 and the figures below unset */
    double land_fraction, axial_tilt_deg, temperature_offset_K;
    bool sea_ice; /* layout world: the polar oceans carry sea ice (docs/generate.md) */
    double jitter;
    int passes;
    double grid_shape; /* the correction's grid-shape weight at the cube's corners */
} pg_planet_generation;

typedef struct pg_planet {
    int tiles, tile_size;
    int64_t n; /* texels per face edge: tiles * tile_size */
    pg_cube_projection projection;
    pg_ellipsoid ellipsoid;
    uint64_t seed;
    float sea_level; /* metres */
    char exemplar[512];
    float *albedo[PG_CUBE_NFACES]; /* n*n*3 */
    float *height[PG_CUBE_NFACES]; /* n*n */
    pg_planet_source source;       /* optional coordinate map (above); freed with the planet */
    /* Share of land area (above sea_level) that drained into closed basins, not the sea,
     * before the final pit pass (pg_drainage_closed_land_share); NaN when unknown. */
    double closed_land_share_before_final;
    pg_planet_generation generation;
    /* Nonzero when the faces were reserved by pg_planet_alloc_rows: the byte length of
     * each face's albedo [f][0] and height [f][1] mapping, unmapped by pg_planet_free. */
    size_t reserved_bytes[PG_CUBE_NFACES][2];
} pg_planet;

/* Allocate the faces (zeroed) and set the geometry. */
pg_status pg_planet_alloc(pg_planet *p, pg_cube_projection proj, int tiles, int tile_size,
                          pg_ellipsoid ell, pg_error *err);
void pg_planet_free(pg_planet *p);

/* As pg_planet_alloc, but only rows [y0[f], y1[f]) of face f are usable (zeroed); the
 * rest of each face is reserved address space, never committed, that faults when
 * touched. For an MPI rank that writes and reads only its own tiles (docs/mpi.md,
 * "Memory per rank"). pg_planet_free frees it as usual. */
pg_status pg_planet_alloc_rows(pg_planet *p, pg_cube_projection proj, int tiles, int tile_size,
                               pg_ellipsoid ell, const int64_t y0[PG_CUBE_NFACES],
                               const int64_t y1[PG_CUBE_NFACES], pg_error *err);

/* Make every row of a planet from pg_planet_alloc_rows usable (the rows not yet
 * written read as zero); nothing to do for any other planet. */
pg_status pg_planet_open_all_rows(pg_planet *p, pg_error *err);

/* ---- the coordinate map (pg_planet_source.c) ---- */

/* Allocate an empty map (every coordinate 0) for an exemplar cube of E texels per face
 * edge; any previous map is freed. */
pg_status pg_planet_source_alloc(pg_planet *p, int face_size, pg_cube_projection proj,
                                 pg_error *err);
void pg_planet_source_free(pg_planet *p);
/* Does the planet carry a coordinate map? */
bool pg_planet_has_source(const pg_planet *p);
/* Unit direction of the centre of the exemplar texel that texel (face, x, y) of the
 * planet came from. The map must be present. */
void pg_planet_source_dir(const pg_planet *p, int face, int64_t x, int64_t y, double dir[3]);
/* The identity map of an exemplar cube of E texels per face edge: every texel points
 * at the exemplar texel whose centre is nearest its own direction - what a copy of
 * the exemplar (pg_planet_from_exemplar) has. */
pg_status pg_planet_source_identity(pg_planet *p, int face_size, pg_cube_projection proj,
                                    pg_error *err);

/* Bytes the faces of a planet of this size take in memory. */
double pg_planet_bytes(int tiles, int tile_size);

/* Fill a planet by reprojecting the exemplar (bilinear, `samples`^2 taps per
 * texel): the planet Earth itself, at this resolution. A reference for synthesis
 * and a fixture for export and inspection. */
pg_status pg_planet_from_exemplar(pg_planet *p, const pg_exemplar *ex, int samples, pg_error *err);

/* The file names of a planet directory. */
void pg_planet_albedo_name(int face, char *buf, size_t size); /* "albedo_+X.png" */
#define PG_PLANET_HEIGHT_NAME "height.exr"
#define PG_PLANET_META_NAME "planet.json"

/* Write each file to the path `path_for(name, user)` returns (the CLI stages
 * temporary names there); NULL from path_for is an out-of-memory error. */
typedef const char *(*pg_planet_path_fn)(const char *name, void *user);
pg_status pg_planet_save(const pg_planet *p, pg_planet_path_fn path_for, void *user, pg_error *err);

/* The albedo faces as pg_planet_save_encoded wrote them: each face's PNG bytes, the
 * same bytes as its file (8-bit RGB, image rows top-down), so that an exporter embeds
 * them instead of encoding them again (pg_export_opts.albedo_png). Owned by the
 * caller: pg_planet_encoded_free frees the bytes and zeroes the struct. */
typedef struct pg_planet_encoded {
    uint8_t *albedo_png[PG_CUBE_NFACES];
    size_t albedo_png_size[PG_CUBE_NFACES];
} pg_planet_encoded;
void pg_planet_encoded_free(pg_planet_encoded *e);

/* pg_planet_save, keeping the albedo faces' PNG bytes in *keep (zeroed first; on
 * failure nothing is kept). */
pg_status pg_planet_save_encoded(const pg_planet *p, pg_planet_path_fn path_for, void *user,
                                 pg_planet_encoded *keep, pg_error *err);

/* planet.json's parameters as a JSON object (NULL when out of memory; caller frees),
 * and writing a JSON object to path_for(name) (frees j; NULL j is out of memory). */
struct pg_json;
struct pg_json *pg_planet_meta_json(const pg_planet *p);
pg_status pg_planet_write_json(struct pg_json *j, const char *name, pg_planet_path_fn path_for,
                               void *user, pg_error *err);

/* A pg_planet_path_fn (also usable with pg_export_write) that names files straight
 * inside d->dir, no temporary names: pass a pg_planet_dir_paths as `user`. */
typedef struct pg_planet_dir_paths {
    const char *dir;
    char buf[4096];
} pg_planet_dir_paths;
const char *pg_planet_dir_path(const char *name, void *user);

/* Save straight into an existing directory, file by file (no temporary names): for
 * tools and tests that build a planet directory. The CLI stages through
 * pg_planet_save instead, so that a failed run leaves nothing. */
pg_status pg_planet_save_dir(const pg_planet *p, const char *dir, pg_error *err);

/* The planet's terrain as the drainage measures read it (pg_drainage.h): its heights
 * (borrowed), face size, projection, ellipsoid and sea level. */
pg_drainage_terrain pg_planet_drainage_terrain(const pg_planet *p);

/* Load a planet directory written by pg_planet_save, or a tiled one written by
 * pg_planet_save_tiles and pg_planet_save_index (pg_planet_tiles.h: index.json and no
 * planet.json). Missing files are named in the error; a directory with neither JSON
 * file is "not a planet output". */
pg_status pg_planet_load(const char *dir, pg_planet *p, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
