/* pg_cli_memory.c - memory in the CLI: the process's peak RSS, its private and shared
 * memory (smaps_rollup, sampled by a watcher thread), the memory a run may use,
 * the check against it that commands make before any work, and the estimate of an
 * exemplar load from its inputs' headers. */
#include "pg_cli.h"

#include "pg_marble.h"

#include "planetgen/pg_image.h"

#include <math.h>
#include <stdio.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

double pg_cli_peak_rss_bytes(void) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return 1024.0 * (double)ru.ru_maxrss;
}

bool pg_cli_smaps(pg_cli_smaps_figures *out) {
    memset(out, 0, sizeof *out);
    FILE *f = fopen("/proc/self/smaps_rollup", "r");
    if (!f) return false;
    char line[256], key[64];
    double kb;
    int seen = 0;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "%63[^:]: %lf kB", key, &kb) == 2) {
            bool dirty = !strcmp(key, "Private_Dirty");
            bool p = dirty || !strcmp(key, "Private_Clean");
            bool s = !strcmp(key, "Shared_Clean") || !strcmp(key, "Shared_Dirty");
            out->private_bytes += p ? kb * 1024.0 : 0;
            out->shared_bytes += s ? kb * 1024.0 : 0;
            out->private_dirty_bytes += dirty ? kb * 1024.0 : 0;
            seen += p || s;
        }
    fclose(f);
    return seen == 4;
}

void pg_cli_sample_memory(pg_cli *cli) {
    pg_cli_smaps_figures m;
    if (!pg_cli_smaps(&m)) return;
    pthread_mutex_lock(&cli->lock);
    if (m.private_bytes > cli->private_peak) cli->private_peak = m.private_bytes;
    if (m.shared_bytes > cli->shared_peak) cli->shared_peak = m.shared_bytes;
    if (m.private_dirty_bytes > cli->private_dirty_peak)
        cli->private_dirty_peak = m.private_dirty_bytes;
    pthread_mutex_unlock(&cli->lock);
}

/* The wait after a sample that took `took` seconds. Reading smaps_rollup walks the page
 * tables of every mapping under the mmap lock: 10-30 ms once the exemplar's cache is
 * mapped (6 x 1024^2, about 1 GB resident), which at a fixed 0.1 s would take 10-30% of a
 * core from the run and stall its page faults. So the watcher waits at least
 * PG_CLI_SMAPS_DUTY times its own last read, keeping its share of one core below
 * 1 / PG_CLI_SMAPS_DUTY; small processes are still sampled every PG_CLI_SMAPS_INTERVAL. */
static double watch_interval(double took) {
    double wait = PG_CLI_SMAPS_DUTY * took;
    return wait > PG_CLI_SMAPS_INTERVAL ? wait : PG_CLI_SMAPS_INTERVAL;
}

static void *memory_watcher(void *arg) {
    pg_cli *cli = arg;
    for (;;) {
        pthread_mutex_lock(&cli->lock);
        bool paused = cli->mem_paused;
        pthread_mutex_unlock(&cli->lock);
        double t0 = pg_cli_now();
        if (!paused) pg_cli_sample_memory(cli);
        double wait = watch_interval(pg_cli_now() - t0);
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        long ns = until.tv_nsec + (long)(wait * 1e9);
        until.tv_sec += ns / 1000000000L;
        until.tv_nsec = ns % 1000000000L;
        pthread_mutex_lock(&cli->lock);
        while (!cli->mem_stop &&
               pthread_cond_timedwait(&cli->mem_wake, &cli->lock, &until) != ETIMEDOUT) {
        }
        bool stop = cli->mem_stop;
        pthread_mutex_unlock(&cli->lock);
        if (stop) return NULL;
    }
}

int pg_cli_memory_watch(pg_cli *cli) {
    if (cli->mem_watching) return 0;
    cli->mem_stop = false;
    if (pthread_create(&cli->mem_watcher, NULL, memory_watcher, cli) != 0) return -1;
    cli->mem_watching = true;
    return 0;
}

void pg_cli_memory_pause(pg_cli *cli, bool paused) {
    pthread_mutex_lock(&cli->lock);
    cli->mem_paused = paused;
    pthread_mutex_unlock(&cli->lock);
}

void pg_cli_memory_peaks(pg_cli *cli, pg_cli_smaps_figures *get, const pg_cli_smaps_figures *set) {
    pthread_mutex_lock(&cli->lock);
    if (get)
        *get = (pg_cli_smaps_figures){cli->private_peak, cli->shared_peak, cli->private_dirty_peak};
    if (set) {
        cli->private_peak = set->private_bytes;
        cli->shared_peak = set->shared_bytes;
        cli->private_dirty_peak = set->private_dirty_bytes;
    }
    pthread_mutex_unlock(&cli->lock);
}

void pg_cli_memory_unwatch(pg_cli *cli) {
    if (!cli->mem_watching) return;
    pthread_mutex_lock(&cli->lock);
    cli->mem_stop = true;
    pthread_cond_signal(&cli->mem_wake);
    pthread_mutex_unlock(&cli->lock);
    pthread_join(cli->mem_watcher, NULL);
    cli->mem_watching = false;
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

double pg_cli_memory_limit(double max_memory_gb, int sharers) {
    if (max_memory_gb > 0) return max_memory_gb * 1e9;
    return pg_cli_available_bytes() / (sharers > 1 ? sharers : 1);
}

int pg_cli_check_memory_shared(pg_cli *cli, const char *what, double need, double have,
                               double max_memory_gb, int sharers) {
    if (!(need <= have)) {
        char limit[96];
        if (max_memory_gb > 0)
            snprintf(limit, sizeof limit, "allowed by --max-memory");
        else if (sharers > 1)
            snprintf(limit, sizeof limit, "available to each of the %d ranks on its machine",
                     sharers);
        else
            snprintf(limit, sizeof limit, "available");
        return pg_cli_usage_error(cli,
                                  "%s: needs about %.2f GB of memory, more than the %.2f GB %s "
                                  "(raise it with --max-memory GB)",
                                  what, need / 1e9, have / 1e9, limit);
    }
    cli->memory_estimate = need;
    return 0;
}

int pg_cli_check_memory(pg_cli *cli, const char *what, double need, double max_memory_gb) {
    return pg_cli_check_memory_shared(cli, what, need, pg_cli_memory_limit(max_memory_gb, 1),
                                      max_memory_gb, 1);
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
