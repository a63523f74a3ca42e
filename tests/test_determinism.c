/* test_determinism.c - the same inputs and seed give byte-identical output files across
 * runs, thread counts (OMP_NUM_THREADS=1 vs 2) and tilings (docs/generate.md), checked by
 * hashing every file the CLI writes: `generate` (per-face PNGs, height.exr, planet.glb,
 * planet.json, previews, globe renders), `synth` (albedo.png, height.exr, coords.png)
 * and `pits` (the corrected DEM for each method).
 *
 * The --json report is hashed too, after dropping the members that measure the run
 * rather than describe the result: timings, peak RSS, page faults, the thread count and the
 * exemplar cache state (the first run prepares the exemplar, later ones load it).
 * Across tilings, planet.json and planet.glb record the tiling itself (tiles,
 * tile_size); the two tilings compared have tile counts and sizes of the same number
 * of digits (2 x 64 and 4 x 32), so those values are masked in place and every other
 * byte must match. The report drops them, and the seam ratios, which are measured
 * over the tile edges and so depend on where the tiling puts them. */
#include "pg_test.h"

#include "planetgen/pg_image.h"

#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILES 64

typedef struct manifest {
    int n;
    char name[MAX_FILES][1024];
    uint64_t hash[MAX_FILES];
} manifest;

static char out[8192], err[8192];
static char dir[512], cache[600];

/* FNV-1a, 64 bits: enough to tell files apart in an equality test. */
static uint64_t fnv1a(const unsigned char *p, size_t n) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

static unsigned char *slurp(const char *path, size_t *n) {
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *buf = malloc((size_t)len + 1);
    assert_non_null(buf);
    *n = fread(buf, 1, (size_t)len, f);
    buf[*n] = '\0';
    fclose(f);
    return buf;
}

/* Blank the digits of the numbers that follow `"key":` (any spaces), in place. */
static void mask_number(unsigned char *p, size_t n, const char *key) {
    size_t k = strlen(key);
    for (size_t i = 0; i + k < n; i++) {
        if (memcmp(p + i, key, k) != 0) continue;
        size_t j = i + k;
        while (j < n && (p[j] == ' ' || p[j] == ':'))
            j++;
        while (j < n && ((p[j] >= '0' && p[j] <= '9') || p[j] == '.'))
            p[j++] = '#';
    }
}

/* Keys of report members that measure the run, not its result; with `tiling`, also the
 * tiling itself and the seam statistic, which is taken over the tile edges and so
 * measures where the tiling puts them. */
static bool volatile_key(const char *key, bool tiling) {
    static const char *words[] = {"seconds",       "rss",           "per_second",
                                  "threads",       "cache",         "faults",
                                  "private_bytes", "private_dirty", "shared_bytes"};
    for (size_t i = 0; i < sizeof words / sizeof *words; i++)
        if (strstr(key, words[i])) return true;
    return tiling && (strstr(key, "tile") || strstr(key, "seam_ratio"));
}

/* Skip one JSON value starting at s[i]; returns the index after it. */
static size_t skip_value(const char *s, size_t i) {
    int depth = 0;
    bool str = false;
    for (; s[i]; i++) {
        char c = s[i];
        if (str) {
            if (c == '\\')
                i++;
            else if (c == '"')
                str = false;
            continue;
        }
        if (c == '"') str = true;
        if (c == '[' || c == '{') depth++;
        if (c == ']' || c == '}') {
            if (depth == 0) return i;
            if (--depth == 0) return i + 1;
        }
        if (c == ',' && depth == 0) return i;
    }
    return i;
}

/* The report without volatile members and without whitespace; stray commas left by
 * dropped members are removed. The caller frees the result. */
static char *normalise_report(const char *s, bool tiling) {
    size_t n = strlen(s), o = 0;
    char *t = malloc(n + 1);
    assert_non_null(t);
    for (size_t i = 0; i < n;) {
        char c = s[i];
        if (c == '"') { /* a string: a key when a ':' follows */
            size_t j = i + 1;
            while (s[j] && s[j] != '"')
                j += s[j] == '\\' ? 2 : 1;
            size_t k = j + 1;
            while (s[k] == ' ' || s[k] == '\n')
                k++;
            char key[128];
            snprintf(key, sizeof key, "%.*s", (int)(j - i - 1), s + i + 1);
            if (s[k] == ':' && volatile_key(key, tiling)) {
                i = skip_value(s, k + 1);
                continue;
            }
            memcpy(t + o, s + i, j + 1 - i);
            o += j + 1 - i;
            i = j + 1;
            continue;
        }
        if (c != ' ' && c != '\n' && c != '\t') t[o++] = c;
        i++;
    }
    t[o] = '\0';
    /* ",," ",}" ",]" "{," "[," -> drop the comma */
    size_t w = 0;
    for (size_t i = 0; i < o; i++) {
        if (t[i] == ',' && (t[i + 1] == ',' || t[i + 1] == '}' || t[i + 1] == ']' || w == 0 ||
                            t[w - 1] == '{' || t[w - 1] == '[' || t[w - 1] == ','))
            continue;
        t[w++] = t[i];
    }
    t[w] = '\0';
    return t;
}

static int cmp_names(const void *a, const void *b) {
    return strcmp((const char *)a, (const char *)b);
}

/* Hash every regular file of `d` (not recursive: the CLI writes flat directories),
 * plus the normalised report `json` when given, masking tiling fields if asked. */
static void hash_outputs(const char *d, const char *json, bool mask_tiling, manifest *m) {
    memset(m, 0, sizeof *m);
    DIR *dp = opendir(d);
    if (!dp) fail_msg("no output directory %s", d);
    struct dirent *e;
    while ((e = readdir(dp)))
        if (e->d_name[0] != '.') {
            assert_true(m->n < MAX_FILES);
            snprintf(m->name[m->n++], sizeof m->name[0], "%s", e->d_name);
        }
    closedir(dp);
    qsort(m->name, (size_t)m->n, sizeof m->name[0], cmp_names);
    for (int i = 0; i < m->n; i++) {
        char p[1024];
        if (snprintf(p, sizeof p, "%s/%s", d, m->name[i]) >= (int)sizeof p)
            fail_msg("path too long: %s/%s", d, m->name[i]);
        size_t n;
        unsigned char *b = slurp(p, &n);
        if (mask_tiling && (strstr(p, ".json") || strstr(p, ".glb"))) {
            mask_number(b, n, "\"tiles\"");
            mask_number(b, n, "\"tile_size\"");
        }
        m->hash[i] = fnv1a(b, n);
        free(b);
    }
    if (json) {
        size_t n;
        unsigned char *b = slurp(json, &n);
        char *t = normalise_report((const char *)b, mask_tiling);
        if (!strstr(t, "\"command\":") || !strstr(t, "\"parameters\":{"))
            fail_msg("normalised report of %s lost its content: %s", json, t);
        assert_true(m->n < MAX_FILES);
        snprintf(m->name[m->n], sizeof m->name[0], "(report %s)", json);
        m->hash[m->n++] = fnv1a((const unsigned char *)t, strlen(t));
        free(t);
        free(b);
    }
}

static void expect_same(const manifest *a, const manifest *b, const char *what) {
    if (a->n != b->n) fail_msg("%s: %d files vs %d", what, a->n, b->n);
    for (int i = 0; i < a->n; i++) {
        if (strcmp(a->name[i], b->name[i]) != 0)
            fail_msg("%s: file %s vs %s", what, a->name[i], b->name[i]);
        if (a->hash[i] != b->hash[i])
            fail_msg("%s: %s differs (%016llx vs %016llx)", what, a->name[i],
                     (unsigned long long)a->hash[i], (unsigned long long)b->hash[i]);
    }
}

/* Run `args` (which writes into outdir) with OMP_NUM_THREADS=threads and the report at
 * json, after emptying outdir (commands that write one file get it created empty); then
 * hash the outputs. */
static void run_and_hash(const char *args, const char *outdir, const char *json, int threads,
                         bool mask_tiling, manifest *m) {
    char cmd[1200], full[4096];
    bool file_out = strncmp(args, "pits", 4) == 0;
    snprintf(cmd, sizeof cmd, "rm -rf '%s'%s%s", outdir, file_out ? " && mkdir -p " : "",
             file_out ? outdir : "");
    assert_int_equal(system(cmd), 0);
    char t[16];
    snprintf(t, sizeof t, "%d", threads);
    setenv("OMP_NUM_THREADS", t, 1);
    snprintf(full, sizeof full, "%s -q --json %s", args, json);
    int rc = pg_test_run_cli(full, out, sizeof out, err, sizeof err);
    unsetenv("OMP_NUM_THREADS");
    if (rc != 0) fail_msg("'%s': exit %d, stderr '%s'", full, rc, err);
    hash_outputs(outdir, json, mask_tiling, m);
    assert_true(m->n >= 2); /* at least one output and the report */
}

static int setup(void **state) {
    (void)state;
    pg_test_scratch_dir("determinism", dir, sizeof dir);
    snprintf(cache, sizeof cache, "%s/synth-cache", getenv("PG_BUILD_DIR"));
    return 0;
}

/* A small planet, N = 128: two runs, 1 vs 2 threads, and 2 x 64 vs 4 x 32 tiles. */
static void test_generate(void **state) {
    (void)state;
    char o[700], json[700], args[2048];
    snprintf(o, sizeof o, "%s/gen", dir);
    snprintf(json, sizeof json, "%s/gen.json", dir);
    const char *fmt = "generate --tiles %d --tile-size %d --seed 7 --cache-dir %s -o %s";
    manifest a, b;
    snprintf(args, sizeof args, fmt, 2, 64, cache, o);
    run_and_hash(args, o, json, 2, false, &a);
    assert_true(a.n >= 15); /* 6 faces, height.exr, planet.glb/json, 2 previews, 4 globes */
    run_and_hash(args, o, json, 2, false, &b);
    expect_same(&a, &b, "generate, second run");
    run_and_hash(args, o, json, 1, false, &b);
    expect_same(&a, &b, "generate, OMP_NUM_THREADS=1 vs 2");
    /* the exemplar prepared in memory, not mapped from the cache file */
    snprintf(args, sizeof args,
             "generate --tiles %d --tile-size %d --seed 7 --no-cache --cache-dir %s -o %s", 2, 64,
             cache, o);
    run_and_hash(args, o, json, 2, false, &b);
    expect_same(&a, &b, "generate, --no-cache vs the mapped cache");
    snprintf(args, sizeof args, fmt, 2, 64, cache, o);
    /* tilings: mask the tiling fields in both */
    run_and_hash(args, o, json, 2, true, &a);
    snprintf(args, sizeof args, fmt, 4, 32, cache, o);
    run_and_hash(args, o, json, 2, true, &b);
    expect_same(&a, &b, "generate, 4 x 32 vs 2 x 64 tiles");
}

/* Flat synthesis, 128^2: two runs, 1 vs 2 threads, whole levels vs 32^2 tiles. */
static void test_synth(void **state) {
    (void)state;
    char o[700], json[700], args[2048];
    snprintf(o, sizeof o, "%s/synth", dir);
    snprintf(json, sizeof json, "%s/synth.json", dir);
    const char *fmt = "synth --size 128 --seed 5 --tile-size %d --cache-dir %s -o %s";
    manifest a, b;
    snprintf(args, sizeof args, fmt, 0, cache, o);
    run_and_hash(args, o, json, 2, false, &a);
    assert_int_equal(a.n, 4); /* albedo.png, coords.png, height.exr, the report */
    run_and_hash(args, o, json, 2, false, &b);
    expect_same(&a, &b, "synth, second run");
    run_and_hash(args, o, json, 1, false, &b);
    expect_same(&a, &b, "synth, OMP_NUM_THREADS=1 vs 2");
    run_and_hash(args, o, json, 2, true, &a);
    snprintf(args, sizeof args, fmt, 32, cache, o);
    run_and_hash(args, o, json, 2, true, &b);
    expect_same(&a, &b, "synth, --tile-size 32 vs whole levels");
}

/* Pit removal on a 256^2 random DEM full of pits, each method, 1 vs 2 threads. */
static void test_pits(void **state) {
    (void)state;
    char dem[700], o[700], json[700], args[2048];
    pg_image img;
    pg_error e = {0};
    assert_int_equal(pg_image_alloc(&img, 256, 256, 1, &e), PG_OK);
    uint64_t x = 88172645463325252ull;
    for (int i = 0; i < 256 * 256; i++) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        img.data[i] = (float)(x % 1000) + 0.01f * (float)(i % 256);
    }
    snprintf(dem, sizeof dem, "%s/dem.exr", dir);
    assert_int_equal(pg_image_write_exr(dem, &img, NULL, &e), PG_OK);
    pg_image_free(&img);
    snprintf(o, sizeof o, "%s/pits", dir);
    snprintf(json, sizeof json, "%s/pits.json", dir);
    const char *methods[] = {"fill", "breach", "hybrid --max-depth 50"};
    for (int k = 0; k < 3; k++) {
        manifest a, b;
        snprintf(args, sizeof args, "pits --method %s --epsilon %s -o %s/out.exr", methods[k], dem,
                 o);
        run_and_hash(args, o, json, 2, false, &a);
        run_and_hash(args, o, json, 2, false, &b);
        expect_same(&a, &b, methods[k]);
        run_and_hash(args, o, json, 1, false, &b);
        expect_same(&a, &b, methods[k]);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_generate),
        cmocka_unit_test(test_synth),
        cmocka_unit_test(test_pits),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
