/* test_pole_gate.c - issue 8's gate on the default planet: `planetgen generate` (T = 4,
 * S = 256, seed 1) then `planetgen inspect`; the LPIPS-style distance of each pole view
 * must be at most 1.15 x the mean of the four equator views' ("ratio_north",
 * "ratio_south" and "pole_equator_ratio" of the inspect JSON). The same run checks that
 * the planet keeps issue 5's seam gate (seam_ratio <= 1.1), which the delivery's
 * magnification could break, and that its neighbourhood fidelity ("neighbourhood_fidelity_ratio",
 * pg_inspect_fidelity_compute) is no worse than the exemplar's own leave-one-out figure
 * (measured 0.78-0.90 for seed 1; the Earth copy scores 0.86, shuffled texels 8.0).
 *
 * Before the fix the default planet failed this gate (north 1.29, south 1.16): it was
 * synthesized at twice the exemplar cube's resolution, so layout earth laid every
 * exemplar feature down twice per axis and the Arctic archipelago came out as a lattice of
 * repeated islands (pg_planet_synth.c, pg_planet_synth_magnification). */
#include "pg_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char out[16384], err[16384];

/* The number after the first occurrence of "key": in json (NaN when absent). */
static double json_number(const char *json, const char *key) {
    char pat[128];
    snprintf(pat, sizeof pat, "\"%s\"", key);
    const char *p = strstr(json, pat);
    if (!p) return strtod("nan", NULL);
    p = strchr(p + strlen(pat), ':');
    return p ? strtod(p + 1, NULL) : strtod("nan", NULL);
}

static void read_file(const char *path, char *buf, size_t size) {
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("cannot open %s", path);
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = 0;
    fclose(f);
}

static void test_default_planet_poles(void **state) {
    (void)state;
    char dir[512], args[2048], path[700];
    pg_test_scratch_dir("pole-gate", dir, sizeof dir);
    snprintf(args, sizeof args, "generate -q --no-glb --cache-dir %s/synth-cache -o %s/p",
             getenv("PG_BUILD_DIR"), dir);
    int rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("generate: exit %d: %s", rc, err);
    snprintf(args, sizeof args, "inspect -q %s/p --json %s/inspect.json", dir, dir);
    rc = pg_test_run_cli(args, out, sizeof out, err, sizeof err);
    if (rc != 0) fail_msg("inspect: exit %d: %s", rc, err);
    static char json[1 << 20];
    snprintf(path, sizeof path, "%s/inspect.json", dir);
    read_file(path, json, sizeof json);
    double north = json_number(json, "ratio_north"), south = json_number(json, "ratio_south");
    double worst = json_number(json, "pole_equator_ratio"), seam = json_number(json, "seam_ratio");
    print_message("default planet: pole/equator north %.3f, south %.3f (gate 1.15); seams %.3f\n",
                  north, south, seam);
    if (!(north <= 1.15 && south <= 1.15))
        fail_msg("pole gate: north %.3f, south %.3f (must be <= 1.15)", north, south);
    /* the top-level figure is the larger pole's */
    assert_true(worst >= north - 1e-9 && worst >= south - 1e-9 && worst <= 1.15);
    if (!(seam <= 1.1)) fail_msg("seam gate: %.3f (must be <= 1.1)", seam);
    double fid = json_number(json, "neighbourhood_fidelity_ratio");
    double rnd = json_number(json, "neighbourhood_fidelity_random_ratio");
    print_message("neighbourhood fidelity %.3f x leave-one-out (random texels %.2f x)\n", fid, rnd);
    if (!(fid <= 1.0)) fail_msg("neighbourhood fidelity: %.3f x leave-one-out (must be <= 1)", fid);
    assert_true(rnd >= 5); /* the baseline separates structure from noise */
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_default_planet_poles)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
