/* test_export_blender.c - Blender (Debian's blender, headless) imports the exported
 * default planet's .glb with its own glTF importer, finds 6 primitives, each with a
 * base-colour image texture and a normal map fed by an image, and renders a frame
 * with Cycles on the CPU that shows the globe (not blank). The script is
 * tests/tools/blender_check_glb.py. */
#include "export_fixture.h"

#include <stdio.h>
#include <string.h>

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

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_blender_import_and_render)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
