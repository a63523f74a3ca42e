/* pg_commands.h - prototypes of the CLI's subcommands; main.c holds the table. */
#ifndef PG_COMMANDS_H
#define PG_COMMANDS_H

#include "pg_cli.h"

int pg_cmd_exemplar(pg_cli *cli, int argc, char **argv);
int pg_cmd_synth(pg_cli *cli, int argc, char **argv);
int pg_cmd_generate(pg_cli *cli, int argc, char **argv);
int pg_cmd_grid(pg_cli *cli, int argc, char **argv);
int pg_cmd_pits(pg_cli *cli, int argc, char **argv);

#endif
