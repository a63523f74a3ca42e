/* bench_export.c - export time, peak memory and .glb size for the default planet
 * (6 x 4x4 x 256^2) and a large one (6 x 8x8 x 512^2), both the Earth reprojected
 * from the default exemplar.
 *
 * usage: bench_export [WORKDIR]   (default /tmp/pg_bench_export)
 *
 * Each planet is first built and saved as a planet directory (in one child
 * process); then another child loads it and exports it (glTF, EXR, previews timed separately), so
 * the peak RSS it reports is that of `planetgen export`: the planet in memory plus the export's own
 * buffers. Wall and CPU seconds are both printed: on a shared machine the CPU time is
 * the steadier figure. Planet directories are kept in WORKDIR and reused by later
 * runs. Prints figures; asserts nothing. */
#include "planetgen/pg_export.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static double now_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double cpu_s(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int make_planet(int tiles, int size, const char *dir) {
    char meta[1300];
    struct stat sb;
    snprintf(meta, sizeof meta, "%s/planet.json", dir);
    if (stat(meta, &sb) == 0) return 0; /* built by an earlier run */
    pg_error err = {0};
    pg_exemplar_opts o;
    pg_exemplar_opts_default(&o);
    pg_exemplar ex;
    pg_planet p;
    if (pg_exemplar_load(&o, &ex, &err) ||
        pg_planet_alloc(&p, PG_CUBE_EQUIANGULAR, tiles, size, pg_ellipsoid_wgs84(), &err) ||
        pg_planet_from_exemplar(&p, &ex, 1, &err)) {
        fprintf(stderr, "bench_export: %s\n", err.msg);
        return 1;
    }
    pg_exemplar_free(&ex);
    mkdir(dir, 0777);
    pg_status st = pg_planet_save_dir(&p, dir, &err);
    pg_planet_free(&p);
    if (st) fprintf(stderr, "bench_export: %s\n", err.msg);
    return st != PG_OK;
}

/* In a child: load, export (three parts timed), print figures. */
static int export_child(const char *dir, const char *out) {
    pg_error err = {0};
    pg_planet p;
    double t0 = now_s();
    if (pg_planet_load(dir, &p, &err) != PG_OK) {
        fprintf(stderr, "bench_export: %s\n", err.msg);
        return 1;
    }
    double t_load = now_s() - t0;
    pg_planet_dir_paths c = {.dir = out};
    mkdir(out, 0777);
    const char *part[3] = {"glb", "exr", "previews"};
    double t[3], cpu[3];
    pg_export_result r, rg = {0};
    for (int k = 0; k < 3; k++) {
        pg_export_opts o;
        pg_export_opts_default(&o);
        o.glb = k == 0, o.exr = k == 1, o.previews = k == 2;
        double s = now_s(), cs = cpu_s();
        if (pg_export_write(&p, &o, pg_planet_dir_path, &c, &r, &err) != PG_OK) {
            fprintf(stderr, "bench_export: %s: %s\n", part[k], err.msg);
            return 1;
        }
        t[k] = now_s() - s;
        cpu[k] = cpu_s() - cs;
        if (k == 0) rg = r;
    }
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("  planet 6 x %dx%d x %d^2 (faces %lld^2): %.2f GB in memory, load %.2f s\n", p.tiles,
           p.tiles, p.tile_size, (long long)p.n, pg_planet_bytes(p.tiles, p.tile_size) / 1e9,
           t_load);
    printf("  mesh %d quads per face edge, %lld triangles, %lld vertices\n", rg.mesh_res,
           (long long)rg.triangles, (long long)rg.vertices);
    printf("  export wall: glb %.2f s, exr %.2f s, previews %.2f s, total %.2f s\n", t[0], t[1],
           t[2], t[0] + t[1] + t[2]);
    printf("  export cpu:  glb %.2f s, exr %.2f s, previews %.2f s, total %.2f s\n", cpu[0], cpu[1],
           cpu[2], cpu[0] + cpu[1] + cpu[2]);
    printf("  planet.glb %.1f MB\n", rg.glb_bytes / 1e6);
    printf("  peak RSS (load + export) %.2f GB\n", (double)ru.ru_maxrss * 1024 / 1e9);
    pg_planet_free(&p);
    return 0;
}

/* Run fn in a child process. The parent never starts OpenMP or OIIO threads, which
 * do not survive fork(). */
static int in_child(int (*fn)(int, int, const char *, const char *), int tiles, int size,
                    const char *a, const char *b) {
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        int rc = fn(tiles, size, a, b);
        fflush(stdout);
        _exit(rc);
    }
    int st;
    waitpid(pid, &st, 0);
    return !(WIFEXITED(st) && WEXITSTATUS(st) == 0);
}

static int make_child(int tiles, int size, const char *dir, const char *unused) {
    (void)unused;
    return make_planet(tiles, size, dir);
}

static int export_child_fn(int tiles, int size, const char *dir, const char *out) {
    (void)tiles, (void)size;
    return export_child(dir, out);
}

static int run_case(const char *work, int tiles, int size) {
    char dir[1024], out[1100];
    snprintf(dir, sizeof dir, "%s/planet_%dx%d", work, tiles, size);
    snprintf(out, sizeof out, "%s/export", dir);
    printf("planet 6 x %dx%d x %d^2\n", tiles, tiles, size);
    fflush(stdout);
    double s = now_s();
    if (in_child(make_child, tiles, size, dir, NULL)) return 1;
    printf("  (built and saved in %.1f s)\n", now_s() - s);
    return in_child(export_child_fn, tiles, size, dir, out);
}

int main(int argc, char **argv) {
    const char *work = argc > 1 ? argv[1] : "/tmp/pg_bench_export";
    mkdir(work, 0777);
    int rc = run_case(work, 4, 256);
    if (!rc) rc = run_case(work, 8, 512);
    return rc;
}
