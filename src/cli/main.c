/* main.c - the planetgen command-line tool: dispatch to subcommands.
 *
 * Each subcommand lives in its own cmd_NAME.c. This file only knows the table,
 * the global flags (--help, --version) and `planetgen help CMD`. Exit codes:
 * 0 success, 1 runtime failure, 2 usage error or bad input. */
#include "pg_commands.h"

#include <stdio.h>
#include <string.h>

typedef struct pg_command {
    const char *name;
    int (*run)(pg_cli *cli, int argc, char **argv);
    const char *summary;
} pg_command;

static const pg_command pg_commands[] = {
    {"exemplar", pg_cmd_exemplar, "load an exemplar, print its statistics, write previews"},
    {"export", pg_cmd_export, "export a planet: glTF globe, EXR heights, previews"},
    {"generate", pg_cmd_generate, "synthesize a whole planet by example on the cube sphere"},
    {"grid", pg_cmd_grid, "describe a cube-sphere grid: counts, texel areas, distortion"},
    {"inspect", pg_cmd_inspect, "realism report of a planet: LPIPS-style poles, seams, pits"},
    {"pits", pg_cmd_pits, "remove pits from a DEM (fill, breach, hybrid) or count them"},
    {"synth", pg_cmd_synth, "synthesize a flat N x N terrain by example (Lefebvre-Hoppe)"},
    {"view", pg_cmd_view, "show a planet as a globe in a browser: write DIR/viewer/, serve it"},
    {NULL, NULL, NULL}};

static void print_usage(FILE *f) {
    fprintf(f, "usage: planetgen [--version] [--help] COMMAND [OPTIONS]\n\n"
               "planetgen synthesizes whole planets by example on a cube sphere.\n\n"
               "commands:\n");
    for (const pg_command *c = pg_commands; c->name; c++)
        fprintf(f, "  %-10s %s\n", c->name, c->summary);
    fprintf(f, "  %-10s %s\n", "help", "show help for a command: planetgen help COMMAND");
    fprintf(f, "\nexit codes: 0 success, 1 runtime failure, 2 usage error or bad input\n");
}

static const pg_command *find_command(const char *name) {
    for (const pg_command *c = pg_commands; c->name; c++)
        if (strcmp(c->name, name) == 0) return c;
    return NULL;
}

static int run_command(const pg_command *c, int argc, char **argv) {
    pg_cli cli;
    pg_cli_init(&cli, c->name);
    if (pg_cli_watch_signals(&cli) != 0) {
        fprintf(stderr, "planetgen %s: cannot start the signal watcher\n", c->name);
        return 1;
    }
    int rc = c->run(&cli, argc, argv);
    pg_cli_memory_unwatch(&cli);
    pg_cli_unwatch_signals(&cli); /* before `cli` leaves scope: see pg_cli.c */
    return rc;
}

int main(int argc, char **argv) {
    pg_cli_block_signals(); /* before any thread exists, so all inherit the mask */
    if (argc < 2) {
        print_usage(stderr);
        return 2;
    }
    const char *a = argv[1];
    if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
        print_usage(stdout);
        return 0;
    }
    if (!strcmp(a, "--version")) {
        printf("planetgen %s\n", pg_version());
        return 0;
    }
    if (!strcmp(a, "help")) {
        if (argc < 3) {
            print_usage(stdout);
            return 0;
        }
        const pg_command *c = find_command(argv[2]);
        if (!c) {
            fprintf(stderr, "planetgen: help: unknown command '%s'\n", argv[2]);
            return 2;
        }
        char *hargv[] = {argv[2], "--help", NULL};
        return run_command(c, 2, hargv);
    }
    const pg_command *c = find_command(a);
    if (!c) {
        fprintf(stderr, "planetgen: unknown command '%s' (see planetgen --help)\n", a);
        return 2;
    }
    return run_command(c, argc - 1, argv + 1);
}
