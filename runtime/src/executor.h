/* The executor interface: how one technique runs the generated program.
 * perma_run drives every technique with the same loop (run.c):
 *
 *     prepare -> launch -> DONE: collect, finish
 *                       -> NEEDS_ROOM: grow the queues, launch again
 *                       -> anything else: the error of that status
 *
 * A technique is one table of these functions in its own file, in the
 * spirit of hiredis' per-variant function tables and Whippletree's
 * technique classes; its name, description and what its label takes are
 * its row of the schedule table (schedules.def, schedule_table.h). */
#ifndef PERMA_EXECUTOR_H
#define PERMA_EXECUTOR_H

#include "internal.h"

/* How a launch ended. */
typedef struct perma_launch_outcome {
    /* The control block header as the launch left it: STATUS
     * (PERMA_KSTATUS_*), its details and the items outstanding. */
    perma_ctl_header header;
    /* Kernels launched (the statistics count them). */
    unsigned launches;
    /* NEEDS_ROOM from a host-driven step (set 0 only, so one queue per
     * procedure): the free slots each queue must have before the next
     * step can run.  Not given when the kernel stalled on its own: then
     * every target that lacks room for a waiting item's emits grows. */
    bool needed_given;
    size_t needed[PERMA_MAX_PROCEDURES];
} perma_launch_outcome;

typedef struct perma_executor {
    perma_technique technique;
    /* Work-groups that live for the whole launch and schedule themselves:
     * only then can queues belong to groups (the distributed strategies),
     * a group keep a local front queue, or the device record a trace. */
    bool persistent;
    /* Launch every kernel the technique uses once on an empty state, so the
     * driver's compile at the first launch happens in perma_build. */
    perma_status (*warm_up)(perma_runtime *rt);
    /* Get ready for a run whose queues were just uploaded. */
    perma_status (*prepare)(perma_runtime *rt);
    /* Run until the work is done, the queues need room or something fails,
     * at the latest until `deadline` (perma_now() seconds); fill *outcome.
     * An error status means the launch itself failed (an OpenCL call, the
     * watchdog); a kernel's failure is an outcome. */
    perma_status (*launch)(perma_runtime *rt, double deadline, perma_launch_outcome *outcome);
} perma_executor;

extern const perma_executor perma_megakernel_executor;

/* The executor of a technique; NULL for an unknown one. */
const perma_executor *perma_executor_for(perma_technique technique);

#endif
