/* pg_span.c - reserved planet-sized arrays with only some rows committed (pg_span.h). */
#define _GNU_SOURCE
#include "pg_span.h"

#include <sys/mman.h>
#include <unistd.h>

pg_status pg_span_reserve(pg_span *s, size_t bytes, pg_error *err) {
    s->base = NULL, s->bytes = 0;
    if (bytes == 0) return PG_OK;
    void *p = mmap(NULL, bytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (p == MAP_FAILED)
        return pg_error_set(err, PG_ERR_NOMEM, "cannot reserve %.1f GB of address space",
                            (double)bytes / 1e9);
    s->base = p, s->bytes = bytes;
    return PG_OK;
}

pg_status pg_span_open(pg_span *s, size_t off, size_t len, pg_error *err) {
    if (!s->base || len == 0 || off >= s->bytes) return PG_OK;
    if (len > s->bytes - off) len = s->bytes - off;
    const size_t page = (size_t)sysconf(_SC_PAGESIZE);
    size_t lo = off / page * page, hi = (off + len + page - 1) / page * page;
    if (mprotect((char *)s->base + lo, hi - lo, PROT_READ | PROT_WRITE) != 0)
        return pg_error_set(err, PG_ERR_NOMEM, "cannot commit %.1f MB of a reserved array",
                            (double)(hi - lo) / 1e6);
    return PG_OK;
}

void pg_span_free(pg_span *s) {
    if (s->base) munmap(s->base, s->bytes);
    s->base = NULL, s->bytes = 0;
}
