/* Command line of the bfs program. */
#ifndef BFS_OPTIONS_H
#define BFS_OPTIONS_H

#include "bfs.h"
#include "example_options.h"

typedef struct bfs_options {
    const char *edge_file;     /* the operand, or NULL */
    unsigned generate;         /* --generate N: vertices of a generated graph, 0 = none */
    unsigned degree;           /* --degree: edges per new vertex when generating */
    unsigned long long seed;   /* --seed */
    unsigned source;
    int directed;              /* --directed: edges are arcs u -> v only */
    const char *output;        /* -o: "vertex level" lines, or NULL */
    example_options common;    /* --technique, --strategy, --groups, --stats, --compare, --repeats */
} bfs_options;

/* Parse argv into *o (defaults first).  PERMA_CLI_OK: run; otherwise the
 * program ends with perma_cli_exit_status(status): the help or version
 * was printed, or the bad usage said (also in `message`). */
perma_cli_status bfs_parse_options(int argc, char **argv, bfs_options *o, char *message, size_t size);

#endif
