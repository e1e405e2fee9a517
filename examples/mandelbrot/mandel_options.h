/* Command line of the mandelbrot program. */
#ifndef MANDEL_OPTIONS_H
#define MANDEL_OPTIONS_H

#include "mandel.h"

typedef struct mandel_options {
    unsigned width, height;
    double region[4];          /* x_min, x_max, y_min, y_max */
    unsigned max_iter, min_size;
    const char *output;
    mandel_run_options run;
    int compare;               /* --compare: timing table instead of an image */
    unsigned repeats;          /* runs per version in --compare */
    int reference;             /* --reference: host brute force instead of perma */
    int stats;                 /* --stats: print the runtime's statistics */
    int help;
    int version;               /* --version */
} mandel_options;

/* Parse argv into *o (defaults first).  MANDEL_ERR_USAGE with a message
 * naming the option on a bad command line. */
mandel_status mandel_parse_options(int argc, char **argv, mandel_options *o,
                                   char *message, size_t size);

void mandel_print_usage(FILE *out);

#endif
