#ifndef PERMA_WATCHDOG_H
#define PERMA_WATCHDOG_H

#include "perma.h"

/* watchdog.c: waiting for a kernel under the time limit and the stall
 * limit.  Past the deadline, or when no item completed anywhere for the
 * stall limit, the abort flag is raised (every group polls it) and the
 * reason kept for perma_watchdog_stop_error; PERMA_ERR_TIMEOUT only if the
 * kernel does not stop within the grace period (rt->hung: the runtime is
 * then unusable).  Its state (the waiter thread, the stop's reason) is
 * opaque outside watchdog.c. */
typedef struct perma_watchdog perma_watchdog;
perma_status perma_watchdog_open(perma_runtime *rt);
/* Frees the watchdog and stops its waiter thread: joined, or detached if
 * rt->hung (it is blocked on the kernel that never ended). */
void perma_watchdog_close(perma_runtime *rt);
/* Launch `kernel` and wait for it. */
perma_status perma_launch_watched(perma_runtime *rt, cl_kernel kernel, size_t global, size_t local, double deadline);
/* Wait for the command of event `done` (enqueued and flushed), lending
 * the runtime's waiter thread to it (started at the first call). */
perma_status perma_watch_event(perma_runtime *rt, cl_event done, double deadline);
/* The error of a launch the watchdog stopped (status ABORTED): the time
 * limit, or the stall with the procedures that had items in flight. */
perma_status perma_watchdog_stop_error(perma_runtime *rt);

#endif
