/* pg_cube.h - the cube sphere: faces and their frames, three face projections, the
 * tile grid, the adjacency map across seams, halo gather, and resampling between
 * equirectangular images and cube faces.
 *
 * The idea (after EarthGen's six 8x8 tile grids with an adjacency map, made exact):
 * a planet is 6 faces, each a T x T grid of tiles, each tile S x S texels. Every face
 * carries the same N x N texel grid (N = T*S) in its own (u, v) frame, and every
 * projection warps u and v by the same rule on every face, so texel rows meet
 * texel rows at every seam. Crossing a seam is therefore an exact integer map: a
 * rotation by a multiple of 90 degrees plus an offset (the cube "unfolded" about
 * the shared edge). Everything here is derived from the face frames below; nothing
 * is hand-tabulated.
 *
 * FACES AND FRAMES. +Z is the planet's north pole. A face is the set of directions
 * whose largest |component| is along its normal n. Its frame (n, e_u, e_v) is
 * right-handed (e_u x e_v = n), so seen from outside the planet u points right and
 * v points up:
 *
 *     face  id  normal n   e_u (u grows)  e_v (v grows)
 *     +X    0   (+1,0,0)   (0,+1,0) east  (0,0,+1) north
 *     -X    1   (-1,0,0)   (0,-1,0) east  (0,0,+1) north
 *     +Y    2   (0,+1,0)   (-1,0,0) east  (0,0,+1) north
 *     -Y    3   (0,-1,0)   (+1,0,0) east  (0,0,+1) north
 *     +Z    4   (0,0,+1)   (+1,0,0)       (0,+1,0)      (north pole at centre)
 *     -Z    5   (0,0,-1)   (+1,0,0)       (0,-1,0)      (south pole at centre)
 *
 * On the four equatorial faces u runs west to east and v south to north; +X is
 * centred on longitude 0, +Y on 90E, -X on 180, -Y on 90W.
 *
 * GRID COORDINATES. (u, v) in [-1, 1]^2 are grid coordinates: texels are uniform in
 * them. Texel (x, y) of a face, 0 <= x, y < N, has its centre at
 * u = (2x + 1)/N - 1, v = (2y + 1)/N - 1; x grows with u, y grows with v. In memory a
 * face is row-major with row y = 0 first (the southern/-v edge). The global texel id
 * is face*N*N + y*N + x; a tile id is face*T*T + ty*T + tx and the tile covers face
 * texels [tx*S, tx*S + S) x [ty*S, ty*S + S).
 *
 * PROJECTIONS map grid coordinates to a unit direction: the cube-plane point is
 * n + A(u) e_u + A(v) e_v, normalised (gnomonic: A(u) = u; equi-angular:
 * A(u) = tan(pi u / 4)); the equal-area map (Rosca & Plonka 2011, see
 * cubesphere/pg_cube_equal_area_rosca_plonka.c) is not separable but has the
 * cube's symmetry. */
#ifndef PLANETGEN_PG_CUBE_H
#define PLANETGEN_PG_CUBE_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_geo.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

enum {
    PG_CUBE_FACE_PX,
    PG_CUBE_FACE_NX,
    PG_CUBE_FACE_PY,
    PG_CUBE_FACE_NY,
    PG_CUBE_FACE_PZ,
    PG_CUBE_FACE_NZ,
    PG_CUBE_NFACES
};

typedef enum pg_cube_projection {
    PG_CUBE_GNOMONIC,
    PG_CUBE_EQUIANGULAR, /* the default */
    PG_CUBE_EQUALAREA
} pg_cube_projection;

#define PG_CUBE_DEFAULT_PROJECTION PG_CUBE_EQUIANGULAR

/* "+X", "-X", ... */
const char *pg_cube_face_name(int face);
/* The face frame: normal, e_u, e_v as integer unit vectors. */
void pg_cube_face_frame(int face, int n[3], int eu[3], int ev[3]);

/* "gnomonic", "equi-angular", "equal-area". */
const char *pg_cube_projection_name(pg_cube_projection p);
/* Parse a projection name; BADINPUT naming `option` if unknown. */
pg_status pg_cube_projection_parse(const char *name, const char *option, pg_cube_projection *out,
                                   pg_error *err);

/* Forward: grid coordinates (u, v) in [-1,1]^2 of `face` -> unit direction. */
void pg_cube_to_dir(pg_cube_projection p, int face, double u, double v, double dir[3]);
/* Inverse: any nonzero direction -> face and grid coordinates in [-1,1]^2. Ties
 * between faces (edges, vertices) go to the lowest face id. */
void pg_cube_from_dir(pg_cube_projection p, const double dir[3], int *face, double *u, double *v);

/* The texel of an n x n face grid whose square holds a direction: the global id
 * (face n + y) n + x of x = floor((u + 1) n / 2), y likewise, from pg_cube_from_dir's
 * (u, v), clamped to the face. For the gnomonic and equi-angular projections the finder
 * tabulates the cells' edges in u's tangent coordinate l_u / l_n (a line on the face),
 * so a direction is placed by comparisons instead of two atan2; within 1e-9 of an edge
 * it takes pg_cube_from_dir's route, so the texel is always the same. The equal-area
 * projection always takes that route. */
typedef struct pg_cube_texel_finder {
    pg_cube_projection proj;
    int64_t n;
    double *edge;   /* n + 1 edges in the tangent coordinate; NULL: pg_cube_from_dir */
    int64_t *start; /* 2n buckets over [-1, 1]: the cell of each one's lower end */
} pg_cube_texel_finder;
pg_status pg_cube_texel_finder_init(pg_cube_texel_finder *f, pg_cube_projection p, int64_t n,
                                    pg_error *err);
void pg_cube_texel_finder_free(pg_cube_texel_finder *f);
int64_t pg_cube_texel_find(const pg_cube_texel_finder *f, const double dir[3]);

/* ---- tile grid ---- */

typedef struct pg_cube_xform {
    int rot;        /* quarter turns counter-clockwise, 0..3 */
    int64_t ox, oy; /* offset */
} pg_cube_xform;
/* p' = R^rot p + o, with R(x, y) = (-y, x). */
void pg_cube_xform_apply(pg_cube_xform t, int64_t x, int64_t y, int64_t *xo, int64_t *yo);
pg_cube_xform pg_cube_xform_inverse(pg_cube_xform t);
/* (a o b)(p) = a(b(p)). */
pg_cube_xform pg_cube_xform_compose(pg_cube_xform a, pg_cube_xform b);

typedef struct pg_cube_grid {
    pg_cube_projection proj;
    int tiles;      /* T >= 1 tiles per face edge */
    int tile_size;  /* S, a power of two */
    int64_t n;      /* N = T*S texels per face edge */
    int64_t ntiles; /* 6*T*T */
    /* edge[f][e]: maps texel coords of the face across edge e of face f into f's
     * extended frame; nbr_face[f][e] is that face. e indexes pg_cube_dir 0..3. */
    pg_cube_xform edge[PG_CUBE_NFACES][4];
    int nbr_face[PG_CUBE_NFACES][4];
} pg_cube_grid;

/* T >= 1, S a power of two in [1, 8192]; BADINPUT otherwise. (The CLI further
 * requires S in 16..8192.) */
pg_status pg_cube_grid_init(pg_cube_grid *g, pg_cube_projection p, int tiles, int tile_size,
                            pg_error *err);

/* The 8 neighbour directions: 4 edges, then 4 corners. */
typedef enum pg_cube_dir {
    PG_CUBE_XP, /* +x (east on equatorial faces) */
    PG_CUBE_YP, /* +y */
    PG_CUBE_XM,
    PG_CUBE_YM,
    PG_CUBE_XPYP,
    PG_CUBE_XMYP,
    PG_CUBE_XMYM,
    PG_CUBE_XPYM
} pg_cube_dir;
/* Offsets (dx, dy) of each direction. */
void pg_cube_dir_offset(pg_cube_dir d, int *dx, int *dy);

typedef struct pg_cube_neighbor {
    int64_t tile;     /* neighbour tile id, or -1: none (a corner at a cube vertex) */
    pg_cube_xform xf; /* neighbour-local texel coords -> this tile's local frame */
} pg_cube_neighbor;

/* All 8 neighbours of a tile. At the 8 cube vertices three faces meet, so the
 * corner neighbour of a tile touching a vertex does not exist (tile = -1). */
void pg_cube_tile_neighbors(const pg_cube_grid *g, int64_t tile, pg_cube_neighbor out[8]);

/* Wrap an extended face coordinate onto the cube: (X, Y) may lie up to N outside
 * [0, N)^2 of `face`. Returns the global texel id it stands for and the rotation
 * that takes vectors in the source face's frame into `face`'s frame. Beyond both
 * edges at once (past a cube vertex) the deeper axis is unfolded first (ties: x),
 * which splits the missing quadrant along its diagonal between the two faces that
 * meet there; see pg_cube_halo_gather. */
int64_t pg_cube_wrap(const pg_cube_grid *g, int face, int64_t x, int64_t y, int *rot);

/* Centre direction of a global texel, and of a texel corner (cx, cy in 0..N). */
void pg_cube_texel_dir(const pg_cube_grid *g, int64_t id, double dir[3]);
void pg_cube_corner_dir(const pg_cube_grid *g, int face, int64_t cx, int64_t cy, double dir[3]);

/* ---- halo gather ---- */

typedef enum pg_cube_vec_kind {
    PG_CUBE_VEC_NONE, /* plain payload: copied */
    PG_CUBE_VEC_F32,  /* two floats at vec_offset: a 2-D vector in the face frame */
    PG_CUBE_VEC_F64,
    PG_CUBE_VEC_I32 /* an integer offset, e.g. a texel displacement */
} pg_cube_vec_kind;

/* Custom rotation of one element by `quarter_turns` (1..3, counter-clockwise). */
typedef void (*pg_cube_rotate_fn)(void *elem, int quarter_turns, void *user);

typedef struct pg_cube_payload {
    size_t elem_size;         /* bytes per texel */
    pg_cube_vec_kind vec;     /* which part, if any, is a 2-D vector to rotate */
    size_t vec_offset;        /* byte offset of the vector inside the element */
    pg_cube_rotate_fn rotate; /* optional: called after copying (instead of vec) */
    void *user;
} pg_cube_payload;

/* Fill the padded buffer of tile `tile`: (S + 2w)^2 elements, row-major, the tile's
 * texel (x, y) at padded position (x + w, y + w), 1 <= w <= S. `field` is the global
 * field (6*N*N elements, global texel ids). The interior is copied too unless
 * `halo_only`. Edge and corner strips are copied from the neighbour tiles through
 * their integer transforms, with vectors rotated into this tile's frame.
 *
 * At a cube vertex (the missing corner neighbour) the w x w corner block is filled
 * by unfolding the two faces that meet there across their shared edge: texel
 * (S-1+i, S-1+j) past the vertex (depths i, j >= 1) takes the texel reached by
 * crossing the deeper edge first (ties: the x edge). So the block holds the seam
 * between the two edge neighbours, split along the diagonal; every halo texel is
 * still an actual texel of the planet, and the first ring stays geometrically
 * adjacent. The cost is a duplicate: texel (S, S) equals (S-1, S). */
pg_status pg_cube_halo_gather(const pg_cube_grid *g, int64_t tile, int w, const void *field,
                              const pg_cube_payload *pl, bool halo_only, void *padded,
                              pg_error *err);

/* Rotate a 2-D vector by quarter turns counter-clockwise (the rule applied to
 * vector payloads). */
void pg_cube_rotate_vec(double *x, double *y, int quarter_turns);

/* ---- resampling ----
 * Images are plain interleaved float buffers. An equirectangular image of width W
 * and height H has pixel (i, j) centred at longitude -180 + (i + 0.5)*360/W and
 * geodetic latitude 90 - (j + 0.5)*180/H (row 0 is north). A cube buffer holds
 * 6*n*n texels of `ch` floats, indexed by global texel id. `ell` gives the ellipsoid
 * on which latitudes are geodetic (NULL: a sphere); directions are geocentric rays.
 * Both run with OpenMP; results do not depend on the thread count. */

/* Equirect -> cube, bilinear with longitude wrap. Within half a pixel of a pole the
 * image is continued to the pole, whose value is the mean of the polar row, so the
 * field is single-valued and continuous there. `samples` >= 1: samples x samples
 * bilinear taps per texel, averaged (anti-aliasing when texels are larger than
 * pixels). */
pg_status pg_cube_from_equirect(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                const float *img, int w, int h, int ch, int samples, float *cube,
                                pg_error *err);

/* The same for the texel rows [row0, row1) of the cube only (row r is row r % n of face
 * r / n, at cube + r * n * ch); the rest of the buffer is not touched. A distributed
 * run fills the rows of its own tiles (docs/mpi.md, "Memory per rank"). */
pg_status pg_cube_from_equirect_rows(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                     const float *img, int w, int h, int ch, int samples,
                                     int64_t row0, int64_t row1, float *cube, pg_error *err);

/* Cube -> equirect, bilinear on the face grid, wrapping across seams. */
pg_status pg_cube_to_equirect(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                              const float *cube, int ch, float *img, int w, int h, pg_error *err);

/* The same from six separate face buffers (n*n texels of ch floats each), for the
 * region of rw x rh pixels at (x0, y0) of the w x h equirectangular grid (img holds
 * rw*rh*ch floats): the pixels have exactly the values of the whole-image call, so
 * an image cut into tiles is the whole image cut. */
pg_status pg_cube_faces_to_equirect(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                    const float *const faces[PG_CUBE_NFACES], int ch, int w, int h,
                                    int x0, int y0, int rw, int rh, float *img, pg_error *err);

/* Bilinear sample of a cube buffer at a direction (ch floats to out). */
void pg_cube_sample(pg_cube_projection p, int64_t n, const float *cube, int ch, const double dir[3],
                    float *out);
/* The same sample with the seam maps of g (pg_cube_grid_init with tiles * tile_size = n
 * texels per face edge) built once by the caller: pg_cube_sample builds them on every
 * call, which costs more than the sample in a loop over millions of directions. */
void pg_cube_sample_grid(const pg_cube_grid *g, const float *cube, int ch, const double dir[3],
                         float *out);
/* The same bilinear sample at a point given on a face of g's grid: fx, fy in texels
 * (texel x's centre is fx = x); taps past an edge come from across the seam. A field on
 * the same projection as the caller's own grid is sampled this way without a
 * direction: a texel of another face size maps to it linearly. */
void pg_cube_sample_face(const pg_cube_grid *g, const float *cube, int ch, int face, double fx,
                         double fy, float *out);
/* Where pg_cube_sample_grid samples a direction: its face and the point on it, in the
 * texels of pg_cube_sample_face. Locating once and sampling several fields there gives
 * the same values as sampling each at the direction, with one projection. */
void pg_cube_locate(const pg_cube_grid *g, const double dir[3], int *face, double *fx, double *fy);
/* A grid for pg_cube_sample_grid over a field of any n texels per face edge (one tile a
 * face; n need not be a power of two, as pg_cube_grid_init asks). */
void pg_cube_sample_grid_init(pg_cube_grid *g, pg_cube_projection p, int64_t n);

/* Solid angle (steradians) of the spherical triangle of unit vectors a, b, c (Van
 * Oosterom & Strackee 1983): texel areas on the unit sphere, two triangles a texel. */
double pg_cube_spherical_triangle(const double a[3], const double b[3], const double c[3]);

/* ---- distortion ---- */

typedef struct pg_cube_distortion {
    double area_min_m2, area_max_m2, area_ratio; /* texel areas on the ellipsoid */
    double max_angle_dev_deg;                    /* worst corner angle vs 90 degrees */
    double mean_texel_km;                        /* sqrt(total area / texel count) */
    double total_area_m2;                        /* sum over all texels */
} pg_cube_distortion;

/* Texel areas and corner angles of the N x N face grid on the ellipsoid, with
 * geodesic texel edges. Uses the cube's symmetry (see the .c file). */
pg_status pg_cube_distortion_compute(pg_cube_projection p, int64_t n, const pg_ellipsoid *ell,
                                     pg_cube_distortion *out, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
