/* test_export_tiles.c - a tiled planet's glTF files (docs/export.md, "Tiled planets"), on
 * the real Earth reprojected onto small planets and on planets that `generate` makes:
 *
 * - a tile's mesh is the globe's mesh there, bit for bit (positions, normals, tangents),
 *   and its normal map the globe's normal map there: one code path for both;
 * - a process that holds only some tiles (the others poisoned with NaN in memory) writes
 *   the same bytes for its tiles as one that holds the planet, reading the ring around
 *   them from the other tiles' height EXRs: nothing else of the planet is read;
 * - `generate --output-layout tiled` in one process and under `mpirun -np 2` writes one
 *   .glb per tile, listed in index.json, byte-identical between the two, each with 0
 *   errors and 0 warnings from the Khronos glTF-Validator; read back from the files,
 *   every border vertex of a tile has the same position bits (and normal) in its
 *   neighbour's file across tile seams, face seams and cube corners, and the tiles hold
 *   Euler's 6 M^2 + 2 distinct vertices (tests/tools/glb_tiles_check.py);
 * - --no-glb writes none and index.json lists none. */
#include "export_fixture.h"

#include "pg_export_internal.h"
#include "planetgen/pg_mpi.h"
#include "planetgen/pg_planet_tiles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Every tile's mesh and normal map against the globe's, for mesh resolution m. */
static void check_tiles_equal_globe(const pg_planet *p, int m) {
    pg_error err = {0};
    pg_cube_grid g;
    assert_int_equal(pg_cube_grid_init(&g, p->projection, p->tiles, p->tile_size, &err), PG_OK);
    pg_export_mesh globe, tile;
    assert_int_equal(pg_export_mesh_build(p, &g, m, 10.0, &globe, &err), PG_OK);
    pg_export_heights hs;
    pg_export_heights_whole(p, &hs);
    const int T = p->tiles, S = p->tile_size, mt = m / T;
    const int64_t n = p->n;
    float *face_nm = malloc((size_t)(n * n * 3) * sizeof(float));
    float *tile_nm = malloc((size_t)S * S * 3 * sizeof(float));
    size_t differ = 0, nm_differ = 0, compared = 0;
    for (int f = 0; f < 6; f++) {
        assert_int_equal(pg_export_normal_map(&hs, &g, &globe, 10.0, f, 0, 0, n, face_nm, &err),
                         PG_OK);
        for (int t = f * T * T; t < (f + 1) * T * T; t++) {
            assert_int_equal(pg_export_mesh_build_tile(&hs, &g, m, 10.0, t, &tile, &err), PG_OK);
            assert_int_equal(tile.nv, (uint32_t)((mt + 1) * (mt + 1)));
            for (int j = 0; j <= mt; j++)
                for (int i = 0; i <= mt; i++) {
                    size_t a = (size_t)j * (mt + 1) + i;
                    size_t b = (size_t)(tile.j0 + j) * (m + 1) + (size_t)(tile.i0 + i);
                    differ += memcmp(tile.pos[0] + 3 * a, globe.pos[f] + 3 * b, 12) != 0;
                    differ += memcmp(tile.nrm[0] + 3 * a, globe.nrm[f] + 3 * b, 12) != 0;
                    differ += memcmp(tile.tan[0] + 4 * a, globe.tan[f] + 4 * b, 16) != 0;
                    compared++;
                }
            int64_t x0 = (int64_t)(t % T) * S, y0 = (int64_t)(t / T % T) * S;
            assert_int_equal(
                pg_export_normal_map(&hs, &g, &tile, 10.0, f, x0, y0, S, tile_nm, &err), PG_OK);
            for (int y = 0; y < S; y++)
                nm_differ += memcmp(tile_nm + (size_t)y * S * 3,
                                    face_nm + ((size_t)(y0 + y) * n + (size_t)x0) * 3,
                                    (size_t)S * 3 * sizeof(float)) != 0;
            pg_export_mesh_free(&tile);
        }
    }
    printf("mesh %d: %zu tile vertices compared with the globe's, %zu arrays differ; "
           "normal-map rows differing %zu\n",
           m, compared, differ, nm_differ);
    assert_int_equal(compared, 6 * (size_t)T * T * (mt + 1) * (mt + 1));
    assert_int_equal(differ, 0);
    assert_int_equal(nm_differ, 0);
    free(face_nm);
    free(tile_nm);
    pg_export_mesh_free(&globe);
}

static void test_tile_mesh_is_the_globe_mesh(void **s) {
    (void)s;
    pg_planet p;
    fixture_earth(&p, 4, 32);
    check_tiles_equal_globe(&p, 128); /* one quad per texel */
    check_tiles_equal_globe(&p, 32);  /* 4 texels per quad: a wider ring */
    p.projection = PG_CUBE_EQUALAREA;
    check_tiles_equal_globe(&p, 64);
    pg_planet_free(&p);
}

/* How many of the first nt tiles' .glb are the same bytes in directories a and b. */
static int identical_glbs(const pg_planet *p, int nt, const char *a, const char *b) {
    int same = 0;
    for (int t = 0; t < nt; t++) {
        char name[64], out[256];
        pg_planet_tile_glb_name(p, t, name);
        same += pg_test_sh(out, sizeof out, "cmp -s '%s/%s' '%s/%s'", a, name, b, name) == 0;
    }
    return same;
}

/* Tiles [first, last) written by a "process" whose planet holds only them: the rest of
 * its heights and albedo are NaN, so any texel read from memory outside them would show.
 * Their .glb must equal the ones written from the whole planet. */
static void test_owned_tiles_only(void **s) {
    (void)s;
    pg_planet p;
    fixture_earth(&p, 4, 32);
    p.seed = 7;
    pg_error err = {0};
    char whole[1024], part[1024];
    pg_test_scratch_dir("export_tiles_whole", whole, sizeof whole);
    pg_test_scratch_dir("export_tiles_part", part, sizeof part);
    const int T = p.tiles, nt = 6 * T * T, S = p.tile_size;
    pg_export_opts o;
    pg_export_opts_default(&o);
    o.mesh_res = 32; /* 4 texels per quad */
    pg_planet_dir_paths dw = {.dir = whole}, dpart = {.dir = part};
    assert_int_equal(pg_planet_save_tiles(&p, 0, nt, pg_planet_dir_path, &dw, &err), PG_OK);
    assert_int_equal(pg_export_tiles_glb(&p, 0, nt, NULL, &o, pg_planet_dir_path, &dw, NULL, &err),
                     PG_OK);
    /* three "ranks": an uneven split that cuts faces in the middle */
    const int cut[4] = {0, 37, 58, nt};
    for (int r = 0; r < 3; r++) {
        pg_planet q;
        assert_int_equal(pg_planet_alloc(&q, p.projection, T, S, p.ellipsoid, &err), PG_OK);
        q.seed = p.seed, q.sea_level = p.sea_level;
        snprintf(q.exemplar, sizeof q.exemplar, "%s", p.exemplar);
        for (int f = 0; f < 6; f++)
            for (int64_t k = 0; k < p.n * p.n; k++) {
                int64_t x = k % p.n, y = k / p.n, t = (f * T + y / S) * T + x / S;
                bool held = t >= cut[r] && t < cut[r + 1];
                q.height[f][k] = held ? p.height[f][k] : NAN;
                for (int c = 0; c < 3; c++)
                    q.albedo[f][3 * k + c] = held ? p.albedo[f][3 * k + c] : NAN;
            }
        assert_int_equal(pg_export_tiles_glb(&q, cut[r], cut[r + 1], whole, &o, pg_planet_dir_path,
                                             &dpart, NULL, &err),
                         PG_OK);
        /* without the other tiles' files the ring cannot be had: refused, not guessed */
        pg_error e2 = {0};
        assert_int_not_equal(pg_export_tiles_glb(&q, cut[r], cut[r + 1], NULL, &o,
                                                 pg_planet_dir_path, &dpart, NULL, &e2),
                             PG_OK);
        printf("tiles [%d, %d) alone: %s\n", cut[r], cut[r + 1], e2.msg);
        pg_planet_free(&q);
    }
    int same = identical_glbs(&p, nt, whole, part);
    printf("%d of %d tile .glb identical when written from the owned tiles only\n", same, nt);
    assert_int_equal(same, nt);
    pg_planet_free(&p);
}

/* The validator on every tile .glb of a tiled directory, and the seams read back. */
static void check_tiled_dir(const char *dir, int ntiles) {
    char cmd[4096], line[1 << 16];
    snprintf(cmd, sizeof cmd, "'%s/scripts/gltf-validate' '%s'/planet_*.glb 2>&1",
             pg_test_source_dir(), dir);
    int rc = fixture_sh(cmd, line, sizeof line);
    int files = 0, clean = 0;
    for (const char *q = line; (q = strstr(q, ".glb errors=")); q++) {
        files++;
        clean += strncmp(q, ".glb errors=0 warnings=0 ", 25) == 0;
    }
    printf("glTF-Validator: %d files, %d with 0 errors and 0 warnings\n", files, clean);
    if (rc) printf("%s", line);
    assert_int_equal(rc, 0);
    assert_int_equal(files, ntiles);
    assert_int_equal(clean, ntiles);
    assert_non_null(strstr(line, "primitives=1 "));
    snprintf(cmd, sizeof cmd, "python3 '%s/tests/tools/glb_tiles_check.py' '%s' 2>&1",
             pg_test_source_dir(), dir);
    rc = fixture_sh(cmd, line, sizeof line);
    printf("%s", line);
    assert_int_equal(rc, 0);
}

static void generate(const char *dir, const char *extra, int np) {
    char args[4096], se[8192];
    if (np <= 1) {
        snprintf(args, sizeof args,
                 "generate -o '%s' --tiles 2 --tile-size 64 --seed 5 --output-layout tiled -q %s",
                 dir, extra);
        int rc = pg_test_run_cli(args, NULL, 0, se, sizeof se);
        if (rc) printf("%s\n", se);
        assert_int_equal(rc, 0);
        return;
    }
    char out[4096];
    int rc = pg_test_sh(out, sizeof out,
                        "env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                        "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 mpirun --oversubscribe "
                        "-np %d -x OMP_NUM_THREADS=1 '%s' generate -o '%s' --tiles 2 "
                        "--tile-size 64 --seed 5 -q %s 2>&1 </dev/null",
                        np, pg_test_cli(), dir, extra);
    if (rc) printf("%s\n", out);
    assert_int_equal(rc, 0);
}

static void test_generate_tiled_glb(void **s) {
    (void)s;
    char one[1024], two[1024];
    pg_test_scratch_dir("export_tiles_gen1", one, sizeof one);
    generate(one, "", 1);
    check_tiled_dir(one, 24);
    if (!pg_mpi_built()) {
        printf("built without MPI: the 2-rank run is skipped\n");
        return;
    }
    pg_test_scratch_dir("export_tiles_gen2", two, sizeof two);
    generate(two, "", 2);
    check_tiled_dir(two, 24);
    pg_planet geo = {.tiles = 2, .tile_size = 64};
    int same = identical_glbs(&geo, 24, one, two);
    printf("%d of 24 tile .glb byte-identical between 1 process and 2 ranks\n", same);
    assert_int_equal(same, 24);
}

static void test_no_glb(void **s) {
    (void)s;
    char dir[1024], out[4096];
    pg_test_scratch_dir("export_tiles_noglb", dir, sizeof dir);
    generate(dir, "--no-glb", 1);
    assert_int_equal(pg_test_sh(out, sizeof out, "ls '%s' | grep -c 'glb$' || true", dir), 0);
    assert_int_equal(atoi(out), 0);
    assert_int_equal(pg_test_sh(out, sizeof out, "grep -c glb '%s/index.json' || true", dir), 0);
    assert_int_equal(atoi(out), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tile_mesh_is_the_globe_mesh),
        cmocka_unit_test(test_owned_tiles_only),
        cmocka_unit_test(test_generate_tiled_glb),
        cmocka_unit_test(test_no_glb),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
