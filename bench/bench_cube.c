/* bench_cube.c - speed of the cubesphere hot paths, printed as figures (never
 * asserted): equirect -> cube resampling in Mpx/s of cube texels written, with 2
 * OpenMP threads; cube -> equirect in Mpx/s of pixels written; halo gather in
 * halo texels/s over all 6*T^2 tiles (T = 8, S = 256) for a few widths and payloads.
 * Usage: bench_cube [N=1024] */
#include "planetgen/pg_cube.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

static double now(void) {
    return omp_get_wtime();
}

static void bench_resample(int64_t n, const pg_ellipsoid *ell, const char *label) {
    const int W = 2700, H = 1350, C = 3; /* Blue Marble's size */
    float *img = malloc((size_t)W * H * C * sizeof *img);
    float *cube = malloc((size_t)6 * n * n * C * sizeof *cube);
    for (size_t i = 0; i < (size_t)W * H * C; i++)
        img[i] = (float)((i * 2654435761u) % 1000) / 1000;
    for (int rep = 0; rep < 2; rep++) { /* first run warms up pages and threads */
        double t = now();
        pg_cube_from_equirect(PG_CUBE_EQUIANGULAR, n, ell, img, W, H, C, 1, cube, NULL);
        double dt = now() - t;
        if (rep)
            printf("equirect->cube  %-7s %dx%d RGB -> 6x%lldx%lld: %.2f s, %.1f Mpx/s\n", label, W,
                   H, (long long)n, (long long)n, dt, 6.0 * n * n / dt / 1e6);
    }
    double t = now();
    pg_cube_to_equirect(PG_CUBE_EQUIANGULAR, n, ell, cube, C, img, W, H, NULL);
    double dt = now() - t;
    printf("cube->equirect  %-7s 6x%lldx%lld -> %dx%d RGB: %.2f s, %.1f Mpx/s\n", label,
           (long long)n, (long long)n, W, H, dt, (double)W * H / dt / 1e6);
    free(img), free(cube);
}

static void bench_halo(int w, size_t elem, pg_cube_vec_kind vec, const char *label) {
    pg_cube_grid g;
    pg_cube_grid_init(&g, PG_CUBE_EQUIANGULAR, 8, 256, NULL);
    int64_t N = g.n, S = g.tile_size, P = S + 2 * w;
    unsigned char *field = malloc((size_t)6 * N * N * elem);
    for (size_t i = 0; i < (size_t)6 * N * N * elem; i++)
        field[i] = (unsigned char)(i * 131);
    int nt = omp_get_max_threads();
    unsigned char *pad = calloc((size_t)nt * P * P, elem);
    pg_cube_payload pl = {elem, vec, 0, NULL, NULL};
    double best = 1e30;
    for (int rep = 0; rep < 10; rep++) {
        double t = now();
#pragma omp parallel for schedule(static)
        for (int64_t k = 0; k < g.ntiles; k++)
            pg_cube_halo_gather(&g, k, w, field, &pl, true,
                                pad + (size_t)omp_get_thread_num() * P * P * elem, NULL);
        best = fmin(best, now() - t);
    }
    double halo = (double)g.ntiles * (double)(P * P - S * S);
    printf("halo gather     T=8 S=256 w=%d %-18s all 384 tiles: %.1f ms, %.0f M halo texels/s\n", w,
           label, best * 1e3, halo / best / 1e6);
    free(field), free(pad);
}

int main(int argc, char **argv) {
    int64_t n = argc > 1 ? atoll(argv[1]) : 1024;
    omp_set_num_threads(2);
    printf("threads: %d\n", omp_get_max_threads());
    pg_ellipsoid wgs = pg_ellipsoid_wgs84();
    bench_resample(n, NULL, "sphere");
    bench_resample(n, &wgs, "wgs84");
    bench_halo(1, 4, PG_CUBE_VEC_NONE, "float");
    bench_halo(4, 4, PG_CUBE_VEC_NONE, "float");
    bench_halo(4, 16, PG_CUBE_VEC_F32, "16 B, vec2 rotated");
    bench_halo(16, 4, PG_CUBE_VEC_NONE, "float");
    return 0;
}
