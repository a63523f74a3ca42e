/* bench_util.h - small helpers the benchmarks share: the machine's load, a whole file
 * read into memory, and a number read from a JSON report by its key (the reports are the
 * CLI's own --json output, so a text search for "key": is enough). Header-only, for
 * bench/ only. */
#ifndef PG_BENCH_UTIL_H
#define PG_BENCH_UTIL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The 1-minute load average, -1 when /proc/loadavg cannot be read. */
static inline double pg_bench_loadavg(void) {
    double l = -1;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f && fscanf(f, "%lf", &l) != 1) l = -1;
    if (f) fclose(f);
    return l;
}

/* The file at path, NUL-terminated (free it), or NULL. */
static inline char *pg_bench_slurp(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)n + 1);
    if (b && fread(b, 1, (size_t)n, f) != (size_t)n) n = 0;
    if (b) b[n] = 0;
    fclose(f);
    return b;
}

/* The number after the first "key": at or after json, NAN when absent (or json NULL). */
static inline double pg_bench_json_number(const char *json, const char *key) {
    char pat[128];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = json ? strstr(json, pat) : NULL;
    return p ? strtod(p + strlen(pat), NULL) : NAN;
}

#endif
