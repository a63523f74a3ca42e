/* pg_cli_options.c - the CLI's declarative option parser: a command's pg_opt table plus
 * the common options, each value checked for type and range with a one-line usage error
 * naming the option; the help text from the same table; the shared exemplar options. */
#include "pg_cli.h"

#include "planetgen/pg_json.h"

#include <errno.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static bool choice_ok(const char *choices, const char *v) {
    size_t n = strlen(v);
    for (const char *p = choices; p && *p;) {
        const char *bar = strchr(p, '|');
        size_t len = bar ? (size_t)(bar - p) : strlen(p);
        if (len == n && strncmp(p, v, n) == 0) return true;
        p = bar ? bar + 1 : NULL;
    }
    return false;
}

/* Store one option value, checking type and range. Returns 0 or 2. */
static int store_value(pg_cli *cli, const pg_opt *o, const char *v) {
    char *end = NULL;
    switch (o->kind) {
    case PG_OPT_FLAG:
        *(bool *)o->dest = true;
        return 0;
    case PG_OPT_STRING:
        if (!*v) return pg_cli_usage_error(cli, "%s: empty value", o->name);
        *(const char **)o->dest = v;
        return 0;
    case PG_OPT_LIST: {
        pg_opt_list *l = o->dest;
        if (!*v) return pg_cli_usage_error(cli, "%s: empty value", o->name);
        if (l->n >= PG_OPT_LIST_MAX)
            return pg_cli_usage_error(cli, "%s: given more than %d times", o->name,
                                      PG_OPT_LIST_MAX);
        l->v[l->n++] = v;
        return 0;
    }
    case PG_OPT_CHOICE:
        if (!choice_ok(o->choices, v))
            return pg_cli_usage_error(cli, "%s: unknown value '%s' (choose %s)", o->name, v,
                                      o->choices);
        *(const char **)o->dest = v;
        return 0;
    case PG_OPT_INT: {
        errno = 0;
        long x = strtol(v, &end, 10);
        if (!*v || *end || errno)
            return pg_cli_usage_error(cli, "%s: '%s' is not an integer", o->name, v);
        if (x < o->min || x > o->max)
            return pg_cli_usage_error(cli, "%s: %ld is out of range [%.0f, %.0f]", o->name, x,
                                      o->min, o->max);
        *(long *)o->dest = x;
        return 0;
    }
    case PG_OPT_DOUBLE: {
        errno = 0;
        double x = strtod(v, &end);
        if (!*v || *end || errno || !isfinite(x))
            return pg_cli_usage_error(cli, "%s: '%s' is not a finite number", o->name, v);
        if (x < o->min || x > o->max)
            return pg_cli_usage_error(cli, "%s: %g is out of range [%g, %g]", o->name, x, o->min,
                                      o->max);
        *(double *)o->dest = x;
        return 0;
    }
    }
    return 2;
}

static const pg_opt *find_opt(const pg_opt *specs, const pg_opt *common, const char *name) {
    for (const pg_opt *o = specs; o && o->name; o++)
        if (!strcmp(o->name, name) || (o->alias && !strcmp(o->alias, name))) return o;
    for (const pg_opt *o = common; o->name; o++)
        if (!strcmp(o->name, name) || (o->alias && !strcmp(o->alias, name))) return o;
    return NULL;
}

static int check_json_path(pg_cli *cli) {
    if (!cli->json_path) return 0;
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", cli->json_path);
    char *slash = strrchr(dir, '/');
    if (slash)
        *slash = '\0';
    else
        snprintf(dir, sizeof dir, ".");
    struct stat st;
    if (stat(dir[0] ? dir : "/", &st) != 0 || !S_ISDIR(st.st_mode))
        return pg_cli_usage_error(cli, "--json %s: directory '%s' does not exist", cli->json_path,
                                  dir);
    if (access(dir[0] ? dir : "/", W_OK) != 0)
        return pg_cli_usage_error(cli, "--json %s: directory '%s' is not writable", cli->json_path,
                                  dir);
    cli->report = pg_json_object();
    return 0;
}

int pg_cli_parse(pg_cli *cli, const pg_opt *specs, int argc, char **argv, const char **pos,
                 int max_pos, int *npos, bool *done) {
    bool help = false;
    const pg_opt common[] = {
        {"--json", NULL, PG_OPT_STRING, &cli->json_path, 0, 0, NULL, "FILE",
         "write a machine-readable summary (inputs, parameters, stage times, peak memory)"},
        {"--quiet", "-q", PG_OPT_FLAG, &cli->quiet, 0, 0, NULL, NULL, "no progress or info output"},
        {"--verbose", "-v", PG_OPT_FLAG, &cli->verbose, 0, 0, NULL, NULL, "more detail"},
        {"--threads", NULL, PG_OPT_INT, &cli->threads, 0, 1024, NULL, "N",
         "OpenMP threads (0 = all cores); results do not depend on it"},
        {"--help", "-h", PG_OPT_FLAG, &help, 0, 0, NULL, NULL, "show this help"},
        PG_OPT_END};
    *npos = 0;
    *done = false;
    cli->t_start = pg_cli_now();
    cli->tty = isatty(STDERR_FILENO);
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (a[0] == '-' && a[1] != '\0') {
            char name[64];
            const char *eq = strchr(a, '=');
            size_t len = eq ? (size_t)(eq - a) : strlen(a);
            if (len >= sizeof name) return pg_cli_usage_error(cli, "unknown option '%s'", a);
            memcpy(name, a, len);
            name[len] = '\0';
            const pg_opt *o = find_opt(specs, common, name);
            if (!o) return pg_cli_usage_error(cli, "unknown option '%s'", name);
            if (o->kind == PG_OPT_FLAG) {
                if (eq) return pg_cli_usage_error(cli, "%s takes no value", name);
                *(bool *)o->dest = true;
                continue;
            }
            /* A following word that is itself an option is not this option's value. */
            const char *v = eq ? eq + 1 : (i + 1 < argc ? argv[i + 1] : NULL);
            if (!eq && v && find_opt(specs, common, v)) v = NULL;
            if (!v) return pg_cli_usage_error(cli, "%s needs a value", name);
            if (!eq) i++;
            int rc = store_value(cli, o, v);
            if (rc) return rc;
        } else {
            if (*npos >= max_pos) return pg_cli_usage_error(cli, "unexpected argument '%s'", a);
            pos[(*npos)++] = a;
        }
    }
    if (help) {
        *done = true;
        return 0;
    }
    if (cli->threads > 0) omp_set_num_threads((int)cli->threads);
    return check_json_path(cli);
}

int pg_cli_parse_or_help(pg_cli *cli, const pg_opt *specs, int argc, char **argv, const char **pos,
                         int max_pos, int *npos, const char *usage, const char *description) {
    bool done = false;
    int rc = pg_cli_parse(cli, specs, argc, argv, pos, max_pos, npos, &done);
    if (rc) return rc;
    if (!done) return -1;
    pg_cli_print_help(cli, usage, description, specs, stdout);
    return 0;
}

void pg_cli_exemplar_opts(const pg_cli_exemplar *e, pg_exemplar_opts *o) {
    pg_exemplar_opts_default(o);
    o->albedo_path = e->albedo;
    o->height_path = e->height;
    o->height_scale = e->height_scale;
    o->height_offset = e->height_offset;
    o->sea_level = e->sea_level;
    o->repair_ocean = !e->no_repair_ocean;
}

static void print_opt_table(const pg_opt *specs, FILE *f) {
    for (const pg_opt *o = specs; o && o->name; o++) {
        char left[96];
        snprintf(left, sizeof left, "%s%s%s%s%s", o->alias ? o->alias : "", o->alias ? ", " : "",
                 o->name, o->metavar ? " " : "", o->metavar ? o->metavar : "");
        fprintf(f, "  %-28s %s", left, o->help ? o->help : "");
        if (o->kind == PG_OPT_CHOICE) fprintf(f, " (%s)", o->choices);
        if (o->kind == PG_OPT_INT || o->kind == PG_OPT_DOUBLE)
            fprintf(f, " [%g..%g]", o->min, o->max);
        fputc('\n', f);
    }
}

void pg_cli_print_help(const pg_cli *cli, const char *usage, const char *description,
                       const pg_opt *specs, FILE *f) {
    fprintf(f, "usage: planetgen %s %s\n\n%s\n\noptions:\n", cli->cmd, usage, description);
    print_opt_table(specs, f);
    fprintf(f, "\ncommon options:\n"
               "  --json FILE                  write a machine-readable summary\n"
               "  -q, --quiet                  no progress or info output\n"
               "  -v, --verbose                more detail\n"
               "  --threads N                  OpenMP threads (0 = all cores)\n"
               "  -h, --help                   show this help\n"
               "\nexit codes: 0 success, 1 runtime failure, 2 usage error or bad input\n");
}
