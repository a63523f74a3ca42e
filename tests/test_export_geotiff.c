/* test_export_geotiff.c - the planet as GIS data, read back by GDAL's own tools:
 * `planetgen export DIR --format geotiff` writes height.tif and albedo.tif that
 * gdalinfo places on -180..180 x -90..90 with the right pixel size, NoData and CRS
 * (EPSG:4326 for a WGS84 planet, the planet's own sphere otherwise), and whose values
 * at pixel centres (gdallocationinfo) lie within the bilinear taps of the cube faces
 * there; a tiled planet gives one GeoTIFF per tile and VRT mosaics equal, pixel for
 * pixel, to the single files, still readable after the directory moves; `generate
 * --geotiff` writes the same; a bad --format or a damaged tiled planet exits 2 and
 * writes nothing (docs/export.md, "GeoTIFF"). */
#include "export_fixture.h"

#include "planetgen/pg_geo.h"
#include "planetgen/pg_planet_tiles.h"
#include "planetgen/pg_raster.h"

#include <math.h>

static char planet_dir[1024];

static int setup(void **state) {
    (void)state;
    fixture_planet_dir("export_geotiff", 2, 32, planet_dir, sizeof planet_dir);
    return 0;
}

/* gdalinfo shows the whole globe, 360/4N degrees a pixel, NoData and the CRS. */
static void check_gdalinfo(const char *file, int n, const char *crs_needle, bool heights) {
    char info[65536], want[256];
    assert_int_equal(pg_test_sh(info, sizeof info, "gdalinfo '%s'", file), 0);
    snprintf(want, sizeof want, "Size is %d, %d", 4 * n, 2 * n);
    assert_non_null(strstr(info, want));
    snprintf(want, sizeof want, "Pixel Size = (%.15f,-%.15f)", 90.0 / n, 90.0 / n);
    assert_non_null(strstr(info, want));
    assert_non_null(strstr(info, "Upper Left  (-180.0000000,  90.0000000)"));
    assert_non_null(strstr(info, "Lower Right ( 180.0000000, -90.0000000)"));
    assert_non_null(strstr(info, crs_needle));
    if (heights) {
        assert_non_null(strstr(info, "Type=Float32"));
        assert_non_null(strstr(info, "NoData Value=-3.4028235e+38"));
    } else {
        assert_non_null(strstr(info, "Band 3 Block="));
        assert_non_null(strstr(info, "Type=Byte, ColorInterp=Blue"));
    }
}

/* The range of the four bilinear taps of `face` (ch floats a texel, channel c) around
 * direction d: any bilinear resampling of the cube lands inside it. */
static bool tap_range(const pg_planet *p, const float *const *faces, int ch, int c,
                      const double d[3], double *lo, double *hi) {
    int f;
    double u, v;
    pg_cube_from_dir(p->projection, d, &f, &u, &v);
    double fx = (u + 1) / 2 * (double)p->n - 0.5, fy = (v + 1) / 2 * (double)p->n - 0.5;
    int64_t x0 = (int64_t)floor(fx), y0 = (int64_t)floor(fy);
    if (x0 < 0 || y0 < 0 || x0 + 1 >= p->n || y0 + 1 >= p->n) return false; /* at a seam */
    *lo = INFINITY, *hi = -INFINITY;
    for (int k = 0; k < 4; k++) {
        double t = faces[f][((y0 + k / 2) * p->n + x0 + k % 2) * ch + c];
        *lo = fmin(*lo, t), *hi = fmax(*hi, t);
    }
    return true;
}

/* gdallocationinfo at 60 pixel centres of height.tif and albedo.tif: each value lies
 * within the bilinear taps of the planet's faces there (heights to 1 mm, albedo to
 * one 8-bit step). */
static void check_values(const pg_planet *p, const char *dir) {
    const int W = (int)(4 * p->n), H = (int)(2 * p->n);
    char coords[8192] = "", out[8192];
    double lat[60], lon[60];
    for (int k = 0; k < 60; k++) {
        int i = (k * 37 + 11) % W, j = (k * 23 + 5) % H;
        lon[k] = -180 + (i + 0.5) * 360.0 / W;
        lat[k] = 90 - (j + 0.5) * 180.0 / H;
        size_t len = strlen(coords);
        snprintf(coords + len, sizeof coords - len, "%.12f %.12f\n", lon[k], lat[k]);
    }
    char cpath[1300];
    snprintf(cpath, sizeof cpath, "%s/points.txt", dir);
    FILE *cf = fopen(cpath, "w");
    assert_non_null(cf);
    fputs(coords, cf);
    fclose(cf);
    const char *files[2] = {"height.tif", "albedo.tif"};
    for (int which = 0; which < 2; which++) {
        assert_int_equal(pg_test_sh(out, sizeof out,
                                    "gdallocationinfo -valonly -b 1 -geoloc '%s/%s' <'%s'", dir,
                                    files[which], cpath),
                         0);
        const float *faces[PG_CUBE_NFACES];
        for (int f = 0; f < PG_CUBE_NFACES; f++)
            faces[f] = which ? p->albedo[f] : p->height[f];
        char *line = out;
        int checked = 0;
        for (int k = 0; k < 60; k++) {
            double got = strtod(line, &line), d[3], lo, hi;
            pg_geo_latlon_to_dir(&p->ellipsoid, lat[k], lon[k], d);
            if (!tap_range(p, faces, which ? 3 : 1, 0, d, &lo, &hi)) continue;
            double tol = which ? 0.5 : 1e-3, scale = which ? 255 : 1;
            if (k < 3)
                printf("%s (%.3f, %.3f): %g in [%g, %g]\n", files[which], lat[k], lon[k], got,
                       lo * scale, hi * scale);
            assert_true(got >= lo * scale - tol && got <= hi * scale + tol);
            checked++;
        }
        printf("%s: %d of 60 points inside the taps (the rest lie on a seam)\n", files[which],
               checked);
        assert_true(checked >= 40);
    }
}

static void test_geotiff_wgs84(void **state) {
    (void)state;
    char args[4096], se[4096], out[1200], path[1300];
    snprintf(out, sizeof out, "%s/gis", planet_dir);
    snprintf(args, sizeof args, "export '%s' -o '%s' --format geotiff -q", planet_dir, out);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    assert_int_equal(pg_test_count_files(out), 2); /* height.tif, albedo.tif and nothing else */
    snprintf(path, sizeof path, "%s/height.tif", out);
    check_gdalinfo(path, 64, "ID[\"EPSG\",4326]]", true);
    snprintf(path, sizeof path, "%s/albedo.tif", out);
    check_gdalinfo(path, 64, "ID[\"EPSG\",4326]]", false);
    pg_planet p;
    pg_error err = {0};
    assert_int_equal(pg_planet_load(planet_dir, &p, &err), PG_OK);
    check_values(&p, out);
    pg_planet_free(&p);
    snprintf(path, sizeof path, "%s/points.txt", out);
    remove(path);
}

/* A planet on another sphere (Mars's radius): a geographic CRS on that sphere. */
static void test_geotiff_other_sphere(void **state) {
    (void)state;
    pg_error err = {0};
    pg_planet p, earth;
    assert_int_equal(pg_planet_load(planet_dir, &earth, &err), PG_OK);
    pg_ellipsoid mars = {3389500, 0};
    assert_int_equal(
        pg_planet_alloc(&p, earth.projection, earth.tiles, earth.tile_size, mars, &err), PG_OK);
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        memcpy(p.height[f], earth.height[f], (size_t)p.n * p.n * sizeof(float));
        memcpy(p.albedo[f], earth.albedo[f], (size_t)p.n * p.n * 3 * sizeof(float));
    }
    char dir[1024], args[4096], se[4096], path[1300];
    pg_test_scratch_dir("export_geotiff_mars", dir, sizeof dir);
    assert_int_equal(pg_planet_save_dir(&p, dir, &err), PG_OK);
    snprintf(args, sizeof args, "export '%s' --format geotiff -q", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    snprintf(path, sizeof path, "%s/height.tif", dir);
    check_gdalinfo(path, 64, "ELLIPSOID[\"planetgen sphere\",3389500,0", true);
    char info[65536];
    assert_int_equal(pg_test_sh(info, sizeof info, "gdalinfo '%s'", path), 0);
    assert_null(strstr(info, "4326"));
    check_values(&p, dir);
    pg_planet_free(&p);
    pg_planet_free(&earth);
}

/* The same planet in the tiled layout: 8 T^2 GeoTIFF tiles per raster plus a VRT,
 * equal pixel for pixel to the single files; the VRT names its tiles relative to
 * itself, so it still reads after the directory is moved. */
static void test_geotiff_tiled(void **state) {
    (void)state;
    pg_error err = {0};
    pg_planet p;
    assert_int_equal(pg_planet_load(planet_dir, &p, &err), PG_OK);
    char dir[1024], args[4096], se[4096], a[1300], b[1300];
    pg_test_scratch_dir("export_geotiff_tiled", dir, sizeof dir);
    pg_planet_dir_paths dp = {.dir = dir};
    const int T = p.tiles, S = p.tile_size;
    assert_int_equal(pg_planet_save_tiles(&p, 0, 6 * T * T, pg_planet_dir_path, &dp, &err), PG_OK);
    assert_int_equal(pg_planet_save_index(&p, pg_planet_dir_path, &dp, &err), PG_OK);
    int before = pg_test_count_files(dir);
    snprintf(args, sizeof args, "export '%s' --format geotiff -q", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    assert_int_equal(pg_test_count_files(dir) - before, 2 * 8 * T * T + 2);
    snprintf(a, sizeof a, "%s/height.vrt", dir);
    check_gdalinfo(a, (int)p.n, "ID[\"EPSG\",4326]]", true);
    snprintf(a, sizeof a, "%s/albedo.vrt", dir);
    check_gdalinfo(a, (int)p.n, "ID[\"EPSG\",4326]]", false);
    /* a tile is where its name says: row 1, column 2 starts at 90 - S and -180 + 2 S
     * pixels of 90/N degrees */
    char info[65536], want[128];
    assert_int_equal(pg_test_sh(info, sizeof info, "gdalinfo '%s/height_1_2.tif'", dir), 0);
    snprintf(want, sizeof want, "Origin = (%.15f,%.15f)", -180 + 2 * S * 90.0 / p.n,
             90 - S * 90.0 / p.n);
    assert_non_null(strstr(info, want));
    /* move the directory: the mosaics still read, and equal the single-file rasters */
    assert_int_equal(pg_test_sh(NULL, 0, "rm -rf '%s.moved' && mv '%s' '%s.moved'", dir, dir, dir),
                     0);
    const char *names[2] = {"height", "albedo"};
    for (int k = 0; k < 2; k++) {
        snprintf(a, sizeof a, "%s.moved/%s.vrt", dir, names[k]);
        snprintf(b, sizeof b, "%s/gis/%s.tif", planet_dir, names[k]);
        pg_image va, vb;
        assert_int_equal(pg_raster_read(a, 0, &va, NULL, &err), PG_OK);
        assert_int_equal(pg_raster_read(b, 0, &vb, NULL, &err), PG_OK);
        assert_int_equal(va.width, vb.width);
        assert_int_equal(va.channels, vb.channels);
        assert_memory_equal(va.data, vb.data, sizeof(float) * va.width * va.height * va.channels);
        pg_image_free(&va), pg_image_free(&vb);
    }
    pg_planet_free(&p);
}

/* generate --geotiff, planet and tiled layouts, on a small planet. */
static void test_generate_geotiff(void **state) {
    (void)state;
    char dir[1024], args[4096], se[4096], path[1300];
    pg_test_scratch_dir("export_geotiff_generate", dir, sizeof dir);
    const char *layouts[2] = {"planet", "tiled"}, *files[2] = {"height.tif", "height.vrt"};
    for (int k = 0; k < 2; k++) {
        snprintf(args, sizeof args,
                 "generate -q --tiles 2 --tile-size 32 --no-glb --geotiff --output-layout %s "
                 "--cache-dir '%s/synth-cache' -o '%s/%s'",
                 layouts[k], getenv("PG_BUILD_DIR"), dir, layouts[k]);
        assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
        snprintf(path, sizeof path, "%s/%s/%s", dir, layouts[k], files[k]);
        check_gdalinfo(path, 64, "planetgen sphere", true); /* generate: the mean sphere */
    }
}

/* An unknown --format; a tiled planet with a tile missing or of the wrong size. */
static void test_bad_input(void **state) {
    (void)state;
    fixture_export_refused(planet_dir, "--format shapefile",
                           "--format 'shapefile': unknown format");
    fixture_export_refused(planet_dir, "--format glb,kml", "unknown format 'kml'");
    pg_error err = {0};
    pg_planet p;
    assert_int_equal(pg_planet_load(planet_dir, &p, &err), PG_OK);
    char dir[1024];
    pg_test_scratch_dir("export_geotiff_damaged", dir, sizeof dir);
    pg_planet_dir_paths dp = {.dir = dir};
    assert_int_equal(pg_planet_save_tiles(&p, 0, 24, pg_planet_dir_path, &dp, &err), PG_OK);
    assert_int_equal(pg_planet_save_index(&p, pg_planet_dir_path, &dp, &err), PG_OK);
    assert_int_equal(pg_test_sh(NULL, 0, "cd '%s' && mv 'height_-Y_1_0.exr' ../hidden.exr", dir),
                     0);
    fixture_export_refused(dir, "--format geotiff", "missing height_-Y_1_0.exr");
    assert_int_equal(pg_test_sh(NULL, 0,
                                "cd '%s' && cp 'albedo_+X_0_0.png' ../a.png && "
                                "oiiotool ../a.png --resize 16x16 -o 'albedo_+X_0_0.png' && "
                                "mv ../hidden.exr 'height_-Y_1_0.exr'",
                                dir),
                     0);
    fixture_export_refused(dir, "--format geotiff", "16x16, but index.json says 32x32");
    pg_planet_free(&p);
}

/* A byte GeoTIFF rounds as the PNG writer does: 65 536 values, the floats closest to
 * each half step between two bytes, come back from a GeoTIFF and a PNG as the same
 * bytes, lround(v 255). (It used to round v * 255 + 0.5 in float and moved some values up by one:
 * the albedo GeoTIFF of a planet under MPI, read back from the ranks' PNG tiles, then differed from
 * one process's.) */
static void test_geotiff_byte_rounding(void **state) {
    (void)state;
    char dir[1024], tif[1100], png[1100];
    pg_test_scratch_dir("export_geotiff_rounding", dir, sizeof dir);
    snprintf(tif, sizeof tif, "%s/r.tif", dir);
    snprintf(png, sizeof png, "%s/r.png", dir);
    pg_error err = {0};
    pg_image img, a, b;
    assert_int_equal(pg_image_alloc(&img, 256, 256, 1, &err), PG_OK);
    /* for every step k, the 257 floats around (k + 1/2) / 255: whether each rounds up
     * or down is decided in the last bits */
    for (int i = 0; i < 65536; i++) {
        float v = (float)(((i / 257) + 0.5) / 255.0);
        for (int j = i % 257 - 128; j < 0; j++)
            v = nextafterf(v, 0.0f);
        for (int j = i % 257 - 128; j > 0; j--)
            v = nextafterf(v, 2.0f);
        img.data[i] = v;
    }
    assert_int_equal(pg_raster_write_geotiff(tif, &img, PG_RASTER_BYTE, NULL, NULL, &err), PG_OK);
    assert_int_equal(pg_image_write_png(png, &img, 8, &err), PG_OK);
    assert_int_equal(pg_raster_read(tif, 0, &a, NULL, &err), PG_OK);
    assert_int_equal(pg_image_read(png, 0, &b, &err), PG_OK);
    int differ = 0;
    for (int i = 0; i < 65536; i++) {
        /* both read back as the files' raw bytes */
        const long want = lround((double)img.data[i] * 255.0);
        differ += lround(a.data[i]) != want || lround(b.data[i]) != want;
    }
    assert_int_equal(differ, 0);
    pg_image_free(&img), pg_image_free(&a), pg_image_free(&b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_geotiff_wgs84), cmocka_unit_test(test_geotiff_other_sphere),
        cmocka_unit_test(test_geotiff_tiled), cmocka_unit_test(test_generate_geotiff),
        cmocka_unit_test(test_bad_input),     cmocka_unit_test(test_geotiff_byte_rounding),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
