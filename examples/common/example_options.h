/*
 * The command-line options the examples' programs (perma-mandelbrot,
 * perma-bfs) share: how perma runs (--technique, --strategy, --groups),
 * --stats, and the --compare table with its --repeats; rows of the
 * command-line engine (perma_cli.h), listed under "perma options".
 */
#ifndef EXAMPLE_OPTIONS_H
#define EXAMPLE_OPTIONS_H

#include <perma_cli.h>

#include "example_session.h"

typedef struct example_options {
    example_run_options run;
    int stats;        /* --stats: print the runtime's statistics */
    int compare;      /* --compare: the timing table instead of one run */
    unsigned repeats; /* --repeats: runs per version in --compare (default 3) */
} example_options;

#define EXAMPLE_OPTION_ROWS 6

/* The defaults into *o, and the rows of the options into rows[], their
 * targets in *o; `table` lists them. */
void example_options_init(example_options *o, perma_cli_option rows[EXAMPLE_OPTION_ROWS], perma_cli_table *table);

#endif
