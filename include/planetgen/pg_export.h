/* pg_export.h - export a planet for other programs: a glTF 2.0 globe, float heights
 * in OpenEXR, and preview images.
 *
 * Files written (names relative to the output directory; each goes through the
 * caller's path_for, so the CLI stages them under temporary names and renames them
 * when everything succeeded):
 *   planet.glb           the globe: one mesh, six primitives (one per cube face),
 *                        each with its own material (baseColorTexture = albedo,
 *                        normalTexture = normals from the height field) and a
 *                        16-bit height PNG referenced from the material's extras
 *                        {"heightTexture": image index, "heightScale": m,
 *                        "heightOffset": m}: metres = heightOffset + heightScale *
 *                        sample / 65535. Scene extras carry the planet parameters.
 *   planet_albedo_px.png ... with external textures: the images as separate files
 *                        (px nx py ny pz nz = +X -X +Y -Y +Z -Z)
 *   height.exr           float32 heights in metres, one part per face ("+X" ...)
 *   albedo.png, relief.png          equirectangular previews (relief: shaded)
 *   globe_north.png, globe_south.png, globe_lon000.png, globe_lon180.png
 *                        orthographic renders from above the poles and above the
 *                        equator at longitudes 0 and 180
 *   height.tif, albedo.tif   with o->geotiff: the planet as GIS rasters, written by
 *                        GDAL (pg_raster.h): equirectangular, 4N x 2N pixels (N the
 *                        face's texels), resampled from the cube by
 *                        pg_cube_faces_to_equirect; heights float32 metres with a
 *                        NoData tag, albedo 8-bit sRGB RGB. The CRS is EPSG:4326 for
 *                        a WGS84 planet, else latitude/longitude on the planet's own
 *                        sphere or ellipsoid; extent -180..180, -90..90.
 *   height_R_C.tif, albedo_R_C.tif, height.vrt, albedo.vrt
 *                        with o->geotiff_tiled instead: the same rasters cut into
 *                        4T x 2T tiles of S x S pixels (row R from the north, column
 *                        C from -180 degrees; T tiles of S texels per face edge),
 *                        each a GeoTIFF, and a GDAL VRT mosaic of each set
 *
 * THE MESH. Each face is a grid of M x M quads (--mesh-res M, a multiple of the
 * tiles per face edge T that divides the face's N = T*S texels, so quads cover whole
 * texels and whole tiles). Vertices lie on the cube-sphere projection's directions on
 * the planet's ellipsoid, raised along the ellipsoid normal by
 * max(height, sea level) * exaggeration: the globe shows the water surface, while
 * the height texture and the EXR keep the sea floor. Positions are ECEF metres
 * (+Z north); the node's rotation turns them to glTF's +Y up. Seam vertices are
 * computed once, from a canonical face, so neighbouring faces share bit-identical
 * positions and normals: the globe is watertight. */
#ifndef PLANETGEN_PG_EXPORT_H
#define PLANETGEN_PG_EXPORT_H

#include "planetgen/pg_planet.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Relief exaggeration by default: Earth's highest land (8.8 km) becomes 88 km, 1.4%
 * of the radius, which a globe viewed whole shows as visible relief; at 1x the
 * relief is 0.14% of the radius, thinner than a pixel. */
#define PG_EXPORT_DEFAULT_EXAGGERATION 10.0
/* Upper bound of the exaggeration option; the relief must also stay below a
 * quarter of the radius (see pg_export_check_planet). */
#define PG_EXPORT_MAX_EXAGGERATION 1000.0
/* The default mesh aims at about this many triangles. */
#define PG_EXPORT_TARGET_TRIANGLES 200000
/* Upper bound on triangles: 2^27 (134 million) keeps the .glb under its 4 GiB limit. */
#define PG_EXPORT_MAX_TRIANGLES (INT64_C(1) << 27)

#define PG_EXPORT_GLB_NAME "planet.glb"
#define PG_EXPORT_ALBEDO_PREVIEW "albedo.png"
#define PG_EXPORT_RELIEF_PREVIEW "relief.png"
#define PG_EXPORT_GEOTIFF_HEIGHT "height"
#define PG_EXPORT_GEOTIFF_ALBEDO "albedo"
/* The NoData value of the height GeoTIFFs (no height is ever this; the tag is written
 * so that no tool takes 0 for NoData). */
#define PG_EXPORT_GEOTIFF_NODATA (-3.4028234663852886e38)

typedef enum pg_export_texture_format {
    PG_EXPORT_TEXTURE_PNG,
    PG_EXPORT_TEXTURE_JPEG
} pg_export_texture_format;

typedef struct pg_export_opts {
    int mesh_res;        /* quads per face edge; 0 = pg_export_default_mesh_res */
    double exaggeration; /* relief factor >= 0 */
    pg_export_texture_format texture_format; /* of the albedo textures */
    int jpeg_quality;                        /* 1..100 */
    bool external_textures;                  /* textures as separate files */
    bool glb, exr, previews;                 /* which outputs to write */
    bool geotiff;                            /* the GIS rasters (off by default) */
    bool geotiff_tiled;                      /* ... as tiles plus VRT mosaics */
    int preview_width;                       /* equirect width; 0: 4 face widths, at most 2048 */
    int globe_size;                          /* orthographic render size in pixels */
    /* Optional, borrowed: the albedo faces already encoded (pg_planet_save_encoded), which
     * planet.glb embeds as they are when its albedo textures are PNG, instead of encoding
     * the same pixels again. NULL: encode them. */
    const pg_planet_encoded *albedo_png;
} pg_export_opts;

/* Defaults: PNG textures embedded, default mesh and exaggeration, all outputs. */
void pg_export_opts_default(pg_export_opts *o);

/* The default mesh resolution: the largest M = T*m (m a power of two dividing S)
 * with 12 M^2 <= PG_EXPORT_TARGET_TRIANGLES * 1.5, at least T. For T = 4, S = 256:
 * M = 128, 196608 triangles. */
int pg_export_default_mesh_res(int tiles, int tile_size);

/* "png" or "jpeg"/"jpg"; BADINPUT naming `option` otherwise. */
pg_status pg_export_texture_format_parse(const char *name, const char *option,
                                         pg_export_texture_format *out, pg_error *err);

/* Check the options against a planet's grid (T tiles of S texels per face edge),
 * before anything is loaded or written: mesh resolution fits, exaggeration in
 * range, JPEG quality, sizes. BADINPUT messages name the option. */
pg_status pg_export_check_opts(const pg_export_opts *o, int tiles, int tile_size, pg_error *err);

/* Checks that need the heights: the exaggerated relief must stay below a quarter of
 * the radius, or the globe would fold through itself. */
pg_status pg_export_check_planet(const pg_export_opts *o, const pg_planet *p, pg_error *err);

typedef struct pg_export_result {
    int mesh_res;
    double exaggeration;
    int64_t vertices, triangles; /* in the .glb (per-face vertices counted per face) */
    double glb_bytes;            /* size of planet.glb as written (0 if not written) */
    double height_min, height_max;
    int nfiles; /* files handed to path_for */
} pg_export_result;

/* Write the outputs `o` selects for planet p. Names go through path_for (see
 * pg_planet.h); the caller commits (renames) them. res may be NULL. */
pg_status pg_export_write(const pg_planet *p, const pg_export_opts *o, pg_planet_path_fn path_for,
                          void *user, pg_export_result *res, pg_error *err);

/* ---- a tiled planet's glTF files (docs/export.md, "Tiled planets") ----
 * One .glb per tile, planet_F_TX_TY.glb (pg_planet_tile_glb_name): one mesh with one
 * primitive, the tile's part of the globe's mesh (--mesh-res M gives M/T quads per tile
 * edge; the tiles together are exactly the globe's vertices), its albedo, normal map and
 * 16-bit heights as in planet.glb, with the tile's own heightOffset and heightScale. A
 * tile's file depends only on the planet's texels around it: seam vertices are
 * bit-identical in the two files that hold them, whichever process wrote each. */

/* Write the .glb of tiles [first, last) of p, which holds those tiles' texels. The
 * texels around them that p does not hold (its other tiles, in a distributed run) are
 * read from dir's committed height_F_TX_TY.exr files, a strip at a time; dir may be
 * NULL when p holds every tile. Memory: one tile's images and mesh, its ring of
 * (M/N + 2) texels, and one neighbour tile's heights while its strip is cut. */
pg_status pg_export_tiles_glb(const pg_planet *p, int first, int last, const char *dir,
                              const pg_export_opts *o, pg_planet_path_fn path_for, void *user,
                              pg_export_result *res, pg_error *err);

/* ---- the browser viewer (docs/export.md, "The browser viewer") ----
 * A page that shows a planet's .glb as a globe with three.js: index.html, viewer.js,
 * three.js under three/ (with its LICENSE), and viewer.json {"glb": URL} naming the
 * .glb, relative to the viewer directory. Everything is compiled into the library;
 * the page loads nothing from the network, but browsers load its ES modules only over
 * HTTP, not from file://. */
#define PG_EXPORT_VIEWER_DIR "viewer"
#define PG_EXPORT_VIEWER_PAGE "index.html"

/* Was three.js compiled in (npm at build time)? Without it the page cannot run. */
bool pg_export_viewer_available(void);

/* Write the viewer's files through path_for. Names contain "/" for subdirectories
 * (three/build/three.module.js): path_for must create the directories. PG_ERR_IO when
 * this build lacks three.js (pg_export_viewer_available). */
pg_status pg_export_viewer_write(const char *glb_url, pg_planet_path_fn path_for, void *user,
                                 pg_error *err);

/* The same for a tiled planet's .glb set (pg_export_tiles_glb): viewer.json lists the n
 * URLs under "tiles", and the page loads them all into one globe. */
pg_status pg_export_viewer_write_tiles(const char *const *urls, int n, pg_planet_path_fn path_for,
                                       void *user, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
