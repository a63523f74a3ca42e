/* realism_gate.c - one gate of the realism report (docs/inspect.md, "Gates") over the
 * inspect JSON reports that test_realism_e2e writes: exits 0 when KEY holds against the
 * gate in every file, 1 when it fails in any (or is missing or null there), 2 on bad
 * arguments. ctest runs it once per gate and layout (CMakeLists.txt); a gate that
 * today's planets fail is registered WILL_FAIL, so it turns red when the figure starts
 * to pass and the mark must go.
 *
 * Usage: realism_gate KEY le|ge GATE FILE.json [FILE.json ...]. The key is read at the
 * top level of the report, which comes before the "earth" object. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The number after the first "KEY": in the file; NaN when absent or null. */
static double read_key(const char *path, const char *key) {
    static char buf[1 << 20];
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "realism_gate: %s: cannot open\n", path);
        return NAN;
    }
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    char pat[160];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = strstr(buf, pat);
    if (!p) return NAN;
    char *end;
    double v = strtod(p + strlen(pat), &end);
    return end == p + strlen(pat) ? NAN : v;
}

int main(int argc, char **argv) {
    if (argc < 5 || (strcmp(argv[2], "le") && strcmp(argv[2], "ge"))) {
        fprintf(stderr, "usage: realism_gate KEY le|ge GATE FILE.json...\n");
        return 2;
    }
    const char *key = argv[1];
    int le = !strcmp(argv[2], "le");
    double gate = strtod(argv[3], NULL);
    int failed = 0;
    for (int i = 4; i < argc; i++) {
        double v = read_key(argv[i], key);
        int ok = isfinite(v) && (le ? v <= gate : v >= gate);
        printf("%s %s: %.4f %s %.4g -> %s\n", argv[i], key, v, le ? "<=" : ">=", gate,
               ok ? "PASS" : "FAIL");
        failed |= !ok;
    }
    return failed;
}
