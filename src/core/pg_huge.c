/* pg_huge.c - large arrays on transparent huge pages (pg_huge.h). */
#define _DEFAULT_SOURCE /* madvise(MADV_HUGEPAGE) */
#include "pg_huge.h"

#include <stdlib.h>
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
