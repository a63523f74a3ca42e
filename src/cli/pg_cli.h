/* pg_cli.h - the CLI's shared machinery: the subcommand table, a declarative option
 * parser with uniform one-line errors, progress reporting, the --json summary, and
 * output-file discipline (temp name, rename when complete, nothing left on failure).
 *
 * A subcommand is a function `int pg_cmd_NAME(pg_cli *cli, int argc, char **argv)`
 * registered in main.c's table. It declares its options as a pg_opt array, calls
 * pg_cli_parse(), validates every input BEFORE creating any output, then works,
 * reporting stages with pg_cli_stage_begin/end. It returns an exit code (0/1/2)
 * through pg_cli_fail()/pg_cli_finish().
 *
 * Implemented by pg_cli.c (a command's life: init, usage error, fail, finish, report),
 * pg_cli_options.c, pg_cli_signals.c, pg_cli_outputs.c, pg_cli_progress.c and
 * pg_cli_memory.c. */
#ifndef PG_CLI_H
#define PG_CLI_H

#include "planetgen/pg_common.h"
#include "planetgen/pg_exemplar.h"

#include <math.h>

#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>

typedef enum pg_opt_kind {
    PG_OPT_FLAG,   /* bool, no value */
    PG_OPT_STRING, /* const char * */
    PG_OPT_INT,    /* long, range-checked [min, max] */
    PG_OPT_DOUBLE, /* double, finite, range-checked [min, max] */
    PG_OPT_CHOICE, /* const char *, one of choices "a|b|c" */
    PG_OPT_LIST    /* pg_opt_list: repeatable, each value appended (at most PG_OPT_LIST_MAX) */
} pg_opt_kind;

#define PG_OPT_LIST_MAX 32

/* The values of a repeatable option, in the order given. */
typedef struct pg_opt_list {
    const char *v[PG_OPT_LIST_MAX];
    int n;
} pg_opt_list;

typedef struct pg_opt {
    const char *name;  /* long form, e.g. "--seed" */
    const char *alias; /* short form, e.g. "-o", or NULL */
    pg_opt_kind kind;
    void *dest; /* bool *, const char **, long *, double *, pg_opt_list * */
    double min, max;
    const char *choices;
    const char *metavar;
    const char *help;
} pg_opt;

#define PG_OPT_END                                                                                 \
    { NULL, NULL, PG_OPT_FLAG, NULL, 0, 0, NULL, NULL, NULL }

#define PG_STAGE_MAX 32

/* Per-invocation state: everything a command needs, no globals. */
typedef struct pg_cli {
    const char *cmd;     /* subcommand name, for messages */
    bool quiet, verbose; /* common options */
    const char *json_path;
    long threads; /* 0 = OpenMP default */
    bool tty;     /* stderr is a terminal: draw a progress bar */
    double t_start;
    /* stages, for progress lines and the JSON report */
    int nstages;
    struct {
        char name[48];
        double seconds;
        double peak_rss_bytes; /* the process's peak RSS when the stage ended */
        /* the process's CPU seconds (all threads) and page faults during the stage */
        double cpu_seconds, minor_faults, major_faults;
        /* smaps_rollup when the stage ended (pg_cli_smaps): private pages (this process's
         * alone) and shared ones (mapped by other processes too) */
        double private_bytes, shared_bytes, private_dirty_bytes;
    } stages[PG_STAGE_MAX];
    /* the largest private and shared memory of the samples taken at stage ends and,
     * while pg_cli_memory_watch runs, every PG_CLI_SMAPS_INTERVAL seconds or more (under
     * lock) */
    double private_peak, shared_peak, private_dirty_peak;
    pthread_t mem_watcher;
    pthread_cond_t mem_wake; /* with lock: wakes the memory watcher to stop */
    bool mem_watching, mem_stop, mem_paused;
    double stage_t0, stage_cpu0, stage_minflt0, stage_majflt0;
    char stage_name[48];
    double last_draw;
    /* the JSON report: commands add "inputs", "parameters" and "results" members */
    struct pg_json *report;
    /* files staged for atomic commit: written as temp names, renamed at finish */
    int nstaged;
    char **staged_tmp, **staged_final;
    char *created_dir;      /* output dir created by us, removed on failure if empty */
    double memory_estimate; /* bytes, from pg_cli_check_memory; 0 = none made */
    /* Guards the staged-file list against the signal watcher (pg_cli_watch_signals). */
    pthread_mutex_t lock;
    pthread_t watcher; /* the signal watcher thread, joined by pg_cli_unwatch_signals */
    bool watching;     /* watcher started and not yet joined */
    bool unwatching;   /* under lock: the watcher's next wake-up is the stop request */
} pg_cli;

/* Initialise a pg_cli for command `cmd`. */
void pg_cli_init(pg_cli *cli, const char *cmd);

/* SIGINT/SIGTERM handling without global state: the caller blocks both signals
 * before any thread starts (pg_cli_block_signals), then a watcher thread waits for
 * them with sigwait; on one it deletes every staged temporary file (and the output
 * dir if we created it and it is empty), prints one line and exits 130 (SIGINT) or
 * 143 (SIGTERM). SIGXFSZ is ignored so a file-size limit surfaces as a write error. */
void pg_cli_block_signals(void);
int pg_cli_watch_signals(pg_cli *cli);
/* Stop and join the watcher; call before the pg_cli goes away. Afterwards SIGINT and
 * SIGTERM stay blocked (pending) and touch nothing. */
void pg_cli_unwatch_signals(pg_cli *cli);

/* Parse argv against specs plus the common options (--json, --quiet, --verbose,
 * --threads, --help). Positional arguments go to pos (at most max_pos). Returns 0,
 * or 2 after printing a one-line usage error; *done is set when --help was handled. */
int pg_cli_parse(pg_cli *cli, const pg_opt *specs, int argc, char **argv, const char **pos,
                 int max_pos, int *npos, bool *done);

/* pg_cli_parse, then --help: returns -1 when the command should go on, otherwise the
 * exit code to return at once (0 after printing help, 2 after a usage error). */
int pg_cli_parse_or_help(pg_cli *cli, const pg_opt *specs, int argc, char **argv, const char **pos,
                         int max_pos, int *npos, const char *usage, const char *description);

/* The exemplar inputs every command that reads an exemplar accepts, so that all of
 * them take the same options with the same meaning. Declare a pg_cli_exemplar set to
 * PG_CLI_EXEMPLAR_INIT, put PG_CLI_EXEMPLAR_OPTS(it) into the option array, and turn
 * it into loader options with pg_cli_exemplar_opts. */
typedef struct pg_cli_exemplar {
    const char *albedo, *height;
    double height_scale, height_offset, sea_level;
    bool no_repair_ocean;
} pg_cli_exemplar;

#define PG_CLI_EXEMPLAR_INIT                                                                       \
    { NULL, NULL, NAN, NAN, NAN, false }
#define PG_CLI_EXEMPLAR_OPTS(e)                                                                      \
    {"--albedo",                                                                                     \
     NULL,                                                                                           \
     PG_OPT_STRING,                                                                                  \
     &(e).albedo,                                                                                    \
     0,                                                                                              \
     0,                                                                                              \
     NULL,                                                                                           \
     "FILE",                                                                                         \
     "global equirectangular albedo (default: Blue Marble from marble-qt-data)"},                    \
        {"--height",  NULL,   PG_OPT_STRING,                                                         \
         &(e).height, 0,      0,                                                                     \
         NULL,        "FILE", "global equirectangular height (default: Marble's tiled relief)"},     \
        {"--height-scale",                                                                           \
         NULL,                                                                                       \
         PG_OPT_DOUBLE,                                                                              \
         &(e).height_scale,                                                                          \
         -1e6,                                                                                       \
         1e6,                                                                                        \
         NULL,                                                                                       \
         "M",                                                                                        \
         "metres per input height unit (overrides the grey calibration)"},                           \
        {"--height-offset",           NULL, PG_OPT_DOUBLE, &(e).height_offset, -1e6, 1e6, NULL, "M", \
         "metres added after scaling"},                                                              \
        {"--no-repair-ocean",                                                                        \
         NULL,                                                                                       \
         PG_OPT_FLAG,                                                                                \
         &(e).no_repair_ocean,                                                                       \
         0,                                                                                          \
         0,                                                                                          \
         NULL,                                                                                       \
         NULL,                                                                                       \
         "keep ocean regions far darker than their depth gives (Blue Marble's band)"},               \
    {                                                                                                \
        "--sea-level", NULL, PG_OPT_DOUBLE, &(e).sea_level, -12000, 12000, NULL, "M",                \
            "sea level in metres (default 0)"                                                        \
    }

void pg_cli_exemplar_opts(const pg_cli_exemplar *e, pg_exemplar_opts *o);

/* Estimated peak bytes of pg_exemplar_load with these options, from the inputs'
 * headers (the Marble relief tiles for the default height). Inputs that cannot be
 * probed or exceed the pixel limit count 0: the loader reports them. */
double pg_cli_exemplar_bytes(const pg_exemplar_opts *o);

/* Print the help text for a command: usage line plus option table. */
void pg_cli_print_help(const pg_cli *cli, const char *usage, const char *description,
                       const pg_opt *specs, FILE *f);

/* Messages: info goes to stdout unless --quiet; errors go to stderr as
 * "planetgen CMD: message". */
void pg_cli_info(const pg_cli *cli, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void pg_cli_verbose(const pg_cli *cli, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Stages: a progress bar with ETA on a tty, else one line per stage; --quiet
 * silences both. pg_cli_progress(frac) updates the bar within a stage. */
void pg_cli_stage_begin(pg_cli *cli, const char *name);
void pg_cli_progress(pg_cli *cli, double frac);
void pg_cli_stage_end(pg_cli *cli);

/* Output discipline. pg_cli_prepare_outdir() checks/creates DIR (remembering that
 * we made it). pg_cli_output_path() returns a temp path to write for the final file
 * DIR/NAME (caller frees nothing; strings live in cli). pg_cli_commit() renames all
 * staged files; pg_cli_abort() deletes them (and the dir if we created it and it is
 * empty). */
pg_status pg_cli_prepare_outdir(pg_cli *cli, const char *dir, pg_error *err);
const char *pg_cli_output_path(pg_cli *cli, const char *dir, const char *name);
pg_status pg_cli_commit(pg_cli *cli, pg_error *err);
void pg_cli_abort(pg_cli *cli);

/* End a command. pg_cli_fail prints err's line and returns its exit code after
 * aborting staged outputs; pg_cli_finish commits outputs, writes the --json report
 * (stages, peak memory) and returns 0 (or 1 if committing fails). */
int pg_cli_fail(pg_cli *cli, const pg_error *err);
int pg_cli_finish(pg_cli *cli);

/* Usage error for an option/argument: prints "planetgen CMD: MSG" and returns 2. */
int pg_cli_usage_error(pg_cli *cli, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* The JSON report object that pg_cli_finish writes; NULL without --json. */
struct pg_json *pg_cli_report(pg_cli *cli);

/* Peak resident set size of this process, in bytes. */
double pg_cli_peak_rss_bytes(void);

/* This process's memory from /proc/self/smaps_rollup: private (Private_Clean +
 * Private_Dirty: pages no other process maps, what this process costs the machine),
 * shared (Shared_Clean + Shared_Dirty: pages other processes map too, such as a cache
 * file mapped by every rank on a node) and private dirty alone (what the process
 * wrote: its allocations, without the clean pages of files that it alone maps, such as
 * the exemplar's cache file in a single process). RSS counts both private and shared.
 * Returns false (all 0) where the file cannot be read. */
typedef struct pg_cli_smaps_figures {
    double private_bytes, shared_bytes, private_dirty_bytes;
} pg_cli_smaps_figures;
bool pg_cli_smaps(pg_cli_smaps_figures *out);

/* Samples pg_cli_smaps into cli->private_peak and shared_peak (stage ends do). */
void pg_cli_sample_memory(pg_cli *cli);

/* A thread that samples pg_cli_sample_memory every PG_CLI_SMAPS_INTERVAL seconds, or
 * PG_CLI_SMAPS_DUTY times its last sample's own time if that is longer (a large process's
 * smaps_rollup is slow to read), so that the peak includes the moments between stage
 * ends (a command's --json report: "peak_private_bytes"). pg_cli_memory_unwatch stops
 * and joins it (main does, after every command; a no-op when none runs). Returns 0, or
 * -1 when it cannot start (the stage ends still sample). */
#define PG_CLI_SMAPS_INTERVAL 0.1
#define PG_CLI_SMAPS_DUTY 25.0
int pg_cli_memory_watch(pg_cli *cli);
void pg_cli_memory_unwatch(pg_cli *cli);
/* Pause (or resume) the watcher's samples, for the moments when a mapping that other
 * processes share is mapped by this one alone: ranks map and unmap the exemplar's cache
 * file at slightly different times, and a page that only one of them maps is counted as
 * its private memory. Stage ends still sample. */
void pg_cli_memory_pause(pg_cli *cli, bool paused);
/* The peaks so far (get), or put back peaks saved earlier (set: samples taken since,
 * which counted such a mapping as private, are forgotten). */
void pg_cli_memory_peaks(pg_cli *cli, pg_cli_smaps_figures *get, const pg_cli_smaps_figures *set);

/* Memory a run may use: MemAvailable from /proc/meminfo. The environment variable
 * PLANETGEN_MEM_AVAILABLE (bytes) replaces it, for containers whose /proc reports the
 * host and for tests that must provoke the refusal without a huge input. */
double pg_cli_available_bytes(void);

/* The check every command that allocates in proportion to its input or parameters
 * makes before any work and any output: `need` is its estimated peak in bytes, `what`
 * names the input or option that sets it. Over the limit (--max-memory GB when
 * max_memory_gb > 0, else pg_cli_available_bytes) it prints one line with the estimate
 * and returns 2; otherwise it records the estimate for the JSON report
 * ("memory_estimate_bytes") and returns 0. */
int pg_cli_check_memory(pg_cli *cli, const char *what, double need, double max_memory_gb);

/* The limit of one of `sharers` processes that share a machine's memory (the ranks of an
 * MPI job on one node): --max-memory GB when max_memory_gb > 0 (a limit per process),
 * else the available memory divided among them. */
double pg_cli_memory_limit(double max_memory_gb, int sharers);
/* pg_cli_check_memory for one such process, against `have` (pg_cli_memory_limit, possibly
 * computed on another machine): the line names the share when sharers > 1. */
int pg_cli_check_memory_shared(pg_cli *cli, const char *what, double need, double have,
                               double max_memory_gb, int sharers);

/* The --max-memory option of those commands; dest is a double, 0 = not given. */
#define PG_CLI_MAX_MEMORY_OPT(dest)                                                                \
    {                                                                                              \
        "--max-memory", NULL, PG_OPT_DOUBLE, &(dest), 0.001, 1e6, NULL, "GB",                      \
            "memory limit for the estimate checked before any work (default: available memory)"    \
    }

/* Shared by the pg_cli*.c files, not for commands: monotonic seconds
 * (pg_cli_progress.c), and the removal of the staged temporaries and of the output
 * directory if we created it and it is empty, with cli->lock held (pg_cli_outputs.c;
 * safe while writers still have the files open: the names go, the data is freed when
 * they close). */
double pg_cli_now(void);
void pg_cli_remove_staged_locked(pg_cli *cli);

#endif
