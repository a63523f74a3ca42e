/* pg_plates_internal.h - what the plate files share: hashing, value noise, small vector
 * algebra, and the texel graph of the cube sphere (centre directions, areas, the 8
 * neighbours of every texel, nearest texel of a direction, multi-source shortest paths).
 *
 * pg_plates_grid is built once per world and read-only afterwards:
 *
 *     dir[3*t .. 3*t+2]   unit centre direction of texel t (global id (face*n + y)*n + x)
 *     area[t]             texel area in km^2 on the sphere of radius_km
 *     nbr[8*t + d]        neighbour of t in pg_cube_dir order d (4 edges, then 4 corners);
 *                         across seams through pg_cube_wrap, so at the 8 cube vertices a
 *                         corner neighbour may repeat an edge neighbour
 *     nlen[8*t + d]       great-circle distance in km from t to that neighbour
 *     texel_reach         the largest angle from a texel's centre to one of its corners:
 *                         a direction lies within it of the texel found for it, which
 *                         the gather's plate caps rely on (pg_plates_cortial2019.c)
 */
#ifndef PG_PLATES_INTERNAL_H
#define PG_PLATES_INTERNAL_H

#include "planetgen/pg_plates.h"
#include "pg_vec3.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#define PG_PLATES_PI 3.14159265358979323846

/* Hash streams: one per kind of random choice, so adding one never shifts another. */
enum {
    PG_PLATES_S_SEED = 1,
    PG_PLATES_S_WEIGHT,
    PG_PLATES_S_POLE,
    PG_PLATES_S_SPEED,
    PG_PLATES_S_CORE,
    PG_PLATES_S_CORE_SIZE,
    PG_PLATES_S_HOTSPOT,
    PG_PLATES_S_WARP,
    PG_PLATES_S_SHAPE,
    PG_PLATES_S_RELIEF,
    PG_PLATES_S_AGE,
    PG_PLATES_S_DETAIL,
    /* PG_PLATES_S_DETAIL uses streams DETAIL + 4 k, k < 3: later streams start past them */
    PG_PLATES_S_SHELF = PG_PLATES_S_DETAIL + 12
};

typedef struct pg_plates_grid {
    int64_t n, count;
    pg_cube_projection proj;
    double radius_km;
    double *dir;
    float *area;
    int64_t *nbr;
    float *nlen;
    pg_cube_texel_finder find; /* pg_plates_grid_nearest's tables */
    double texel_reach; /* largest angle from a texel's centre to one of its corners, radians */
} pg_plates_grid;

/* ---- hashing and noise (pg_plates_noise.c) ---- */
uint64_t pg_plates_hash(uint64_t seed, uint64_t stream, uint64_t index);
/* Uniform in [0, 1) from the hash. */
double pg_plates_unit(uint64_t seed, uint64_t stream, uint64_t index);
/* Uniform unit vector from the hash. */
void pg_plates_random_dir(uint64_t seed, uint64_t stream, uint64_t index, double out[3]);
/* Smooth value noise on 3-D space, about -1..1, features of size 1/freq; fBm of
 * `octaves` octaves (gain 0.5, lacunarity 2). */
double pg_plates_fbm(uint64_t seed, uint64_t stream, const double p[3], double freq, int octaves);

/* ---- vectors (pg_vec3.h) ---- */
/* Angle in radians between unit vectors. */
static inline double pg_plates_angle(const double a[3], const double b[3]) {
    double c[3];
    pg_vec3_cross(a, b, c);
    return atan2(sqrt(pg_vec3_dot(c, c)), pg_vec3_dot(a, b));
}
/* Rotate v by angle `ang` about the unit axis k (Rodrigues). */
void pg_plates_rotate(const double k[3], double ang, const double v[3], double out[3]);

/* ---- the texel graph (pg_plates_grid.c) ---- */
pg_status pg_plates_grid_init(pg_plates_grid *g, int64_t n, pg_cube_projection proj,
                              double radius_km, pg_error *err);
void pg_plates_grid_free(pg_plates_grid *g);
/* The texel whose cell contains direction d. */
int64_t pg_plates_grid_nearest(const pg_plates_grid *g, const double d[3]);
/* Multi-source Dijkstra over the 8-neighbour graph: dist[t] = 0 where src[t], else the
 * shortest path in km; when `plate` is not NULL a path stays on the plate of its source.
 * Unreached texels get INFINITY. Serial, in a fixed order: deterministic. */
pg_status pg_plates_grid_distance(const pg_plates_grid *g, const uint8_t *src, const uint8_t *plate,
                                  float *dist, pg_error *err);

/* A texel with a sort key; qsort order by key, then texel id (a total order, so sorts
 * are deterministic). */
typedef struct pg_plates_keyed {
    double key;
    int64_t id;
} pg_plates_keyed;
int pg_plates_keyed_cmp(const void *a, const void *b);

/* ---- stages ---- */
/* Grow plates from hashed seeds (pg_plates_seed.c): plate ids, Euler poles, initial
 * crust type and age. */
typedef struct pg_plates_state {
    uint8_t *plate; /* world plate id */
    uint8_t *crust; /* world crust type */
    float *age;     /* world crust age, Myr */
    float *relief;  /* world tectonic relief, m (uplift accumulated by the simulation) */
} pg_plates_state;

pg_status pg_plates_seed(const pg_plates_params *p, const pg_plates_grid *g, pg_plates_world *w,
                         pg_plates_state *s, pg_error *err);
/* Move the plates for p->steps steps (pg_plates_cortial2019.c). caps: the gather skips
 * plates by their caps (always, but for the test below: the result is the same). */
pg_status pg_plates_simulate(const pg_plates_params *p, const pg_plates_grid *g, pg_plates_world *w,
                             pg_plates_state *s, bool caps, pg_error *err);
/* TEST ONLY: pg_plates_generate with the gather's plate caps off, which must give the same
 * world byte for byte (tests/test_plates.c). */
pg_status pg_plates_generate_uncapped(const pg_plates_params *p, pg_plates_world *out,
                                      pg_error *err);
/* Compose the final elevation and set sea level (pg_plates_relief.c). */
pg_status pg_plates_relief(const pg_plates_params *p, const pg_plates_grid *g, pg_plates_world *w,
                           const pg_plates_state *s, pg_error *err);

/* Parsons & Sclater (1977) ocean depth in metres (positive) for crust age in Myr. */
double pg_plates_ocean_depth(double age_myr);

#endif
