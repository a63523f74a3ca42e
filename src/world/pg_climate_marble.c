/* pg_climate_marble.c - physical units for Marble's climate maps (marble-qt-data
 * maps/earth/temp-*, precip-*: Legates & Willmott 1989 and CRU CL 2.0 monthly means
 * as 8-bit grey, 2160x1080). The maps carry no units; their palettes
 * (tempcolors.leg, precipcolors.leg) give only grey anchors. The mappings below were
 * derived from the anchors and checked against station normals (docs/world.md).
 *
 * Temperature: linear, grey 0 -> -69 deg C, grey 255 -> +42 deg C (0.435 K per grey
 * level). Check: Vostok, July (-67) reads grey 6 -> -66.4; the South Pole, July (-60)
 * 21 -> -60.0; Verkhoyansk, December (about -42) 56 -> -44.5; Moscow, July (+18) 200
 * -> +18.1; London, December (+5) 169 -> +4.6; Libyan Sahara, July (+31) 228 -> +30.2.
 *
 * Precipitation (monthly mm): the legend anchors of precipcolors.leg sit at grey
 * fractions 0, .04, .16, .25, .35, .5, .75, .87, .93, 1; reading them as 0, 10, 40,
 * 64, 90, 128, 256, 512, 768, 1024 mm (linear, 256 mm per unit, up to 128 mm, then
 * doubling) matches the stations: London, July (about 45 mm) grey 49 -> 49; NYC,
 * July (about 115) 105 -> 105; Manaus, December (about 220) 168 -> 209; Singapore,
 * December (about 255) 191 -> 255. The top is saturated (Cherrapunji's July, 2700
 * mm, reads 238 -> 830). Monotone by construction. */
#include "planetgen/pg_climate.h"

double pg_climate_marble_temp_c(double grey) {
    return -69.0 + 111.0 * grey / 255.0;
}

double pg_climate_marble_precip_mm(double grey) {
    static const double g[] = {0.0, 0.5, 0.75, 0.87, 0.93, 1.0};
    static const double mm[] = {0.0, 128.0, 256.0, 512.0, 768.0, 1024.0};
    double x = grey / 255.0;
    if (x <= 0.0) return 0.0;
    for (int k = 1; k < 6; k++)
        if (x <= g[k]) return mm[k - 1] + (mm[k] - mm[k - 1]) * (x - g[k - 1]) / (g[k] - g[k - 1]);
    return 1024.0;
}
