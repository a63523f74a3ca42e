/* pg_exemplar.h - the exemplar: a global albedo map and a global height map in
 * metres, equirectangular, on one common grid.
 *
 * The default exemplar comes from Debian's marble-qt-data: NASA Blue Marble
 * (2700x1350 RGB) and Marble's tiled global relief (8x16 grey JPEG tiles of
 * 675x675, 10800x5400). The relief is 8-bit grey, not metres; pg_exemplar_calibrate
 * derives a grey -> metres mapping from the Blue Marble water mask (see
 * data/README.md for the derivation and the limits of this data).
 *
 * Any other global equirectangular pair works: a height map with float or 16-bit
 * signed samples is taken as metres; an 8-bit or 16-bit unsigned one as a grey
 * ramp to calibrate, unless --height-scale/--height-offset are given.
 *
 * Row 0 is the north edge (+90 deg), column 0 the west edge (-180 deg). */
#ifndef PLANETGEN_PG_EXEMPLAR_H
#define PLANETGEN_PG_EXEMPLAR_H

#include "planetgen/pg_calibration.h"
#include "planetgen/pg_image.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pg_exemplar_opts {
    const char *albedo_path; /* NULL: Blue Marble */
    const char *height_path; /* NULL: the Marble relief tiles */
    const char *relief_dir;  /* NULL: Marble's relief tiles (for the tiled default) */
    double height_scale;     /* NaN: automatic (metres in = 1; grey = calibrated) */
    double height_offset;    /* NaN: automatic */
    double sea_level;        /* NaN: automatic (0 m after calibration / for metres) */
    uint64_t max_pixels;     /* per input image; 0 = PG_IMAGE_DEFAULT_MAX_PIXELS */
    int grid_width;          /* common grid width (2:1); 0 = the coarser input's width */
    bool repair_ocean;       /* pg_exemplar_repair_ocean after the load; default on */
} pg_exemplar_opts;

void pg_exemplar_opts_default(pg_exemplar_opts *o);

typedef struct pg_exemplar {
    int width, height; /* common grid, width == 2 * height */
    float *albedo;     /* RGB interleaved, 0..1, sRGB-encoded */
    float *elevation;  /* metres, width*height */
    float sea_level;   /* metres */
    char albedo_src[512], height_src[512];
    int albedo_w, albedo_h, height_w, height_h; /* input sizes */
    bool height_is_grey;                        /* the height input was a grey ramp (calibrated) */
    pg_calibration calib;                       /* valid when height_is_grey */
    char notes[512];                            /* e.g. "alpha channel ignored" */
} pg_exemplar;

typedef struct pg_exemplar_stats {
    float albedo_min[3], albedo_max[3], albedo_mean[3];
    float height_min, height_max, height_mean;
    double land_fraction; /* area-weighted (cos latitude): height > sea level */
} pg_exemplar_stats;

pg_status pg_exemplar_load(const pg_exemplar_opts *o, pg_exemplar *ex, pg_error *err);

/* A 64-bit fingerprint of what pg_exemplar_load(o) would read: every option, the
 * identity of every source file (path, device, inode, size, modification and change
 * times) and the library's source hash; nothing is decoded. albedo_src and height_src
 * (src_size bytes each) receive the names pg_exemplar_load gives the sources. A file
 * that cannot be stat'ed fails with PG_ERR_IO: load it to get the real error. */
pg_status pg_exemplar_fingerprint(const pg_exemplar_opts *o, uint64_t *fp, char *albedo_src,
                                  char *height_src, size_t src_size, pg_error *err);
void pg_exemplar_free(pg_exemplar *ex);
void pg_exemplar_compute_stats(const pg_exemplar *ex, pg_exemplar_stats *st);

/* Assemble Marble's tiled relief (rows x cols tiles RRRRRR/RRRRRR_CCCCCC.jpg) into one
 * single-channel image of raw grey values. */
pg_status pg_exemplar_assemble_relief(const char *dir, int rows, int cols, pg_image *out,
                                      pg_error *err);

/* Blue Marble water classifier: 1 where the pixel is open water (ocean, large lakes).
 * albedo is RGB 0..1. */
void pg_exemplar_water_mask(const float *albedo, int width, int height, uint8_t *mask);

/* Fit the grey -> metres mapping on a grey relief and a water mask of the same grid. */
pg_status pg_exemplar_calibrate(const float *grey, const uint8_t *water, int width, int height,
                                pg_calibration *c, pg_error *err);

/* Fraction of pixels where (height <= sea level) agrees with the water mask. */
double pg_exemplar_mask_agreement(const float *height, float sea_level, const uint8_t *water,
                                  size_t n);

/* Repaint, in place, the large ocean regions whose colour is far darker than the
 * albedo's own depth-to-colour curve gives for their depth (Blue Marble's Southern
 * Ocean band without bathymetry; data/README.md, "Ocean colour repair"). Every other
 * texel is left bit for bit. *repaired receives the texels repainted.
 * pg_exemplar_load calls it when opts.repair_ocean is set. */
pg_status pg_exemplar_repair_ocean(pg_exemplar *ex, uint64_t *repaired, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
