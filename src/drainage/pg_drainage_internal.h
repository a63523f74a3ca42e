/* pg_drainage_internal.h - cube geometry shared by the drainage sources: texel centres
 * in face-local coordinates and their points on the ellipsoid.
 *
 * pg_cube_to_dir computes the same face-local vector l = (l_u, l_v, l_n) for (u, v) on
 * every face and only then turns it into the face's frame. So one n x n table of l
 * gives every face's texel directions exactly: on +X the direction is (l_n, l_u, l_v),
 * on +Z it is (l_u, l_v, l_n), and the other faces are rotations of these about the
 * polar axis (-X, +Y, -Y) or the mirror (x, y, z) -> (x, -y, -z) (-Z), which map the
 * ellipsoid onto itself. */
#ifndef PLANETGEN_PG_DRAINAGE_INTERNAL_H
#define PLANETGEN_PG_DRAINAGE_INTERNAL_H

#include "planetgen/pg_drainage.h"

/* l for the centre of texel (x, y), at l + 3 * (y * n + x); n*n*3 doubles. */
void pg_drainage_local_centres(pg_cube_projection p, int64_t n, double *l);

/* The direction on +X (polar = 0) or +Z (polar = 1) of face-local l. */
void pg_drainage_local_to_dir(const double l[3], int polar, double d[3]);

/* Where the ray along unit d meets the ellipsoid with semi-axes a, a, b. */
void pg_drainage_surface_point(const double d[3], double a, double b, double p[3]);

#endif
