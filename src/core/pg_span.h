/* pg_span.h - a planet-sized array of which one process commits only the rows it uses.
 *
 * DESIGN
 * ------
 * Under mpirun each rank indexes the planet's arrays (the delivered heights, the faces
 * of the planet) by cube texel id, as one process does, but touches only the rows of
 * its own tiles. Allocating the whole array with malloc would ask the kernel to commit
 * the whole planet's bytes in every rank: 103 GB of heights at 25.8 Gpx, refused
 * outright under strict overcommit and by the default heuristic on a smaller machine.
 * A span instead reserves the whole address range with no access (PROT_NONE: no commit
 * charge in any overcommit mode), then opens read-write only the byte ranges the rank
 * uses (pg_span_open), rounded out to whole pages: only those are charged, and they
 * read as zero until written, as calloc's memory does. A touch anywhere else faults at
 * once, so a rank that strays past its rows cannot go unnoticed in the tests.
 *
 * Ownership: the caller owns the pg_span and frees it with pg_span_free, which unmaps
 * the whole range; the pointer `base` is valid (for the opened ranges) until then.
 * Library-internal: not part of the installed API. */
#ifndef PG_SPAN_H
#define PG_SPAN_H

#include "planetgen/pg_common.h"

#include <stddef.h>

typedef struct pg_span {
    void *base;   /* start of the reserved range, NULL when empty */
    size_t bytes; /* its length, as asked */
} pg_span;

/* Reserve bytes of address space, none of it accessible yet. PG_ERR_NOMEM when the
 * address space itself is not there. */
pg_status pg_span_reserve(pg_span *s, size_t bytes, pg_error *err);

/* Make [off, off + len) readable and writable (and zero), rounded out to pages and
 * clipped to the span; opening a range twice is harmless. PG_ERR_NOMEM when the kernel
 * will not commit it. */
pg_status pg_span_open(pg_span *s, size_t off, size_t len, pg_error *err);

/* Unmap the whole range; s becomes empty. Safe on an empty span. */
void pg_span_free(pg_span *s);

#endif
