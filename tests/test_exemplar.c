/* test_exemplar.c - the default exemplar from marble-qt-data: relief assembly,
 * orientation of both maps, the grey -> metres calibration and the ocean colour
 * repair, on the real data; the repair's rule on small synthetic exemplars. */
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

/* Share of the water texels 1-4 km deep between 58 and 72 S, 60 W to 95 E (Blue
 * Marble's band without bathymetry) that wear the abyss's near-black (blue < 30/255);
 * elsewhere at those depths the ocean is navy, blue 45-130. */
static double band_black_share(const pg_exemplar *ex, const float *albedo) {
    size_t n = 0, black = 0;
    for (int y = 0; y < ex->height; y++) {
        double lat = 90 - (y + 0.5) * 180.0 / ex->height;
        if (lat > -58 || lat < -72) continue;
        for (int x = 0; x < ex->width; x++) {
            double lon = -180 + (x + 0.5) * 360.0 / ex->width;
            size_t i = (size_t)y * ex->width + x;
            float z = ex->elevation[i];
            if (lon < -60 || lon > 95 || z > -1000 || z < -4000) continue;
            n++;
            black += albedo[3 * i + 2] < 30.0f / 255;
        }
    }
    return n ? (double)black / n : NAN;
}

/* The repair on the real data (the default load): the band is repainted, and every
 * other texel is Blue Marble's own byte; without it (--no-repair-ocean), every texel is. */
static void test_ocean_repair_blue_marble(void **state) {
    fixture *f = *state;
    pg_error err = {0};
    pg_exemplar rep;
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    assert_true(o.repair_ocean);
    o.repair_ocean = false;
    assert_int_equal(pg_exemplar_load(&o, &rep, &err), PG_OK);
    const pg_exemplar *ex = &f->ex;
    pg_image raw = {0};
    assert_int_equal(pg_image_read(PG_MARBLE_ALBEDO, 0, &raw, &err), PG_OK);
    assert_int_equal(raw.width, ex->width); /* the common grid is the albedo's */
    const size_t n = (size_t)ex->width * ex->height;
    float *rawf = malloc(3 * n * sizeof *rawf);
    assert_non_null(rawf);
    size_t changed = 0, south = 0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            rawf[3 * i + c] = raw.data[i * raw.channels + c] * raw.unit_scale;
    assert_memory_equal(rawf, rep.albedo, 3 * n * sizeof *rawf); /* without the repair */
    assert_true(strstr(rep.notes, "repainted") == NULL);
    for (size_t i = 0; i < n; i++) {
        int diff = 0;
        for (int c = 0; c < 3; c++)
            diff |= rawf[3 * i + c] != ex->albedo[3 * i + c];
        if (!diff) continue;
        changed++;
        size_t y = i / (size_t)ex->width;
        south += 90 - (y + 0.5) * 180.0 / ex->height < -55;
        assert_true(ex->elevation[i] < ex->sea_level); /* only the ocean */
        for (int c = 0; c < 3; c++)                    /* on the 8-bit grid */
            assert_float_equal(ex->albedo[3 * i + c] * 255, roundf(ex->albedo[3 * i + c] * 255),
                               1e-3);
    }
    double before = band_black_share(ex, rawf), after = band_black_share(ex, ex->albedo);
    print_message("repainted %zu texels (%.0f%% south of 55 S); band at 1-4 km black: %.2f -> "
                  "%.3f\n",
                  changed, 100.0 * south / changed, before, after);
    assert_true(strstr(ex->notes, "ocean texels repainted") != NULL);
    assert_true(before > 0.5);
    assert_true(after < 0.05);
    assert_true(changed > 20000 && changed < 0.05 * n);
    assert_true(south > 0.7 * changed);
    free(rawf);
    pg_image_free(&raw);
    pg_exemplar_free(&rep);
}

/* A synthetic exemplar: ocean whose colour follows depth (blue 200 at the coast down to
 * 20 at 5 km, as Blue Marble's), depth rising from 5 km to 0 along x. The water rule
 * (blue under 0.6) leaves the shallowest 1.3 km out of the curve, so the squares
 * below sit in 2.6-3.1 km of water. */
static void synthetic(pg_exemplar *ex, int w, int h, int follows) {
    memset(ex, 0, sizeof *ex);
    ex->width = w, ex->height = h;
    ex->albedo = malloc((size_t)3 * w * h * sizeof *ex->albedo);
    ex->elevation = malloc((size_t)w * h * sizeof *ex->elevation);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            double d = 5000.0 * (w - x) / w; /* metres below sea level */
            ex->elevation[i] = (float)-d;
            int b = follows ? (int)lround(200 - 180 * d / 5000) : 90;
            int g = follows ? (int)lround(120 - 120 * d / 5000) : 40;
            ex->albedo[3 * i] = 2.0f / 255;
            ex->albedo[3 * i + 1] = (float)g * (1.0f / 255);
            ex->albedo[3 * i + 2] = (float)b * (1.0f / 255);
        }
}

/* paint a square of side s at (x0, y0) the abyss's colour (r, 0, 18) */
static void dark_square(pg_exemplar *ex, int x0, int y0, int s, int r) {
    for (int y = y0; y < y0 + s; y++)
        for (int x = x0; x < x0 + s; x++) {
            float *a = ex->albedo + 3 * ((size_t)y * ex->width + x);
            a[0] = (float)r * (1.0f / 255), a[1] = 0, a[2] = 18.0f / 255;
        }
}

static void test_ocean_repair_rule(void **state) {
    (void)state;
    const int w = 400, h = 200; /* 80 000 texels: a region needs 16 */
    pg_error err = {0};
    uint64_t rep = 0;
    pg_exemplar ex, ref;
    /* a large dark square in 1-2 km of water is repainted to the colour around it; a
     * dark square of 9 texels (under the region size) and one that is redder than the
     * curve (a different hue, not missing shading) stay */
    synthetic(&ex, w, h, 1);
    synthetic(&ref, w, h, 1);
    dark_square(&ex, 150, 50, 40, 2);
    dark_square(&ex, 150, 150, 3, 2);
    dark_square(&ex, 200, 120, 20, 60);
    assert_int_equal(pg_exemplar_repair_ocean(&ex, &rep, &err), PG_OK);
    assert_int_equal(rep, 40 * 40);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            int in_big = x >= 150 && x < 190 && y >= 50 && y < 90;
            for (int c = 0; c < 3; c++) {
                float v = ex.albedo[3 * i + c], r = ref.albedo[3 * i + c];
                if (in_big) /* the curve's colour: within 2 steps of the truth */
                    assert_true(fabsf(v - r) * 255 <= 2.01f);
                else if (!(x >= 150 && x < 153 && y >= 150 && y < 153) &&
                         !(x >= 200 && x < 220 && y >= 120 && y < 140))
                    assert_true(v == r); /* bit for bit */
            }
        }
    float *small = ex.albedo + 3 * ((size_t)151 * w + 151), *red;
    assert_true(small[2] == 18.0f / 255); /* left dark */
    red = ex.albedo + 3 * ((size_t)130 * w + 210);
    assert_true(red[0] == 60.0f * (1.0f / 255) && red[2] == 18.0f / 255);
    pg_exemplar_free(&ex);
    /* an ocean of one colour: the dark square is repainted that colour */
    synthetic(&ex, w, h, 0);
    dark_square(&ex, 150, 50, 40, 2);
    assert_int_equal(pg_exemplar_repair_ocean(&ex, &rep, &err), PG_OK);
    assert_int_equal(rep, 40 * 40);
    float *sq = ex.albedo + 3 * ((size_t)70 * w + 170);
    assert_true(sq[1] == 40.0f * (1.0f / 255) && sq[2] == 90.0f * (1.0f / 255));
    pg_exemplar_free(&ex);
    /* texture within the curve's reach (blue and green +-15 steps, hashed per texel)
     * is the ocean's own variety: nothing changes */
    synthetic(&ex, w, h, 1);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        uint32_t k = (uint32_t)i * 2654435761u;
        int d = (int)(k >> 27) - 15; /* -15..16 */
        for (int c = 1; c < 3; c++) {
            float v = ex.albedo[3 * i + c] * 255 + (float)(d > 15 ? 15 : d);
            ex.albedo[3 * i + c] = fminf(255, fmaxf(0, v)) * (1.0f / 255);
        }
    }
    float *before = malloc((size_t)3 * w * h * sizeof *before);
    assert_non_null(before);
    memcpy(before, ex.albedo, (size_t)3 * w * h * sizeof *before);
    assert_int_equal(pg_exemplar_repair_ocean(&ex, &rep, &err), PG_OK);
    assert_int_equal(rep, 0);
    assert_memory_equal(before, ex.albedo, (size_t)3 * w * h * sizeof *before);
    free(before);
    pg_exemplar_free(&ex);
    pg_exemplar_free(&ref);
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
        cmocka_unit_test(test_ocean_repair_blue_marble),
        cmocka_unit_test(test_ocean_repair_rule),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
