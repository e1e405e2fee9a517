/* The megakernel: one launch of the persistent kernel (its groups schedule
 * themselves, kernels/perma_scheduler.cl) under the watchdog, until the
 * work is done or no group can start anything. */
#include "clock.h"
#include "executor.h"
#include "state.h"
#include "trace.h"
#include "watchdog.h"

static size_t global_size(const perma_runtime *rt)
{
    return (size_t)rt->work_groups * rt->group_size;
}

/* On an empty state (nothing outstanding) every group leaves at once. */
static perma_status warm_up(perma_runtime *rt)
{
    perma_status st = perma_state_bind(rt, rt->build.kernel, PERMA_MEGAKERNEL_USER_ARGS);
    if (st != PERMA_OK)
        return st;
    size_t local = rt->group_size, global = global_size(rt);
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (warm-up)",
                   clEnqueueNDRangeKernel(rt->queue, rt->build.kernel, 1, NULL, &global, &local, 0, NULL, NULL));
    return PERMA_OK;
}

static perma_status prepare(perma_runtime *rt)
{
    (void)rt;
    return PERMA_OK;
}

static perma_status launch(perma_runtime *rt, double deadline, perma_launch_outcome *outcome)
{
    perma_status st = perma_state_bind(rt, rt->build.kernel, PERMA_MEGAKERNEL_USER_ARGS);
    if (st != PERMA_OK)
        return st;
    perma_trace_launch_begins(rt, perma_now());
    st = perma_launch_watched(rt, rt->build.kernel, global_size(rt), rt->group_size, deadline);
    perma_trace_launch_ends(rt, perma_now());
    if (st != PERMA_OK)
        return st;
    outcome->launches = 1;
    return perma_state_read_header(rt, &outcome->header);
}

const perma_executor perma_megakernel_executor = {
    .technique = PERMA_TECHNIQUE_MEGAKERNEL,
    .persistent = true,
    .warm_up = warm_up,
    .prepare = prepare,
    .launch = launch,
};
