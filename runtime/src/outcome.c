/* The error a failed launch's status words stand for: which procedure
 * emitted too much, which queue slot a bounded wait gave up on, or the
 * watchdog's stop (the details as kernels/perma_abi.h defines them). */
#include "internal.h"

static perma_status emit_limit_error(perma_runtime *rt, uint32_t proc, uint32_t code)
{
    if (proc >= rt->proc_count)
        return perma_set_error(rt, PERMA_ERR_EMIT_LIMIT, "a procedure emitted more than it declared");
    const perma_proc_info *p = &rt->procs[proc];
    if (code & PERMA_EMIT_ERROR_UNDECLARED) {
        uint32_t t = code & PERMA_EMIT_ERROR_DETAIL;
        return perma_set_error(rt, PERMA_ERR_EMIT_LIMIT,
                               "procedure '%s' emitted into '%s', which is not listed in its .emits",
                               p->name, t < rt->proc_count ? rt->procs[t].name : "?");
    }
    uint32_t e = code & PERMA_EMIT_ERROR_DETAIL;
    if (e >= p->emit_count)
        return perma_set_error(rt, PERMA_ERR_EMIT_LIMIT, "procedure '%s' emitted more than it declared", p->name);
    return perma_set_error(rt, PERMA_ERR_EMIT_LIMIT,
                           "procedure '%s' emitted more than its declared maximum of %u item(s) into '%s' "
                           "for one input item", p->name, p->emit_max[e], p->emit_target_name[e]);
}

/* A bounded wait on a queue slot ran out: name the queue and the side that
 * waited (details as kernels/perma_prelude.cl PERMA_WAIT_WRITING says). */
static perma_status spin_limit_error(perma_runtime *rt, uint32_t detail, uint32_t pos)
{
    uint32_t index = detail & ~(uint32_t)PERMA_WAIT_WRITING;
    if (detail == PERMA_DETAIL_NONE || rt->proc_count == 0 || index >= rt->state.queue_count)
        return perma_set_error(rt, PERMA_ERR_DEVICE,
                               "a bounded wait in the kernel ran out (a queue slot was never published or freed)");
    const char *name = rt->procs[index % rt->proc_count].name;
    unsigned set = index / rt->proc_count;
    if (detail & PERMA_WAIT_WRITING)
        return perma_set_error(rt, PERMA_ERR_DEVICE,
                               "a bounded wait in the kernel ran out: a group waited to write position %u of queue "
                               "'%s' (queue set %u), whose slot was never freed by the group that claimed the item "
                               "before it", pos, name, set);
    return perma_set_error(rt, PERMA_ERR_DEVICE,
                           "a bounded wait in the kernel ran out: a group waited to read position %u of queue '%s' "
                           "(queue set %u), which was never published by the group that reserved it", pos, name, set);
}

perma_status perma_outcome_error(perma_runtime *rt, const perma_ctl_header *outcome)
{
    switch (outcome->status) {
    case PERMA_KSTATUS_EMIT_LIMIT:
        return emit_limit_error(rt, outcome->detail_proc, outcome->detail_edge);
    case PERMA_KSTATUS_SPIN_LIMIT:
        return spin_limit_error(rt, outcome->detail_proc, outcome->detail_edge);
    case PERMA_KSTATUS_ABORTED:
        return perma_watchdog_stop_error(rt);
    }
    return perma_set_error(rt, PERMA_ERR_DEVICE, "the kernel ended with unknown status %u", outcome->status);
}
