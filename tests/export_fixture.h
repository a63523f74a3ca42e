/* export_fixture.h - planet directories for the export tests, made from the real
 * Earth exemplar (pg_planet_from_exemplar + pg_planet_save), and small helpers to
 * run external tools and read their figures. Header-only: each export test is its
 * own executable. */
#ifndef EXPORT_FIXTURE_H
#define EXPORT_FIXTURE_H

#include "pg_test.h"

#include "planetgen/pg_planet.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

/* The Earth reprojected onto a planet of 6 x tiles^2 x tile_size^2, saved as a
 * planet directory in the scratch dir `tag`; the path goes to dir. */
static inline void fixture_planet_dir(const char *tag, int tiles, int tile_size, char *dir,
                                      size_t size) {
    pg_error err = {0};
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    o.grid_width = 2700; /* the Blue Marble's width: enough for faces up to 1024 */
    pg_exemplar ex;
    assert_int_equal(pg_exemplar_load(&o, &ex, &err), PG_OK);
    pg_planet p;
    assert_int_equal(
        pg_planet_alloc(&p, PG_CUBE_EQUIANGULAR, tiles, tile_size, pg_ellipsoid_wgs84(), &err),
        PG_OK);
    p.seed = 42;
    assert_int_equal(pg_planet_from_exemplar(&p, &ex, 2, &err), PG_OK);
    pg_test_scratch_dir(tag, dir, size);
    assert_int_equal(pg_planet_save_dir(&p, dir, &err), PG_OK);
    pg_planet_free(&p);
    pg_exemplar_free(&ex);
}

/* The Earth reprojected onto an in-memory planet of 6 x tiles^2 x tile_size^2 (the
 * exemplar at 1350 columns, faces up to 256). */
static inline void fixture_earth(pg_planet *p, int tiles, int tile_size) {
    pg_error err = {0};
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    o.grid_width = 1350;
    pg_exemplar ex;
    assert_int_equal(pg_exemplar_load(&o, &ex, &err), PG_OK);
    assert_int_equal(
        pg_planet_alloc(p, PG_CUBE_EQUIANGULAR, tiles, tile_size, pg_ellipsoid_wgs84(), &err),
        PG_OK);
    assert_int_equal(pg_planet_from_exemplar(p, &ex, 1, &err), PG_OK);
    pg_exemplar_free(&ex);
}

/* `planetgen export DIR -o DIR/bad OPTS` must exit 2 with `needle` in its message
 * and write nothing. */
static inline void fixture_export_refused(const char *dir, const char *opts, const char *needle) {
    char args[4096], err[4096], out[1200];
    snprintf(out, sizeof out, "%s/bad", dir);
    snprintf(args, sizeof args, "export '%s' -o '%s' %s", dir, out, opts);
    int rc = pg_test_run_cli(args, NULL, 0, err, sizeof err);
    printf("%s -> %d: %s", opts, rc, err);
    assert_int_equal(rc, 2);
    assert_non_null(strstr(err, needle));
    assert_int_equal(pg_test_count_files(out), 0); /* nothing written */
}

/* Run a shell command, capturing its stdout into out; returns the exit status. */
static inline int fixture_sh(const char *cmd, char *out, size_t size) {
    FILE *f = popen(cmd, "r");
    if (!f) return -1;
    size_t n = 0;
    if (out && size) {
        n = fread(out, 1, size - 1, f);
        out[n] = '\0';
    } else {
        char tmp[4096];
        while (fread(tmp, 1, sizeof tmp, f) > 0) {
        }
    }
    int st = pclose(f);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* Fraction of pixels of an image that differ from its corner pixel (the background)
 * by more than 8/255 in some channel. */
static inline double fixture_foreground_fraction(const char *png) {
    pg_image img;
    pg_error err = {0};
    if (pg_image_read(png, 0, &img, &err) != PG_OK) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    int ch = img.channels < 3 ? img.channels : 3;
    size_t np = (size_t)img.width * img.height, fg = 0;
    for (size_t i = 0; i < np; i++) {
        int diff = 0;
        for (int c = 0; c < ch; c++) {
            float d = (img.data[i * img.channels + c] - img.data[c]) * img.unit_scale;
            diff |= d > 8.0f / 255 || d < -8.0f / 255;
        }
        fg += (size_t)diff;
    }
    pg_image_free(&img);
    return (double)fg / (double)np;
}

#endif
