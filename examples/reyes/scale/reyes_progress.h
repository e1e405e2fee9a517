/*
 * reyes-render's progress line on stderr:
 *
 *     reyes-render: 12/64 buckets, 21.4%, 3.2 s elapsed, about 11.8 s left
 *
 * the items (buckets, or frames) done of all, the share of the job done,
 * the time since the render started and an estimate of the time left (from
 * the rate so far, once there is one).  The share counts the items done
 * plus, for each renderer of this process, an estimate of its current
 * item from its perma runs (perma_config.progress): once no subdivision
 * is queued, the items of the procedures that make pixels (dice,
 * rasterize, stitch) completed of those completed or queued, never going
 * back within an item.  On a
 * terminal the line is redrawn in place at most every 0.1 s; elsewhere
 * (--progress into a file or a pipe, mpirun's forwarded output) a line is
 * written at the start, at most every 2 s, and at the end.  Any thread may
 * report; the line is drawn under a lock.
 */
#ifndef REYES_PROGRESS_H
#define REYES_PROGRESS_H

#include <pthread.h>
#include <stdio.h>

#include "perma.h"

/* Seconds between the runtime's progress callbacks (perma_config). */
#define REYES_PROGRESS_INTERVAL 0.1

/* Renderers whose current item's share is estimated (devices of a farm;
 * under MPI rank 0's own). */
#define REYES_PROGRESS_RENDERERS 64

typedef struct reyes_progress {
    pthread_mutex_t lock;
    FILE *out;
    int terminal;               /* redraw one line in place */
    const char *program, *unit; /* "reyes-render", "buckets" or "frames" */
    unsigned total, done;
    double share[REYES_PROGRESS_RENDERERS]; /* of each renderer's current item, 0..1 */
    double start, drawn_at;
    int drawn;                  /* a line (without its newline, on a terminal) is shown */
} reyes_progress;

/* One renderer's place, the user of reyes_progress_runtime. */
typedef struct reyes_progress_slot {
    reyes_progress *progress;
    unsigned renderer;
} reyes_progress_slot;

/* Whether to show the line: not with --quiet, always with --progress, else
 * when stderr is a terminal (*terminal: whether it is). */
int reyes_progress_wanted(int forced, int quiet, int *terminal);

/* Start the line for `total` items of `unit` and draw it; `program`'s
 * last path component begins the line. */
void reyes_progress_start(reyes_progress *p, FILE *out, int terminal, const char *program, const char *unit,
                          unsigned total);
/* An item of renderer `renderer` is done (any renderer index: remote
 * ranks' too). */
void reyes_progress_item_done(reyes_progress *p, int renderer);
/* perma_config.progress (reyes_options.progress) with a reyes_progress_slot
 * as the user: the share of the renderer's current item. */
void reyes_progress_runtime(void *slot, const perma_progress *progress);
/* The last line (with its newline) after a success; after a failure the
 * line is ended where it stands, so the error starts a line of its own. */
void reyes_progress_finish(reyes_progress *p, int succeeded);
void reyes_progress_free(reyes_progress *p);

/* The line itself, for the tests: "12/64 buckets, 21.4%, 3.2 s elapsed,
 * about 11.8 s left" (no estimate while nothing is done, and none at the
 * end). */
void reyes_progress_format(char *out, size_t size, unsigned done, unsigned total, const char *unit, double share,
                           double elapsed, int finished);

#endif
