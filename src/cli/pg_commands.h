/* pg_commands.h - prototypes of the CLI's subcommands; main.c holds the table. */
#ifndef PG_COMMANDS_H
#define PG_COMMANDS_H

#include "pg_cli.h"

int pg_cmd_exemplar(pg_cli *cli, int argc, char **argv);
int pg_cmd_synth(pg_cli *cli, int argc, char **argv);
struct pg_exemplar;
void pg_synth_cli_report_prep(pg_cli *cli, const struct pg_exemplar *src); /* cmd_synth.c */
int pg_cmd_generate(pg_cli *cli, int argc, char **argv);
int pg_cmd_grid(pg_cli *cli, int argc, char **argv);
int pg_cmd_inspect(pg_cli *cli, int argc, char **argv);
int pg_cmd_pits(pg_cli *cli, int argc, char **argv);
int pg_cmd_export(pg_cli *cli, int argc, char **argv);
int pg_cmd_view(pg_cli *cli, int argc, char **argv);

#endif
