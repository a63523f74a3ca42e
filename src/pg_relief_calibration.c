/* pg_relief_calibration.c - Blue Marble water mask and the grey -> metres mapping
 * for Marble's 8-bit relief.
 *
 * The relief is a grey rendering of elevation with bathymetry, not metres. Two facts
 * pin it down: where sea level lies on the grey ramp, and how the ramp spreads above
 * and below it. Sea level is estimated from the data: the grey threshold that best
 * separates Blue Marble's water pixels from its land pixels (maximum agreement).
 * The spread is fixed by known extremes: the brightest land grey is Everest's
 * +8848 m and the darkest ocean grey the Challenger Deep's -10935 m, with the ramp
 * linear between each extreme and sea level. data/README.md discusses the limits. */
#include "planetgen/pg_exemplar.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PG_EVEREST_M 8848.0f
#define PG_CHALLENGER_M -10935.0f

void pg_exemplar_water_mask(const float *albedo, int width, int height, uint8_t *mask) {
    size_t n = (size_t)width * height;
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++) {
        float r = albedo[3 * i], g = albedo[3 * i + 1], b = albedo[3 * i + 2];
        /* Water is blue-dominant and not bright: deep ocean is dark navy, shelves are
         * teal (g close to b). Ice and cloud-free snow are bright and grey-white, land
         * is green, brown or tan (r >= b). */
        mask[i] = (b > r + 0.03f && b >= g - 0.02f && b < 0.6f) ? 1 : 0;
    }
}

/* Histogram of grey (256 bins, values rounded) split by the water mask. */
static void grey_histograms(const float *grey, const uint8_t *water, size_t n, double *hw,
                            double *hl) {
    memset(hw, 0, 256 * sizeof *hw);
    memset(hl, 0, 256 * sizeof *hl);
    for (size_t i = 0; i < n; i++) {
        int g = (int)lrintf(grey[i]);
        g = g < 0 ? 0 : (g > 255 ? 255 : g);
        if (water[i])
            hw[g] += 1;
        else
            hl[g] += 1;
    }
}

pg_status pg_exemplar_calibrate(const float *grey, const uint8_t *water, int width, int height,
                                pg_calibration *c, pg_error *err) {
    size_t n = (size_t)width * height;
    double hw[256], hl[256];
    grey_histograms(grey, water, n, hw, hl);
    double total_w = 0, total_l = 0;
    int gmin = 255, gmax = 0;
    for (int g = 0; g < 256; g++) {
        total_w += hw[g];
        total_l += hl[g];
        if (hw[g] + hl[g] > 0) {
            gmin = g < gmin ? g : gmin;
            gmax = g > gmax ? g : gmax;
        }
    }
    if (total_w < 0.01 * n || total_l < 0.01 * n)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "cannot calibrate the relief: the albedo shows %.1f%% water; give "
                            "--sea-level and --height-scale",
                            100.0 * total_w / n);
    /* Agreement(t) = water below t + land at or above t; maximise over t. */
    double below_w = 0, below_l = 0, best = -1;
    int best_t = 0;
    for (int t = 0; t <= 256; t++) {
        double agree = below_w + (total_l - below_l);
        if (agree > best) {
            best = agree;
            best_t = t;
        }
        if (t < 256) {
            below_w += hw[t];
            below_l += hl[t];
        }
    }
    /* Sea level sits between the last water grey and the first land grey. */
    float sea = best_t - 0.5f;
    if (sea <= gmin || sea >= gmax)
        return pg_error_set(err, PG_ERR_BADINPUT, "cannot calibrate the relief: sea level grey "
                                                  "%.1f is outside its range",
                            sea);
    c->nknots = 3;
    c->grey[0] = (float)gmin;
    c->metres[0] = PG_CHALLENGER_M;
    c->grey[1] = sea;
    c->metres[1] = 0.0f;
    c->grey[2] = (float)gmax;
    c->metres[2] = PG_EVEREST_M;
    c->sea_grey = sea;
    c->mask_agreement = best / (double)n;
    c->from_mask = true;
    return PG_OK;
}

float pg_calibration_apply(const pg_calibration *c, float grey) {
    int k = 1;
    while (k < c->nknots - 1 && grey > c->grey[k]) k++;
    float g0 = c->grey[k - 1], g1 = c->grey[k];
    float t = (grey - g0) / (g1 - g0);
    return c->metres[k - 1] + t * (c->metres[k] - c->metres[k - 1]);
}
