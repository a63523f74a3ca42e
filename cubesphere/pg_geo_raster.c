/* pg_geo_raster.c - cell sizes of georeferenced rasters (pg_geo.h): the bridge between
 * GDAL's georeferencing (pg_raster.h, in core) and the geodesy of this module.
 *
 * A geographic raster's cells are latitude/longitude rectangles, whose true area on
 * the ellipsoid depends only on the row (pg_geo_latlon_band_areas, exact through the
 * authalic latitude); a projected raster's cells are parallelograms of the
 * geotransform's determinant, in the CRS's metres. Nothing else has a cell size. */
#include "planetgen/pg_geo.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bool pg_geo_raster_has_cells(const pg_georef *g) {
    return g && g->has_transform && g->unit > 0 &&
           (g->kind == PG_CRS_PROJECTED || (g->kind == PG_CRS_GEOGRAPHIC && g->a > 0));
}

static bool north_up(const pg_georef *g) {
    return g->transform[2] == 0 && g->transform[4] == 0;
}

pg_status pg_geo_raster_row_areas(const pg_georef *g, int width, int height, const char *what,
                                  double *rows, pg_error *err) {
    (void)width;
    if (!pg_geo_raster_has_cells(g))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: no geotransform with a geographic or projected CRS, so no cell "
                            "size (give --cell-size)",
                            what);
    const double *t = g->transform;
    if (g->kind == PG_CRS_PROJECTED) {
        double a = fabs(t[1] * t[5] - t[2] * t[4]) * g->unit * g->unit;
        for (int j = 0; j < height; j++)
            rows[j] = a;
        return PG_OK;
    }
    if (!north_up(g))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: a rotated geographic grid has no row-wise cell areas (give "
                            "--cell-size)",
                            what);
    double *lat = malloc(((size_t)height + 1) * sizeof *lat);
    if (!lat) return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", what);
    for (int j = 0; j <= height; j++)
        lat[j] = (t[3] + j * t[5]) * g->unit;
    pg_ellipsoid e = {g->a, g->f};
    pg_geo_latlon_band_areas(&e, (size_t)height, lat, t[1] * g->unit, rows);
    free(lat);
    return PG_OK;
}

bool pg_geo_raster_is_global(const pg_georef *g, int width, int height) {
    if (!pg_geo_raster_has_cells(g) || g->kind != PG_CRS_GEOGRAPHIC || !north_up(g)) return false;
    const double *t = g->transform;
    double dx = t[1] * g->unit, dy = t[5] * g->unit, top = t[3] * g->unit;
    double tol = 0.01;
    return dx > 0 && dy < 0 && fabs(width * dx - 360) < tol * dx && fabs(top - 90) < tol * -dy &&
           fabs(top + height * dy + 90) < tol * -dy;
}

pg_status pg_geo_raster_global(const pg_ellipsoid *e, int width, int height, pg_georef *g,
                               pg_error *err) {
    pg_status st = pg_raster_geographic_crs(e->a, e->f, g, err);
    if (st != PG_OK) return st;
    const double t[6] = {-180, 360.0 / width, 0, 90, 0, -180.0 / height};
    memcpy(g->transform, t, sizeof t);
    g->has_transform = true;
    return PG_OK;
}
