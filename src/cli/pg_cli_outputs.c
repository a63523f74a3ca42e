/* pg_cli_outputs.c - the CLI's output discipline: the output directory checked or
 * created (and remembered, so a failure removes it if it stays empty), every output
 * written under a temporary name in it, and all of them renamed into place when the
 * command succeeded or removed when it failed. The staged-file list is guarded by the
 * pg_cli's lock, which the signal watcher (pg_cli_signals.c) takes too. */
#include "pg_cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Remove staged temporaries; the caller holds cli->lock. Safe while writers still
 * have the files open: the names go, the data is freed when they close. */
void pg_cli_remove_staged_locked(pg_cli *cli) {
    for (int i = 0; i < cli->nstaged; i++)
        unlink(cli->staged_tmp[i]);
    if (cli->created_dir) rmdir(cli->created_dir);
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
    pg_cli_remove_staged_locked(cli); /* rmdir only succeeds if empty: never removes user files */
    free_staged(cli);
    free(cli->created_dir);
    cli->created_dir = NULL;
    pthread_mutex_unlock(&cli->lock);
}
