/* pg_export_internal.h - the pieces of the export module, shared between its files
 * and its tests: the globe mesh, the normal maps, the previews. */
#ifndef PG_EXPORT_INTERNAL_H
#define PG_EXPORT_INTERNAL_H

#include "planetgen/pg_export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The subdivided-cube globe. Vertex (i, j) of face f, 0 <= i, j <= m, sits at grid
 * coordinates u = 2i/m - 1, v = 2j/m - 1 and is stored at j*(m+1) + i. Every vertex
 * has a canonical slot: the lowest face id holding the same cube point (vertices on
 * seams belong to 2 faces, cube corners to 3). Positions, heights and normals are
 * computed once per canonical slot and copied, so seams are bit-identical. */
typedef struct pg_export_mesh {
    int m;           /* quads per face edge */
    uint32_t nv, ni; /* vertices and indices per face */
    uint32_t *canon; /* 6*nv: canonical slot f*nv + j*(m+1) + i of every vertex */
    double *vheight; /* 6*nv, canonical slots: max(height, sea level), metres */
    float *pos[PG_CUBE_NFACES], *nrm[PG_CUBE_NFACES], *tan[PG_CUBE_NFACES];
    float *uv;     /* nv x 2, shared by the faces: face texture, V = 0 at the +v edge */
    uint32_t *idx; /* ni, shared: two counter-clockwise triangles per quad */
} pg_export_mesh;

/* Canonical slot of vertex (i, j) of face f on an m-quad face grid. */
void pg_export_mesh_canonical(int m, int face, int i, int j, int *cface, int *ci, int *cj);

pg_status pg_export_mesh_build(const pg_planet *p, const pg_cube_grid *g, int m,
                               double exaggeration, pg_export_mesh *mesh, pg_error *err);
void pg_export_mesh_free(pg_export_mesh *mesh);

/* Tangent-space normal map of one face (n x n x 3, 0..1, face rows bottom-up): the
 * normals of the full-resolution surface relative to the mesh's coarse surface
 * (the height minus its bilinear interpolation between mesh vertices), x along +u,
 * y along +v, so the texture adds exactly the detail the mesh lacks. */
pg_status pg_export_normal_map(const pg_planet *p, const pg_cube_grid *g,
                               const pg_export_mesh *mesh, double exaggeration, int face,
                               float *rgb, pg_error *err);

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
