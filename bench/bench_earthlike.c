/* bench_earthlike.c - the Earth-likeness figures (pg_earthlike.h) of a planet and of
 * Earth at the same size, side by side, with the seconds each took. Figures only;
 * nothing is asserted.
 *
 * Earth is the default exemplar reprojected onto a cube (pg_planet_from_exemplar) of
 * the planet's projection, ellipsoid and face size, or of the default projection,
 * WGS84 and face size N when no planet is given.
 *
 * usage: bench_earthlike [PLANET_DIR] [--n N] [--threads T] */
#include "planetgen/pg_earthlike.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_planet.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void print_figures(const char *name, const pg_earthlike *e, double secs) {
    printf("== %s (N = %lld): %.3f s\n", name, (long long)e->n, secs);
    printf("  land_fraction           %.4f  (total area %.6e m^2)\n", e->land_fraction,
           e->total_area_m2);
    printf("  landmasses              %llu (>= 1e4 km^2: %llu, >= 1e6 km^2: %llu)\n",
           (unsigned long long)e->landmasses, (unsigned long long)e->landmasses_1e4,
           (unsigned long long)e->landmasses_1e6);
    printf("  largest_landmass        %.4g km^2, share %.4f\n", e->largest_landmass_km2,
           e->largest_landmass_share);
    printf("  rank_size_slope         %.4f\n", e->rank_size_slope);
    int K = PG_EARTHLIKE_QUANTILES;
    printf("  land   mean %.1f m, sd %.1f m, quantiles 5/50/95%%: %.1f %.1f %.1f\n", e->land_mean_m,
           e->land_std_m, e->land_quantiles[K / 20], e->land_quantiles[K / 2],
           e->land_quantiles[K - K / 20 - 1]);
    printf("  ocean  mean %.1f m, sd %.1f m, quantiles 5/50/95%%: %.1f %.1f %.1f\n",
           e->ocean_mean_m, e->ocean_std_m, e->ocean_quantiles[K / 20], e->ocean_quantiles[K / 2],
           e->ocean_quantiles[K - K / 20 - 1]);
    printf("  ice_equator_fraction    %.4f\n", e->ice_equator_fraction);
    printf("  ice_polar_fraction      %.4f\n", e->ice_polar_fraction);
    printf("  desert_band_ratio       %.4f\n", e->desert_band_ratio);
    printf("  zonal (band: ocean ice desert grass forest mountain)\n");
    for (int b = PG_EARTHLIKE_BANDS - 1; b >= 0; b--) {
        printf("   %+3d..%+3d:", -90 + 10 * b, -80 + 10 * b);
        for (int t = 0; t < PG_TYPE_COUNT; t++)
            printf(" %.3f", e->zonal[b][t]);
        printf("\n");
    }
}

static int compute(const char *name, const pg_planet *p, pg_earthlike *e) {
    pg_error err = {0};
    double t0 = omp_get_wtime();
    if (pg_earthlike_compute(p, e, &err) != PG_OK) {
        fprintf(stderr, "%s: %s\n", name, err.msg);
        return 1;
    }
    print_figures(name, e, omp_get_wtime() - t0);
    return 0;
}

static int novelty(const char *name, const pg_planet *p, const pg_exemplar *ex) {
    pg_error err = {0};
    pg_earthlike_novelty nv;
    double t0 = omp_get_wtime();
    if (pg_earthlike_novelty_compute(p, ex, &nv, &err) != PG_OK) {
        fprintf(stderr, "%s: %s\n", name, err.msg);
        return 1;
    }
    printf("  novelty vs Earth (%s): agreement %.4f, chance %.4f, kappa %.4f, novelty %.4f, "
           "chance_zonal %.4f, kappa_zonal %.4f, f_p %.4f, f_e %.4f: %.3f s\n",
           name, nv.agreement, nv.chance, nv.kappa, nv.novelty, nv.chance_zonal, nv.kappa_zonal,
           nv.planet_land_fraction, nv.earth_land_fraction, omp_get_wtime() - t0);
    return 0;
}

int main(int argc, char **argv) {
    const char *dir = NULL;
    int n = 1024;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc)
            n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc)
            omp_set_num_threads(atoi(argv[++i]));
        else
            dir = argv[i];
    }
    pg_error err = {0};
    pg_planet planet = {0}, earth;
    pg_earthlike ep, ee;
    int rc = 0;
    if (dir && pg_planet_load(dir, &planet, &err) != PG_OK) {
        fprintf(stderr, "%s: %s\n", dir, err.msg);
        return 1;
    }
    pg_exemplar ex;
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    if (pg_exemplar_load(&o, &ex, &err) != PG_OK) {
        fprintf(stderr, "exemplar: %s\n", err.msg);
        return 1;
    }
    int tiles = dir ? planet.tiles : (n >= 256 ? n / 256 : 1),
        ts = dir ? planet.tile_size : n / tiles;
    pg_cube_projection proj = dir ? planet.projection : PG_CUBE_DEFAULT_PROJECTION;
    pg_ellipsoid ell = dir ? planet.ellipsoid : pg_ellipsoid_wgs84();
    double t0 = omp_get_wtime();
    if (pg_planet_alloc(&earth, proj, tiles, ts, ell, &err) != PG_OK ||
        pg_planet_from_exemplar(&earth, &ex, 2, &err) != PG_OK) {
        fprintf(stderr, "earth: %s\n", err.msg);
        return 1;
    }
    printf("threads %d; Earth reprojected onto 6 x %lld^2 in %.2f s\n", omp_get_max_threads(),
           (long long)earth.n, omp_get_wtime() - t0);
    rc |= compute("Earth", &earth, &ee);
    rc |= novelty("Earth", &earth, &ex);
    if (dir && !rc) {
        rc |= compute(dir, &planet, &ep);
        rc |= novelty(dir, &planet, &ex);
        double wl, wo, per[PG_TYPE_COUNT];
        pg_earthlike_w1(&ep, &ee, &wl, &wo);
        double r = pg_earthlike_zonal_correlation(&ep, &ee, per);
        printf("== planet vs Earth: W1 land %.1f m, W1 ocean %.1f m, zonal correlation %.4f "
               "(per type:",
               wl, wo, r);
        for (int t = 0; t < PG_TYPE_COUNT; t++)
            printf(" %s %.3f", pg_types_name(t), per[t]);
        printf(")\n");
        pg_planet_free(&planet);
    }
    pg_planet_free(&earth);
    pg_exemplar_free(&ex);
    return rc;
}
