/* pg_export_internal.h - the pieces of the export module, shared between its files
 * and its tests: the globe mesh, the normal maps, the previews. */
#ifndef PG_EXPORT_INTERNAL_H
#define PG_EXPORT_INTERNAL_H

#include "planetgen/pg_export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Where the mesh and the normal maps read heights: the planet's faces for the tiles
 * [first, last) it holds (all of them for a whole planet), and for a tile's glTF file
 * (pg_export_tiles.c) strips of the other tiles' texels around it, read from their
 * files. Any texel asked for outside both is NaN, which the tile writer refuses. */
typedef struct pg_export_strip {
    int64_t tile;         /* global tile id f T^2 + ty T + tx */
    int64_t x0, y0, w, h; /* face texels [x0, x0 + w) x [y0, y0 + h) */
    float *data;          /* w x h heights, row-major */
} pg_export_strip;

typedef struct pg_export_heights {
    const pg_planet *p;
    int64_t first, last; /* tiles of p in memory */
    int nstrips;
    pg_export_strip *strips;
} pg_export_heights;

/* The whole planet in memory. */
void pg_export_heights_whole(const pg_planet *p, pg_export_heights *h);
/* Height of texel (x, y) of face (inside the face), or NaN when not held. */
double pg_export_height_at(const pg_export_heights *h, int face, int64_t x, int64_t y);

/* The globe's vertices by canonical slot (see pg_export_mesh): positions, normals and
 * max(height, sea level), for every slot of the globe (dense, indexed by slot) or for
 * the slots a tile needs (hashed). */
typedef struct pg_export_verts {
    int m;                  /* quads per face edge */
    uint32_t nv;            /* (m + 1)^2 slots per face */
    const uint32_t *canon;  /* dense: the mesh's canonical table; NULL: hashed */
    int64_t *keys;          /* hashed: open addressing, -1 = empty */
    uint32_t *index;        /* hashed: keys[k]'s row */
    size_t cap, n;          /* hash capacity (power of two), rows used */
    double *pos, *nrm, *vh; /* per row: 3, 3, 1 */
} pg_export_verts;

/* Row of vertex (i, j) of face f, or -1 when the store does not hold it. */
int64_t pg_export_verts_find(const pg_export_verts *v, int f, int i, int j);

/* The subdivided-cube globe, or one tile of it. Vertex (i, j) of face f, 0 <= i, j <= m,
 * sits at grid coordinates u = 2i/m - 1, v = 2j/m - 1 and is stored at j*(m+1) + i.
 * Every vertex has a canonical slot: the lowest face id holding the same cube point
 * (vertices on seams belong to 2 faces, cube corners to 3), slot f*(m+1)^2 + j*(m+1) + i
 * of that face. Positions, heights and normals are functions of the canonical slot and
 * the texels around it alone, computed by the same code for the globe and for a tile, so
 * seams between faces and between tiles are bit-identical. A tile's primitive holds the
 * vertices i0..i0+mt, j0..j0+mt of its face, stored at (j - j0)*(mt+1) + (i - i0). */
typedef struct pg_export_mesh {
    int m;                /* quads per face edge */
    int nprims;           /* 6: the globe, a primitive per face; 1: a tile */
    int face, i0, j0, mt; /* the tile (globe: face 0, 0, 0, m) */
    uint32_t nv, ni;      /* vertices and indices per primitive */
    uint32_t *canon;      /* globe only: 6*nv, canonical slot of every vertex */
    pg_export_verts verts;
    float *pos[PG_CUBE_NFACES], *nrm[PG_CUBE_NFACES], *tan[PG_CUBE_NFACES];
    float *uv;     /* nv x 2, shared by the primitives: V = 0 at the +v edge */
    uint32_t *idx; /* ni, shared: two counter-clockwise triangles per quad */
} pg_export_mesh;

/* Canonical slot of vertex (i, j) of face f on an m-quad face grid. */
void pg_export_mesh_canonical(int m, int face, int i, int j, int *cface, int *ci, int *cj);

pg_status pg_export_mesh_build(const pg_planet *p, const pg_cube_grid *g, int m,
                               double exaggeration, pg_export_mesh *mesh, pg_error *err);

/* The mesh of tile t (face-major id) alone, heights from h: the same vertices, normals
 * and tangents, bit for bit, as the globe's mesh there. Needs h to hold the tile and
 * the texels within m/n + 2 texels of it (pg_export_tile_ring). */
pg_status pg_export_mesh_build_tile(const pg_export_heights *h, const pg_cube_grid *g, int m,
                                    double exaggeration, int64_t t, pg_export_mesh *mesh,
                                    pg_error *err);
void pg_export_mesh_free(pg_export_mesh *mesh);

/* Tangent-space normal map of the texels [x0, x0 + w)^2 of a face (w x w x 3, 0..1,
 * rows bottom-up): the normals of the full-resolution surface relative to the mesh's
 * coarse surface (the height minus its bilinear interpolation between mesh vertices),
 * x along +u, y along +v, so the texture adds exactly the detail the mesh lacks. The
 * globe passes the whole face, a tile its own texels; the values do not depend on the
 * window. */
pg_status pg_export_normal_map(const pg_export_heights *h, const pg_cube_grid *g,
                               const pg_export_mesh *mesh, double exaggeration, int face,
                               int64_t x0, int64_t y0, int64_t w, float *rgb, pg_error *err);

/* The .glb of tile t (face-major id) through path_for (pg_planet_tile_glb_name): its
 * mesh (pg_export_mesh_build_tile), albedo, normal map and 16-bit heights with the
 * tile's own height range in the material extras, the planet's parameters and the
 * tile's place in the scene extras. res (may be NULL) accumulates. */
pg_status pg_export_tile_glb_write(const pg_export_heights *h, const pg_cube_grid *g,
                                   const pg_export_opts *o, int64_t t, pg_planet_path_fn path_for,
                                   void *user, pg_export_result *res, pg_error *err);

/* Equirectangular previews and orthographic globe renders. */
pg_status pg_export_previews(const pg_planet *p, const pg_export_opts *o,
                             pg_planet_path_fn path_for, void *user, int *nfiles, pg_error *err);

/* The GIS rasters (pg_export_geotiff.c): height.tif and albedo.tif, or with
 * o->geotiff_tiled one pair per tile plus height.vrt and albedo.vrt. */
pg_status pg_export_geotiff(const pg_planet *p, const pg_export_opts *o, pg_planet_path_fn path_for,
                            void *user, int *nfiles, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
