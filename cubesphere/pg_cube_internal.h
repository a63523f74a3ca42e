/* pg_cube_internal.h - helpers shared by the cubesphere/ sources, not public API. */
#ifndef PG_CUBE_INTERNAL_H
#define PG_CUBE_INTERNAL_H

#include "planetgen/pg_cube.h"

/* Fill g's face edge tables for an N x N face grid as a single tile per face (no
 * validation): what resampling needs to wrap across seams for any n. */
void pg_cube_grid_init_faces(pg_cube_grid *g, pg_cube_projection p, int64_t n);

/* Equal-area map of Rosca & Plonka (2011) on one face, in the face's local frame
 * (x along e_u, y along e_v, z along the normal). */
void pg_cube_rp_forward(double a, double b, double local[3]);
void pg_cube_rp_inverse(const double local[3], double *a, double *b);

#endif
