/* test_pits_gdal.c - `planetgen pits` on georeferenced rasters, checked with GDAL's own
 * tools (gdal_translate makes the inputs, gdalinfo and gdallocationinfo read the
 * outputs): a GeoTIFF made from a real Marble relief tile keeps its CRS, geotransform
 * and NoData through pits, its NoData cells stay NoData and are outlets, and its cell
 * areas are the true areas on WGS84 (projected rasters: metres; --cell-size
 * overrides); an SRTM .hgt and an Arc/Info ASCII grid are read and written back as
 * GeoTIFF; --co and --cog reach GDAL's writer; and a raster GDAL cannot open, --global
 * without a whole-globe grid, bad creation options and a signed DEM to PNG exit 2 with
 * one line and write nothing (docs/pits.md, "GIS rasters"). */
#include "pg_test.h"

#include "planetgen/pg_geo.h"
#include "planetgen/pg_raster.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RELIEF "/usr/share/marble/data/maps/earth/srtm/3/000002/000002_000005.jpg"

static char dir[1024];

/* The part of a gdalinfo report from `from` to the end of its line (or to `to`). */
static void section(const char *info, const char *from, const char *to, char *out, size_t size) {
    const char *a = strstr(info, from);
    assert_non_null(a);
    const char *b = to ? strstr(a, to) : strchr(a, '\n');
    assert_non_null(b);
    snprintf(out, size, "%.*s", (int)(b - a), a);
}

/* gdalinfo of in and out agree on the origin, the pixel size, the NoData value and
 * the coordinate system: word for word where in is a GeoTIFF, else (an SRTM tile's or
 * an ESRI .prj's spelling, which GeoTIFF keys do not keep) as gdalsrsinfo's PROJ
 * string. */
static void same_georeferencing(const char *in, const char *out) {
    static char a[65536], b[65536];
    assert_int_equal(pg_test_sh(a, sizeof a, "gdalinfo '%s'", in), 0);
    assert_int_equal(pg_test_sh(b, sizeof b, "gdalinfo '%s'", out), 0);
    const char *keys[][2] = {{"Origin = ", NULL},
                             {"Pixel Size = ", NULL},
                             {"NoData Value=", NULL},
                             {"Coordinate System is:", "Data axis"}};
    size_t nkeys = strstr(a, "Driver: GTiff") ? 4 : 3;
    if (nkeys == 3) {
        char pa[1024], pb[1024];
        assert_int_equal(pg_test_sh(pa, sizeof pa, "gdalsrsinfo -o proj4 '%s'", in), 0);
        assert_int_equal(pg_test_sh(pb, sizeof pb, "gdalsrsinfo -o proj4 '%s'", out), 0);
        printf("CRS %s", pb);
        assert_true(strstr(pa, "+proj=") != NULL);
        assert_string_equal(pa, pb);
    }
    for (size_t i = 0; i < nkeys; i++) {
        char sa[8192], sb[8192];
        section(a, keys[i][0], keys[i][1], sa, sizeof sa);
        section(b, keys[i][0], keys[i][1], sb, sizeof sb);
        printf("%.60s\n", sb);
        assert_string_equal(sa, sb);
    }
}

/* Lines on stderr. */
static int lines(const char *s) {
    int n = 0;
    for (; *s; s++)
        n += *s == '\n';
    return n;
}

static int setup(void **state) {
    (void)state;
    pg_test_scratch_dir("pits_gdal", dir, sizeof dir);
    /* the tile as a GeoTIFF on WGS84, then a window reaching 1 degree past its west and
     * north edges, which GDAL fills with NoData: a real DEM with a NoData margin */
    if (pg_test_sh(
            NULL, 0,
            "cd '%s' && gdal_translate -q -ot Float32 -a_srs EPSG:4326 -a_ullr 0 45 22.5 22.5 "
            "-a_nodata -9999 '%s' raw.tif && gdal_translate -q -projwin -1 46 22.5 22.5 raw.tif "
            "dem.tif && cp '%s' plain.jpg",
            dir, RELIEF, RELIEF) != 0)
        return -1;
    /* an SRTM tile (int16, NoData -32768) and an Arc/Info ASCII grid with its .prj */
    if (pg_test_sh(
            NULL, 0,
            "cd '%s' && gdal_translate -q -ot Int16 -outsize 1201 1201 -a_ullr 9.99958333333 "
            "47.00041666667 11.00041666667 45.99958333333 -of SRTMHGT raw.tif N46E010.hgt && "
            "gdal_translate -q -of AAIGrid raw.tif grid.asc",
            dir) != 0)
        return -1;
    return 0;
}

/* pits keeps the GeoTIFF's CRS, geotransform and NoData; NoData cells come back as
 * NoData; every other cell only goes down (breach); nothing is left to fill. */
static void test_geotiff_keeps_georeferencing(void **state) {
    (void)state;
    char args[4096], se[4096], so[8192], in[1200], out[1200];
    snprintf(in, sizeof in, "%s/dem.tif", dir);
    snprintf(out, sizeof out, "%s/dem_breach.tif", dir);
    snprintf(args, sizeof args,
             "pits --method breach --sea-level 10 '%s' -o '%s' --json '%s/b.json'", in, out, dir);
    assert_int_equal(pg_test_run_cli(args, so, sizeof so, se, sizeof se), 0);
    same_georeferencing(in, out);
    pg_image a, b;
    pg_georef ga, gb;
    pg_error err = {0};
    assert_int_equal(pg_raster_read(in, 0, &a, &ga, &err), PG_OK);
    assert_int_equal(pg_raster_read(out, 0, &b, &gb, &err), PG_OK);
    assert_true(gb.has_nodata && gb.nodata == -9999 && gb.kind == PG_CRS_GEOGRAPHIC);
    size_t n = (size_t)a.width * a.height, nodata = 0, lowered = 0;
    for (size_t i = 0; i < n; i++) {
        if (a.data[i] == -9999) {
            nodata++;
            assert_true(b.data[i] == -9999);
        } else {
            assert_true(b.data[i] <= a.data[i]);
            lowered += b.data[i] < a.data[i];
        }
    }
    printf("%zu NoData cells, %zu lowered\n", nodata, lowered);
    assert_int_equal(nodata, 705 * 705 - 675 * 675);
    assert_true(lowered > 1000);
    char js[16384];
    assert_int_equal(pg_test_sh(js, sizeof js, "cat '%s/b.json'", dir), 0);
    assert_true(pg_test_json_number(strstr(js, "\"before\""), "depressions") > 1000);
    assert_true(pg_test_json_number(strstr(js, "\"after\""), "depressions") == 0);
    assert_true(pg_test_json_number(js, "nodata") == -9999);
    /* gdallocationinfo reads the carved DEM where the input has NoData and land */
    char v[65536];
    assert_int_equal(pg_test_sh(v, sizeof v, "gdalinfo '%s'", out), 0);
    assert_non_null(strstr(v, "ID[\"EPSG\",4326]]"));
    assert_int_equal(
        pg_test_sh(v, sizeof v, "gdallocationinfo -valonly -geoloc '%s' -0.5 45.5", out), 0);
    assert_true(atof(v) == -9999);
    pg_image_free(&a), pg_image_free(&b);
    pg_georef_free(&ga), pg_georef_free(&gb);
}

/* depression area / cells: a cell's true area on WGS84 within the tile's latitudes;
 * a projected CRS gives the geotransform's square metres; --cell-size overrides. */
static void test_cell_areas(void **state) {
    (void)state;
    char args[4096], se[4096], js[16384];
    snprintf(args, sizeof args, "pits --stats '%s/dem.tif' --sea-level 10 --json '%s/s.json'", dir,
             dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    assert_int_equal(pg_test_sh(js, sizeof js, "cat '%s/s.json'", dir), 0);
    double area = pg_test_json_number(js, "depression_area_m2"),
           cells = pg_test_json_number(js, "depression_cells");
    pg_ellipsoid w = pg_ellipsoid_wgs84();
    double step = 1 / 30.0, north[2] = {45, 45 - step}, south[2] = {22.5 + step, 22.5}, rows[2];
    pg_geo_latlon_band_areas(&w, 1, north, step, rows);     /* the tile's northernmost row */
    pg_geo_latlon_band_areas(&w, 1, south, step, rows + 1); /* its southernmost */
    printf("mean depression cell %.6g m^2, rows %.6g .. %.6g\n", area / cells, rows[0], rows[1]);
    assert_true(cells > 1000 && area / cells > rows[0] && area / cells < rows[1]);
    /* the same cells in UTM 32N metres: 30 km / 675 a side */
    snprintf(args, sizeof args,
             "cd '%s' && gdal_translate -q -ot Float32 -a_srs EPSG:32632 -a_ullr 500000 5200000 "
             "530000 5170000 '%s' utm.tif",
             dir, RELIEF);
    assert_int_equal(pg_test_sh(NULL, 0, "%s", args), 0);
    const char *runs[2] = {"", "--cell-size 7"};
    const double want[2] = {(30000.0 / 675) * (30000.0 / 675), 49};
    for (int k = 0; k < 2; k++) {
        snprintf(args, sizeof args,
                 "pits --stats '%s/utm.tif' --sea-level 10 %s --json '%s/u.json'", dir, runs[k],
                 dir);
        assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
        assert_int_equal(pg_test_sh(js, sizeof js, "cat '%s/u.json'", dir), 0);
        double a = pg_test_json_number(js, "depression_area_m2"),
               c = pg_test_json_number(js, "depression_cells");
        printf("%s: %.9g m^2 per cell\n", runs[k], a / c);
        assert_true(c > 1000 && fabs(a / c / want[k] - 1) < 1e-9);
    }
}

/* An SRTM tile (.hgt, int16, NoData -32768) and an Arc/Info ASCII grid (.asc with its
 * .prj), both made by gdal_translate, come back as GeoTIFFs with their georeferencing;
 * the ASCII grid gives the same heights as the GeoTIFF it was made from. */
static void test_hgt_and_asc(void **state) {
    (void)state;
    char args[4096], se[4096];
    const char *inputs[2] = {"N46E010.hgt", "grid.asc"};
    for (int k = 0; k < 2; k++) {
        char in[1200], out[1200];
        snprintf(in, sizeof in, "%s/%s", dir, inputs[k]);
        snprintf(out, sizeof out, "%s/%s.tif", dir, inputs[k]);
        snprintf(args, sizeof args, "pits --method fill --epsilon '%s' -o '%s'", in, out);
        assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
        same_georeferencing(in, out);
        char v[65536];
        assert_int_equal(pg_test_sh(v, sizeof v, "gdalinfo '%s'", out), 0);
        assert_non_null(strstr(v, "Type=Float32"));
    }
    char ref[1200];
    snprintf(ref, sizeof ref, "%s/raw_fill.tif", dir);
    snprintf(args, sizeof args, "pits --method fill --epsilon '%s/raw.tif' -o '%s'", dir, ref);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    pg_image a, b;
    pg_error err = {0};
    char asc_out[1200];
    snprintf(asc_out, sizeof asc_out, "%s/grid.asc.tif", dir);
    assert_int_equal(pg_raster_read(ref, 0, &a, NULL, &err), PG_OK);
    assert_int_equal(pg_raster_read(asc_out, 0, &b, NULL, &err), PG_OK);
    assert_int_equal(a.width, b.width);
    assert_memory_equal(a.data, b.data, sizeof(float) * a.width * a.height);
    pg_image_free(&a), pg_image_free(&b);
}

/* --co options and --cog reach GDAL's writer, as gdalinfo shows. */
static void test_creation_options(void **state) {
    (void)state;
    char args[4096], se[4096], v[65536];
    snprintf(args, sizeof args,
             "pits -q '%s/dem.tif' -o '%s/tiled.tif' --co TILED=YES --co BLOCKXSIZE=128 "
             "--co BLOCKYSIZE=128 --co COMPRESS=LZW",
             dir, dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    assert_int_equal(pg_test_sh(v, sizeof v, "gdalinfo '%s/tiled.tif'", dir), 0);
    assert_non_null(strstr(v, "Block=128x128"));
    assert_non_null(strstr(v, "COMPRESSION=LZW"));
    snprintf(args, sizeof args, "pits -q '%s/dem.tif' -o '%s/cog.tif' --cog --co COMPRESS=ZSTD",
             dir, dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, se, sizeof se), 0);
    assert_int_equal(pg_test_sh(v, sizeof v, "gdalinfo '%s/cog.tif'", dir), 0);
    assert_non_null(strstr(v, "LAYOUT=COG"));
    assert_non_null(strstr(v, "COMPRESSION=ZSTD"));
    same_georeferencing(strcat(strcpy(se, dir), "/dem.tif"), strcat(strcpy(v, dir), "/cog.tif"));
}

static void expect_refusal(const char *args_fmt, const char *needle) {
    char out_dir[1200], args[4096], se[4096];
    snprintf(out_dir, sizeof out_dir, "%s/bad", dir);
    assert_int_equal(pg_test_sh(NULL, 0, "rm -rf '%s' && mkdir '%s'", out_dir, out_dir), 0);
    snprintf(args, sizeof args, args_fmt, dir, out_dir);
    int rc = pg_test_run_cli(args, NULL, 0, se, sizeof se);
    printf("%s\n -> %d: %s", args, rc, se);
    assert_int_equal(rc, 2);
    assert_int_equal(lines(se), 1);
    assert_non_null(strstr(se, needle));
    assert_int_equal(pg_test_count_files(out_dir), 0);
}

/* A raster GDAL cannot open, --global without a whole-globe grid (a regional GeoTIFF,
 * or a grid with no geotransform that is not 2:1), and bad creation options: exit 2,
 * one line naming the file or option, nothing written. */
static void test_bad_input(void **state) {
    (void)state;
    assert_int_equal(pg_test_sh(NULL, 0, "cd '%s' && printf 'not elevation' > N00E000.hgt", dir),
                     0);
    expect_refusal("pits '%s/N00E000.hgt' -o '%s/o.tif'", "N00E000.hgt: not a raster GDAL");
    expect_refusal("pits --global '%s/dem.tif' -o '%s/o.tif'", "whole-globe geographic grid");
    expect_refusal("pits --stats '%s/dem.tif' --global%.0s", "whole-globe");
    expect_refusal("pits --global '%s/plain.jpg' -o '%s/o.tif'", "no geotransform and is 675x675");
    expect_refusal("pits '%s/dem.tif' -o '%s/o.tif' --co NO_SUCH_OPTION=1", "NO_SUCH_OPTION");
    expect_refusal("pits '%s/dem.tif' -o '%s/o.tif' --co COMPRESS=NOPE", "NOPE");
    expect_refusal("pits '%s/dem.tif' -o '%s/o.tif' --co TILED",
                   "--co 'TILED': expected KEY=VALUE");
    expect_refusal("pits '%s/dem.tif' -o '%s/o.exr' --cog", "--cog: only for a GeoTIFF");
    expect_refusal("pits '%s/dem.tif' -o '%s/o.tif' --global --cell-size 30", "give one");
    expect_refusal("pits '%s/N46E010.hgt' -o '%s/o.png'", "a signed DEM");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_geotiff_keeps_georeferencing),
        cmocka_unit_test(test_cell_areas),
        cmocka_unit_test(test_hgt_and_asc),
        cmocka_unit_test(test_creation_options),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
