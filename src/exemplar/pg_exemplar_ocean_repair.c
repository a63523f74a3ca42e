/* pg_exemplar_ocean_repair.c - mending ocean texels whose colour contradicts their depth.
 *
 * WHY. Blue Marble's ocean is painted from bathymetry: its colour is a function of depth,
 * teal on the shelves, navy at 3 km, the darkest navy beyond 4.5 km (data/README.md,
 * "Ocean colour repair" gives the curve). Along 60-72 S, between about 60 W and 95 E,
 * the bathymetry stops and a band of the Southern Ocean, rises and slopes included, is
 * painted the abyss's near-black. The synthesis copies that band wherever the ocean is
 * cold, and it showed on every world as a black strip along its southern ice coast.
 *
 * HOW. The albedo's own depth-to-colour curve is measured: the per-channel median
 * colour of every 100 m bin of depth over the water texels (water by elevation and by
 * the colour rule pg_exemplar_water_mask, which keeps ice over the sea out). A texel
 * below sea level is suspect where it is darker than its bin's median by more than
 * PG_OR_DARKER in some channel and brighter in none. A
 * suspect texel alone is ordinary scatter (a seamount one texel off between the two
 * inputs); only 8-connected regions of suspects (the longitude wraps) of at least
 * PG_OR_MIN_SHARE of the grid are repaired. Each texel of such a region takes the curve's
 * colour at its depth, interpolated between bin centres, on the 8-bit grid the albedo
 * came on, so the repaired ocean follows the relief under it.
 *
 * CORRECTNESS. Only texels in large regions that disagree with the albedo's own curve
 * change: an albedo whose ocean colour does not follow depth (a flat ocean colour) has
 * a flat curve, no suspect, and is left as it was; everything outside the regions is
 * untouched bit for bit. Deterministic and independent of the thread count: medians
 * come from integer histograms, and the regions are labelled in texel order. */
#include "planetgen/pg_exemplar.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PG_OR_BIN_M 100.0    /* depth bin */
#define PG_OR_BINS 120       /* 0..12 km */
#define PG_OR_MIN_COUNT 32   /* texels for a bin's median; sparser bins borrow */
#define PG_OR_DARKER 20      /* in 8-bit steps */
#define PG_OR_MIN_SHARE 2e-4 /* of the grid: 730 texels of Blue Marble's 2700 x 1350 */

static int pg_or_byte(float v) {
    long k = lrintf(v * 255.0f);
    return k < 0 ? 0 : (k > 255 ? 255 : (int)k);
}

/* Water here: below sea level and coloured as water (not ice over the sea). */
static int pg_or_water(const pg_exemplar *ex, const uint8_t *wmask, size_t i) {
    return wmask[i] && ex->elevation[i] < ex->sea_level;
}

static int pg_or_bin(const pg_exemplar *ex, size_t i) {
    double d = (ex->sea_level - ex->elevation[i]) / PG_OR_BIN_M;
    return d >= PG_OR_BINS - 1 ? PG_OR_BINS - 1 : (int)d;
}

/* The median byte per channel of each depth bin (curve[3 * bin + c]); a bin with too
 * few texels takes the nearest shallower bin's median (the deepest trenches). Returns
 * 0 when no bin has enough texels. */
static int pg_or_curve(const pg_exemplar *ex, const uint8_t *wmask, float *curve) {
    uint32_t(*h)[3][256] = calloc(PG_OR_BINS, sizeof *h);
    if (!h) return -1;
    const size_t n = (size_t)ex->width * ex->height;
    for (size_t i = 0; i < n; i++)
        if (pg_or_water(ex, wmask, i)) {
            int b = pg_or_bin(ex, i);
            for (int c = 0; c < 3; c++)
                h[b][c][pg_or_byte(ex->albedo[3 * i + c])]++;
        }
    int have = 0, last = -1;
    for (int b = 0; b < PG_OR_BINS; b++) {
        uint64_t total = 0;
        for (int k = 0; k < 256; k++)
            total += h[b][0][k];
        if (total < PG_OR_MIN_COUNT) {
            for (int c = 0; c < 3; c++)
                curve[3 * b + c] = last < 0 ? NAN : curve[3 * last + c];
            continue;
        }
        for (int c = 0; c < 3; c++) {
            uint64_t acc = 0;
            int k = 0;
            while (k < 255 && 2 * (acc + h[b][c][k]) < total + 1)
                acc += h[b][c][k++];
            curve[3 * b + c] = (float)k;
        }
        last = b;
        have = 1;
    }
    free(h);
    return have;
}

/* The curve's colour (bytes) at depth d metres, linear between bin centres. */
static void pg_or_colour(const float *curve, double d, float out[3]) {
    double x = d / PG_OR_BIN_M - 0.5;
    int b0 = x < 0 ? 0 : (int)x;
    if (b0 > PG_OR_BINS - 2) b0 = PG_OR_BINS - 2;
    double t = fmin(1, fmax(0, x - b0));
    for (int c = 0; c < 3; c++) {
        float v0 = curve[3 * b0 + c], v1 = curve[3 * (b0 + 1) + c];
        if (isnan(v1)) v1 = v0;
        if (isnan(v0)) v0 = v1;
        out[c] = (float)(v0 + t * (v1 - v0));
    }
}

/* Suspects are below sea level, whatever their colour: the colour rule of the curve's
 * water calls the band's darkest texels (blue under 8/255) land. Ice over the sea is
 * brighter than the curve, so it is never suspect. */
static void pg_or_flag(const pg_exemplar *ex, const float *curve, uint8_t *flag) {
    const int64_t n = (int64_t)ex->width * ex->height;
#pragma omp parallel for schedule(static)
    for (int64_t i = 0; i < n; i++) {
        flag[i] = 0;
        if (!(ex->elevation[i] < ex->sea_level)) continue;
        const float *m = curve + 3 * pg_or_bin(ex, (size_t)i);
        if (isnan(m[0])) continue;
        int darker = 0, brighter = 0;
        for (int c = 0; c < 3; c++) {
            float d = m[c] - (float)pg_or_byte(ex->albedo[3 * i + c]);
            darker |= d > PG_OR_DARKER;
            brighter |= -d > PG_OR_DARKER;
        }
        flag[i] = darker && !brighter;
    }
}

/* Labels the 8-connected regions of flag == 1 in texel order; regions of at least
 * min_size texels become 2, the others 3. queue holds width * height texel ids. */
static void pg_or_regions(const pg_exemplar *ex, uint8_t *flag, uint32_t *queue, size_t min_size) {
    const int w = ex->width, hgt = ex->height;
    const size_t n = (size_t)w * hgt;
    for (size_t s = 0; s < n; s++) {
        if (flag[s] != 1) continue;
        size_t head = 0, tail = 0;
        queue[tail++] = (uint32_t)s;
        flag[s] = 4; /* in the region being grown */
        while (head < tail) {
            uint32_t c = queue[head++];
            int x = (int)(c % (uint32_t)w), y = (int)(c / (uint32_t)w);
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int yy = y + dy, xx = (x + dx + w) % w;
                    if ((!dx && !dy) || yy < 0 || yy >= hgt) continue;
                    size_t j = (size_t)yy * w + xx;
                    if (flag[j] != 1) continue;
                    flag[j] = 4;
                    queue[tail++] = (uint32_t)j;
                }
        }
        uint8_t mark = tail >= min_size ? 2 : 3;
        for (size_t k = 0; k < tail; k++)
            flag[queue[k]] = mark;
    }
}

pg_status pg_exemplar_repair_ocean(pg_exemplar *ex, uint64_t *repaired, pg_error *err) {
    *repaired = 0;
    const size_t n = (size_t)ex->width * ex->height;
    uint8_t *wmask = malloc(n), *flag = malloc(n);
    uint32_t *queue = malloc(n * sizeof *queue);
    float curve[3 * PG_OR_BINS];
    int have = wmask && flag && queue ? 0 : -1;
    if (!have) {
        pg_exemplar_water_mask(ex->albedo, ex->width, ex->height, wmask);
        have = pg_or_curve(ex, wmask, curve);
    }
    if (have > 0) {
        pg_or_flag(ex, curve, flag);
        pg_or_regions(ex, flag, queue, (size_t)ceil(PG_OR_MIN_SHARE * (double)n));
        for (size_t i = 0; i < n; i++) {
            if (flag[i] != 2) continue;
            float col[3];
            pg_or_colour(curve, ex->sea_level - ex->elevation[i], col);
            for (int c = 0; c < 3; c++)
                ex->albedo[3 * i + c] = (float)lrintf(col[c]) * (1.0f / 255);
            (*repaired)++;
        }
    }
    free(wmask);
    free(flag);
    free(queue);
    if (have < 0)
        return pg_error_set(err, PG_ERR_NOMEM, "exemplar: out of memory for the ocean repair");
    return PG_OK;
}
