/* cmd_view.c - `planetgen view DIR [--serve PORT]`: write DIR/viewer/, a page that
 * shows the planet as a globe in a browser (docs/export.md, "The browser viewer"), and
 * optionally serve DIR on 127.0.0.1 until interrupted.
 *
 * DIR is a planet directory with a planet.glb (written by generate or export), shown
 * in place as ../planet.glb, or a tiled one (generate --output-layout tiled: index.json
 * and per-tile files). A tiled planet's own .glb per tile (planet_F_TX_TY.glb, which
 * generate writes) are shown in place, all loaded into one globe; a tiled directory
 * without them (--no-glb) has its tiles assembled and exported as viewer/planet.glb.
 * Everything the user can get wrong - DIR, the port - is checked before anything is
 * written: the port is bound first, so a port in use leaves no viewer behind. The
 * viewer's files are staged like every output and renamed into place together; the
 * directories they need (viewer/three/...) are made on the way and removed again if the
 * command fails. */
#include "pg_commands.h"
#include "pg_serve.h"

#include "planetgen/pg_export.h"
#include "planetgen/pg_json.h"
#include "planetgen/pg_planet_tiles.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define VIEW_MAX_DIRS 16

typedef struct view_ctx {
    pg_cli *cli;
    char viewer[4096]; /* DIR/viewer */
    int ndirs;         /* subdirectories we created, in creation order */
    char *dirs[VIEW_MAX_DIRS];
} view_ctx;

static bool exists(const char *dir, const char *name) {
    char path[4096];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* mkdir -p of viewer/SUB, remembering what we made. */
static bool make_subdirs(view_ctx *c, const char *sub, size_t len) {
    char path[4096];
    int n = snprintf(path, sizeof path, "%s/%.*s", c->viewer, (int)len, sub);
    if (n < 0 || (size_t)n >= sizeof path) return false;
    for (char *p = path + strlen(c->viewer) + 1;; p++) {
        if (*p != '/' && *p != '\0') continue;
        char keep = *p;
        *p = '\0';
        if (mkdir(path, 0777) == 0) {
            if (c->ndirs == VIEW_MAX_DIRS) return false;
            c->dirs[c->ndirs++] = strdup(path);
        } else if (errno != EEXIST) {
            return false;
        }
        if (!keep) return true;
        *p = keep;
    }
}

/* pg_planet_path_fn for the viewer's files: names may hold subdirectories. */
static const char *viewer_path(const char *name, void *user) {
    view_ctx *c = user;
    const char *slash = strrchr(name, '/');
    if (!slash) return pg_cli_output_path(c->cli, c->viewer, name);
    if (!make_subdirs(c, name, (size_t)(slash - name))) return NULL;
    char dir[4096];
    int n = snprintf(dir, sizeof dir, "%s/%.*s", c->viewer, (int)(slash - name), name);
    if (n < 0 || (size_t)n >= sizeof dir) return NULL;
    return pg_cli_output_path(c->cli, dir, slash + 1);
}

static void remove_subdirs(view_ctx *c, bool failed) {
    for (int i = c->ndirs - 1; i >= 0; i--) {
        if (failed) rmdir(c->dirs[i]); /* only if empty: never removes user files */
        free(c->dirs[i]);
    }
    c->ndirs = 0;
}

/* A tiled planet (index.json), checked by run_view: its tiles assembled in memory and
 * exported as viewer/planet.glb with the default mesh and exaggeration. */
static pg_status export_tiled(pg_cli *cli, const char *dir, view_ctx *c, pg_error *err) {
    pg_export_opts o;
    pg_export_opts_default(&o);
    o.exr = o.previews = false;
    pg_planet p;
    pg_cli_stage_begin(cli, "load tiles");
    pg_status st = pg_planet_load_tiles(dir, &p, err);
    pg_cli_stage_end(cli);
    if (st) return st;
    st = pg_export_check_planet(&o, &p, err);
    pg_cli_stage_begin(cli, "export globe");
    if (!st) st = pg_export_write(&p, &o, viewer_path, c, NULL, err);
    pg_cli_stage_end(cli);
    pg_planet_free(&p);
    return st;
}

/* Before anything is written: every tile present, and memory for the whole planet (as
 * planetgen export's estimate in cmd_export.c, without the previews). */
static int check_tiled(pg_cli *cli, const char *dir, double max_memory_gb) {
    pg_error err = {0};
    int T, S;
    if (pg_planet_tiles_check(dir, &T, &S, &err)) return pg_cli_fail(cli, &err);
    double n = (double)T * S, verts = 6.0 * pow(pg_export_default_mesh_res(T, S) + 1.0, 2);
    return pg_cli_check_memory(cli, dir, 300e6 + 6 * n * n * 48 + verts * 160, max_memory_gb);
}

/* The URLs, relative to DIR/viewer, of a tiled planet's .glb per tile when every tile
 * has one (in tile order), else NULL. */
static char **tile_glb_urls(const char *dir, int *n) {
    pg_error err = {0};
    int T, S;
    *n = 0;
    if (pg_planet_tiles_check(dir, &T, &S, &err)) return NULL;
    const pg_planet geo = {.tiles = T, .tile_size = S};
    const int nt = 6 * T * T;
    char **urls = calloc((size_t)nt, sizeof *urls);
    for (int t = 0; urls && t < nt; t++) {
        char name[64], url[96];
        pg_planet_tile_glb_name(&geo, t, name);
        if (!exists(dir, name)) break;
        char *u = url + snprintf(url, sizeof url, "../");
        for (const char *c = name; *c; c++) /* "+" spelled out: a URL path keeps it literal */
            u += *c == '+' ? snprintf(u, 4, "%%2B") : snprintf(u, 2, "%c", *c);
        if (!(urls[t] = strdup(url))) break;
        *n = t + 1;
    }
    if (*n == nt) return urls;
    for (int t = 0; urls && t < *n; t++)
        free(urls[t]);
    free(urls);
    *n = 0;
    return NULL;
}

static void free_urls(char **urls, int n) {
    for (int t = 0; t < n; t++)
        free(urls[t]);
    free(urls);
}

/* Serve until SIGINT or SIGTERM, then exit 0. The address is printed even with --quiet:
 * it is what the user waits for. The CLI's watcher is stopped first: its message says
 * the command wrote nothing, which is not true once the viewer is in place. */
static int serve_until_signal(pg_cli *cli, pg_serve *srv, const char *dir, int port) {
    printf("serving  %s at http://127.0.0.1:%d/viewer/index.html (Ctrl-C stops)\n", dir, port);
    fflush(stdout);
    pg_cli_unwatch_signals(cli);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    int sig = 0;
    sigwait(&set, &sig);
    pg_serve_stop(srv);
    return 0;
}

static int run_view(pg_cli *cli, const char *dir, long port, double max_memory_gb) {
    pg_error err = {0};
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return pg_cli_usage_error(cli, "%s: not a directory", dir);
    bool glb = exists(dir, PG_EXPORT_GLB_NAME), tiled = !glb && exists(dir, PG_PLANET_INDEX_NAME);
    if (!glb && !tiled && exists(dir, PG_PLANET_META_NAME))
        return pg_cli_usage_error(cli, "%s: no %s (run planetgen export %s)", dir,
                                  PG_EXPORT_GLB_NAME, dir);
    if (!glb && !tiled)
        return pg_cli_usage_error(cli, "%s: not a planet output (no %s or %s)", dir,
                                  PG_EXPORT_GLB_NAME, PG_PLANET_INDEX_NAME);
    if (!pg_export_viewer_available()) {
        pg_export_viewer_write(NULL, NULL, NULL, &err); /* only to fill err with the reason */
        return pg_cli_fail(cli, &err);
    }
    int nurls = 0;
    char **urls = tiled ? tile_glb_urls(dir, &nurls) : NULL;
    int rc = tiled && !urls ? check_tiled(cli, dir, max_memory_gb) : 0;
    if (rc) return rc;
    pg_serve *srv = NULL;
    int bound = 0;
    if (port >= 0 && pg_serve_start(dir, port, &srv, &bound, &err)) {
        free_urls(urls, nurls);
        return pg_cli_fail(cli, &err);
    }
    view_ctx c = {.cli = cli};
    snprintf(c.viewer, sizeof c.viewer, "%s/%s", dir, PG_EXPORT_VIEWER_DIR);
    pg_status s = pg_cli_prepare_outdir(cli, c.viewer, &err);
    bool made_viewer = !s && cli->created_dir != NULL;
    if (!s && tiled && !urls) s = export_tiled(cli, dir, &c, &err);
    if (!s && urls)
        s = pg_export_viewer_write_tiles((const char *const *)urls, nurls, viewer_path, &c, &err);
    else if (!s)
        s = pg_export_viewer_write(tiled ? PG_EXPORT_GLB_NAME : "../" PG_EXPORT_GLB_NAME,
                                   viewer_path, &c, &err);
    free_urls(urls, nurls);
    if (s) { /* the staged files, then the directories they were in */
        pg_cli_abort(cli);
        remove_subdirs(&c, true);
        if (made_viewer) rmdir(c.viewer);
        pg_serve_stop(srv);
        return pg_cli_fail(cli, &err);
    }
    pg_json *r = pg_cli_report(cli);
    if (r) {
        pg_json_set_string(pg_json_set_object(r, "inputs"), "planet", dir);
        pg_json *res = pg_json_set_object(r, "results");
        pg_json_set_string(res, "viewer", c.viewer);
        pg_json_set_bool(res, "tiled", tiled);
        pg_json_set_number(res, "tile_glb_files", nurls);
        if (srv) pg_json_set_number(res, "port", bound);
    }
    rc = pg_cli_finish(cli);
    remove_subdirs(&c, rc != 0);
    if (rc) {
        pg_serve_stop(srv);
        return rc;
    }
    pg_cli_info(cli, "viewer   %s/%s\n", c.viewer, PG_EXPORT_VIEWER_PAGE);
    if (srv) return serve_until_signal(cli, srv, dir, bound);
    pg_cli_info(cli,
                "open it through a local server: planetgen view %s --serve 8000, or\n"
                "         python3 -m http.server --bind 127.0.0.1 --directory %s 8000,\n"
                "         then http://127.0.0.1:8000/viewer/index.html\n",
                dir, dir);
    return 0;
}

int pg_cmd_view(pg_cli *cli, int argc, char **argv) {
    long port = -1;
    double max_memory_gb = 0;
    const pg_opt opts[] = {
        {"--serve", NULL, PG_OPT_INT, &port, 0, 65535, NULL, "PORT",
         "serve DIR on http://127.0.0.1:PORT/ until interrupted (0: any free port)"},
        PG_CLI_MAX_MEMORY_OPT(max_memory_gb),
        PG_OPT_END};
    const char *pos[1];
    int npos;
    int rc = pg_cli_parse_or_help(
        cli, opts, argc, argv, pos, 1, &npos, "DIR [--serve PORT]",
        "Write DIR/viewer/, a page that shows the planet in DIR as an interactive globe\n"
        "(three.js, no network), and with --serve, serve DIR on 127.0.0.1 until Ctrl-C.\n"
        "DIR holds planet.glb (generate, export) or a tiled planet (index.json): its .glb\n"
        "per tile are loaded into one globe, or without them (--no-glb) the tiles are\n"
        "exported to DIR/viewer/planet.glb.");
    if (rc >= 0) return rc;
    if (npos != 1) return pg_cli_usage_error(cli, "expected one planet directory (see --help)");
    return run_view(cli, pos[0], port, max_memory_gb);
}
