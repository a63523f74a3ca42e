/* pg_array.c - the growable-array helper; see pg_array.h for the design. */
#include "pg_array.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The doubling capacity for `need` elements from `cap`; exactly `need` if doubling
 * would overflow size_t. Precondition: need > cap. */
static size_t grown_capacity(size_t cap, size_t need) {
    size_t c = cap ? cap : PG_ARRAY_MIN_CAP;
    while (c < need) {
        if (c > SIZE_MAX / 2) return need;
        c *= 2;
    }
    return c;
}

pg_status pg_array_reserve(void *pdata, size_t *cap, size_t need, size_t elem_size, pg_error *err) {
    if (need <= *cap) return PG_OK;
    if (elem_size == 0) return pg_error_set(err, PG_ERR_BADINPUT, "array: element size 0");
    if (need > SIZE_MAX / elem_size)
        return pg_error_set(err, PG_ERR_NOMEM,
                            "array: %zu elements of %zu bytes do not fit in memory", need,
                            elem_size);
    size_t c = grown_capacity(*cap, need);
    if (c > SIZE_MAX / elem_size) c = need; /* the doubled size overflows: take no more */
    void *old, *grown;
    memcpy(&old, pdata, sizeof old);
    grown = realloc(old, c * elem_size);
    if (!grown)
        return pg_error_set(err, PG_ERR_NOMEM, "array: out of memory for %zu elements of %zu bytes",
                            c, elem_size);
    memcpy(pdata, &grown, sizeof grown);
    *cap = c;
    return PG_OK;
}
