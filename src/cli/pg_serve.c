/* pg_serve.c - the static file server of `planetgen view --serve` (pg_serve.h) over
 * libmicrohttpd. The socket is bound here rather than by the library, so that a port
 * in use is refused with its errno before `view` writes anything.
 *
 * What a request can reach: the URL path (which libmicrohttpd has already
 * percent-decoded) must start with "/" and contain no "." or ".." segment and no
 * backslash or NUL, so it names a file at or below root; only regular files are
 * served, with a Content-Type from the extension (module scripts must come as
 * text/javascript or the browser refuses them). "/" redirects to the viewer page. */
#include "pg_serve.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <microhttpd.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

struct pg_serve {
    struct MHD_Daemon *daemon;
    const char *root;
};

static const struct {
    const char *ext, *type;
} mime_types[] = {
    {".html", "text/html; charset=utf-8"},
    {".js", "text/javascript; charset=utf-8"},
    {".json", "application/json"},
    {".glb", "model/gltf-binary"},
    {".gltf", "model/gltf+json"},
    {".bin", "application/octet-stream"},
    {".png", "image/png"},
    {".jpg", "image/jpeg"},
    {".jpeg", "image/jpeg"},
    {".exr", "image/x-exr"},
    {".tif", "image/tiff"},
    {".txt", "text/plain; charset=utf-8"},
};

static const char *mime_type(const char *path) {
    const char *dot = strrchr(path, '.');
    for (size_t i = 0; dot && i < sizeof mime_types / sizeof mime_types[0]; i++)
        if (!strcmp(dot, mime_types[i].ext)) return mime_types[i].type;
    return "application/octet-stream";
}

/* A path that stays under root: "/" first, no "." or ".." segment, no backslash. */
static int safe_path(const char *url) {
    if (url[0] != '/' || strchr(url, '\\')) return 0;
    for (const char *s = url; *s;) {
        const char *seg = s + 1, *end = strchr(seg, '/');
        size_t n = end ? (size_t)(end - seg) : strlen(seg);
        if ((n == 1 && seg[0] == '.') || (n == 2 && seg[0] == '.' && seg[1] == '.')) return 0;
        s = seg + n;
    }
    return 1;
}

static enum MHD_Result respond_text(struct MHD_Connection *c, unsigned code, const char *text) {
    struct MHD_Response *r =
        MHD_create_response_from_buffer(strlen(text), (void *)text, MHD_RESPMEM_PERSISTENT);
    if (!r) return MHD_NO;
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, "text/plain; charset=utf-8");
    enum MHD_Result ret = MHD_queue_response(c, code, r);
    MHD_destroy_response(r);
    return ret;
}

static enum MHD_Result respond_file(struct MHD_Connection *c, const char *path) {
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (fd >= 0) close(fd);
        return respond_text(c, MHD_HTTP_NOT_FOUND, "not found\n");
    }
    struct MHD_Response *r = MHD_create_response_from_fd64((uint64_t)st.st_size, fd);
    if (!r) {
        close(fd);
        return MHD_NO;
    }
    MHD_add_response_header(r, MHD_HTTP_HEADER_CONTENT_TYPE, mime_type(path));
    MHD_add_response_header(r, MHD_HTTP_HEADER_CACHE_CONTROL, "no-cache");
    enum MHD_Result ret = MHD_queue_response(c, MHD_HTTP_OK, r);
    MHD_destroy_response(r); /* closes fd once sent */
    return ret;
}

static enum MHD_Result handle(void *cls, struct MHD_Connection *c, const char *url,
                              const char *method, const char *version, const char *upload,
                              size_t *upload_size, void **req) {
    (void)version;
    (void)upload;
    (void)upload_size;
    (void)req;
    const pg_serve *s = cls;
    if (strcmp(method, MHD_HTTP_METHOD_GET) && strcmp(method, MHD_HTTP_METHOD_HEAD))
        return respond_text(c, MHD_HTTP_METHOD_NOT_ALLOWED, "only GET and HEAD\n");
    if (!strcmp(url, "/")) {
        struct MHD_Response *r = MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
        if (!r) return MHD_NO;
        MHD_add_response_header(r, MHD_HTTP_HEADER_LOCATION, "/viewer/index.html");
        enum MHD_Result ret = MHD_queue_response(c, MHD_HTTP_FOUND, r);
        MHD_destroy_response(r);
        return ret;
    }
    if (!safe_path(url)) return respond_text(c, MHD_HTTP_FORBIDDEN, "forbidden\n");
    char path[4096];
    size_t n = strlen(url);
    int len =
        snprintf(path, sizeof path, "%s%s%s", s->root, url, url[n - 1] == '/' ? "index.html" : "");
    if (len < 0 || (size_t)len >= sizeof path)
        return respond_text(c, MHD_HTTP_NOT_FOUND, "not found\n");
    return respond_file(c, path);
}

/* The listening socket on 127.0.0.1:port, or -1 with errno set. */
static int listen_local(long port) {
    int fd = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return -1;
    int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (bind(fd, (struct sockaddr *)&a, sizeof a) != 0 || listen(fd, 64) != 0) {
        int e = errno;
        close(fd);
        errno = e;
        return -1;
    }
    return fd;
}

pg_status pg_serve_start(const char *root, long port, pg_serve **out, int *bound, pg_error *err) {
    *out = NULL;
    int fd = listen_local(port);
    if (fd < 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "--serve %ld: cannot listen on 127.0.0.1:%ld: %s",
                            port, port, strerror(errno));
    struct sockaddr_in a;
    socklen_t alen = sizeof a;
    getsockname(fd, (struct sockaddr *)&a, &alen);
    pg_serve *s = calloc(1, sizeof *s);
    if (!s) {
        close(fd);
        return pg_error_set(err, PG_ERR_NOMEM, "out of memory");
    }
    s->root = root;
    /* MHD_USE_ITC: needed by MHD_quiesce_daemon, which hands the socket back to us */
    s->daemon =
        MHD_start_daemon(MHD_USE_AUTO_INTERNAL_THREAD | MHD_USE_ITC, 0, NULL, NULL, handle, s,
                         MHD_OPTION_LISTEN_SOCKET, fd, MHD_OPTION_THREAD_POOL_SIZE, (unsigned)4,
                         MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)60, MHD_OPTION_END);
    if (!s->daemon) {
        close(fd);
        free(s);
        return pg_error_set(err, PG_ERR_IO, "--serve %ld: cannot start the HTTP server", port);
    }
    *bound = ntohs(a.sin_port);
    *out = s;
    return PG_OK;
}

void pg_serve_stop(pg_serve *s) {
    if (!s) return;
    MHD_socket fd = MHD_quiesce_daemon(s->daemon); /* the socket is ours again */
    MHD_stop_daemon(s->daemon);
    if (fd != MHD_INVALID_SOCKET) close(fd);
    free(s);
}
