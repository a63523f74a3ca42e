/* test_readme_table.c - the README's bad-input table is a tested contract: every
 * row must name at least one test, and every test it names must exist. This test
 * parses the table under "## Bad input" in README.md and, for each `FILE.c:FUNCTION`
 * in a row's last column, checks that tests/FILE.c defines `static void FUNCTION(void
 * **...)` and registers it with cmocka_unit_test(FUNCTION), so ctest runs it. A row
 * without a test, a renamed test or an unregistered one fails here. */
#include "pg_test.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *read_text(const char *path) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    if (buf) buf[fread(buf, 1, (size_t)n, f)] = '\0';
    fclose(f);
    return buf;
}

/* Does tests/file define and register function `fn`? Sets *why on failure. */
static bool test_registered(const char *file, const char *fn, const char **why) {
    char path[1024], pat[256];
    snprintf(path, sizeof path, "%s/tests/%s", pg_test_source_dir(), file);
    char *src = read_text(path);
    if (!src) {
        *why = "no such file in tests/";
        return false;
    }
    bool ok = true;
    snprintf(pat, sizeof pat, "void %s(void **", fn);
    if (!strstr(src, pat)) {
        *why = "no such function";
        ok = false;
    }
    snprintf(pat, sizeof pat, "cmocka_unit_test(%s)", fn);
    if (ok && !strstr(src, pat)) {
        *why = "not registered with cmocka_unit_test";
        ok = false;
    }
    free(src);
    return ok;
}

/* The tests named in one row's last cell: `FILE.c:FUNCTION` tokens. Returns how many,
 * failing the test for any that is missing. */
static int check_row(const char *row, int lineno) {
    const char *last = strrchr(row, '|');
    const char *cell = last;
    while (cell > row && *(cell - 1) != '|')
        cell--;
    int n = 0;
    for (const char *p = cell; p < last; p++) {
        if (*p != '`') continue;
        const char *q = strchr(p + 1, '`');
        if (!q || q > last) break;
        char tok[256];
        snprintf(tok, sizeof tok, "%.*s", (int)(q - p - 1), p + 1);
        char *colon = strstr(tok, ".c:");
        if (colon) {
            colon[2] = '\0';
            const char *fn = colon + 3, *why = "";
            if (!test_registered(tok, fn, &why))
                fail_msg("README.md line %d: %s:%s: %s", lineno, tok, fn, why);
            n++;
        }
        p = q;
    }
    if (n == 0) fail_msg("README.md line %d: the row names no test: %s", lineno, row);
    return n;
}

static void test_every_row_names_registered_tests(void **state) {
    (void)state;
    char path[1024];
    snprintf(path, sizeof path, "%s/README.md", pg_test_source_dir());
    char *text = read_text(path);
    assert_non_null(text);
    const char *sec = strstr(text, "\n## Bad input\n");
    if (!sec) fail_msg("README.md has no '## Bad input' section");
    int rows = 0, refs = 0, lineno = 1;
    for (const char *p = text; p < sec; p++)
        lineno += *p == '\n';
    bool in_table = false;
    for (const char *line = sec + 1; *line; lineno++) {
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) : strlen(line);
        if (len > 3 && !strncmp(line, "## ", 3) && line != sec + 1) break; /* next section */
        if (len > 0 && line[0] == '|') {
            char *row = strndup(line, len);
            if (!in_table) {
                in_table = true; /* the header row; the separator follows */
                if (!strstr(row, "| tests |")) fail_msg("bad-input table lacks a 'tests' column");
            } else if (strncmp(row, "|---", 4) != 0) {
                refs += check_row(row, lineno);
                rows++;
            }
            free(row);
        } else if (in_table) {
            break; /* the table ended */
        }
        if (!end) break;
        line = end + 1;
    }
    free(text);
    /* the table is not empty: it held 26 rows when this test was written */
    if (rows < 20) fail_msg("bad-input table has only %d rows", rows);
    printf("bad-input table: %d rows, %d test references, all registered\n", rows, refs);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_row_names_registered_tests),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
