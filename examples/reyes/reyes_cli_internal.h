/* The command line of reyes-render as the engine (perma_cli.h) takes it:
 * the table (reyes_cli_options.c), used by the parse and the --help text
 * (reyes_cli.c). */
#ifndef REYES_CLI_INTERNAL_H
#define REYES_CLI_INTERNAL_H

#include "reyes_cli.h"

#define REYES_CLI_ROWS 48 /* room for the table's rows */

/* The rows, the table that lists them and the command line; the pointers
 * point into the struct itself, which stays where it was filled. */
typedef struct reyes_cli_description {
    perma_cli_option rows[REYES_CLI_ROWS];
    perma_cli_option models; /* the operands */
    perma_cli_table table;
    perma_cli cli;
} reyes_cli_description;

/* Describe the command line of `program` with its targets in *cli. */
void reyes_cli_describe(reyes_cli *cli, const char *program, reyes_cli_description *d);

#endif
