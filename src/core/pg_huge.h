/* pg_huge.h - large arrays on transparent huge pages, where the kernel allows it.
 *
 * With transparent huge pages in "madvise" mode (Debian's default), a big array gets
 * 2 MB pages only when it is aligned to them and asked for with madvise. That means
 * 512 times fewer page faults when the array is first touched, and on a virtual
 * machine each fault can cost the other threads a TLB shootdown. It also means fewer
 * TLB misses when the array is read at random (the synthesis tables, the labels of
 * the tiled fill).
 *
 * Ownership: the caller frees the block with free(), and may realloc() it (the new block
 * keeps malloc's alignment only). The memory is not zeroed, except pg_huge_calloc's.
 * Library-internal: not part of the installed API. */
#ifndef PG_HUGE_H
#define PG_HUGE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* `bytes` rounded up to whole 2 MB pages, aligned to them, advised as huge pages;
 * NULL when the allocation fails. */
void *pg_huge_alloc(size_t bytes);

/* For arrays of any size: pg_huge_alloc from PG_HUGE_MIN_BYTES up, malloc below it, where
 * rounding up to 2 MB would waste more than the faults it saves. */
#define PG_HUGE_MIN_BYTES ((size_t)8 << 20)
void *pg_huge_malloc(size_t bytes);

/* pg_huge_malloc, zeroed (a calloc whose big arrays fault 2 MB at a time). */
void *pg_huge_calloc(size_t count, size_t size);

#ifdef __cplusplus
}
#endif

#endif
