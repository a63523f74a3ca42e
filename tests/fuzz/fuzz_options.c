/* fuzz_options.c - libFuzzer harness for the CLI option parser (src/cli/pg_cli_options.c).
 *
 * The input is split at NUL and newline bytes into argv words and parsed against a
 * spec with every option kind (flag, string, int, double, choice) plus the common
 * options. Whatever the words, the parser must return 0 or 2 without crashing and
 * must leave every destination either untouched or in range. */
#include "fuzz_common.h"

#include "pg_cli.h"

#include "planetgen/pg_json.h"

#include <math.h>
#include <string.h>

#define MAX_WORDS 64

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size > 4096) return 0;
    char *buf = malloc(size + 1);
    if (!buf) return 0;
    memcpy(buf, data, size);
    buf[size] = '\0';
    char *argv[MAX_WORDS + 1];
    int argc = 0;
    argv[argc++] = "fuzz";
    for (char *p = buf; argc < MAX_WORDS && p < buf + size;) {
        argv[argc++] = p;
        while (p < buf + size && *p != '\n' && *p != '\0')
            p++;
        *p++ = '\0';
    }
    argv[argc] = NULL;
    bool flag = false;
    const char *str = NULL, *choice = NULL;
    long n = 7;
    double x = 0.5;
    const pg_opt opts[] = {{"--flag", "-f", PG_OPT_FLAG, &flag, 0, 0, NULL, NULL, "a flag"},
                           {"--str", "-o", PG_OPT_STRING, &str, 0, 0, NULL, "S", "a string"},
                           {"--int", NULL, PG_OPT_INT, &n, -5, 5000, NULL, "N", "an int"},
                           {"--dbl", NULL, PG_OPT_DOUBLE, &x, 0, 1, NULL, "X", "a double"},
                           {"--choice", NULL, PG_OPT_CHOICE, &choice, 0, 0, "aa|b|ccc", "C", ""},
                           PG_OPT_END};
    pg_cli cli;
    pg_cli_init(&cli, "fuzz");
    cli.quiet = true;
    const char *pos[3];
    int npos = 0;
    bool done = false;
    int rc = pg_cli_parse(&cli, opts, argc, argv, pos, 3, &npos, &done);
    if (rc != 0 && rc != 2) abort();
    if (n < -5 || n > 5000 || !(x >= 0 && x <= 1)) abort();
    if (choice && strcmp(choice, "aa") && strcmp(choice, "b") && strcmp(choice, "ccc")) abort();
    if (npos < 0 || npos > 3) abort();
    pg_json_free(cli.report);
    free(buf);
    return 0;
}
