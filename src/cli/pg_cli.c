/* pg_cli.c - a command's life in the CLI: its pg_cli, the usage error, the failure line
 * and the finish that writes the --json report and commits the outputs. The rest of the
 * shared machinery: pg_cli_options.c (option parsing, help), pg_cli_signals.c (the
 * SIGINT/SIGTERM watcher), pg_cli_outputs.c (staged outputs), pg_cli_progress.c
 * (messages, stages, progress), pg_cli_memory.c (memory estimates and limits).
 *
 * The invariants every command gets from these files:
 *  - a usage error is one line "planetgen CMD: ..." naming the option, exit 2;
 *  - outputs are written under temporary names and renamed only when the whole
 *    command succeeded, so a failed run leaves no partial files behind;
 *  - progress is a bar with ETA on a terminal, one line per stage otherwise. */
#include "pg_cli.h"

#include "planetgen/pg_json.h"

#include <omp.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

void pg_cli_init(pg_cli *cli, const char *cmd) {
    memset(cli, 0, sizeof *cli);
    cli->cmd = cmd;
    pthread_mutex_init(&cli->lock, NULL);
    pthread_cond_init(&cli->mem_wake, NULL);
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
        pg_json_set_number(s, "cpu_seconds", cli->stages[i].cpu_seconds);
        pg_json_set_number(s, "minor_faults", cli->stages[i].minor_faults);
        pg_json_set_number(s, "major_faults", cli->stages[i].major_faults);
        pg_json_set_number(s, "private_bytes", cli->stages[i].private_bytes);
        pg_json_set_number(s, "shared_bytes", cli->stages[i].shared_bytes);
        pg_json_set_number(s, "private_dirty_bytes", cli->stages[i].private_dirty_bytes);
    }
    pg_json_set_number(cli->report, "seconds_total", pg_cli_now() - cli->t_start);
    pg_json_set_number(cli->report, "peak_rss_bytes", pg_cli_peak_rss_bytes());
    pg_cli_sample_memory(cli);
    pthread_mutex_lock(&cli->lock);
    pg_json_set_number(cli->report, "peak_private_bytes", cli->private_peak);
    pg_json_set_number(cli->report, "peak_shared_bytes", cli->shared_peak);
    pg_json_set_number(cli->report, "peak_private_dirty_bytes", cli->private_dirty_peak);
    pthread_mutex_unlock(&cli->lock);
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
