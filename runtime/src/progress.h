#ifndef PERMA_PROGRESS_H
#define PERMA_PROGRESS_H

#include "perma.h"

/* progress.c: the progress of a run (perma_get_progress, config.progress),
 * told by the run loop and sampled by the watchdog from the watch page.
 * Its state is opaque outside progress.c. */
typedef struct perma_progress_state perma_progress_state;
perma_status perma_progress_open(perma_runtime *rt);
void perma_progress_close(perma_runtime *rt);
void perma_progress_run_begins(perma_runtime *rt, double start); /* the seeds are uploaded */
void perma_progress_launch_begins(perma_runtime *rt);            /* the watch page is cleared */
void perma_progress_kernel_started(perma_runtime *rt);           /* a watched kernel is enqueued */
void perma_progress_sample(perma_runtime *rt, double now);       /* while it runs */
void perma_progress_launch_ends(perma_runtime *rt);              /* the statistics are collected */
double perma_progress_stop_clock(perma_runtime *rt);             /* the run's seconds, as readers see them */
void perma_progress_run_ends(perma_runtime *rt);                 /* the final statistics are in */

#endif
