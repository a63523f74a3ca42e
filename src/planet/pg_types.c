/* pg_types.c - terrain types of exemplar texels, type maps and presets: the type
 * constraint of Gain, Merry & Marais 2015 ("Parallel, realistic and controllable
 * terrain synthesis", §5: each output region names the exemplar types it may use) and
 * EarthGen's four planet kinds (seed 004 §4.2: Earth, Snow, Grassland, Desert).
 *
 * THE RULE (one texel, sRGB albedo r, g, b in 0..1, height h, sea level h0; luma
 * L = 0.299 r + 0.587 g + 0.114 b, chroma C = max - min), first match wins:
 *   ice       L >= 0.62 and C <= 0.14          bright and grey-white: ice sheets, snow,
 *                                              sea ice (at any height)
 *   ocean     h <= h0
 *   mountain  h >= 2500 m
 *   forest    L < 0.22 and g >= r              dark and green-dominant
 *   desert    L >= 0.40, or r - b >= 0.18 and L >= 0.30   bright, warm: sand, rock
 *   grass     everything else                  grassland, savanna, tundra, sparse cover
 * Thresholds were set by looking at Blue Marble (dark green Amazon/taiga, olive plains,
 * tan Sahara/Arabia/Australia, white Antarctica/Greenland) and at the classified
 * exemplar preview that `planetgen generate --verbose` can write.
 *
 * PRESETS (allowed types everywhere): earth = all; desert = desert + mountain;
 * snow = ice (a frozen world: land ice sheets, sea under sea ice);
 * grassland = grass + forest + ocean.
 *
 * INLAND WATER. Blue Marble draws lakes near black (Victoria, Tanganyika, Baikal, Ladoga,
 * the Great Lakes: every channel at most 20 of 255) where the relief holds their surface
 * above sea level. The rule above calls them forest or grass (mountain above 2500 m), and
 * the synthesis copied them onto a new planet's forests as black blobs on ground whose
 * height has no lake (the previews of seed 1 showed several, each a few tens of
 * kilometres wide). pg_types_exemplar gives such texels (height above sea level, every
 * channel <= PG_TYPES_LAKE_MAX), and the texels of the (2 PG_TYPES_LAKE_RIM + 1)^2 square
 * round each on its face that are not ice (the JPEG's dark rims), the type
 * PG_TYPE_EXCLUDED, which no mask allows, so wherever types are in use (layout world, a
 * preset, a type map) the synthesis's fix-up replaces them. Without types (layouts earth
 * and free with neither) lakes are copied as before. pg_types_classify, which the report
 * also uses, is unchanged.
 *
 * TYPE MAPS are equirectangular images of type colours (pg_types_colour), plus black
 * for "any type"; a pixel within 24 per channel of a colour names it. */
#include "planetgen/pg_types.h"

#include "planetgen/pg_guide.h"
#include "planetgen/pg_image.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const names[PG_TYPE_COUNT] = {"ocean", "ice",    "desert",
                                                 "grass", "forest", "mountain"};
static const uint8_t colours[PG_TYPE_COUNT][3] = {{0, 0, 255}, {255, 255, 255}, {255, 255, 0},
                                                  {0, 255, 0}, {0, 128, 0},     {128, 128, 128}};

const char *pg_types_name(int type) {
    return type >= 0 && type < PG_TYPE_COUNT ? names[type] : "?";
}

void pg_types_colour(int type, uint8_t rgb[3]) {
    memcpy(rgb, colours[type >= 0 && type < PG_TYPE_COUNT ? type : 0], 3);
}

int pg_types_classify(const uint8_t rgb[3], float height_m, float sea_level) {
    float r = rgb[0] / 255.0f, g = rgb[1] / 255.0f, b = rgb[2] / 255.0f;
    float L = 0.299f * r + 0.587f * g + 0.114f * b;
    float mx = r > g ? (r > b ? r : b) : (g > b ? g : b);
    float mn = r < g ? (r < b ? r : b) : (g < b ? g : b);
    if (L >= 0.62f && mx - mn <= 0.14f) return PG_TYPE_ICE;
    if (height_m <= sea_level) return PG_TYPE_OCEAN;
    if (height_m >= 2500.0f) return PG_TYPE_MOUNTAIN;
    if (L < 0.22f && g >= r) return PG_TYPE_FOREST;
    if (L >= 0.40f || (r - b >= 0.18f && L >= 0.30f)) return PG_TYPE_DESERT;
    return PG_TYPE_GRASS;
}

static bool is_lake(const uint8_t rgb[3], float height_m, float sea_level) {
    return height_m > sea_level && rgb[0] <= PG_TYPES_LAKE_MAX && rgb[1] <= PG_TYPES_LAKE_MAX &&
           rgb[2] <= PG_TYPES_LAKE_MAX;
}

/* Row y of face f in near: 1 where a lake texel lies within PG_TYPES_LAKE_RIM along the
 * row of face f (the first half of a separable square dilation). */
static void lake_row(const pg_synth_exemplar *ex, int f, int y, uint8_t *near) {
    const int E = ex->face_size, R = PG_TYPES_LAKE_RIM;
    const size_t row = ((size_t)f * E + (size_t)y) * E;
    int last = -2 * R - 2; /* the last lake texel seen */
    for (int x = 0; x < E + R; x++) {
        if (x < E &&
            is_lake(ex->albedo + (row + (size_t)x) * 3, ex->height[row + (size_t)x], ex->sea_level))
            last = x;
        if (x - R >= 0) near[row + (size_t)(x - R)] = x - last <= 2 * R;
    }
}

uint8_t *pg_types_exemplar(const pg_synth_exemplar *ex) {
    const int E = ex->face_size, R = PG_TYPES_LAKE_RIM;
    size_t n = (size_t)ex->nfaces * E * E;
    uint8_t *t = malloc(n), *near = malloc(n);
    if (!t || !near) {
        free(t), free(near);
        return NULL;
    }
#pragma omp parallel for schedule(static)
    for (size_t i = 0; i < n; i++)
        t[i] = (uint8_t)pg_types_classify(ex->albedo + i * 3, ex->height[i], ex->sea_level);
#pragma omp parallel for schedule(static)
    for (int k = 0; k < ex->nfaces * E; k++)
        lake_row(ex, k / E, k % E, near);
#pragma omp parallel for schedule(static)
    for (int k = 0; k < ex->nfaces * E; k++) {
        /* the columns: a texel is excluded when a row within R of it has a lake within R */
        const int f = k / E, y = k % E;
        for (int dy = -R; dy <= R; dy++) {
            if (y + dy < 0 || y + dy >= E) continue;
            const uint8_t *src = near + ((size_t)f * E + (size_t)(y + dy)) * E;
            uint8_t *dst = t + ((size_t)f * E + (size_t)y) * E;
            for (int x = 0; x < E; x++) /* ice is never dark: a rim keeps it */
                if (src[x] && dst[x] != PG_TYPE_ICE) dst[x] = (uint8_t)PG_TYPE_EXCLUDED;
        }
    }
    free(near);
    return t;
}

#define BIT(t) ((uint8_t)(1u << (t)))

pg_status pg_types_preset(const char *name, uint8_t *mask, pg_error *err) {
    if (!strcmp(name, "earth"))
        *mask = PG_TYPES_ALL;
    else if (!strcmp(name, "desert"))
        *mask = BIT(PG_TYPE_DESERT) | BIT(PG_TYPE_MOUNTAIN);
    else if (!strcmp(name, "snow"))
        *mask = BIT(PG_TYPE_ICE);
    else if (!strcmp(name, "grassland"))
        *mask = BIT(PG_TYPE_GRASS) | BIT(PG_TYPE_FOREST) | BIT(PG_TYPE_OCEAN);
    else
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--preset %s: unknown (earth, desert, snow, grassland)", name);
    return PG_OK;
}

/* The mask a colour names, or 0 if none. */
static uint8_t colour_mask(const uint8_t c[3]) {
    if (c[0] <= 24 && c[1] <= 24 && c[2] <= 24) return PG_TYPES_ALL;
    for (int t = 0; t < PG_TYPE_COUNT; t++) {
        int ok = 1;
        for (int k = 0; k < 3; k++)
            ok &= abs((int)c[k] - (int)colours[t][k]) <= 24;
        if (ok) return BIT(t);
    }
    return 0;
}

/* Collect up to 6 distinct unnamed colours into a message. */
static void list_unknown(const pg_image *img, char *buf, size_t size, size_t *count) {
    uint32_t seen[6];
    int ns = 0;
    *count = 0;
    buf[0] = 0;
    for (size_t i = 0; i < (size_t)img->width * img->height; i++) {
        uint8_t c[3];
        for (int k = 0; k < 3; k++) {
            float v = img->data[i * img->channels + (img->channels >= 3 ? k : 0)] * img->unit_scale;
            c[k] = (uint8_t)(v <= 0 ? 0 : v >= 1 ? 255 : v * 255.0f + 0.5f);
        }
        if (colour_mask(c)) continue;
        (*count)++;
        uint32_t key = (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | c[2];
        int dup = 0;
        for (int j = 0; j < ns; j++)
            dup |= seen[j] == key;
        if (dup || ns == 6) continue;
        seen[ns++] = key;
        char one[24];
        snprintf(one, sizeof one, "%s#%02x%02x%02x", ns > 1 ? ", " : "", c[0], c[1], c[2]);
        strncat(buf, one, size - strlen(buf) - 1);
    }
}

pg_status pg_types_map_load(const char *path, pg_types_map *m, pg_error *err) {
    memset(m, 0, sizeof *m);
    pg_image img;
    pg_status st = pg_guide_read_equirect(path, "--types", &img, err);
    if (st) return st;
    char unknown[200];
    size_t count;
    list_unknown(&img, unknown, sizeof unknown, &count);
    if (count) {
        pg_image_free(&img);
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "--types %s: %zu pixels have colours that name no type (%s); use "
                            "ocean #0000ff, ice #ffffff, desert #ffff00, grass #00ff00, forest "
                            "#008000, mountain #808080, any #000000",
                            path, count, unknown);
    }
    m->width = img.width;
    m->height = img.height;
    m->mask = malloc((size_t)img.width * img.height);
    if (!m->mask) {
        pg_image_free(&img);
        return pg_error_set(err, PG_ERR_NOMEM, "--types %s: out of memory", path);
    }
    for (size_t i = 0; i < (size_t)img.width * img.height; i++) {
        uint8_t c[3];
        for (int k = 0; k < 3; k++) {
            float v = img.data[i * img.channels + (img.channels >= 3 ? k : 0)] * img.unit_scale;
            c[k] = (uint8_t)(v <= 0 ? 0 : v >= 1 ? 255 : v * 255.0f + 0.5f);
        }
        m->mask[i] = colour_mask(c);
    }
    pg_image_free(&img);
    return PG_OK;
}

void pg_types_map_free(pg_types_map *m) {
    free(m->mask);
    memset(m, 0, sizeof *m);
}
