/* pg_export_viewer_assets.h - the browser viewer's files, compiled into the library
 * from export/viewer/ and from three.js (npm, pinned by export/viewer/package-lock.json)
 * by scripts/embed-files.cmake. Library-internal: pg_export_viewer.c writes them. */
#ifndef PG_EXPORT_VIEWER_ASSETS_H
#define PG_EXPORT_VIEWER_ASSETS_H

#include <stddef.h>

typedef struct pg_viewer_asset {
    const char *name; /* path inside the viewer directory, "/"-separated; NULL ends */
    const unsigned char *data;
    size_t size;
} pg_viewer_asset;

extern const pg_viewer_asset pg_viewer_assets[];
/* 1 when three.js was found at build time (npm), 0 when the viewer lacks it */
extern const int pg_viewer_has_three;

#endif
