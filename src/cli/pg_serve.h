/* pg_serve.h - a static file server on 127.0.0.1 for `planetgen view --serve`
 * (docs/export.md, "The browser viewer"): browsers load ES modules only over HTTP, so
 * the viewer needs one. It serves the regular files under one directory, read-only,
 * GET and HEAD only, to this machine only, through libmicrohttpd's own threads. */
#ifndef PG_SERVE_H
#define PG_SERVE_H

#include "planetgen/pg_common.h"

typedef struct pg_serve pg_serve;

/* Listen on 127.0.0.1:port (0: a free port the system picks) and serve root, whose
 * path the caller keeps alive until pg_serve_stop. A port that cannot be bound (in
 * use, privileged) is PG_ERR_BADINPUT naming --serve. The bound port goes to *bound. */
pg_status pg_serve_start(const char *root, long port, pg_serve **out, int *bound, pg_error *err);

/* Stop serving, close the socket and free s (NULL is a no-op). */
void pg_serve_stop(pg_serve *s);

#endif
