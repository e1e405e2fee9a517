/* Kernel-per-procedure: take every queued item of the next non-empty
 * queue, visiting the queues round-robin: breadth-first, level by level,
 * like Patney and Owens' bound/split loop. */
#include "state.h"
#include "steps.h"

static int next_round_robin(const perma_runtime *rt, const perma_ctl_block *ctl, unsigned *cursor)
{
    unsigned n = rt->proc_count;
    for (unsigned i = 0; i < n; ++i) {
        unsigned q = (*cursor + i) % n;
        if (perma_steps_queued(ctl, q) > 0) {
            *cursor = (q + 1) % n;
            return (int)q;
        }
    }
    return -1;
}

static uint32_t take_all(const perma_runtime *rt, uint32_t available)
{
    (void)rt;
    return available;
}

const perma_step_executor perma_kernel_per_procedure_executor = {
    .executor = {
        .technique = PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE,
        .persistent = false,
        .warm_up = perma_steps_warm_up,
        .prepare = perma_steps_prepare,
        .launch = perma_steps_launch,
    },
    .policy = { next_round_robin, take_all, false },
};
