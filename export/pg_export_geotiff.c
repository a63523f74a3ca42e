/* pg_export_geotiff.c - the planet as GIS data: equirectangular GeoTIFFs of the
 * heights and the albedo, written by GDAL (pg_raster.h), so QGIS and GDAL open a
 * planet like any global DEM.
 *
 * The rasters are 4N x 2N pixels for faces of N texels: at the equator a face spans
 * 90 degrees in N texels, so a pixel is about a texel there. Pixel (i, j) is centred
 * at longitude -180 + (i + 0.5) 360 / 4N and geodetic latitude 90 - (j + 0.5) 180 / 2N
 * on the planet's ellipsoid, which is what the geotransform (-180, 360/4N, 0, 90, 0,
 * -180/2N) and the geographic CRS on that ellipsoid say; each value is the bilinear
 * sample of the cube there (pg_cube_faces_to_equirect, the resampler of the
 * previews). A tiled export cuts the same grid into S x S tiles: the resampler gives
 * a region exactly the pixels of the whole image, so the VRT mosaic of the tiles is
 * the single-file raster, pixel for pixel. */
#include "pg_export_internal.h"

#include "planetgen/pg_geo.h"
#include "planetgen/pg_raster.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct geotiff_job {
    const pg_planet *p;
    int W, H;        /* the whole equirectangular grid */
    pg_georef whole; /* its georeferencing (CRS, geotransform) */
    pg_planet_path_fn path_for;
    void *user;
    int *nfiles;
} geotiff_job;

/* The rw x rh region at (x0, y0) of the grid, of the faces `faces` (ch floats). */
static pg_status resample(const geotiff_job *j, const float *const faces[PG_CUBE_NFACES], int ch,
                          int x0, int y0, int rw, int rh, pg_image *img, pg_error *err) {
    pg_status st = pg_image_alloc(img, rw, rh, ch, err);
    if (st == PG_OK)
        st = pg_cube_faces_to_equirect(j->p->projection, j->p->n, &j->p->ellipsoid, faces, ch, j->W,
                                       j->H, x0, y0, rw, rh, img->data, err);
    return st;
}

/* Write one raster (heights or albedo) of the region as `name`; the staged path it
 * went to is copied into staged (may be NULL). */
static pg_status write_region(const geotiff_job *j, bool heights, int x0, int y0, int rw, int rh,
                              const char *name, char **staged, pg_error *err) {
    const pg_planet *p = j->p;
    const float *faces[PG_CUBE_NFACES];
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        faces[f] = heights ? p->height[f] : p->albedo[f];
    pg_georef g;
    pg_status st = pg_georef_copy(&g, &j->whole, err);
    if (st != PG_OK) return st;
    g.transform[0] = j->whole.transform[0] + x0 * j->whole.transform[1];
    g.transform[3] = j->whole.transform[3] + y0 * j->whole.transform[5];
    g.has_nodata = heights;
    g.nodata = PG_EXPORT_GEOTIFF_NODATA;
    pg_image img = {0};
    st = resample(j, faces, heights ? 1 : 3, x0, y0, rw, rh, &img, err);
    const char *path = st == PG_OK ? j->path_for(name, j->user) : NULL;
    if (st == PG_OK && !path) st = pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", name);
    if (st == PG_OK)
        st = pg_raster_write_geotiff(path, &img, heights ? PG_RASTER_FLOAT32 : PG_RASTER_BYTE, &g,
                                     NULL, err);
    if (st == PG_OK) (*j->nfiles)++;
    if (st == PG_OK && staged && !(*staged = strdup(path)))
        st = pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", name);
    pg_image_free(&img);
    pg_georef_free(&g);
    return st;
}

static pg_status write_whole(const geotiff_job *j, pg_error *err) {
    pg_status st =
        write_region(j, true, 0, 0, j->W, j->H, PG_EXPORT_GEOTIFF_HEIGHT ".tif", NULL, err);
    if (st == PG_OK)
        st = write_region(j, false, 0, 0, j->W, j->H, PG_EXPORT_GEOTIFF_ALBEDO ".tif", NULL, err);
    return st;
}

/* The tiles of one raster and the VRT over them. */
static pg_status write_tiled_set(const geotiff_job *j, bool heights, pg_error *err) {
    const int S = j->p->tile_size, cols = j->W / S, rows = j->H / S, n = cols * rows;
    const char *base = heights ? PG_EXPORT_GEOTIFF_HEIGHT : PG_EXPORT_GEOTIFF_ALBEDO;
    char **staged = calloc((size_t)n, sizeof *staged), **names = calloc((size_t)n, sizeof *names);
    pg_status st = staged && names ? PG_OK : pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    for (int t = 0; st == PG_OK && t < n; t++) {
        char name[96];
        snprintf(name, sizeof name, "%s_%d_%d.tif", base, t / cols, t % cols);
        if (!(names[t] = strdup(name))) st = pg_error_set(err, PG_ERR_NOMEM, "out of memory");
        if (st == PG_OK)
            st = write_region(j, heights, t % cols * S, t / cols * S, S, S, name, &staged[t], err);
    }
    char vrt_name[64];
    snprintf(vrt_name, sizeof vrt_name, "%s.vrt", base);
    const char *vrt = st == PG_OK ? j->path_for(vrt_name, j->user) : NULL;
    if (st == PG_OK && !vrt) st = pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    if (st == PG_OK)
        st = pg_raster_build_vrt(vrt, n, (const char *const *)staged, (const char *const *)names,
                                 err);
    if (st == PG_OK) (*j->nfiles)++;
    for (int t = 0; t < n; t++) {
        if (staged) free(staged[t]);
        if (names) free(names[t]);
    }
    free(staged);
    free(names);
    return st;
}

pg_status pg_export_geotiff(const pg_planet *p, const pg_export_opts *o, pg_planet_path_fn path_for,
                            void *user, int *nfiles, pg_error *err) {
    if (4 * p->n > 1 << 30)
        return pg_error_set(err, PG_ERR_BADINPUT, "GeoTIFF: faces of %lld texels are too large",
                            (long long)p->n);
    geotiff_job j = {p, (int)(4 * p->n), (int)(2 * p->n), {0}, path_for, user, nfiles};
    pg_status st = pg_geo_raster_global(&p->ellipsoid, j.W, j.H, &j.whole, err);
    if (st == PG_OK && o->geotiff_tiled) {
        st = write_tiled_set(&j, true, err);
        if (st == PG_OK) st = write_tiled_set(&j, false, err);
    } else if (st == PG_OK) {
        st = write_whole(&j, err);
    }
    pg_georef_free(&j.whole);
    return st;
}
