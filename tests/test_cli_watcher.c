/* test_cli_watcher.c - the CLI's signal watcher and the lifetime of its pg_cli.
 *
 * Regression test for a bug found when `mpirun -np 7` on a 6-tile planet (every rank
 * refuses with exit 2, mpirun then SIGTERMs the ranks still exiting) deleted
 * /lib/x86_64-linux-gnu/libz.so.1: the watcher thread was detached and outlived the
 * pg_cli on run_command's stack, so a SIGTERM during exit made it unlink whatever the
 * dead frame's staged-file list pointed to. The contract now: after
 * pg_cli_unwatch_signals the watcher is joined, and a SIGTERM neither removes a file
 * nor ends the process; before it, a SIGTERM still removes the staged files and exits
 * 143. */
#include "pg_cli.h"
#include "pg_test.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* Runs in the forked child, so it reports failure instead of asserting: a cmocka
 * assert there would unwind into a second copy of the test runner. */
static int touch(const char *path) {
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fputs("staged\n", f);
    return fclose(f);
}

static int exists(const char *path) {
    struct stat st;
    return stat(path, &st) == 0;
}

/* A child: a heap pg_cli with one staged file that exists on disk. If `unwatch`, the
 * file is committed (renamed to its final name), the watcher stopped, and the pg_cli
 * poisoned and freed (what a returned stack frame amounts to). Then the child signals
 * itself and waits; exit 0 if it is still alive 300 ms later. The parent checks the
 * exit status and the file: the staged name is returned in `staged`; the final name
 * is DIR/staged-1.txt. */
static int run_child(const char *dir, int unwatch, char *staged, size_t staged_size) {
    char name[64];
    snprintf(name, sizeof name, "staged-%d.txt", unwatch);
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(fds[0]);
        pg_cli_block_signals();
        pg_cli *cli = malloc(sizeof *cli);
        pg_cli_init(cli, "watcher-test");
        if (pg_cli_watch_signals(cli) != 0) _exit(3);
        const char *tmp = pg_cli_output_path(cli, dir, name);
        if (!tmp) _exit(4);
        if (touch(tmp) != 0) _exit(7);
        if (write(fds[1], tmp, strlen(tmp) + 1) < 0) _exit(5);
        close(fds[1]);
        if (unwatch) {
            /* as run_command does: the command has committed, then the watcher stops */
            pg_error e = {0};
            if (pg_cli_commit(cli, &e) != PG_OK) _exit(6);
            pg_cli_unwatch_signals(cli);
            memset(cli, 0xA5, sizeof *cli);
            free(cli);
        }
        kill(getpid(), SIGTERM);
        struct timespec ts = {0, 300 * 1000 * 1000};
        nanosleep(&ts, NULL);
        _exit(0);
    }
    close(fds[1]);
    ssize_t n = read(fds[0], staged, staged_size - 1);
    close(fds[0]);
    staged[n > 0 ? n : 0] = '\0';
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    return WEXITSTATUS(status);
}

/* Watching: SIGTERM removes the staged file and exits 128 + 15. */
static void test_sigterm_while_watching(void **s) {
    (void)s;
    char dir[1024], staged[4096];
    pg_test_scratch_dir("cli_watcher_on", dir, sizeof dir);
    assert_int_equal(run_child(dir, 0, staged, sizeof staged), 128 + SIGTERM);
    assert_true(staged[0] != '\0');
    assert_false(exists(staged));
}

/* Unwatched and the pg_cli gone: SIGTERM touches nothing and the process lives on. */
static void test_sigterm_after_unwatch(void **s) {
    (void)s;
    char dir[1024], staged[4096];
    pg_test_scratch_dir("cli_watcher_off", dir, sizeof dir);
    assert_int_equal(run_child(dir, 1, staged, sizeof staged), 0);
    char final[4200];
    snprintf(final, sizeof final, "%s/staged-1.txt", dir);
    assert_true(staged[0] != '\0');
    assert_false(exists(staged)); /* renamed by the commit */
    assert_true(exists(final));   /* and nothing removed it afterwards */
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sigterm_while_watching),
        cmocka_unit_test(test_sigterm_after_unwatch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
