#ifndef PERMA_STATS_H
#define PERMA_STATS_H

#include "perma.h"
#include "state.h"

/* stats.c: the run's statistics. */
void perma_stats_reset(perma_runtime *rt);
perma_status perma_stats_collect(perma_runtime *rt);  /* after each launch */
/* At the end of a run, from the queues' records (state.h). */
void perma_stats_finish(perma_runtime *rt, const perma_queue_state *queues, unsigned count);
/* Free the per-group records (perma_destroy). */
void perma_stats_release(perma_runtime *rt);

#endif
