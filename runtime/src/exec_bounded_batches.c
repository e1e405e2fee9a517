/* Bounded batches: take at most batch_limit items from the tail of the
 * highest-priority non-empty queue (last in, first out), so the queues
 * hold O(N + p * k) items instead of a whole tree level. */
#include "state.h"
#include "steps.h"

#define DEFAULT_BATCH_LIMIT 4096

static int highest_priority(const perma_runtime *rt, const perma_ctl_block *ctl, unsigned *cursor)
{
    (void)cursor;
    for (unsigned i = 0; i < rt->proc_count; ++i)
        if (perma_steps_queued(ctl, rt->build.order[i]) > 0)
            return (int)rt->build.order[i];
    return -1;
}

static uint32_t take_at_most_the_limit(const perma_runtime *rt, uint32_t available)
{
    uint32_t limit = rt->config.schedule.batch_limit ? rt->config.schedule.batch_limit : DEFAULT_BATCH_LIMIT;
    return available > limit ? limit : available;
}

const perma_step_executor perma_bounded_batches_executor = {
    .executor = {
        .technique = PERMA_TECHNIQUE_BOUNDED_BATCHES,
        .persistent = false,
        .warm_up = perma_steps_warm_up,
        .prepare = perma_steps_prepare,
        .launch = perma_steps_launch,
    },
    .policy = { highest_priority, take_at_most_the_limit, true },
};
