/* pg_climate_biome.c - the biome-ish classes that synthesis needs from the climate:
 * ice, and desert / aridity.
 *
 * Ice: an annual mean below -10 deg C (PG_CLIMATE_ICE_C). On Earth every ice sheet
 * interior is far below it (Greenland summit about -30, Antarctica -20 to -55) and
 * the Arctic's perennial sea ice lies near -15 to -20, while the seasonal sea ice
 * edge and the temperate glacier margins sit between -10 and 0. The threshold keeps
 * the ice sheets and polar oceans and leaves boreal forest (Moscow +5, Yakutsk
 * -9) free; its known failure is the driest Siberian interior (Verkhoyansk -15),
 * which is permafrost, not ice, because too little snow falls.
 *
 * Aridity: Holdridge's (1967) life-zone potential evapotranspiration, PET = 58.93 mm
 * per degree of biotemperature (the mean of T clamped to 0..30 deg C; with only an
 * annual mean we clamp the mean), and its ratio to precipitation. Desert: the
 * classic < 250 mm/yr bound (Meigs' arid lands; Koppen's BW lies near it for warm
 * climates), restricted to annual means above 0 deg C so that the dry polar
 * interiors count as ice or tundra, not sand. */
#include "planetgen/pg_climate.h"

#include <math.h>

bool pg_climate_is_ice(float temperature_c) {
    return temperature_c < PG_CLIMATE_ICE_C;
}

double pg_climate_pet_ratio(float temperature_c, float precipitation_mm) {
    double bt = fmin(fmax((double)temperature_c, 0.0), 30.0);
    double pet = 58.93 * bt;
    return pet / fmax((double)precipitation_mm, 1.0);
}

bool pg_climate_is_desert(float temperature_c, float precipitation_mm) {
    return precipitation_mm < PG_CLIMATE_DESERT_MM && temperature_c > 0.0f;
}
