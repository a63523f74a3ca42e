/* fuzz_image.c - libFuzzer harness for the image and exemplar loaders.
 *
 * The first input byte picks the file type (the extension decides which decoder
 * OpenImageIO tries first) and the role; the rest is the file. The file is read as a
 * plain image, as an EXR through OpenEXR's C API, and as the height map of an
 * exemplar whose albedo is a small valid map, so the loader's own checks (size, 2:1,
 * NaN/Inf, calibration) run on whatever decodes. Limits are small so that absurd
 * headers must be refused before allocation rather than by running out of memory. */
#include "fuzz_common.h"

#include "planetgen/pg_exemplar.h"

#include <string.h>

static const char *const exts[] = {".png", ".jpg", ".tif", ".exr"};

static void ensure_albedo(const char *dir, char *path, size_t size) {
    snprintf(path, size, "%s/albedo.png", dir);
    struct stat st;
    if (stat(path, &st) == 0) return;
    pg_image img;
    pg_error err = {0};
    if (pg_image_alloc(&img, 64, 32, 3, &err) != PG_OK) return;
    for (int i = 0; i < 64 * 32; i++) {
        int water = (i % 64) < 40; /* a map that is partly "ocean blue" */
        img.data[3 * i + 0] = water ? 0.05f : 0.4f;
        img.data[3 * i + 1] = water ? 0.10f : 0.35f;
        img.data[3 * i + 2] = water ? 0.35f : 0.2f;
    }
    pg_image_write_png(path, &img, 8, &err);
    pg_image_free(&img);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    char dir[256], path[512], albedo[512];
    pg_fuzz_dir(dir, sizeof dir);
    snprintf(path, sizeof path, "%s/input%s", dir, exts[data[0] & 3]);
    if (pg_fuzz_write(path, data + 1, size - 1) != 0) return 0;
    pg_error err = {0};
    pg_image img;
    if (pg_image_read(path, 1 << 22, &img, &err) == PG_OK) pg_image_free(&img);
    pg_error_clear(&err);
    if ((data[0] & 3) == 3 && pg_image_read_exr(path, NULL, &img, &err) == PG_OK)
        pg_image_free(&img);
    pg_error_clear(&err);
    ensure_albedo(dir, albedo, sizeof albedo);
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    o.albedo_path = albedo;
    o.height_path = path;
    o.max_pixels = 1 << 22;
    pg_exemplar ex;
    if (pg_exemplar_load(&o, &ex, &err) == PG_OK) pg_exemplar_free(&ex);
    return 0;
}
