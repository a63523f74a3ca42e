/* test_exemplar.c - the default exemplar from marble-qt-data: relief assembly,
 * orientation of both maps, and the grey -> metres calibration, on the real data. */
#include "pg_marble.h"
#include "pg_test.h"

#include "planetgen/pg_equirect.h"
#include "planetgen/pg_exemplar.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct fixture {
    pg_exemplar ex;
    pg_image relief;
} fixture;

static int setup(void **state) {
    fixture *f = calloc(1, sizeof *f);
    pg_error err = {0};
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    if (pg_exemplar_load(&o, &f->ex, &err) != PG_OK ||
        pg_exemplar_assemble_relief(PG_MARBLE_RELIEF_DIR, 8, 16, &f->relief, &err) != PG_OK) {
        fprintf(stderr, "cannot load the default exemplar: %s\n", err.msg);
        free(f);
        return -1;
    }
    *state = f;
    return 0;
}

static int teardown(void **state) {
    fixture *f = *state;
    pg_exemplar_free(&f->ex);
    pg_image_free(&f->relief);
    free(f);
    return 0;
}

static float height_at(const pg_exemplar *ex, double lat, double lon) {
    float h;
    pg_equirect_sample(ex->elevation, ex->width, ex->height, 1, lat, lon, &h);
    return h;
}

static void albedo_at(const pg_exemplar *ex, double lat, double lon, float *rgb) {
    pg_equirect_sample(ex->albedo, ex->width, ex->height, 3, lat, lon, rgb);
}

static void test_relief_assembly_size(void **state) {
    fixture *f = *state;
    assert_int_equal(f->relief.width, 10800);
    assert_int_equal(f->relief.height, 5400);
    assert_int_equal(f->relief.channels, 1);
    /* Tiles must land in their place: row 0 is the north. The Tibetan plateau at
     * 32N 90E is far brighter (higher) than the Bay of Bengal at 15N 88E. */
    float tibet, bengal;
    pg_equirect_sample(f->relief.data, 10800, 5400, 1, 32, 90, &tibet);
    pg_equirect_sample(f->relief.data, 10800, 5400, 1, 15, 88, &bengal);
    assert_true(tibet > bengal + 100);
    /* Mirror check: the Andes (15S 70W) are high, the same latitude in the eastern
     * Indian Ocean (15S 70E) is ocean. */
    float andes, indian;
    pg_equirect_sample(f->relief.data, 10800, 5400, 1, -15.9, -69.3, &andes);
    pg_equirect_sample(f->relief.data, 10800, 5400, 1, -15.9, 69.3, &indian);
    assert_true(andes > indian + 100);
}

static void test_heights_in_metres(void **state) {
    fixture *f = *state;
    const pg_exemplar *ex = &f->ex;
    assert_true(height_at(ex, 32, 90) > 4000);   /* Tibet */
    assert_true(height_at(ex, 15, 88) < -1500);  /* Bay of Bengal */
    assert_true(height_at(ex, -3.1, -60) < 400); /* Amazon lowlands */
    assert_true(height_at(ex, -3.1, -60) > 0);
    assert_true(height_at(ex, 72.6, -38.5) > 2500); /* Greenland ice */
    assert_true(height_at(ex, 25, -62) < -4500);    /* Atlantic abyss */
    pg_exemplar_stats s;
    pg_exemplar_compute_stats(ex, &s);
    /* plausible extremes: highest land about +8.8 km, deepest about -11 km (the
     * common grid averages 4x4 relief pixels, so peaks are a little lower) */
    assert_true(s.height_max > 6000 && s.height_max < 9000);
    assert_true(s.height_min < -8000 && s.height_min > -11500);
    /* Earth's land fraction is 29%. */
    assert_true(s.land_fraction > 0.25 && s.land_fraction < 0.33);
}

static void test_blue_marble_orientation(void **state) {
    fixture *f = *state;
    const pg_exemplar *ex = &f->ex;
    float rgb[3];
    /* north up: Greenland's ice (72N 40W) and Antarctica (85S) are white */
    albedo_at(ex, 72, -40, rgb);
    assert_true(rgb[0] > 0.7 && rgb[1] > 0.7 && rgb[2] > 0.7);
    albedo_at(ex, -85, 0, rgb);
    assert_true(rgb[0] > 0.7 && rgb[1] > 0.7 && rgb[2] > 0.7);
    /* Siberia (60N 100E) is land, the same latitude south (60S 100E) is ocean */
    float sib[3], so[3];
    albedo_at(ex, 60, 100, sib);
    albedo_at(ex, -60, 100, so);
    assert_true(sib[0] > so[0] + 0.05);
    assert_true(so[2] > so[0]);
    /* east right: Australia (25S 134E) is red desert, 25S 134W is the Pacific */
    float aus[3], pac[3];
    albedo_at(ex, -25, 134, aus);
    albedo_at(ex, -25, -134, pac);
    assert_true(aus[0] > aus[2] + 0.1);
    assert_true(pac[2] > pac[0] + 0.05);
}

static void test_calibration_agrees_with_water_mask(void **state) {
    fixture *f = *state;
    const pg_exemplar *ex = &f->ex;
    size_t n = (size_t)ex->width * ex->height;
    uint8_t *water = malloc(n);
    pg_exemplar_water_mask(ex->albedo, ex->width, ex->height, water);
    double agree = pg_exemplar_mask_agreement(ex->elevation, ex->sea_level, water, n);
    size_t nw = 0;
    for (size_t i = 0; i < n; i++)
        nw += water[i];
    free(water);
    print_message("below-sea-level vs Blue Marble water: %.2f%% agree (%.1f%% water)\n",
                  100 * agree, 100.0 * nw / n);
    assert_true(agree >= 0.90);
    /* the mask itself must be meaningful: mostly water, but not all */
    assert_true(nw > 0.5 * n && nw < 0.8 * n);
    assert_true(ex->height_is_grey);
    assert_true(ex->calib.reference_points);
    /* knots rise strictly */
    for (int k = 1; k < ex->calib.nknots; k++) {
        assert_true(ex->calib.grey[k] > ex->calib.grey[k - 1]);
        assert_true(ex->calib.metres[k] > ex->calib.metres[k - 1]);
    }
}

/* The fingerprint names the sources as the load does, repeats for the same files and
 * options, and changes with an option or with a file rewritten in place. */
static void test_fingerprint(void **state) {
    fixture *f = *state;
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    uint64_t a, b;
    char an[512], hn[512];
    pg_error err = {0};
    assert_int_equal(pg_exemplar_fingerprint(&o, &a, an, hn, sizeof an, &err), PG_OK);
    assert_string_equal(an, f->ex.albedo_src);
    assert_string_equal(hn, f->ex.height_src);
    assert_int_equal(pg_exemplar_fingerprint(&o, &b, an, hn, sizeof an, &err), PG_OK);
    assert_true(a == b);
    o.sea_level = 1;
    assert_int_equal(pg_exemplar_fingerprint(&o, &b, an, hn, sizeof an, &err), PG_OK);
    assert_true(a != b);
    /* a copy of the albedo, then the same bytes written again: a new modification time */
    char dir[512], copy[700], cmd[1600];
    pg_test_scratch_dir("exemplar-fingerprint", dir, sizeof dir);
    snprintf(copy, sizeof copy, "%s/albedo.jpg", dir);
    snprintf(cmd, sizeof cmd, "cp '%s' '%s'", PG_MARBLE_ALBEDO, copy);
    assert_int_equal(system(cmd), 0);
    pg_exemplar_opts_default(&o);
    o.albedo_path = copy;
    assert_int_equal(pg_exemplar_fingerprint(&o, &a, an, hn, sizeof an, &err), PG_OK);
    assert_string_equal(an, copy);
    snprintf(cmd, sizeof cmd, "touch -d '2001-01-01 00:00:00' '%s'", copy);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(pg_exemplar_fingerprint(&o, &b, an, hn, sizeof an, &err), PG_OK);
    assert_true(a != b);
    /* a missing source: an error, so the caller loads and reports it */
    o.albedo_path = "/nonexistent/albedo.png";
    assert_int_equal(pg_exemplar_fingerprint(&o, &b, an, hn, sizeof an, &err), PG_ERR_IO);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_relief_assembly_size),
        cmocka_unit_test(test_heights_in_metres),
        cmocka_unit_test(test_blue_marble_orientation),
        cmocka_unit_test(test_calibration_agrees_with_water_mask),
        cmocka_unit_test(test_fingerprint),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
