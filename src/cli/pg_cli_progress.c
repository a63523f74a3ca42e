/* pg_cli_progress.c - what a command says while it works: info and verbose lines on
 * stdout, and stages (a progress bar with ETA on a terminal, one line per stage
 * otherwise; --quiet silences both) whose times, CPU seconds, page faults and peak memory go to the
 * report. */
#include "pg_cli.h"

#include <stdarg.h>
#include <stdio.h>
#include <sys/resource.h>
#include <time.h>

double pg_cli_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
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

/* CPU seconds and page faults of the process so far. */
static void usage_now(double *cpu, double *minflt, double *majflt) {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    *cpu = (double)ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
           1e-6 * ru.ru_stime.tv_usec;
    *minflt = (double)ru.ru_minflt;
    *majflt = (double)ru.ru_majflt;
}

void pg_cli_stage_begin(pg_cli *cli, const char *name) {
    pg_cli_sample_memory(cli);
    snprintf(cli->stage_name, sizeof cli->stage_name, "%s", name);
    cli->stage_t0 = pg_cli_now();
    usage_now(&cli->stage_cpu0, &cli->stage_minflt0, &cli->stage_majflt0);
    cli->last_draw = 0;
    if (!cli->quiet && cli->tty) pg_cli_progress(cli, 0.0);
}

void pg_cli_progress(pg_cli *cli, double frac) {
    if (cli->quiet || !cli->tty) return;
    double t = pg_cli_now();
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
    double dt = pg_cli_now() - cli->stage_t0;
    pg_cli_sample_memory(cli);
    if (cli->nstages < PG_STAGE_MAX) {
        snprintf(cli->stages[cli->nstages].name, sizeof cli->stages[0].name, "%s", cli->stage_name);
        cli->stages[cli->nstages].seconds = dt;
        cli->stages[cli->nstages].peak_rss_bytes = pg_cli_peak_rss_bytes();
        double cpu, minflt, majflt;
        usage_now(&cpu, &minflt, &majflt);
        cli->stages[cli->nstages].cpu_seconds = cpu - cli->stage_cpu0;
        cli->stages[cli->nstages].minor_faults = minflt - cli->stage_minflt0;
        cli->stages[cli->nstages].major_faults = majflt - cli->stage_majflt0;
        pg_cli_smaps_figures m;
        pg_cli_smaps(&m);
        cli->stages[cli->nstages].private_bytes = m.private_bytes;
        cli->stages[cli->nstages].shared_bytes = m.shared_bytes;
        cli->stages[cli->nstages].private_dirty_bytes = m.private_dirty_bytes;
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
