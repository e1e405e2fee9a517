#ifndef PERMA_LAYOUT_H
#define PERMA_LAYOUT_H

#include "perma.h"
#include "queues.h"

#include <stddef.h>

/* layout.c: the procedure graph, the batch sizes and the __local layout
 * of a build. */
perma_status perma_build_layout(perma_runtime *rt);
/* The __local memory one group may use: the device's, or
 * config.local_memory_limit when lower. */
size_t perma_local_memory(const perma_runtime *rt);

/* The build's queue layout for the planner (queues.h): queue
 * sets (one per persistent group with a distributed strategy, else 1),
 * the queues' starting capacity and the cap on their bytes
 * (config.queue_memory_limit, or half the device's largest allocation: a
 * regrowth holds the old and the new queue buffers at once). */
unsigned perma_queue_sets(const perma_runtime *rt);
size_t perma_queue_memory_limit(const perma_runtime *rt);
void perma_queue_layout_fill(const perma_runtime *rt, unsigned sets, perma_queue_layout *out);

#endif
