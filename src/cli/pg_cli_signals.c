/* pg_cli_signals.c - SIGINT/SIGTERM in the CLI without global state: both signals are
 * blocked before any thread starts, and a watcher thread takes them with sigwait,
 * removes the staged outputs under the pg_cli's lock, prints one line and exits 128 +
 * signal; pg_cli_unwatch_signals stops and joins it before the pg_cli goes away. */
#include "pg_cli.h"

#include <signal.h>
#include <stdio.h>
#include <unistd.h>

void pg_cli_block_signals(void) {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &set, NULL);
    signal(SIGXFSZ, SIG_IGN);
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
    pg_cli_remove_staged_locked(cli);
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
