/* The error a failed launch's status words stand for: which procedure
 * emitted too much, or the watchdog's stop (the details as kernels/perma_abi.h defines them). */
#include "internal.h"
#include "outcome.h"
#include "watchdog.h"

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

perma_status perma_outcome_error(perma_runtime *rt, const perma_ctl_header *outcome)
{
    switch (outcome->status) {
    case PERMA_KSTATUS_EMIT_LIMIT:
        return emit_limit_error(rt, outcome->detail_proc, outcome->detail_edge);
    case PERMA_KSTATUS_ABORTED:
        return perma_watchdog_stop_error(rt);
    }
    return perma_set_error(rt, PERMA_ERR_DEVICE, "the kernel ended with unknown status %u", outcome->status);
}
