/* pg_common.h - result codes and the error context shared by every planetgen API.
 *
 * The idea (after OpenEXRCore): every fallible function returns a pg_status and, on
 * failure, writes one human-readable line into a caller-owned pg_error. There is no
 * global error state, so any number of planets can be built concurrently. The line
 * always names the file or option at fault, because the CLI prints it verbatim. */
#ifndef PLANETGEN_PG_COMMON_H
#define PLANETGEN_PG_COMMON_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pg_status {
    PG_OK = 0,
    PG_ERR_BADINPUT,   /* the caller's data or parameters are wrong: CLI exit 2 */
    PG_ERR_IO,         /* the system failed us (disk full, permissions): CLI exit 1 */
    PG_ERR_NOMEM,      /* allocation failed or would exceed a limit: CLI exit 1 */
    PG_ERR_RUNTIME,    /* anything else that went wrong while working: CLI exit 1 */
    PG_ERR_INTERRUPTED /* a signal asked us to stop: CLI exit 1 */
} pg_status;

#define PG_ERROR_MSG_MAX 512

typedef struct pg_error {
    pg_status status;
    char msg[PG_ERROR_MSG_MAX];
} pg_error;

/* Record an error (printf-style) and return the status, so call sites read
 * `return pg_error_set(err, PG_ERR_BADINPUT, "%s: not an image", path);`.
 * err may be NULL. The first error recorded wins: later calls do not overwrite it,
 * so the root cause survives the unwinding of callers. */
pg_status pg_error_set(pg_error *err, pg_status st, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

void pg_error_clear(pg_error *err);

/* The CLI exit code for a status: 0, 2 for bad input, 1 otherwise. */
int pg_status_exit_code(pg_status st);

const char *pg_status_name(pg_status st);

/* Write n bytes to a new file at path (replacing it). IO naming the path when it cannot
 * be opened, or when the write or the close falls short (a full disk shows there). */
pg_status pg_write_file(const char *path, const void *data, size_t n, pg_error *err);

/* Library version, e.g. "0.1.0". */
const char *pg_version(void);

#ifdef __cplusplus
}
#endif

#endif
