/* pg_test.c - see pg_test.h. Tests run the real CLI binary through /bin/sh, the way
 * a user would, so exit codes and messages are checked end to end. */
#include "pg_test.h"

#include <dirent.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static const char *env_or_die(const char *name) {
    const char *v = getenv(name);
    if (!v || !*v) {
        fprintf(stderr, "test environment variable %s is not set (run under ctest)\n", name);
        exit(1);
    }
    return v;
}

const char *pg_test_source_dir(void) {
    return env_or_die("PG_SOURCE_DIR");
}

/* PG_CLI_WRAPPER, when set, replaces the CLI path: scripts/valgrind-suite points it at
 * a wrapper that runs $PG_CLI under valgrind, so every CLI process a test spawns is
 * checked too. The wrapper execs, so signals sent to its pid reach the CLI. */
const char *pg_test_cli(void) {
    const char *w = getenv("PG_CLI_WRAPPER");
    if (w && *w) return w;
    return env_or_die("PG_CLI");
}

void pg_test_scratch_dir(const char *tag, char *out, size_t out_size) {
    snprintf(out, out_size, "%s/test-scratch/%s", env_or_die("PG_BUILD_DIR"), tag);
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s'", out, out);
    if (system(cmd) != 0) {
        fprintf(stderr, "cannot create scratch dir %s\n", out);
        exit(1);
    }
}

static void slurp(const char *path, char *buf, size_t size) {
    if (!buf || size == 0) return;
    buf[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (!f) return;
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = '\0';
    fclose(f);
}

int pg_test_run_cli(const char *args, char *out, size_t out_size, char *errbuf, size_t err_size) {
    char outp[256], errp[256];
    snprintf(outp, sizeof outp, "/tmp/pg_test_out.%d", (int)getpid());
    snprintf(errp, sizeof errp, "/tmp/pg_test_err.%d", (int)getpid());
    size_t cmdlen = strlen(args) + 1024;
    char *cmd = malloc(cmdlen);
    snprintf(cmd, cmdlen, "'%s' %s >%s 2>%s </dev/null", pg_test_cli(), args, outp, errp);
    int st = system(cmd);
    free(cmd);
    slurp(outp, out, out_size);
    slurp(errp, errbuf, err_size);
    unlink(outp);
    unlink(errp);
    if (st == -1 || !WIFEXITED(st)) return -1;
    return WEXITSTATUS(st);
}

int pg_test_sh(char *out, size_t size, const char *fmt, ...) {
    char cmd[16384];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    FILE *f = popen(cmd, "r");
    if (!f) return -1;
    char tmp[4096];
    size_t n = 0, k;
    while ((k = fread(tmp, 1, sizeof tmp, f)) > 0) {
        size_t c = out && n + 1 < size ? (k < size - 1 - n ? k : size - 1 - n) : 0;
        if (c) memcpy(out + n, tmp, c);
        n += c;
    }
    if (out && size) out[n] = '\0';
    int st = pclose(f);
    return st == -1 || !WIFEXITED(st) ? -1 : WEXITSTATUS(st);
}

int pg_test_count_files(const char *dir) {
    DIR *d = opendir(dir);
    if (!d) return 0;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        char p[4096];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        struct stat s;
        if (stat(p, &s) != 0) continue;
        if (S_ISDIR(s.st_mode))
            n += pg_test_count_files(p);
        else
            n++;
    }
    closedir(d);
    return n;
}

int pg_test_file_nonempty(const char *path) {
    struct stat s;
    return stat(path, &s) == 0 && S_ISREG(s.st_mode) && s.st_size > 0;
}

double pg_test_json_number(const char *from, const char *key) {
    char pat[128];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = strstr(from, pat);
    if (!p) return NAN;
    char *end;
    double v = strtod(p + strlen(pat), &end);
    return end == p + strlen(pat) ? NAN : v;
}
