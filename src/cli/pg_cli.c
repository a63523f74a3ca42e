/* pg_cli.c - shared CLI machinery: options, messages, progress, outputs, report.
 *
 * The invariants every command gets from here:
 *  - a usage error is one line "planetgen CMD: ..." naming the option, exit 2;
 *  - outputs are written under temporary names and renamed only when the whole
 *    command succeeded, so a failed run leaves no partial files behind;
 *  - progress is a bar with ETA on a terminal, one line per stage otherwise. */
#include "pg_cli.h"

#include "pg_marble.h"
#include "planetgen/pg_image.h"
#include "planetgen/pg_json.h"

#include <errno.h>
#include <math.h>
#include <omp.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

void pg_cli_init(pg_cli *cli, const char *cmd) {
    memset(cli, 0, sizeof *cli);
    cli->cmd = cmd;
    pthread_mutex_init(&cli->lock, NULL);
}

void pg_cli_block_signals(void) {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set, NULL);
    signal(SIGXFSZ, SIG_IGN);
}

/* Remove staged temporaries; the caller holds cli->lock. Safe while writers still
 * have the files open: the names go, the data is freed when they close. */
static void remove_staged_locked(pg_cli *cli) {
    for (int i = 0; i < cli->nstaged; i++)
        unlink(cli->staged_tmp[i]);
    if (cli->created_dir) rmdir(cli->created_dir);
}

static void *signal_watcher(void *arg) {
    pg_cli *cli = arg;
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    int sig = 0;
    if (sigwait(&set, &sig) != 0) return NULL;
    /* Hold the lock for good: no commit may rename files after this point. */
    pthread_mutex_lock(&cli->lock);
    if (cli->unwatching) { /* woken by pg_cli_unwatch_signals: the command is over */
        pthread_mutex_unlock(&cli->lock);
        return NULL;
    }
    remove_staged_locked(cli);
    char msg[160];
    int n = snprintf(msg, sizeof msg, "\nplanetgen %s: interrupted by %s; no output written\n",
                     cli->cmd, sig == SIGINT ? "SIGINT" : "SIGTERM");
    if (write(STDERR_FILENO, msg + (cli->tty ? 0 : 1), (size_t)n - (cli->tty ? 0 : 1)) < 0) {
        /* nothing more to do: we are exiting */
    }
    _exit(128 + sig);
}

int pg_cli_watch_signals(pg_cli *cli) {
    if (pthread_create(&cli->watcher, NULL, signal_watcher, cli) != 0) return -1;
    cli->watching = true;
    return 0;
}

/* The watcher must be gone before the pg_cli is: a SIGTERM that arrives while the
 * process exits (mpirun sends one to every rank as soon as one rank fails) once woke a
 * detached watcher on a dead stack frame, which then unlinked whatever strings the
 * stale staged-file list pointed to, system libraries included. The wake-up is a
 * SIGTERM directed at the watcher thread with `unwatching` set, so no other signal
 * number is taken from the user or from MPI. Signals that arrive afterwards stay
 * blocked and pending; the process ends with the command's own exit code. */
void pg_cli_unwatch_signals(pg_cli *cli) {
    if (!cli->watching) return;
    pthread_mutex_lock(&cli->lock);
    cli->unwatching = true;
    pthread_mutex_unlock(&cli->lock);
    pthread_kill(cli->watcher, SIGTERM);
    pthread_join(cli->watcher, NULL);
    cli->watching = false;
}

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

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

int pg_cli_usage_error(pg_cli *cli, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "planetgen %s: ", cli->cmd);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    pg_json_free(cli->report);
    cli->report = NULL;
    return 2;
}

static bool choice_ok(const char *choices, const char *v) {
    size_t n = strlen(v);
    for (const char *p = choices; p && *p;) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        if (len == n && strncmp(p, v, n) == 0) return true;
        p = bar ? bar + 1 : NULL;
    }
    return false;
}

/* Store one option value, checking type and range. Returns 0 or 2. */
static int store_value(pg_cli *cli, const pg_opt *o, const char *v) {
    char *end = NULL;
    switch (o->kind) {
    case PG_OPT_FLAG:
        *(bool *)o->dest = true;
        return 0;
    case PG_OPT_STRING:
        if (!*v) return pg_cli_usage_error(cli, "%s: empty value", o->name);
        *(const char **)o->dest = v;
        return 0;
    case PG_OPT_CHOICE:
        if (!choice_ok(o->choices, v))
            return pg_cli_usage_error(cli, "%s: unknown value '%s' (choose %s)", o->name, v,
                                      o->choices);
        *(const char **)o->dest = v;
        return 0;
    case PG_OPT_INT: {
        errno = 0;
        long x = strtol(v, &end, 10);
        if (!*v || *end || errno)
            return pg_cli_usage_error(cli, "%s: '%s' is not an integer", o->name, v);
        if (x < o->min || x > o->max)
            return pg_cli_usage_error(cli, "%s: %ld is out of range [%.0f, %.0f]", o->name, x,
                                      o->min, o->max);
        *(long *)o->dest = x;
        return 0;
    }
    case PG_OPT_DOUBLE: {
        errno = 0;
        double x = strtod(v, &end);
        if (!*v || *end || errno || !isfinite(x))
            return pg_cli_usage_error(cli, "%s: '%s' is not a finite number", o->name, v);
        if (x < o->min || x > o->max)
            return pg_cli_usage_error(cli, "%s: %g is out of range [%g, %g]", o->name, x, o->min,
                                      o->max);
        *(double *)o->dest = x;
        return 0;
    }
    }
    return 2;
}

static const pg_opt *find_opt(const pg_opt *specs, const pg_opt *common, const char *name) {
    for (const pg_opt *o = specs; o && o->name; o++)
        if (!strcmp(o->name, name) || (o->alias && !strcmp(o->alias, name))) return o;
    for (const pg_opt *o = common; o->name; o++)
        if (!strcmp(o->name, name) || (o->alias && !strcmp(o->alias, name))) return o;
    return NULL;
}

static int check_json_path(pg_cli *cli) {
    if (!cli->json_path) return 0;
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", cli->json_path);
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = '\0';
    else
        snprintf(dir, sizeof dir, ".");
    struct stat st;
    if (stat(dir[0] ? dir : "/", &st) != 0 || !S_ISDIR(st.st_mode))
        return pg_cli_usage_error(cli, "--json %s: directory '%s' does not exist", cli->json_path,
                                  dir);
    if (access(dir[0] ? dir : "/", W_OK) != 0)
        return pg_cli_usage_error(cli, "--json %s: directory '%s' is not writable", cli->json_path,
                                  dir);
    cli->report = pg_json_object();
    return 0;
}

int pg_cli_parse(pg_cli *cli, const pg_opt *specs, int argc, char **argv, const char **pos,
                 int max_pos, int *npos, bool *done) {
    bool help = false;
    const pg_opt common[] = {
        {"--json", NULL, PG_OPT_STRING, &cli->json_path, 0, 0, NULL, "FILE",
         "write a machine-readable summary (inputs, parameters, stage times, peak memory)"},
        {"--quiet", "-q", PG_OPT_FLAG, &cli->quiet, 0, 0, NULL, NULL, "no progress or info output"},
        {"--verbose", "-v", PG_OPT_FLAG, &cli->verbose, 0, 0, NULL, NULL, "more detail"},
        {"--threads", NULL, PG_OPT_INT, &cli->threads, 0, 1024, NULL, "N",
         "OpenMP threads (0 = all cores); results do not depend on it"},
        {"--help", "-h", PG_OPT_FLAG, &help, 0, 0, NULL, NULL, "show this help"},
        PG_OPT_END};
    *npos = 0;
    *done = false;
    cli->t_start = now_s();
    cli->tty = isatty(STDERR_FILENO);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (a[0] == '-' && a[1] != '\0') {
            char name[64];
            const char *eq = strchr(a, '=');
            size_t len = eq ? (size_t)(eq - a) : strlen(a);
            if (len >= sizeof name) return pg_cli_usage_error(cli, "unknown option '%s'", a);
            memcpy(name, a, len);
            name[len] = '\0';
            const pg_opt *o = find_opt(specs, common, name);
            if (!o) return pg_cli_usage_error(cli, "unknown option '%s'", name);
            if (o->kind == PG_OPT_FLAG) {
                if (eq) return pg_cli_usage_error(cli, "%s takes no value", name);
                *(bool *)o->dest = true;
                continue;
            }
            /* A following word that is itself an option is not this option's value. */
            const char *v = eq ? eq + 1 : (i + 1 < argc ? argv[i + 1] : NULL);
            if (!eq && v && find_opt(specs, common, v)) v = NULL;
            if (!v) return pg_cli_usage_error(cli, "%s needs a value", name);
            if (!eq) i++;
            int rc = store_value(cli, o, v);
            if (rc) return rc;
        } else {
            if (*npos >= max_pos) return pg_cli_usage_error(cli, "unexpected argument '%s'", a);
            pos[(*npos)++] = a;
        }
    }
    if (help) {
        *done = true;
        return 0;
    }
    if (cli->threads > 0) omp_set_num_threads((int)cli->threads);
    return check_json_path(cli);
}

int pg_cli_parse_or_help(pg_cli *cli, const pg_opt *specs, int argc, char **argv, const char **pos,
                         int max_pos, int *npos, const char *usage, const char *description) {
    bool done = false;
    int rc = pg_cli_parse(cli, specs, argc, argv, pos, max_pos, npos, &done);
    if (rc) return rc;
    if (!done) return -1;
    pg_cli_print_help(cli, usage, description, specs, stdout);
    return 0;
}

void pg_cli_exemplar_opts(const pg_cli_exemplar *e, pg_exemplar_opts *o) {
    pg_exemplar_opts_default(o);
    o->albedo_path = e->albedo;
    o->height_path = e->height;
    o->height_scale = e->height_scale;
    o->height_offset = e->height_offset;
    o->sea_level = e->sea_level;
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

static void print_opt_table(const pg_opt *specs, FILE *f) {
    for (const pg_opt *o = specs; o && o->name; o++) {
        char left[96];
        snprintf(left, sizeof left, "%s%s%s%s%s", o->alias ? o->alias : "", o->alias ? ", " : "",
                 o->name, o->metavar ? " " : "", o->metavar ? o->metavar : "");
        fprintf(f, "  %-28s %s", left, o->help ? o->help : "");
        if (o->kind == PG_OPT_CHOICE) fprintf(f, " (%s)", o->choices);
        if (o->kind == PG_OPT_INT || o->kind == PG_OPT_DOUBLE)
            fprintf(f, " [%g..%g]", o->min, o->max);
        fputc('\n', f);
    }
}

void pg_cli_print_help(const pg_cli *cli, const char *usage, const char *description,
                       const pg_opt *specs, FILE *f) {
    fprintf(f, "usage: planetgen %s %s\n\n%s\n\noptions:\n", cli->cmd, usage, description);
    print_opt_table(specs, f);
    fprintf(f, "\ncommon options:\n"
               "  --json FILE                  write a machine-readable summary\n"
               "  -q, --quiet                  no progress or info output\n"
               "  -v, --verbose                more detail\n"
               "  --threads N                  OpenMP threads (0 = all cores)\n"
               "  -h, --help                   show this help\n"
               "\nexit codes: 0 success, 1 runtime failure, 2 usage error or bad input\n");
}

void pg_cli_info(const pg_cli *cli, const char *fmt, ...) {
    if (cli->quiet) return;
    va_list ap;
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    fflush(stdout);
}

void pg_cli_verbose(const pg_cli *cli, const char *fmt, ...) {
    if (cli->quiet || !cli->verbose) return;
    va_list ap;
    va_start(ap, fmt);
    vprintf(fmt, ap);
    va_end(ap);
    fflush(stdout);
}

void pg_cli_stage_begin(pg_cli *cli, const char *name) {
    snprintf(cli->stage_name, sizeof cli->stage_name, "%s", name);
    cli->stage_t0 = now_s();
    cli->last_draw = 0;
    if (!cli->quiet && cli->tty) pg_cli_progress(cli, 0.0);
}

void pg_cli_progress(pg_cli *cli, double frac) {
    if (cli->quiet || !cli->tty) return;
    double t = now_s();
    if (frac > 0 && frac < 1 && t - cli->last_draw < 0.1) return;
    cli->last_draw = t;
    if (frac < 0) frac = 0;
    if (frac > 1) frac = 1;
    int filled = (int)(frac * 30 + 0.5);
    char bar[31];
    for (int i = 0; i < 30; i++)
        bar[i] = i < filled ? '#' : '.';
    bar[30] = '\0';
    double el = t - cli->stage_t0;
    if (frac > 0.01)
        fprintf(stderr, "\r%-24s [%s] %3.0f%%  ETA %5.1fs ", cli->stage_name, bar, 100 * frac,
                el / frac - el);
    else
        fprintf(stderr, "\r%-24s [%s] %3.0f%%  ETA   ?   ", cli->stage_name, bar, 100 * frac);
    fflush(stderr);
}

void pg_cli_stage_end(pg_cli *cli) {
    double dt = now_s() - cli->stage_t0;
    if (cli->nstages < PG_STAGE_MAX) {
        snprintf(cli->stages[cli->nstages].name, sizeof cli->stages[0].name, "%s", cli->stage_name);
        cli->stages[cli->nstages].seconds = dt;
        cli->stages[cli->nstages].peak_rss_bytes = pg_cli_peak_rss_bytes();
        cli->nstages++;
    }
    if (cli->quiet) return;
    if (cli->tty) {
        cli->last_draw = 0;
        pg_cli_progress(cli, 1.0);
        fprintf(stderr, " %.2f s\n", dt);
    } else {
        fprintf(stderr, "planetgen %s: %s done in %.2f s\n", cli->cmd, cli->stage_name, dt);
    }
}

pg_status pg_cli_prepare_outdir(pg_cli *cli, const char *dir, pg_error *err) {
    struct stat st;
    if (stat(dir, &st) == 0) {
        if (!S_ISDIR(st.st_mode))
            return pg_error_set(err, PG_ERR_BADINPUT, "-o %s: exists and is not a directory", dir);
        if (access(dir, W_OK) != 0)
            return pg_error_set(err, PG_ERR_BADINPUT, "-o %s: directory is not writable", dir);
        return PG_OK;
    }
    /* Create the directory and any missing parents. */
    char path[4096];
    snprintf(path, sizeof path, "%s", dir);
    for (char *p = path + 1; *p; p++) {
        if (*p != '/') continue;
        *p = '\0';
        if (mkdir(path, 0777) != 0 && errno != EEXIST)
            return pg_error_set(err, PG_ERR_BADINPUT, "-o %s: cannot create '%s': %s", dir, path,
                                strerror(errno));
        *p = '/';
    }
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return pg_error_set(err, PG_ERR_BADINPUT, "-o %s: cannot create directory: %s", dir,
                            strerror(errno));
    free(cli->created_dir);
    cli->created_dir = strdup(dir);
    return PG_OK;
}

const char *pg_cli_output_path(pg_cli *cli, const char *dir, const char *name) {
    char fin[4096], tmp[4096];
    snprintf(fin, sizeof fin, "%s/%s", dir, name);
    /* Keep the extension last so libraries that pick a format by suffix still work. */
    snprintf(tmp, sizeof tmp, "%s/.tmp-%d-%s", dir, (int)getpid(), name);
    pthread_mutex_lock(&cli->lock);
    char **t = realloc(cli->staged_tmp, (cli->nstaged + 1) * sizeof *t);
    if (t) cli->staged_tmp = t;
    char **f = realloc(cli->staged_final, (cli->nstaged + 1) * sizeof *f);
    if (f) cli->staged_final = f;
    const char *ret = NULL;
    if (t && f) {
        cli->staged_tmp[cli->nstaged] = strdup(tmp);
        cli->staged_final[cli->nstaged] = strdup(fin);
        ret = cli->staged_tmp[cli->nstaged++];
    }
    pthread_mutex_unlock(&cli->lock);
    return ret;
}

static void free_staged(pg_cli *cli) {
    for (int i = 0; i < cli->nstaged; i++) {
        free(cli->staged_tmp[i]);
        free(cli->staged_final[i]);
    }
    free(cli->staged_tmp);
    free(cli->staged_final);
    cli->staged_tmp = cli->staged_final = NULL;
    cli->nstaged = 0;
}

pg_status pg_cli_commit(pg_cli *cli, pg_error *err) {
    pthread_mutex_lock(&cli->lock);
    pg_status st = PG_OK;
    for (int i = 0; i < cli->nstaged; i++) {
        if (rename(cli->staged_tmp[i], cli->staged_final[i]) != 0) {
            pg_error_set(err, PG_ERR_IO, "%s: cannot rename into place: %s", cli->staged_final[i],
                         strerror(errno));
            /* Remove what is not yet renamed; renamed files are complete. */
            for (int j = i; j < cli->nstaged; j++)
                unlink(cli->staged_tmp[j]);
            st = PG_ERR_IO;
            break;
        }
    }
    free_staged(cli);
    pthread_mutex_unlock(&cli->lock);
    return st;
}

void pg_cli_abort(pg_cli *cli) {
    pthread_mutex_lock(&cli->lock);
    remove_staged_locked(cli); /* rmdir only succeeds if empty: never removes user files */
    free_staged(cli);
    free(cli->created_dir);
    cli->created_dir = NULL;
    pthread_mutex_unlock(&cli->lock);
}

/* Messages from writers name the temporary file they wrote; the user knows the
 * final name, so print that instead. */
static void print_failure(pg_cli *cli, const char *msg) {
    pthread_mutex_lock(&cli->lock);
    for (int i = 0; i < cli->nstaged; i++) {
        const char *hit = strstr(msg, cli->staged_tmp[i]);
        if (!hit) continue;
        fprintf(stderr, "planetgen %s: %.*s%s%s\n", cli->cmd, (int)(hit - msg), msg,
                cli->staged_final[i], hit + strlen(cli->staged_tmp[i]));
        pthread_mutex_unlock(&cli->lock);
        return;
    }
    pthread_mutex_unlock(&cli->lock);
    fprintf(stderr, "planetgen %s: %s\n", cli->cmd, msg);
}

int pg_cli_fail(pg_cli *cli, const pg_error *err) {
    if (cli->tty && !cli->quiet) fputc('\n', stderr);
    print_failure(cli, err && err->msg[0] ? err->msg : "failed");
    pg_cli_abort(cli);
    pg_json_free(cli->report);
    cli->report = NULL;
    return pg_status_exit_code(err ? err->status : PG_ERR_RUNTIME);
}

struct pg_json *pg_cli_report(pg_cli *cli) {
    return cli->report;
}

/* Stage the report as one more output, so it too appears only on success. */
static pg_status stage_report(pg_cli *cli, pg_error *err) {
    if (!cli->report) return PG_OK;
    pg_json_set_string(cli->report, "command", cli->cmd);
    pg_json_set_string(cli->report, "version", pg_version());
    pg_json *st = pg_json_set_array(cli->report, "stages");
    for (int i = 0; i < cli->nstages; i++) {
        pg_json *s = pg_json_push_object(st);
        pg_json_set_string(s, "name", cli->stages[i].name);
        pg_json_set_number(s, "seconds", cli->stages[i].seconds);
        pg_json_set_number(s, "peak_rss_bytes", cli->stages[i].peak_rss_bytes);
    }
    pg_json_set_number(cli->report, "seconds_total", now_s() - cli->t_start);
    pg_json_set_number(cli->report, "peak_rss_bytes", pg_cli_peak_rss_bytes());
    if (cli->memory_estimate > 0)
        pg_json_set_number(cli->report, "memory_estimate_bytes", cli->memory_estimate);
    pg_json_set_number(cli->report, "threads", omp_get_max_threads());
    /* Split --json into directory and file name; a bare name lives in ".". */
    char dir[4096], name[4096];
    const char *slash = strrchr(cli->json_path, '/');
    snprintf(name, sizeof name, "%s", slash ? slash + 1 : cli->json_path);
    if (slash)
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - cli->json_path), cli->json_path);
    else
        snprintf(dir, sizeof dir, ".");
    const char *tmp = pg_cli_output_path(cli, dir[0] ? dir : "/", name);
    FILE *f = tmp ? fopen(tmp, "w") : NULL;
    if (!f) return pg_error_set(err, PG_ERR_IO, "--json %s: cannot write", cli->json_path);
    int wr = pg_json_write(cli->report, f);
    if (fclose(f) != 0 || wr != 0)
        return pg_error_set(err, PG_ERR_IO, "--json %s: write failed (disk full?)", cli->json_path);
    return PG_OK;
}

int pg_cli_finish(pg_cli *cli) {
    pg_error err = {0};
    if (stage_report(cli, &err) != PG_OK || pg_cli_commit(cli, &err) != PG_OK)
        return pg_cli_fail(cli, &err);
    free(cli->created_dir);
    cli->created_dir = NULL;
    pg_json_free(cli->report);
    cli->report = NULL;
    return 0;
}
