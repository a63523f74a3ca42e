/* test_export_f3d.c - f3d (Debian's VTK-based viewer) renders the exported .glb of
 * the default planet offscreen to a PNG in which at least 20% of the pixels are not
 * background. f3d needs an X display even for --output, so it runs under xvfb-run.
 * Both the embedded and the external-texture variants are rendered. */
#include "export_fixture.h"

#include <stdio.h>
#include <string.h>

static void render(const char *glb, const char *png) {
    char cmd[4096], out[16384];
    snprintf(cmd, sizeof cmd,
             "xvfb-run -a f3d --output='%s' --resolution=400,400 --camera-view-angle=18 '%s' "
             "2>&1",
             png, glb);
    int rc = fixture_sh(cmd, out, sizeof out);
    if (rc != 0) printf("%s\n", out);
    assert_int_equal(rc, 0);
    double fg = fixture_foreground_fraction(png);
    printf("f3d %s: %.1f%% of pixels differ from the background\n", png, 100 * fg);
    assert_true(fg >= 0.20);
}

static void test_f3d_renders_globe(void **s) {
    (void)s;
    if (fixture_sh("command -v f3d >/dev/null && command -v xvfb-run >/dev/null", NULL, 0) != 0)
        fail_msg("f3d or xvfb-run is not installed: run scripts/bootstrap");
    char dir[1024], args[4096], glb[1200], png[1200];
    fixture_planet_dir("export_f3d", 4, 256, dir, sizeof dir);
    snprintf(args, sizeof args, "export '%s' --no-previews -q", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    snprintf(glb, sizeof glb, "%s/planet.glb", dir);
    snprintf(png, sizeof png, "%s/f3d.png", dir);
    render(glb, png);
    snprintf(args, sizeof args, "export '%s' -o '%s/ext' --external-textures --no-previews -q", dir,
             dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    snprintf(glb, sizeof glb, "%s/ext/planet.glb", dir);
    snprintf(png, sizeof png, "%s/f3d_external.png", dir);
    render(glb, png);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_f3d_renders_globe)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
