/* Summing the runtime's statistics over the runs of a bucketed render. */
#ifndef REYES_RENDER_STATS_H
#define REYES_RENDER_STATS_H

#include "reyes.h"

/* Add one run's statistics (perma_get_stats, perma_get_procedure_stats per
 * procedure) to *total: counts and times summed, peaks and capacities the
 * largest.  Also sets total->peak_queue_bytes and total->seconds. */
void reyes_stats_add_run(reyes_stats *total, const perma_stats *run,
                         const perma_procedure_stats procedures[REYES_PROC_COUNT]);

#endif
