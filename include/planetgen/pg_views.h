/* pg_views.h - square gnomonic views of a planet, for looking at it and for the
 * LPIPS-style pole check (pg_lpips.h, pg_inspect.h).
 *
 * A view is what a camera far above the surface sees through a gnomonic (rectilinear)
 * lens: pixel (i, j) of an N x N view (row 0 at the top) looks along
 *   c + x r + y u,  x = t((2i+1)/N - 1),  y = t(1 - (2j+1)/N),  t = tan(fov/2),
 * with c the view centre and (r, u) the right and up directions of its frame, seen
 * from outside (r x u = c). Six views are fixed: the north pole, the south pole and the
 * equator at longitudes 0, 90E, 180 and 90W. These are the six cube-face centres, so
 * the pole views and the equator views sit at equivalent places of the cube grid and
 * any difference between them is the planet's, not the grid's.
 *
 * Frames: north pole: up towards longitude 180 (0 at the bottom, as Arctic maps put
 * it); south pole: up towards longitude 0; equator: up north, right east.
 *
 * The same view can be rendered from any source through a sampler callback; samplers
 * for a cube buffer (a planet or an exemplar reprojected onto the cube) and for an
 * equirectangular image (the original exemplar) are provided. Every view pixel is a
 * Gaussian-weighted average of finer point samples, so fine sources do not alias and
 * sources of different resolution can be seen through one common filter. */
#ifndef PLANETGEN_PG_VIEWS_H
#define PLANETGEN_PG_VIEWS_H

#include "planetgen/pg_cube.h"
#include "planetgen/pg_image.h"
#include "planetgen/pg_view.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

#define PG_VIEWS_COUNT 6
#define PG_VIEWS_DEFAULT_SIZE 512
#define PG_VIEWS_DEFAULT_FOV_DEG 40.0 /* the field of view across a side */

enum { PG_VIEW_NORTH, PG_VIEW_SOUTH, PG_VIEW_EQ_0, PG_VIEW_EQ_90E, PG_VIEW_EQ_180, PG_VIEW_EQ_90W };

typedef struct pg_views_centre {
    const char *name; /* "north", "south", "equator_0", "equator_90e", ... */
    double lat_deg, lon_deg;
    bool pole;
} pg_views_centre;

const pg_views_centre *pg_views_centre_get(int view);

/* Unit centre c, right r and up u of a view (r x u = c). */
void pg_views_frame(int view, double c[3], double r[3], double u[3]);

/* A source: writes RGB (sRGB 0..1) and height in metres at a unit direction. */
typedef void (*pg_views_sampler)(void *user, const double dir[3], float rgbh[4]);

/* Render `view` at size x size with field fov_deg (0 < fov < 120). Every pixel is a
 * Gaussian-weighted average of point samples on a PG_VIEWS_SUPERSAMPLE times finer grid,
 * with standard deviation sigma_deg on the sphere (at least half a pixel, so the view
 * never aliases). BADINPUT for bad parameters. */
pg_status pg_views_render(int view, int size, double fov_deg, double sigma_deg, pg_views_sampler s,
                          void *user, pg_view *out, pg_error *err);

/* Point samples per pixel side before the Gaussian reduction. */
#define PG_VIEWS_SUPERSAMPLE 2

/* The common prefilter for comparing views of sources of different resolutions:
 * sigma = PG_VIEWS_PREFILTER_SPACINGS x the coarsest sample spacing among the view's
 * pixels, the planet's texels (90/n degrees at a face centre) and the exemplar's
 * pixels at the equator (360/W degrees). 0.5 spacing is the standard deviation of
 * bilinear reconstruction from that spacing (box * tent: variance 1/12 + 1/6 = 1/4),
 * so every source is seen at the detail all of them can hold, uniformly over the
 * sphere. Without it the equirectangular exemplar's polar rows, which hold east-west
 * detail down to a kilometre, would make an exact copy of the Earth look distorted at
 * the poles. */
#define PG_VIEWS_PREFILTER_SPACINGS 0.5
double pg_views_prefilter_deg(int size, double fov_deg, double planet_texel_deg,
                              double exemplar_pixel_deg);

/* Sampler over a cube buffer of 6*n*n texels of 4 floats (R, G, B, height), global
 * texel ids as in pg_cube.h; bilinear, the same values as pg_cube_sample (which it calls
 * near face edges, to wrap taps across the seams). */
typedef struct pg_views_cube_src {
    pg_cube_projection proj;
    int64_t n;
    const float *rgbh;
} pg_views_cube_src;
void pg_views_sample_cube(void *user, const double dir[3], float rgbh[4]);

/* Sampler over an equirectangular pair (row 0 north, column 0 at -180): rgb is
 * 3-channel, height 1-channel (may be NULL: height 0). Latitudes are geodetic on ell. */
typedef struct pg_views_equirect_src {
    const float *rgb, *height;
    int width, height_px;
    pg_ellipsoid ell;
} pg_views_equirect_src;
void pg_views_sample_equirect(void *user, const double dir[3], float rgbh[4]);

/* Place views side by side: `count` views of equal size into one RGB image of
 * count*size + (count-1)*gap by size pixels, gaps white. The caller frees out. */
pg_status pg_views_montage(const pg_view *const *views, int count, int gap, pg_image *out,
                           pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
