/* pg_huge.c - large arrays on transparent huge pages (pg_huge.h). */
#define _DEFAULT_SOURCE /* madvise(MADV_HUGEPAGE) */
#include "pg_huge.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

void *pg_huge_alloc(size_t bytes) {
    const size_t huge = (size_t)2 << 20;
    if (bytes > (size_t)-1 - huge) return NULL;
    size_t rounded = (bytes + huge - 1) / huge * huge;
    void *p = aligned_alloc(huge, rounded ? rounded : huge);
#ifdef MADV_HUGEPAGE
    if (p) madvise(p, rounded ? rounded : huge, MADV_HUGEPAGE);
#endif
    return p;
}

void *pg_huge_malloc(size_t bytes) {
    return bytes >= PG_HUGE_MIN_BYTES ? pg_huge_alloc(bytes) : malloc(bytes);
}

void *pg_huge_calloc(size_t count, size_t size) {
    if (size && count > SIZE_MAX / size) return NULL;
    size_t bytes = count * size;
    if (bytes < PG_HUGE_MIN_BYTES) return calloc(count, size);
    void *p = pg_huge_alloc(bytes);
    if (p) memset(p, 0, bytes);
    return p;
}
