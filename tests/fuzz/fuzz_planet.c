/* fuzz_planet.c - libFuzzer harness for the planet-directory readers that
 * `planetgen export` and `planetgen inspect` use (pg_planet_load: planet.json
 * through nlohmann/json, face PNGs through OpenImageIO, height.exr through
 * OpenEXR's C API).
 *
 * A small valid planet directory is made once per process. The first input byte
 * picks which of its files the rest of the input replaces; then the directory is
 * loaded, and the original file is restored for the next run. */
#include "fuzz_common.h"

#include "planetgen/pg_planet.h"

#include <string.h>

static void ensure_planet(const char *dir) {
    char meta[600];
    snprintf(meta, sizeof meta, "%s/planet.json", dir);
    struct stat st;
    if (stat(meta, &st) == 0) return;
    pg_planet p;
    pg_error err = {0};
    if (pg_planet_alloc(&p, PG_CUBE_EQUIANGULAR, 1, 16, pg_ellipsoid_sphere(), &err) != PG_OK)
        return;
    for (int f = 0; f < PG_CUBE_NFACES; f++)
        for (int i = 0; i < 16 * 16; i++) {
            p.height[f][i] = (float)(i * 3 - 200 * f);
            p.albedo[f][3 * i] = 0.1f * f;
        }
    pg_planet_save_dir(&p, dir, &err);
    pg_planet_free(&p);
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s/orig' && cp '%s'/*.* '%s/orig/'", dir, dir, dir);
    if (system(cmd) != 0) return;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    static const char *const names[] = {"planet.json", "height.exr", "albedo_+X.png",
                                        "albedo_-Z.png"};
    char dir[256], pdir[300], path[600], orig[600];
    pg_fuzz_dir(dir, sizeof dir);
    snprintf(pdir, sizeof pdir, "%s/planet", dir);
    mkdir(pdir, 0700);
    ensure_planet(pdir);
    const char *name = names[data[0] & 3];
    snprintf(path, sizeof path, "%s/%s", pdir, name);
    snprintf(orig, sizeof orig, "%s/orig/%s", pdir, name);
    if (pg_fuzz_write(path, data + 1, size - 1) != 0) return 0;
    pg_planet p;
    pg_error err = {0};
    if (pg_planet_load(pdir, &p, &err) == PG_OK) pg_planet_free(&p);
    char cmd[1300];
    snprintf(cmd, sizeof cmd, "cp '%s' '%s'", orig, path);
    if (system(cmd) != 0) abort();
    return 0;
}
