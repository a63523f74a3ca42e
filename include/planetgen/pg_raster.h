/* pg_raster.h - georeferenced rasters through GDAL: reading any raster GDAL reads
 * (GeoTIFF, VRT, Arc/Info ASCII grids, SRTM .hgt, ...) with its coordinate system,
 * geotransform and NoData, and writing GeoTIFF (or Cloud-Optimized GeoTIFF) and VRT
 * mosaics that carry them.
 *
 * The idea: GDAL is the field's library for georeferenced rasters, so planetgen never
 * writes GeoTIFF tags or VRT XML itself; pg_image.h (OpenImageIO, OpenEXR) stays for
 * textures, PNG, JPEG and EXR and for rasters without georeferencing. The adapter
 * (src/adapters/pg_gdal.c) uses GDAL's C API only; no GDAL type crosses this header.
 * GDAL's own messages never reach stderr: each call catches them (a thread-local
 * handler) and the first error becomes the pg_error line, naming the file.
 *
 * The geotransform is GDAL's: the map position of pixel corner (col, row) is
 *   x = t[0] + col t[1] + row t[2],   y = t[3] + col t[4] + row t[5].
 * A north-up grid has t[2] = t[4] = 0 and t[5] < 0; row 0 is the top (north). */
#ifndef PLANETGEN_PG_RASTER_H
#define PLANETGEN_PG_RASTER_H

#include "planetgen/pg_image.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What the coordinate system is, as far as cell sizes are concerned. */
typedef enum pg_crs_kind {
    PG_CRS_NONE,       /* no coordinate system */
    PG_CRS_GEOGRAPHIC, /* latitude/longitude on an ellipsoid (a, f); unit = degrees per unit */
    PG_CRS_PROJECTED,  /* planar; unit = metres per unit */
    PG_CRS_OTHER       /* anything else (geocentric, vertical, engineering, ...) */
} pg_crs_kind;

/* The georeferencing of a raster. Owns crs_wkt (free with pg_georef_free). A zeroed
 * struct is "no georeferencing". */
typedef struct pg_georef {
    bool has_transform;  /* a geotransform is set (not GDAL's default 0,1,0,0,0,1) */
    double transform[6]; /* GDAL order, above */
    bool has_nodata;
    double nodata;
    char *crs_wkt;    /* the CRS as WKT (GDAL's), or NULL */
    pg_crs_kind kind; /* derived from crs_wkt */
    double a, f;      /* ellipsoid of the CRS (any kind with one); 0, 0 otherwise */
    double unit;      /* PG_CRS_GEOGRAPHIC: degrees per CRS unit; PROJECTED: metres per unit */
    char crs_name[128];
} pg_georef;

void pg_georef_free(pg_georef *g);
/* A deep copy (dst is overwritten; free it with pg_georef_free). */
pg_status pg_georef_copy(pg_georef *dst, const pg_georef *src, pg_error *err);
/* Has a geotransform or a coordinate system. */
bool pg_georef_present(const pg_georef *g);

/* Open path with GDAL and read its size, band count, driver short name (e.g. "GTiff",
 * "SRTMHGT", "AAIGrid") and georeferencing, without pixels. BADINPUT, naming the path,
 * if GDAL cannot open it. geo and driver may be NULL. */
pg_status pg_raster_probe(const char *path, int *width, int *height, int *bands, char driver[32],
                          pg_georef *geo, pg_error *err);

/* Read every band of path as interleaved floats holding the raw values (like
 * pg_image_read: an int16 -400 stays -400.0; src_type and unit_scale say what the
 * file held), row 0 at the top, with its georeferencing into geo (may be NULL).
 * Refuses (BADINPUT, before allocating) rasters above max_pixels (0 = the default of
 * pg_image.h), unsupported sample types (complex), and unreadable blocks. */
pg_status pg_raster_read(const char *path, uint64_t max_pixels, pg_image *out, pg_georef *geo,
                         pg_error *err);

/* How to write a GeoTIFF. */
typedef enum pg_raster_type {
    PG_RASTER_FLOAT32, /* data as it is */
    PG_RASTER_BYTE     /* data 0..1, rounded to 0..255 (colour: sRGB-encoded as given) */
} pg_raster_type;

#define PG_RASTER_MAX_OPTIONS 32

typedef struct pg_raster_write_opts {
    const char *const *options; /* GDAL creation options "KEY=VALUE"; NULL = none */
    int noptions;
    bool cog; /* Cloud-Optimized GeoTIFF (GDAL's COG driver) instead of GTiff */
} pg_raster_write_opts;

/* Check creation options before anything is read or written: each must be KEY=VALUE,
 * and GDAL's GTiff (or COG) driver must know the key and accept the value. BADINPUT
 * naming `option` and the offending entry otherwise. */
pg_status pg_raster_check_options(const pg_raster_write_opts *o, const char *option, pg_error *err);

/* Write img (1 band, or 3 as RGB) as a GeoTIFF at path, with geo's coordinate system,
 * geotransform and NoData (geo may be NULL: a plain TIFF). Without creation options
 * the GeoTIFF is DEFLATE-compressed (with a predictor for floats). o may be NULL. */
pg_status pg_raster_write_geotiff(const char *path, const pg_image *img, pg_raster_type type,
                                  const pg_georef *geo, const pg_raster_write_opts *o,
                                  pg_error *err);

/* The coordinate system of latitude/longitude in degrees on the ellipsoid (a, f), as
 * WKT in geo->crs_wkt (kind, a, f, unit and name filled too): EPSG:4326 when (a, f)
 * is WGS84's to 1 mm and 1e-12, otherwise a geographic CRS on that sphere or
 * ellipsoid with the Greenwich-like meridian at longitude 0. */
pg_status pg_raster_geographic_crs(double a, double f, pg_georef *geo, pg_error *err);

/* Write a GDAL VRT at path that mosaics the n rasters at src (GDALBuildVRT). The VRT
 * refers to source i by names[i] (relative to the VRT's directory), so the sources
 * can be staged under temporary names and renamed next to the VRT afterwards. */
pg_status pg_raster_build_vrt(const char *path, int n, const char *const *src,
                              const char *const *names, pg_error *err);

#ifdef __cplusplus
}
#endif

#endif
