/* pg_cli_memory.c - memory in the CLI: the process's peak RSS, the memory a run may use,
 * the check against it that commands make before any work, and the estimate of an
 * exemplar load from its inputs' headers. */
#include "pg_cli.h"

#include "pg_marble.h"

#include "planetgen/pg_image.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>

double pg_cli_peak_rss_bytes(void) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return 1024.0 * (double)ru.ru_maxrss;
}

double pg_cli_available_bytes(void) {
    const char *env = getenv("PLANETGEN_MEM_AVAILABLE");
    if (env && *env) {
        char *end = NULL;
        double v = strtod(env, &end);
        if (end && !*end && v >= 0 && isfinite(v)) return v;
    }
    FILE *f = fopen("/proc/meminfo", "r");
    double kb = 0;
    char line[256];
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "MemAvailable: %lf kB", &kb) == 1) break;
    if (f) fclose(f);
    return kb > 0 ? kb * 1024.0 : 8e9;
}

int pg_cli_check_memory(pg_cli *cli, const char *what, double need, double max_memory_gb) {
    double have = max_memory_gb > 0 ? max_memory_gb * 1e9 : pg_cli_available_bytes();
    if (!(need <= have))
        return pg_cli_usage_error(cli,
                                  "%s: needs about %.2f GB of memory, more than the %.2f GB %s "
                                  "(raise it with --max-memory GB)",
                                  what, need / 1e9, have / 1e9,
                                  max_memory_gb > 0 ? "allowed by --max-memory" : "available");
    cli->memory_estimate = need;
    return 0;
}

/* Pixels and channels of one exemplar input from its header; 0 when it cannot be read
 * or is above the pixel limit. */
static double probe_values(const char *path, uint64_t max_pixels, int *width) {
    int w = 0, h = 0, c = 0;
    pg_error err = {0};
    if (pg_image_probe(path, &w, &h, &c, &err) != PG_OK) return 0;
    if ((double)w * h > (double)(max_pixels ? max_pixels : PG_IMAGE_DEFAULT_MAX_PIXELS)) return 0;
    *width = w;
    return (double)w * h * c;
}

/* Measured: the default pair (2700 x 1350 JPEG albedo, 10800 x 5400 grey relief from
 * 8-bit tiles) peaks at 457 MB. Each decoded input value is held as a float next to
 * its decoding buffer (6 B per value, rounded up), and each grid pixel carries albedo,
 * elevation, water mask, resampling scratch and the relief preview (48 B); 64 MB of
 * libraries. This gives 654 MB for the default pair. */
double pg_cli_exemplar_bytes(const pg_exemplar_opts *o) {
    int aw = 0, hw = 0;
    double a = probe_values(o->albedo_path ? o->albedo_path : PG_MARBLE_ALBEDO, o->max_pixels, &aw);
    double h;
    if (o->height_path) {
        h = probe_values(o->height_path, o->max_pixels, &hw);
    } else { /* Marble's relief: ROWS x COLS grey tiles of 675^2 */
        hw = PG_MARBLE_RELIEF_COLS * 675;
        h = (double)hw * PG_MARBLE_RELIEF_ROWS * 675;
    }
    double gw = o->grid_width > 0 ? o->grid_width : (aw && hw ? (aw < hw ? aw : hw) : aw + hw);
    return 64e6 + 6 * (a + h) + 48 * gw * (gw / 2);
}
