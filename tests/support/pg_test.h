/* pg_test.h - shared helpers for planetgen's cmocka tests: where the sources, the
 * build and the CLI are, scratch directories, and running the CLI as a user would. */
#ifndef PG_TEST_H
#define PG_TEST_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

/* Paths from ctest's environment (PG_SOURCE_DIR, PG_BUILD_DIR, PG_CLI; PG_CLI_WRAPPER,
 * when set, is returned by pg_test_cli instead of PG_CLI). */
const char *pg_test_source_dir(void);
const char *pg_test_cli(void);

/* A fresh, empty scratch directory under the build tree, named after `tag`.
 * Returns a static-storage path valid until the next call with the same buffer. */
void pg_test_scratch_dir(const char *tag, char *out, size_t out_size);

/* Run the CLI with a shell-quoted argument string; capture stderr (and stdout) into
 * the caller's buffers (may be NULL). Returns the exit code, or -1 if it was killed. */
int pg_test_run_cli(const char *args, char *out, size_t out_size, char *errbuf, size_t err_size);

/* Run a shell command (printf-style) and capture its stdout into out (may be NULL;
 * cut at size). Returns the exit code, or -1 if it was killed. */
int pg_test_sh(char *out, size_t size, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Number of regular files (recursively) under dir; 0 if dir does not exist. */
int pg_test_count_files(const char *dir);

/* Does the file exist and have size > 0? */
int pg_test_file_nonempty(const char *path);

/* The default exemplar (pg_exemplar_opts_default) prepared with the default parameters,
 * through the cache PG_BUILD_DIR/synth-cache; NULL (the reason on stderr) on failure.
 * Free with pg_synth_exemplar_free. */
struct pg_synth_exemplar;
struct pg_synth_exemplar *pg_test_default_exemplar(void);

/* The number after "key": at or after `from` in a JSON text; NaN when absent or null. */
double pg_test_json_number(const char *from, const char *key);

#endif
