/* pg_common.c - error context helpers and version; see pg_common.h. */
#include "planetgen/pg_common.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

pg_status pg_error_set(pg_error *err, pg_status st, const char *fmt, ...) {
    if (!err || err->status != PG_OK) return st;
    err->status = st;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
    return st;
}

void pg_error_clear(pg_error *err) {
    if (!err) return;
    err->status = PG_OK;
    err->msg[0] = '\0';
}

int pg_status_exit_code(pg_status st) {
    if (st == PG_OK) return 0;
    return st == PG_ERR_BADINPUT ? 2 : 1;
}

const char *pg_status_name(pg_status st) {
    switch (st) {
    case PG_OK:
        return "ok";
    case PG_ERR_BADINPUT:
        return "bad input";
    case PG_ERR_IO:
        return "i/o error";
    case PG_ERR_NOMEM:
        return "out of memory";
    case PG_ERR_RUNTIME:
        return "runtime error";
    case PG_ERR_INTERRUPTED:
        return "interrupted";
    }
    return "unknown";
}

const char *pg_version(void) {
    return PG_VERSION_STRING;
}

pg_status pg_write_file(const char *path, const void *data, size_t n, pg_error *err) {
    FILE *f = fopen(path, "wb");
    if (!f) return pg_error_set(err, PG_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    size_t w = fwrite(data, 1, n, f);
    if (fclose(f) != 0 || w != n)
        return pg_error_set(err, PG_ERR_IO, "%s: write failed (disk full?)", path);
    return PG_OK;
}
