/* Command line of the bfs program. */
#ifndef BFS_OPTIONS_H
#define BFS_OPTIONS_H

#include "bfs.h"

typedef struct bfs_options {
    const char *edge_file;     /* the positional argument, or NULL */
    unsigned generate;         /* --generate N: vertices of a generated graph, 0 = none */
    unsigned degree;           /* --degree: edges per new vertex when generating */
    unsigned long long seed;   /* --seed */
    unsigned source;
    int directed;              /* --directed: edges are arcs u -> v only */
    const char *output;        /* -o: "vertex level" lines, or NULL */
    bfs_run_options run;
    int compare;
    unsigned repeats;
    int stats;
    int help;
    int version;               /* --version */
} bfs_options;

/* Parse argv into *o (defaults first).  BFS_ERR_USAGE with a message naming
 * the option on a bad command line. */
bfs_status bfs_parse_options(int argc, char **argv, bfs_options *o, char *message, size_t size);

void bfs_print_usage(FILE *out);

#endif
