/* bench_generate_cli.c - the whole `planetgen generate` run as a user meets it, this
 * build against a "before" planetgen side by side (docs/generate.md, "Performance of the
 * whole run"): the default planet (6 x 4^2 x 256^2) in layouts world (seed 1), free
 * (seed 7) and earth (seed 1), each binary run twice in turn on its own cache directory
 * and the second run measured (a warm cache, as on a user's second run), then a cold
 * exemplar preparation (an empty cache directory) for each. Figures come from each run's
 * --json report (stages with wall and CPU seconds and page faults) and from wait4 (the
 * whole process: wall, CPU, faults, peak RSS). Every target is printed with both
 * binaries' figures and their ratio; nothing is asserted.
 *
 * usage: bench_generate_cli [--before PLANETGEN] [--cache-dir DIR] [--layouts L,L,...]
 *                           [--no-cold]
 * The before binary is also taken from the environment variable
 * PG_BENCH_BEFORE_PLANETGEN (bench/run sets it from PG_BENCH_BEFORE_REV); without one, only this
 * build's figures are printed. The cache directory (default: a fresh temporary one) gets
 * a subdirectory per binary, since cache formats differ between versions. */
#define _GNU_SOURCE /* wait4 */
#include "bench_util.h"
#include <dirent.h>
#include <limits.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define NSTAGE 4
static const char *const stage_names[NSTAGE] = {"prepare exemplar", "synthesize", "write planet",
                                                "write previews and globe"};

/* What one run measured. */
typedef struct figures {
    bool ok;
    double wall, cpu, peak_mb, minflt, majflt; /* the whole process */
    double stage[NSTAGE], stage_cpu[NSTAGE];   /* wall and CPU seconds per stage */
    double stage_minflt[NSTAGE], stage_majflt[NSTAGE];
    double synth, mpx_s, gain_pit, final_pits, counts, render, prep;
} figures;

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void parse_report(const char *json, figures *f) {
    char *t = pg_bench_slurp(json);
    if (!t) return;
    const char *res = strstr(t, "\"results\"");
    f->prep = pg_bench_json_number(res, "exemplar_prep_seconds");
    f->synth = pg_bench_json_number(res, "synth_seconds");
    f->mpx_s = pg_bench_json_number(res, "synthesized_mpx_per_second");
    f->gain_pit = pg_bench_json_number(res, "gain_pit_seconds");
    f->final_pits = pg_bench_json_number(res, "final_pits_seconds");
    f->counts = pg_bench_json_number(res, "depression_count_seconds");
    f->render = pg_bench_json_number(res, "render_seconds");
    const char *st = strstr(t, "\"stages\"");
    for (int i = 0; i < NSTAGE; i++) {
        char pat[96];
        snprintf(pat, sizeof pat, "\"name\": \"%s\"", stage_names[i]);
        const char *s = st ? strstr(st, pat) : NULL;
        f->stage[i] = pg_bench_json_number(s, "seconds");
        f->stage_cpu[i] = pg_bench_json_number(s, "cpu_seconds");
        f->stage_minflt[i] = pg_bench_json_number(s, "minor_faults");
        f->stage_majflt[i] = pg_bench_json_number(s, "major_faults");
    }
    free(t);
}

/* Run BIN generate ARGS... with --cache-dir CACHE -o OUT --json OUT.json -q. */
static figures run_generate(const char *bin, const char *cache, const char *out,
                            const char *const *args) {
    figures f;
    memset(&f, 0, sizeof f);
    char json[PATH_MAX + 8], cmd[3 * PATH_MAX];
    snprintf(json, sizeof json, "%s.json", out);
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s'", out, json);
    if (system(cmd) != 0) return f;
    const char *argv[32];
    int n = 0;
    argv[n++] = bin;
    argv[n++] = "generate";
    argv[n++] = "-q";
    for (int i = 0; args[i] && n < 24; i++)
        argv[n++] = args[i];
    argv[n++] = "--cache-dir";
    argv[n++] = cache;
    argv[n++] = "-o";
    argv[n++] = out;
    argv[n++] = "--json";
    argv[n++] = json;
    argv[n] = NULL;
    double t0 = now_s();
    pid_t pid = fork();
    if (pid == 0) {
        execv(bin, (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    struct rusage ru;
    if (pid < 0 || wait4(pid, &status, 0, &ru) != pid) return f;
    f.wall = now_s() - t0;
    f.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    f.cpu = ru.ru_utime.tv_sec + 1e-6 * ru.ru_utime.tv_usec + ru.ru_stime.tv_sec +
            1e-6 * ru.ru_stime.tv_usec;
    f.peak_mb = ru.ru_maxrss / 1024.0;
    f.minflt = (double)ru.ru_minflt;
    f.majflt = (double)ru.ru_majflt;
    if (f.ok) parse_report(json, &f);
    return f;
}

/* Bytes of the exemplar cache files (*.pgsx) in dir. */
static double cache_mb(const char *dir) {
    DIR *d = opendir(dir);
    double total = 0;
    for (struct dirent *e; d && (e = readdir(d));) {
        const char *dot = strrchr(e->d_name, '.');
        char path[PATH_MAX + 300];
        struct stat sb;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (dot && !strcmp(dot, ".pgsx") && stat(path, &sb) == 0) total += (double)sb.st_size;
    }
    if (d) closedir(d);
    return total / 1e6;
}

static void row(const char *what, double before, double after, const char *goal, bool have) {
    if (have && before > 0 && after > 0)
        printf("  %-44s %10.3f %10.3f %8.2fx  %s\n", what, before, after, before / after, goal);
    else
        printf("  %-44s %10s %10.3f %9s  %s\n", what, have ? "n/a" : "-", after, "", goal);
}

static void row_up(const char *what, double before, double after, const char *goal, bool have) {
    /* higher is better: the ratio is after / before */
    if (have && before > 0 && after > 0)
        printf("  %-44s %10.3f %10.3f %8.2fx  %s\n", what, before, after, after / before, goal);
    else
        printf("  %-44s %10s %10.3f %9s  %s\n", what, have ? "n/a" : "-", after, "", goal);
}

static void report(const char *layout, const figures *b, const figures *a, bool have) {
    printf("\n%s  (seconds unless stated; ratio = before / after, or after / before for "
           "rates)\n",
           layout);
    printf("  %-44s %10s %10s %9s  %s\n", "figure", "before", "after", "ratio", "target");
    row_up("synthesis, synthesized Mpx/s", b->mpx_s, a->mpx_s, ">= 3.5", have);
    row("synthesis (pyramid)", b->synth, a->synth, "", have);
    row("whole run, wall", b->wall, a->wall, "", have);
    row("whole run / synthesis", b->wall / b->synth, a->wall / a->synth, "<= 2", have);
    row("load the cached exemplar (stage)", b->stage[0], a->stage[0], "<= 0.3 s", have);
    row("  of which the cache itself", b->prep, a->prep, "", have);
    row("synthesize stage (+ final pits, counts, render)", b->stage[1], a->stage[1], "", have);
    row("  final pits", b->final_pits, a->final_pits, "", have);
    row("  depression counts", b->counts, a->counts, "", have);
    row("write planet", b->stage[2], a->stage[2], "", have);
    row("write planet / synthesis", b->stage[2] / b->synth, a->stage[2] / a->synth, "<= 0.3", have);
    row("previews and globe", b->stage[3], a->stage[3], "", have);
    row("previews and globe / synthesis", b->stage[3] / b->synth, a->stage[3] / a->synth, "<= 0.3",
        have);
    double bo = b->wall,
           ao = a->wall; /* outside the stages: inputs (layout world: plates, climate) */
    for (int i = 0; i < NSTAGE; i++)
        bo -= b->stage[i], ao -= a->stage[i];
    row("outside the stages (world: plates, climate)", bo, ao, "", have);
    row("  / synthesis", bo / b->synth, ao / a->synth, "<= 0.3", have);
    row("CPU seconds, whole run", b->cpu, a->cpu, "", have);
    row("peak RSS, MB", b->peak_mb, a->peak_mb, "", have);
    row("page faults, whole run, minor", b->minflt, a->minflt, "", have);
    row("page faults, whole run, major", b->majflt, a->majflt, "", have);
    printf("  page faults (minor / major) per stage, after:");
    for (int i = 0; i < NSTAGE; i++)
        printf(" %s %.0f/%.0f;", stage_names[i], a->stage_minflt[i], a->stage_majflt[i]);
    printf("\n");
}

int main(int argc, char **argv) {
    const char *before = getenv("PG_BENCH_BEFORE_PLANETGEN"), *layouts = "world,free,earth";
    char root[PATH_MAX] = "";
    bool cold = true;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--before") && i + 1 < argc)
            before = argv[++i];
        else if (!strcmp(argv[i], "--cache-dir") && i + 1 < argc)
            snprintf(root, sizeof root, "%s", argv[++i]);
        else if (!strcmp(argv[i], "--layouts") && i + 1 < argc)
            layouts = argv[++i];
        else if (!strcmp(argv[i], "--no-cold"))
            cold = false;
        else {
            fprintf(stderr, "usage: bench_generate_cli [--before PLANETGEN] [--cache-dir DIR] "
                            "[--layouts L,L,...] [--no-cold]\n");
            return 2;
        }
    }
    char after[PATH_MAX];
    ssize_t len = readlink("/proc/self/exe", after, sizeof after - 16);
    if (len <= 0) return 1;
    after[len] = 0;
    snprintf(strrchr(after, '/') + 1, 16, "planetgen");
    if (!root[0]) {
        snprintf(root, sizeof root, "/tmp/pg_bench_generate_cli_XXXXXX");
        if (!mkdtemp(root)) return 1;
    } else if (mkdir(root, 0755) != 0 && access(root, W_OK) != 0) {
        fprintf(stderr, "bench_generate_cli: --cache-dir %s: cannot create\n", root);
        return 2;
    }
    bool have = before && *before && access(before, X_OK) == 0;
    if (before && *before && !have)
        fprintf(stderr, "bench_generate_cli: %s: not executable\n", before);
    const char *bins[2] = {have ? before : NULL, after}, *tags[2] = {"before", "after"};
    char cache[2][PATH_MAX + 16], out[2][PATH_MAX + 16];
    for (int k = 0; k < 2; k++) {
        snprintf(cache[k], sizeof cache[k], "%s/cache-%s", root, tags[k]);
        snprintf(out[k], sizeof out[k], "%s/planet-%s", root, tags[k]);
    }
    printf("bench_generate_cli: after %s\n                    before %s\n", after,
           have ? before : "(none: set PG_BENCH_BEFORE_PLANETGEN or --before)");
    printf("threads %s (OMP_NUM_THREADS), load average %.1f at the start, work dir %s\n",
           getenv("OMP_NUM_THREADS") ? getenv("OMP_NUM_THREADS") : "default", pg_bench_loadavg(),
           root);
    char list[256];
    snprintf(list, sizeof list, "%s", layouts);
    for (char *lay = strtok(list, ","); lay; lay = strtok(NULL, ",")) {
        const char *seed = !strcmp(lay, "free") ? "7" : "1";
        const char *args[] = {"--layout", lay, "--seed", seed, NULL};
        figures f[2];
        memset(f, 0, sizeof f);
        /* two rounds, the binaries in turn; the second round is measured */
        for (int round = 0; round < 2; round++)
            for (int k = 0; k < 2; k++)
                if (bins[k]) f[k] = run_generate(bins[k], cache[k], out[k], args);
        for (int k = 0; k < 2; k++)
            if (bins[k] && !f[k].ok)
                fprintf(stderr, "bench_generate_cli: %s %s failed\n", tags[k], lay);
        char title[128];
        snprintf(title, sizeof title, "layout %s, seed %s, warm cache, load %.1f", lay, seed,
                 pg_bench_loadavg());
        report(title, &f[0], &f[1], have);
    }
    if (cold) {
        figures f[2];
        memset(f, 0, sizeof f);
        const char *args[] = {"--layout", "earth", "--seed", "1", "--no-glb", NULL};
        for (int k = 0; k < 2; k++) {
            if (!bins[k]) continue;
            char cmd[2 * PATH_MAX], c[PATH_MAX + 24];
            snprintf(c, sizeof c, "%s-cold", cache[k]);
            snprintf(cmd, sizeof cmd, "rm -rf '%s'", c);
            if (system(cmd) != 0) return 1;
            f[k] = run_generate(bins[k], c, out[k], args);
        }
        printf("\ncold exemplar preparation, 6 x 1024^2 (empty cache; load %.1f)\n",
               pg_bench_loadavg());
        printf("  %-44s %10s %10s %9s  %s\n", "figure", "before", "after", "ratio", "target");
        row("prepare exemplar stage (sources + prep)", f[0].stage[0], f[1].stage[0], "<= 8 s",
            have);
        row("  CPU seconds", f[0].stage_cpu[0], f[1].stage_cpu[0], "", have);
        char c0[PATH_MAX + 24], c1[PATH_MAX + 24];
        snprintf(c0, sizeof c0, "%s-cold", cache[0]);
        snprintf(c1, sizeof c1, "%s-cold", cache[1]);
        row("cache file, MB", have ? cache_mb(c0) : 0, cache_mb(c1), "no larger than before", have);
    }
    return 0;
}
