/* test_view.c - `planetgen view` in a real browser: Debian's Chromium, headless, WebGL
 * through SwiftShader, loads the viewer that `view DIR --serve 0` serves on 127.0.0.1
 * and shows the Earth fixture's planet.glb. For the views from the north pole, the
 * south pole and a cube corner (where three faces meet) it asserts that the page
 * reports itself ready with its six faces and no error (read back with --dump-dom),
 * that the globe covers at least 20% of the screenshot, and that no background pixel
 * lies inside the globe's disc: a crack along a face seam would show the magenta
 * background through the globe (back faces are culled). A tiled planet (index.json)
 * with its .glb per tile is shown from those 24 files, loaded into one globe, with no
 * crack along the tile and face seams at the cube corner; without them its
 * viewer/planet.glb is assembled from the tiles and shown the same way; the tiles load
 * back bit for bit. The server gives nothing outside DIR. Bad input (no
 * planet, a port in use or out of range) exits 2 with one line and writes nothing. */
#include "export_fixture.h"

#include "planetgen/pg_export.h"
#include "planetgen/pg_planet_tiles.h"

#include <arpa/inet.h>
#include <math.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#define SHOT_W 800
#define SHOT_H 600

/* `planetgen view DIR --serve 0` in the background; its port from its stdout. */
typedef struct server {
    pid_t pid;
    int port;
} server;

/* The server of the test that runs, in cmocka's state, so that the teardown stops it
 * even when an assertion ended the test early (ctest would otherwise wait for the
 * orphan, which holds the test's output pipe). */
static int teardown_server(void **state) {
    server *s = *state;
    if (s->pid > 0) {
        kill(s->pid, SIGTERM);
        waitpid(s->pid, NULL, 0);
    }
    s->pid = 0;
    return 0;
}

static void serve(const char *dir, server *out) {
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    server s = {fork(), 0};
    assert_true(s.pid >= 0);
    if (s.pid == 0) {
        dup2(fds[1], STDOUT_FILENO);
        close(fds[0]);
        close(fds[1]);
        execl(pg_test_cli(), "planetgen", "view", dir, "--serve", "0", (char *)NULL);
        _exit(127);
    }
    close(fds[1]);
    FILE *f = fdopen(fds[0], "r");
    char line[2048];
    while (f && fgets(line, sizeof line, f)) {
        printf("view: %s", line);
        const char *p = strstr(line, "http://127.0.0.1:");
        if (p && !strncmp(line, "serving", 7)) {
            s.port = atoi(p + strlen("http://127.0.0.1:"));
            break;
        }
    }
    if (f) fclose(f); /* the server keeps running; its later output goes nowhere */
    *out = s;
    assert_true(s.port > 0);
}

static void stop(server *s) {
    assert_int_equal(kill(s->pid, SIGTERM), 0);
    int st = 0;
    assert_int_equal(waitpid(s->pid, &st, 0), s->pid);
    s->pid = 0;
    assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0); /* a clean stop */
}

/* The response head of one raw HTTP request to the server (the path is sent as is). */
static void http_head(int port, const char *method, const char *path, char *out, size_t size) {
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    assert_int_equal(connect(fd, (struct sockaddr *)&a, sizeof a), 0);
    char req[1024];
    int n = snprintf(req, sizeof req, "%s %s HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n", method, path);
    assert_int_equal(write(fd, req, (size_t)n), n);
    size_t got = 0;
    ssize_t r;
    while (got + 1 < size && (r = read(fd, out + got, size - 1 - got)) > 0)
        got += (size_t)r;
    out[got] = '\0';
    close(fd);
    char *end = strstr(out, "\r\n\r\n");
    if (end) *end = '\0';
}

/* The server gives the viewer's module as JavaScript (browsers refuse modules served
 * otherwise) and nothing outside DIR, whatever the path says. */
static void check_server_paths(int port) {
    char head[8192];
    http_head(port, "GET", "/viewer/viewer.js", head, sizeof head);
    assert_non_null(strstr(head, " 200 "));
    assert_non_null(strstr(head, "text/javascript"));
    http_head(port, "HEAD", "/planet.glb", head, sizeof head);
    assert_non_null(strstr(head, " 200 "));
    const char *outside[] = {"/../planet.json", "/viewer/../../etc/passwd",
                             "/viewer/%2e%2e/%2e%2e/etc/passwd", "/./planet.glb"};
    for (int i = 0; i < 4; i++) {
        http_head(port, "GET", outside[i], head, sizeof head);
        printf("GET %s: %.40s\n", outside[i], head);
        assert_non_null(strstr(head, " 403 "));
    }
    http_head(port, "POST", "/planet.glb", head, sizeof head);
    assert_non_null(strstr(head, " 405 "));
}

/* Chromium, headless, with WebGL through SwiftShader (the machine has no GPU). The
 * virtual-time budget lets the page load and draw before the dump or screenshot. */
static int chromium(const char *scratch, const char *what, const char *url, char *out,
                    size_t size) {
    char cmd[8192];
    snprintf(cmd, sizeof cmd,
             "chromium --headless --no-sandbox --use-angle=swiftshader "
             "--enable-unsafe-swiftshader --window-size=%d,%d --hide-scrollbars "
             "--virtual-time-budget=60000 --user-data-dir='%s/chromium-profile' %s '%s' "
             "2>/dev/null",
             SHOT_W, SHOT_H, scratch, what, url);
    return fixture_sh(cmd, out, size);
}

/* Load the page until it reports itself done (a slow load can outlast the budget):
 * it must be ready, with `faces` primitives and an empty error list. */
static void expect_ready(const char *scratch, const char *url, int faces) {
    static char dom[1 << 16];
    const char *body = NULL;
    for (int attempt = 0; attempt < 3; attempt++) {
        assert_int_equal(chromium(scratch, "--dump-dom", url, dom, sizeof dom), 0);
        body = strstr(dom, "<body");
        assert_non_null(body);
        if (!strstr(body, "data-status=\"loading\"")) break;
        printf("page still loading after the time budget; again\n");
    }
    const char *errors = strstr(dom, "<pre id=\"pg-errors\">");
    assert_non_null(errors);
    if (strncmp(errors, "<pre id=\"pg-errors\"></pre>", 26))
        printf("page errors: %.400s\n", errors);
    assert_true(!strncmp(errors, "<pre id=\"pg-errors\"></pre>", 26)); /* no error at all */
    assert_non_null(strstr(body, "data-status=\"ready\""));
    char want[32];
    snprintf(want, sizeof want, "data-faces=\"%d\"", faces);
    const char *got = strstr(body, "data-faces=");
    printf("page %.40s, expected %s\n", got ? got : "without data-faces", want);
    assert_non_null(strstr(body, want));
}

/* Strongly magenta: the background of the crack views (bg=ff00ff), blended or not. */
static int magenta(const float *px, float scale) {
    float r = px[0] * scale, g = px[1] * scale, b = px[2] * scale;
    return r - g > 0.38f && b - g > 0.38f;
}

typedef struct disc_figures {
    double coverage;  /* share of the frame that is globe */
    double radius;    /* of the disc with the globe's area, pixels */
    long holes;       /* background pixels within 0.97 of that radius */
    long disc_pixels; /* pixels tested */
} disc_figures;

/* The globe's disc from the screenshot itself: the globe's pixels give its area and
 * centroid, hence the disc; a crack is far too thin to move either. */
static disc_figures measure_disc(const char *png) {
    pg_image img;
    pg_error err = {0};
    assert_int_equal(pg_image_read(png, 0, &img, &err), PG_OK);
    assert_int_equal(img.width, SHOT_W);
    assert_int_equal(img.height, SHOT_H);
    double n = 0, sx = 0, sy = 0;
    for (int y = 0; y < img.height; y++)
        for (int x = 0; x < img.width; x++)
            if (!magenta(img.data + ((size_t)y * img.width + x) * img.channels, img.unit_scale)) {
                n++;
                sx += x;
                sy += y;
            }
    disc_figures d = {n / ((double)img.width * img.height), sqrt(n / M_PI), 0, 0};
    double cx = n > 0 ? sx / n : 0, cy = n > 0 ? sy / n : 0, r = 0.97 * d.radius;
    for (int y = 0; y < img.height; y++)
        for (int x = 0; x < img.width; x++) {
            if ((x - cx) * (x - cx) + (y - cy) * (y - cy) > r * r) continue;
            d.disc_pixels++;
            d.holes +=
                magenta(img.data + ((size_t)y * img.width + x) * img.channels, img.unit_scale);
        }
    pg_image_free(&img);
    return d;
}

/* One view: ready without errors, then a screenshot with a globe and no crack. */
static void check_view(const char *scratch, int port, const char *view, const char *shot_name,
                       int faces) {
    char url[512], shot[1300], what[1400];
    snprintf(url, sizeof url, "http://127.0.0.1:%d/viewer/index.html?view=%s&ui=0&bg=ff00ff", port,
             view);
    expect_ready(scratch, url, faces);
    snprintf(shot, sizeof shot, "%s/%s", scratch, shot_name);
    snprintf(what, sizeof what, "--screenshot='%s'", shot);
    disc_figures d = {0};
    for (int attempt = 0; attempt < 3 && d.coverage < 0.01; attempt++) {
        assert_int_equal(chromium(scratch, what, url, NULL, 0), 0);
        d = measure_disc(shot);
    }
    printf("view %-7s globe %.1f%% of the frame, disc radius %.0f px, %ld background pixels "
           "among %ld inside the disc\n",
           view, 100 * d.coverage, d.radius, d.holes, d.disc_pixels);
    assert_true(d.coverage >= 0.20);
    assert_true(d.disc_pixels > 0);
    assert_int_equal(d.holes, 0);
}

static void test_browser_views(void **state) {
    server *srv = *state;
    if (fixture_sh("command -v chromium >/dev/null", NULL, 0) != 0)
        fail_msg("chromium is not installed: run scripts/bootstrap --test");
    char dir[1024], args[2048];
    fixture_planet_dir("view", 2, 64, dir, sizeof dir);
    snprintf(args, sizeof args, "export '%s' --no-previews -q", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    serve(dir, srv);
    check_server_paths(srv->port);
    check_view(dir, srv->port, "north", "north.png", 6);
    check_view(dir, srv->port, "south", "south.png", 6);
    check_view(dir, srv->port, "corner", "corner.png", 6);
    /* the shaded relief at 4 times the exported exaggeration, from the corner */
    char url[512];
    snprintf(url, sizeof url, "http://127.0.0.1:%d/viewer/index.html?mode=relief&relief=40",
             srv->port);
    expect_ready(dir, url, 6);
    stop(srv);
}

/* The Earth fixture saved as tiles (the layout of generate --output-layout tiled). */
static void tiled_fixture(const char *tag, pg_planet *p, char *dir, size_t size) {
    pg_error err = {0};
    char planet_dir[1024];
    fixture_planet_dir(tag, 2, 64, planet_dir, sizeof planet_dir);
    assert_int_equal(pg_planet_load(planet_dir, p, &err), PG_OK);
    snprintf(dir, size, "%s/tiled", planet_dir);
    assert_int_equal(mkdir(dir, 0777), 0);
    pg_planet_dir_paths paths = {.dir = dir};
    assert_int_equal(
        pg_planet_save_tiles(p, 0, 6 * p->tiles * p->tiles, pg_planet_dir_path, &paths, &err),
        PG_OK);
    assert_int_equal(pg_planet_save_index(p, pg_planet_dir_path, &paths, &err), PG_OK);
}

static void test_tiled(void **state) {
    server *srv = *state;
    pg_planet p, q;
    pg_error err = {0};
    char dir[1100], path[1300];
    tiled_fixture("view_tiled", &p, dir, sizeof dir);
    /* the tiles load back to the same planet, bit for bit */
    assert_int_equal(pg_planet_load(dir, &q, &err), PG_OK);
    assert_int_equal(q.n, p.n);
    for (int f = 0; f < PG_CUBE_NFACES; f++) {
        assert_memory_equal(q.height[f], p.height[f], (size_t)p.n * p.n * sizeof(float));
        assert_memory_equal(q.albedo[f], p.albedo[f], (size_t)p.n * p.n * 3 * sizeof(float));
    }
    pg_planet_free(&q);
    serve(dir, srv);
    snprintf(path, sizeof path, "%s/viewer/planet.glb", dir);
    assert_true(pg_test_file_nonempty(path)); /* assembled from the tiles */
    check_view(dir, srv->port, "corner", "tiled_corner.png", 6);
    stop(srv);
    /* with the .glb per tile that generate writes: those are shown, nothing assembled */
    char viewer[1200], cmd[1400], out[256];
    snprintf(viewer, sizeof viewer, "%s/viewer", dir);
    snprintf(cmd, sizeof cmd, "rm -r '%s'", viewer);
    assert_int_equal(fixture_sh(cmd, out, sizeof out), 0);
    pg_planet_dir_paths paths = {.dir = dir};
    pg_export_opts o;
    pg_export_opts_default(&o);
    const int nt = 6 * p.tiles * p.tiles;
    assert_int_equal(
        pg_export_tiles_glb(&p, 0, nt, NULL, &o, pg_planet_dir_path, &paths, NULL, &err), PG_OK);
    assert_int_equal(pg_planet_save_index_glb(&p, true, pg_planet_dir_path, &paths, &err), PG_OK);
    pg_planet_free(&p);
    serve(dir, srv);
    assert_false(pg_test_file_nonempty(path));
    check_view(dir, srv->port, "corner", "tiles_corner.png", nt);
    check_view(dir, srv->port, "north", "tiles_north.png", nt);
    stop(srv);
}

/* One refusal: exit 2, one line naming `needle`, and DIR/viewer not created. */
static void expect_refused(const char *dir, const char *opts, const char *needle) {
    char args[2048], err[4096], viewer[1200];
    snprintf(args, sizeof args, "view '%s' %s", dir, opts);
    int rc = pg_test_run_cli(args, NULL, 0, err, sizeof err);
    printf("view %s -> %d: %s", opts, rc, err);
    assert_int_equal(rc, 2);
    assert_non_null(strstr(err, needle));
    int lines = 0;
    for (const char *c = err; *c; c++)
        lines += *c == '\n';
    assert_int_equal(lines, 1);
    snprintf(viewer, sizeof viewer, "%s/viewer", dir);
    struct stat st;
    assert_int_not_equal(stat(viewer, &st), 0); /* nothing written */
}

static void test_view_bad_input(void **s) {
    (void)s;
    char dir[1024], empty[1200], args[2048];
    fixture_planet_dir("view_bad", 1, 16, dir, sizeof dir);
    /* a planet directory without planet.glb: the message says how to make one */
    expect_refused(dir, "", "run planetgen export");
    snprintf(empty, sizeof empty, "%s/empty", dir);
    assert_int_equal(mkdir(empty, 0777), 0);
    expect_refused(empty, "", "not a planet output");
    snprintf(args, sizeof args, "%s/nonexistent", dir);
    expect_refused(args, "", "not a directory");
    snprintf(args, sizeof args, "export '%s' --no-previews -q", dir);
    assert_int_equal(pg_test_run_cli(args, NULL, 0, NULL, 0), 0);
    expect_refused(dir, "--serve 65536", "--serve");
    expect_refused(dir, "--serve http", "--serve");
    /* a port in use: bound here first */
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = 0};
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    assert_int_equal(bind(fd, (struct sockaddr *)&a, sizeof a), 0);
    assert_int_equal(listen(fd, 1), 0);
    assert_int_equal(getsockname(fd, (struct sockaddr *)&a, &len), 0);
    char opt[64];
    snprintf(opt, sizeof opt, "--serve %d", ntohs(a.sin_port));
    expect_refused(dir, opt, "in use");
    close(fd);
    /* a tiled directory missing a tile names the file */
    pg_planet p;
    char tiled[1100], path[1300];
    tiled_fixture("view_bad_tiled", &p, tiled, sizeof tiled);
    pg_planet_free(&p);
    snprintf(path, sizeof path, "%s/height_-Z_1_0.exr", tiled);
    assert_int_equal(unlink(path), 0);
    expect_refused(tiled, "", "height_-Z_1_0.exr");
}

int main(void) {
    server views = {0}, tiled = {0};
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_view_bad_input),
        cmocka_unit_test_prestate_setup_teardown(test_browser_views, NULL, teardown_server, &views),
        cmocka_unit_test_prestate_setup_teardown(test_tiled, NULL, teardown_server, &tiled),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
