/* pg_array.h - room for one more element: the growable-array helper of the library.
 *
 * DESIGN
 * ------
 * A growable array in planetgen is three plain fields of its owner, never a hidden
 * object: a typed pointer `T *a`, a count `n` the owner maintains, and a capacity
 * `cap` this helper maintains. Before writing element n the owner asks for room:
 *
 *     if (PG_ARRAY_RESERVE(v->a, &v->cap, v->n + 1, err)) return ...;
 *     v->a[v->n++] = x;
 *
 * Keeping the fields in the owner's struct keeps the element type visible to the
 * compiler (no void * element access, no element-size bookkeeping at every read),
 * lets each owner keep its own extra fields (a FIFO's head, an out-of-memory flag
 * for push functions that cannot return a status), and leaves freeing with the
 * owner: free(v->a) is all there is.
 *
 * Growth doubles the capacity, starting at PG_ARRAY_MIN_CAP, until it holds `need`
 * elements: amortised O(1) per element and O(log n) reallocations. The capacities are
 * powers of two times PG_ARRAY_MIN_CAP, so an array reaches the same large sizes
 * whatever its first capacity would have been. When doubling would overflow size_t
 * the capacity becomes exactly `need`; when need * elem_size itself does not fit in
 * size_t the call is refused (PG_ERR_NOMEM) instead of wrapping around to a small
 * allocation. On any failure the array, its contents and *cap are left as they were,
 * so the owner may still use or free it.
 *
 * The array pointer is passed by address as `void *` and read and written through
 * memcpy, not through a `void **` cast of a `T **` (which would access a T * object
 * as a void * object: undefined under C's aliasing rules). This assumes every object
 * pointer has void *'s representation, as on every platform planetgen builds on.
 * PG_ARRAY_RESERVE takes the pointer itself and supplies &ptr and sizeof *ptr, so the
 * element size cannot be mistyped. Library-internal: not part of the installed API. */
#ifndef PG_ARRAY_H
#define PG_ARRAY_H

#include "planetgen/pg_common.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The first capacity of an empty array, in elements. */
#define PG_ARRAY_MIN_CAP 16

/* Grows the array whose pointer is at `pdata` (a T **; the pointer may be NULL when
 * *cap is 0) to a capacity of at least `need` elements of `elem_size` bytes. need <=
 * *cap: nothing to do, PG_OK. elem_size 0: PG_ERR_BADINPUT. need * elem_size beyond
 * size_t, or realloc failing: PG_ERR_NOMEM, array unchanged. err may be NULL. */
pg_status pg_array_reserve(void *pdata, size_t *cap, size_t need, size_t elem_size, pg_error *err);

/* pg_array_reserve for the typed pointer lvalue `ptr`, its element size from its type. */
#define PG_ARRAY_RESERVE(ptr, cap, need, err)                                                      \
    pg_array_reserve(&(ptr), (cap), (need), sizeof *(ptr), (err))

#ifdef __cplusplus
}
#endif

#endif
