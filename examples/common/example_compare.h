/*
 * The --compare harness of the examples (mandelbrot, bfs): time sequential
 * C and a perma program under every schedule on the same input, each the
 * best of N runs after one untimed warm-up (for perma the program build is
 * reported on its own and PoCL's compile at the first launch falls into
 * the warm-up), and print one table whose last column is the example's
 * check of each result against the sequential one.
 */
#ifndef EXAMPLE_COMPARE_H
#define EXAMPLE_COMPARE_H

#include <perma.h>
#include <stdio.h>

#include "example_session.h"

/* What an example plugs into the harness: its perma program, built once
 * per schedule and run again and again (example_session.h). */
typedef struct example_compare {
    const example_program *program;
    void *program_data; /* the program's data */
    /* The last column after a schedule's last run, e.g. "identical". */
    const char *(*check)(void *data);
    void *data;                /* handed to check */
    const char *check_heading; /* "image", "levels" */
    int items_column;          /* print the items each perma run executed */
} example_compare;

/* Seconds on a monotonic clock. */
double example_compare_now(void);

/* The best time of `repeats` calls of run(data) after one untimed call;
 * negative if a call returned nonzero. */
double example_compare_best(unsigned repeats, int (*run)(void *data), void *data);

/* The table: its heading, and one row (build < 0 prints "-"; items only
 * when the example has that column). */
void example_compare_header(const example_compare *ex, FILE *out);
void example_compare_row(const example_compare *ex, FILE *out, const char *version, double seconds,
                         double sequential, double build, unsigned long long items, const char *check);

/* One row per schedule the examples compare: the megakernel with every
 * strategy, kernel-per-procedure and bounded-batches. */
int example_compare_schedules(const example_compare *ex, unsigned work_groups, unsigned repeats,
                              double sequential, FILE *out, char *message, size_t size);

#endif
