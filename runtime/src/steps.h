/* The machinery the host-driven techniques share (steps.c): each step
 * moves items of one queue into a plain input array (perma_take_kernel)
 * and runs them with one ordinary NDRange (perma_step_kernel), which emits
 * into the queues.  A technique only says which queue comes next and how
 * many of its items to take (exec_kernel_per_procedure.c,
 * exec_bounded_batches.c). */
#ifndef PERMA_STEPS_H
#define PERMA_STEPS_H

#include "executor.h"
#include "state.h"

typedef struct perma_step_policy {
    /* The queue to serve next, or -1 when every queue is empty; *cursor is
     * the policy's to keep between the steps of a run (0 at its start). */
    int (*choose)(const perma_runtime *rt, const perma_ctl_block *ctl, unsigned *cursor);
    /* How many of the `available` queued items to take. */
    uint32_t (*take)(const perma_runtime *rt, uint32_t available);
    /* Take from the tail (last in, first out) instead of the head. */
    bool from_tail;
} perma_step_policy;

/* A host-driven technique: the executor (whose launch is
 * perma_steps_launch) and its policy. */
typedef struct perma_step_executor {
    perma_executor executor;
    perma_step_policy policy;
} perma_step_executor;

extern const perma_step_executor perma_kernel_per_procedure_executor;
extern const perma_step_executor perma_bounded_batches_executor;

/* Items queued in queue q of a control block. */
static inline uint32_t perma_steps_queued(const perma_ctl_block *ctl, unsigned q)
{
    return ctl->queues[q].tail - ctl->queues[q].head;
}

/* What the host-driven techniques keep between launches of a run (the
 * policy's cursor, the step in flight); opaque outside steps.c, made by
 * the first perma_steps_prepare, freed by perma_steps_release
 * (perma_destroy). */
typedef struct perma_steps_state perma_steps_state;

perma_status perma_steps_warm_up(perma_runtime *rt);
perma_status perma_steps_prepare(perma_runtime *rt);
void perma_steps_release(perma_runtime *rt);
/* The launch of a perma_step_executor (rt->executor). */
perma_status perma_steps_launch(perma_runtime *rt, double deadline, perma_launch_outcome *outcome);

#endif
