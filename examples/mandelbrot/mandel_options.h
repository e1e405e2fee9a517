/* Command line of the mandelbrot program. */
#ifndef MANDEL_OPTIONS_H
#define MANDEL_OPTIONS_H

#include "example_options.h"
#include "mandel.h"

typedef struct mandel_options {
    unsigned size[2];          /* width, height */
    double region[4];          /* x_min, x_max, y_min, y_max */
    unsigned max_iter, min_size;
    const char *output;
    int reference;             /* --reference: host brute force instead of perma */
    example_options common;    /* --technique, --strategy, --groups, --stats, --compare, --repeats */
} mandel_options;

/* Parse argv into *o (defaults first).  PERMA_CLI_OK: run; otherwise the
 * program ends with perma_cli_exit_status(status): the help or version
 * was printed, or the bad usage said (also in `message`). */
perma_cli_status mandel_parse_options(int argc, char **argv, mandel_options *o, char *message, size_t size);

#endif
