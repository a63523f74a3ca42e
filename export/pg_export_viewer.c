/* pg_export_viewer.c - the browser viewer's files (pg_export.h, docs/export.md, "The
 * browser viewer"): the page and its module from export/viewer/ and the pinned three.js
 * files, all compiled in by scripts/embed-files.cmake, plus viewer.json naming the .glb.
 * Only the files the page imports are shipped, byte for byte as npm installed them. */
#include "planetgen/pg_export.h"

#include "pg_export_viewer_assets.h"
#include "planetgen/pg_json.h"

#include <stdio.h>

bool pg_export_viewer_available(void) {
    return pg_viewer_has_three != 0;
}

static pg_status write_asset(const pg_viewer_asset *a, pg_planet_path_fn path_for, void *user,
                             pg_error *err) {
    const char *path = path_for(a->name, user);
    if (!path) return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", a->name);
    return pg_write_file(path, a->data, a->size, err);
}

/* The page's files, then viewer.json naming one .glb (glb_url) or a tile set (urls). */
static pg_status write_viewer(const char *glb_url, const char *const *urls, int n,
                              pg_planet_path_fn path_for, void *user, pg_error *err) {
    if (!pg_export_viewer_available())
        return pg_error_set(err, PG_ERR_IO,
                            "this planetgen was built without three.js (npm was missing at build "
                            "time): install npm (scripts/bootstrap) and rebuild");
    for (const pg_viewer_asset *a = pg_viewer_assets; a->name; a++) {
        pg_status st = write_asset(a, path_for, user, err);
        if (st) return st;
    }
    pg_json *j = pg_json_object();
    if (j && glb_url) pg_json_set_string(j, "glb", glb_url);
    pg_json *arr = j && urls ? pg_json_set_array(j, "tiles") : NULL;
    for (int k = 0; arr && k < n; k++)
        pg_json_push_string(arr, urls[k]);
    return pg_planet_write_json(j, "viewer.json", path_for, user, err);
}

pg_status pg_export_viewer_write(const char *glb_url, pg_planet_path_fn path_for, void *user,
                                 pg_error *err) {
    return write_viewer(glb_url, NULL, 0, path_for, user, err);
}

pg_status pg_export_viewer_write_tiles(const char *const *urls, int n, pg_planet_path_fn path_for,
                                       void *user, pg_error *err) {
    return write_viewer(NULL, urls, n, path_for, user, err);
}
