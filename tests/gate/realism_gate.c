/* realism_gate.c - one gate of the realism report (docs/inspect.md, "Gates") over the
 * inspect JSON reports that test_realism_e2e writes: exits 0 when KEY holds against the
 * gate in every file, 1 when it fails in any (or is missing or null there), 2 on bad
 * arguments. ctest runs it once per gate and layout (CMakeLists.txt); a gate that
 * today's planets fail is registered WILL_FAIL, so it turns red when the figure starts
 * to pass and the mark must go.
 *
 * Usage: realism_gate KEY le|ge GATE FILE.json [FILE.json ...]. The key is read at the
 * top level of the report, which comes before the "earth" object. GATE is a number, or
 * PATH*F for a gate relative to another figure of the same report: PATH names it by its
 * keys from the top, dot-separated ("earth.ice_polar_fraction*0.8": 0.8 times Earth's own
 * figure; "results.earth.earthlike.land_std_m*0.25"). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char buf[1 << 20];

static int load(const char *path) {
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "realism_gate: %s: cannot open\n", path);
        return -1;
    }
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    return 0;
}

/* The number after the dot-separated keys of path, each found after the one before (the
 * first "KEY": for a single key); NaN when absent or null. */
static double read_path(const char *path) {
    const char *at = buf, *k = path;
    char pat[160];
    while (*k) {
        size_t len = strcspn(k, ".");
        snprintf(pat, sizeof pat, "\"%.*s\":", (int)len, k);
        at = strstr(at, pat);
        if (!at) return NAN;
        at += strlen(pat);
        k += len + (k[len] == '.');
    }
    char *end;
    double v = strtod(at, &end);
    return end == at ? NAN : v;
}

/* The gate for the loaded report: a number, or PATH*F. */
static double gate_of(const char *g) {
    const char *star = strchr(g, '*');
    if (!star) return strtod(g, NULL);
    char path[160];
    snprintf(path, sizeof path, "%.*s", (int)(star - g), g);
    return read_path(path) * strtod(star + 1, NULL);
}

int main(int argc, char **argv) {
    if (argc < 5 || (strcmp(argv[2], "le") && strcmp(argv[2], "ge"))) {
        fprintf(stderr, "usage: realism_gate KEY le|ge GATE FILE.json...\n");
        return 2;
    }
    const char *key = argv[1];
    int le = !strcmp(argv[2], "le");
    int failed = 0;
    for (int i = 4; i < argc; i++) {
        double v = NAN, gate = NAN;
        if (!load(argv[i])) {
            v = read_path(key);
            gate = gate_of(argv[3]);
        }
        int ok = isfinite(v) && isfinite(gate) && (le ? v <= gate : v >= gate);
        printf("%s %s: %.4f %s %.4g -> %s\n", argv[i], key, v, le ? "<=" : ">=", gate,
               ok ? "PASS" : "FAIL");
        failed |= !ok;
    }
    return failed;
}
