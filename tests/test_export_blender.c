/* test_export_blender.c - Blender (Debian's blender, headless) imports the exported
 * default planet's .glb with its own glTF importer, finds 6 primitives, each with a
 * base-colour image texture and a normal map fed by an image, and renders a frame
 * with Cycles on the CPU that shows the globe (not blank). The script is
 * tests/tools/blender_check_glb.py.
 *
 * Then the shipped scripts/blender_import.py, driven by
 * tests/tools/blender_check_displacement.py on a small Earth: every face's material has
 * its Displacement fed by the 16-bit height image, calibrated from the material extras;
 * adaptive subdivision is on; the sea surface lies at sea level; and a Cycles close-up
 * of the Himalaya differs from the same scene without displacement where the mountains
 * are (the height pass says where), far more than over the lowlands. The script also
 * takes a tiled planet directory: without its .glb files (planetgen view assembles one)
 * and with its .glb per tile, joined into one closed surface. */
#include "export_fixture.h"

#include "planetgen/pg_export.h"
#include "planetgen/pg_planet_tiles.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static long figure(const char *out, const char *key) {
    const char *p = strstr(out, key);
    return p ? strtol(p + strlen(key), NULL, 10) : -1;
}

static void test_blender_import_and_render(void **s) {
    (void)s;
    char out[65536];
    if (fixture_sh("command -v blender >/dev/null", NULL, 0) != 0)
        fail_msg("blender is not installed: run scripts/bootstrap");
    char dir[1024], args[4096];
    fixture_planet_dir("export_blender", 4, 256, dir, sizeof dir);
    snprintf(args, sizeof args, "export '%s' --no-previews -q", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    char cmd[8192], png[1200];
    snprintf(png, sizeof png, "%s/blender.png", dir);
    snprintf(cmd, sizeof cmd,
             "blender -b --factory-startup --python '%s/tests/tools/blender_check_glb.py' -- "
             "'%s/planet.glb' '%s' 2>&1",
             pg_test_source_dir(), dir, png);
    int rc = fixture_sh(cmd, out, sizeof out);
    printf("%s\n", strstr(out, "PRIMITIVES") ? strstr(out, "PRIMITIVES") : out);
    assert_int_equal(rc, 0);
    assert_int_equal(figure(out, "PRIMITIVES "), 6);
    assert_int_equal(figure(out, "BASECOLOR "), 6);
    assert_int_equal(figure(out, "NORMALMAP "), 6);
    assert_int_equal(figure(out, "TRIANGLES "), 196608);
    assert_non_null(strstr(out, "RENDERED"));
    /* the globe covers about pi/4 (2/2.3)^2 = 59% of the frame; lit, it is not blank */
    double fg = fixture_foreground_fraction(png);
    printf("blender render: %.1f%% of pixels differ from the background\n", 100 * fg);
    assert_true(fg > 0.3);
}

static double figure_double(const char *out, const char *key) {
    const char *p = strstr(out, key);
    return p ? strtod(p + strlen(key), NULL) : NAN;
}

/* Mean absolute difference (over RGB, 0..1) between two renders within the pixels whose
 * height (metres, from the height pass) lies in [lo, hi); the pixel count to *count. */
static double masked_difference(const pg_image *a, const pg_image *b, const pg_image *h,
                                double offset, double scale, double lo, double hi, long *count) {
    double sum = 0;
    *count = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
        double m = offset + scale * h->data[i * h->channels];
        if (m < lo || m >= hi) continue;
        for (int c = 0; c < 3; c++)
            sum += fabs(a->data[i * a->channels + c] * a->unit_scale -
                        b->data[i * b->channels + c] * b->unit_scale) /
                   3;
        ++*count;
    }
    return *count ? sum / *count : NAN;
}

/* The close-up: 1500 km from the Himalaya (86.9 E, 28 N), 55 degrees from the vertical. */
#define CLOSEUP "86.9,28,1500,55"

static void run_displacement_check(const char *glb, const char *dir, char *out, size_t size) {
    char cmd[8192];
    snprintf(cmd, sizeof cmd,
             "blender -b --factory-startup --python '%s/tests/tools/blender_check_displacement.py' "
             "-- '%s/scripts/blender_import.py' '%s' '%s' " CLOSEUP " 2>&1",
             pg_test_source_dir(), pg_test_source_dir(), glb, dir);
    int rc = fixture_sh(cmd, out, size);
    const char *p = strstr(out, "FACES");
    printf("%s\n", p ? p : out);
    assert_int_equal(rc, 0);
}

static void test_blender_script_displacement(void **s) {
    (void)s;
    static char out[1 << 17];
    char dir[1024], args[2048], glb[1200], path[3][1300];
    fixture_planet_dir("export_blender_disp", 2, 64, dir, sizeof dir);
    snprintf(args, sizeof args, "export '%s' --no-previews -q", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    snprintf(glb, sizeof glb, "%s/planet.glb", dir);
    run_displacement_check(glb, dir, out, sizeof out);
    assert_int_equal(figure(out, "FACES "), 6);
    assert_int_equal(figure(out, "DISPLACED "), 6);
    assert_int_equal(figure(out, "CALIBRATED "), 6);
    assert_int_equal(figure(out, "ADAPTIVE "), 1);
    assert_true(figure_double(out, "SEA_ERROR_M ") < 1.0); /* float32 at 6400 km: 0.5 m */
    double offset = figure_double(out, "HEIGHT_OFFSET "),
           scale = figure_double(out, "HEIGHT_SCALE ");
    assert_true(scale > 0);
    const char *names[3] = {"displaced.png", "flat.png", "heights.exr"};
    pg_image img[3];
    pg_error err = {0};
    for (int i = 0; i < 3; i++) {
        snprintf(path[i], sizeof path[i], "%s/%s", dir, names[i]);
        assert_int_equal(pg_image_read(path[i], 0, &img[i], &err), PG_OK);
        assert_int_equal(img[i].width, img[0].width);
        assert_int_equal(img[i].height, img[0].height);
    }
    long mountains, lowland, frame = (long)img[0].width * img[0].height;
    double dm = masked_difference(&img[0], &img[1], &img[2], offset, scale, 3000, 1e9, &mountains);
    double dl = masked_difference(&img[0], &img[1], &img[2], offset, scale, 0, 200, &lowland);
    printf("displaced vs flat: mean difference %.4f over %ld mountain pixels (above 3000 m), "
           "%.4f over %ld lowland pixels (0..200 m)\n",
           dm, mountains, dl, lowland);
    assert_true(mountains > frame / 20 && lowland > frame / 50); /* the frame holds both */
    assert_true(dm > 0.03);
    assert_true(dm > 3 * dl);
    for (int i = 0; i < 3; i++)
        pg_image_free(&img[i]);
}

/* The Earth fixture (6 x tiles^2 x tile_size^2) saved as tiles in DIR/tiled (the layout
 * of generate --output-layout tiled), with each tile's .glb when glb; DIR and the tiled
 * directory go to dir and tiled. */
static void tiled_fixture(const char *tag, int tiles, int tile_size, bool glb, char *dir,
                          char *tiled) {
    pg_planet p;
    pg_error err = {0};
    fixture_planet_dir(tag, tiles, tile_size, dir, 1024);
    assert_int_equal(pg_planet_load(dir, &p, &err), PG_OK);
    snprintf(tiled, 1100, "%s/tiled", dir);
    assert_int_equal(mkdir(tiled, 0777), 0);
    pg_planet_dir_paths paths = {.dir = tiled};
    const int nt = 6 * p.tiles * p.tiles;
    pg_export_opts o;
    pg_export_opts_default(&o);
    assert_int_equal(pg_planet_save_tiles(&p, 0, nt, pg_planet_dir_path, &paths, &err), PG_OK);
    if (glb)
        assert_int_equal(
            pg_export_tiles_glb(&p, 0, nt, NULL, &o, pg_planet_dir_path, &paths, NULL, &err),
            PG_OK);
    assert_int_equal(pg_planet_save_index_glb(&p, glb, pg_planet_dir_path, &paths, &err), PG_OK);
    pg_planet_free(&p);
}

/* A tiled planet directory (index.json, no planet.glb): the script has planetgen view
 * assemble viewer/planet.glb from the tiles and displaces all six faces. */
static void test_blender_script_tiled(void **s) {
    (void)s;
    static char out[1 << 16];
    char dir[1024], tiled[1100], cmd[8192], path[1300];
    tiled_fixture("export_blender_tiled", 1, 32, false, dir, tiled);
    snprintf(path, sizeof path, "%s/scene.blend", dir);
    snprintf(cmd, sizeof cmd,
             "blender -b --factory-startup --python '%s/scripts/blender_import.py' -- '%s' "
             "--planetgen '%s' --save '%s' 2>&1",
             pg_test_source_dir(), tiled, pg_test_cli(), path);
    int rc = fixture_sh(cmd, out, sizeof out);
    const char *line = strstr(out, "planetgen: ");
    printf("%s\n", line ? line : out);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(out, "6 faces displaced"));
    assert_true(pg_test_file_nonempty(path));
    snprintf(path, sizeof path, "%s/viewer/planet.glb", tiled);
    assert_true(pg_test_file_nonempty(path));
}

/* A tiled planet with its .glb per tile (as generate writes it): the script imports the
 * 24 files and joins them into one closed surface - after welding the bit-identical
 * border vertices, Euler's 6 M^2 + 2 vertices and 6 M^2 quads, no boundary edge (a
 * crack would leave some) - and displaces every tile's material. */
static void test_blender_script_tile_glbs(void **s) {
    (void)s;
    static char out[1 << 16];
    char dir[1024], tiled[1100], cmd[8192], want[128];
    tiled_fixture("export_blender_tile_glbs", 2, 32, true, dir, tiled);
    const int m = pg_export_default_mesh_res(2, 32);
    snprintf(cmd, sizeof cmd,
             "blender -b --factory-startup --python '%s/scripts/blender_import.py' --python-expr "
             "\"import bpy, bmesh; o = bpy.data.objects['planet']; bm = bmesh.new(); "
             "bm.from_mesh(o.data); print('planetgen-check vertices %%d quads %%d boundary %%d "
             "materials %%d' %% (len(bm.verts), len(bm.faces), sum(e.is_boundary for e in "
             "bm.edges), len(o.data.materials)))\" -- '%s' 2>&1",
             pg_test_source_dir(), tiled);
    int rc = fixture_sh(cmd, out, sizeof out);
    const char *line = strstr(out, "planetgen: ");
    printf("%s\n", line ? line : out);
    assert_int_equal(rc, 0);
    assert_non_null(strstr(out, "24 tile files"));
    assert_non_null(strstr(out, "24 faces displaced"));
    snprintf(want, sizeof want, "planetgen-check vertices %d quads %d boundary 0 materials 24",
             6 * m * m + 2, 6 * m * m);
    assert_non_null(strstr(out, want));
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_blender_import_and_render),
                                       cmocka_unit_test(test_blender_script_displacement),
                                       cmocka_unit_test(test_blender_script_tiled),
                                       cmocka_unit_test(test_blender_script_tile_glbs)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
