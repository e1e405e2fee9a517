/*
 * A built perma program of an example (mandelbrot, bfs), run again and
 * again: the example says how to build it (register its procedures, bind
 * its buffers) and what to seed before each run; the session does the
 * rest (a runtime configured by the run options, a message naming the
 * step that failed).  The --compare harness (example_compare.h) times
 * sessions under every schedule.
 */
#ifndef EXAMPLE_SESSION_H
#define EXAMPLE_SESSION_H

#include <perma.h>
#include <stddef.h>
#include <stdio.h>

/* How an example's perma program runs. */
typedef struct example_run_options {
    perma_schedule schedule; /* zero = megakernel/shared */
    unsigned work_groups;    /* 0 = the runtime's default */
} example_run_options;

/* An example's perma program over its data (handed to both functions). */
typedef struct example_program {
    const char *name; /* the messages' prefix: "perma-bfs" */
    /* Once: register the procedures and bind the buffers.  PERMA_OK, or
     * the failure with *step saying what failed ("binding buffers"). */
    perma_status (*build)(perma_runtime *rt, void *data, const char **step);
    /* Before each run: reset the outputs and seed the queues. */
    perma_status (*seed)(perma_runtime *rt, void *data);
} example_program;

typedef struct example_session example_session;

/* Functions that can fail return 0, or 1 (a runtime failure, the status
 * of the examples' programs) with "NAME: STEP: why" in `message`. */
int example_session_create(const example_program *program, void *data, const example_run_options *options,
                           example_session **out, char *message, size_t size);
int example_session_run(example_session *s, char *message, size_t size);
perma_runtime *example_session_runtime(example_session *s);
void example_session_destroy(example_session *s);

/* Create a session, run it once and destroy it (the build included).
 * With `out`, the programs' report there: "device: ..." before the run
 * and, with `stats`, the runtime's statistics after it. */
int example_session_once(const example_program *program, void *data, const example_run_options *options,
                         FILE *out, int stats, char *message, size_t size);

#endif
