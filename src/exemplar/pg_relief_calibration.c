/* pg_relief_calibration.c - Blue Marble water mask and the grey -> metres mapping
 * for Marble's 8-bit relief.
 *
 * The relief is a grey rendering of elevation with bathymetry, not metres. Two facts
 * pin it down: where sea level lies on the grey ramp, and how the ramp spreads above
 * and below it. Sea level is estimated from the data: the grey threshold that best
 * separates Blue Marble's water pixels from its land pixels (maximum agreement).
 * For an arbitrary grey relief the spread is fixed by known extremes: the brightest
 * land grey is Everest's +8848 m and the darkest ocean grey the Challenger Deep's
 * -10935 m, linear between each extreme and sea level.
 *
 * Marble's relief is not linear (lowlands are already bright: the Amazon at 50 m is
 * 14 grey steps above the coast, Lake Victoria at 1135 m is 85), so for it the
 * ramp is read off the data itself: at surveyed reference points with flat, known
 * elevations (lakes, ice domes, abyssal plains) the relief's local median grey
 * becomes a knot of a piecewise-linear map. data/README.md lists the points and
 * discusses the limits. */
#include "planetgen/pg_exemplar.h"

#include <math.h>
#include <stddef.h>
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
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "cannot calibrate the relief: sea level grey "
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
    c->reference_points = false;
    return PG_OK;
}

typedef struct ref_point {
    const char *name;
    double lat, lon, metres;
} ref_point;

/* Flat, well-surveyed places, so that a 7x7 median (26 km at 10800 px) is their
 * elevation. The extremes are the map's darkest and brightest greys instead: the
 * Challenger Deep and Everest are narrower than a pixel window. */
static const ref_point marble_refs[] = {
    {"Nares Abyssal Plain", 25.0, -62.0, -5850},
    {"Mid-Atlantic Ridge crest, 30N", 30.0, -42.0, -2600},
    {"central North Sea", 56.0, 3.0, -90},
    {"Amazon floodplain at Manaus", -3.1, -60.0, 50},
    {"Moscow", 55.75, 37.6, 150},
    {"Lake Victoria", -1.0, 33.0, 1135},
    {"Greenland ice sheet summit", 72.58, -38.46, 3216},
    {"Lake Titicaca", -15.9, -69.3, 3812},
    {"Dome A, Antarctica", -80.37, 77.35, 4093},
};

static int cmp_float(const void *a, const void *b) {
    float x = *(const float *)a, y = *(const float *)b;
    return x < y ? -1 : x > y;
}

static float median_grey(const pg_image *r, double lat, double lon) {
    int cx = (int)((lon + 180.0) / 360.0 * r->width);
    int cy = (int)((90.0 - lat) / 180.0 * r->height);
    float v[49];
    int k = 0;
    for (int dy = -3; dy <= 3; dy++) {
        for (int dx = -3; dx <= 3; dx++) {
            int x = ((cx + dx) % r->width + r->width) % r->width;
            int y = cy + dy < 0 ? 0 : (cy + dy >= r->height ? r->height - 1 : cy + dy);
            v[k++] = r->data[(size_t)y * r->width + x];
        }
    }
    qsort(v, k, sizeof *v, cmp_float);
    return v[k / 2];
}

static void add_knot(pg_calibration *c, float grey, float metres) {
    int i = c->nknots++;
    while (i > 0 && c->metres[i - 1] > metres) {
        c->grey[i] = c->grey[i - 1];
        c->metres[i] = c->metres[i - 1];
        i--;
    }
    c->grey[i] = grey;
    c->metres[i] = metres;
}

pg_status pg_calibration_marble_refs(const pg_image *relief, pg_calibration *c, pg_error *err) {
    /* Comparisons rather than fminf/fmaxf, which are library calls: they reduce in
     * parallel (no "simd" clause: clang with the sanitizers cannot vectorise the loop
     * and -Werror turns its notice into an error), and give the same extremes (a NaN
     * fails both comparisons, as fminf/fmaxf ignore it). */
    float gmin = INFINITY, gmax = -INFINITY;
    const float *d = relief->data;
    const ptrdiff_t n = (ptrdiff_t)relief->width * relief->height;
#pragma omp parallel for reduction(min : gmin) reduction(max : gmax)
    for (ptrdiff_t i = 0; i < n; i++) {
        gmin = d[i] < gmin ? d[i] : gmin;
        gmax = d[i] > gmax ? d[i] : gmax;
    }
    c->nknots = 0;
    add_knot(c, gmin, PG_CHALLENGER_M);
    add_knot(c, c->sea_grey, 0.0f);
    add_knot(c, gmax, PG_EVEREST_M);
    for (size_t i = 0; i < sizeof marble_refs / sizeof *marble_refs; i++)
        add_knot(c, median_grey(relief, marble_refs[i].lat, marble_refs[i].lon),
                 (float)marble_refs[i].metres);
    /* Knots are sorted by metres; the ramp must rise with them. */
    for (int i = 1; i < c->nknots; i++)
        if (!(c->grey[i] > c->grey[i - 1]))
            return pg_error_set(err, PG_ERR_BADINPUT,
                                "relief calibration: grey does not rise with elevation near "
                                "%.0f m (is this Marble's relief?)",
                                c->metres[i]);
    c->reference_points = true;
    return PG_OK;
}

double pg_exemplar_mask_agreement(const float *height, float sea_level, const uint8_t *water,
                                  size_t n) {
    size_t agree = 0;
    for (size_t i = 0; i < n; i++)
        agree += (height[i] <= sea_level) == (water[i] != 0);
    return n ? (double)agree / (double)n : 0.0;
}

float pg_calibration_apply(const pg_calibration *c, float grey) {
    int k = 1;
    while (k < c->nknots - 1 && grey > c->grey[k])
        k++;
    float g0 = c->grey[k - 1], g1 = c->grey[k];
    float t = (grey - g0) / (g1 - g0);
    return c->metres[k - 1] + t * (c->metres[k] - c->metres[k - 1]);
}
