/* perma_run: launch, grow and relaunch until the work is done. */
#include "internal.h"

#include <string.h>

#define DEFAULT_TIME_LIMIT 600.0

static perma_status copy_host_buffers(perma_runtime *rt, unsigned flag)
{
    for (unsigned i = 0; i < rt->buffer_count; ++i) {
        perma_buffer_binding *b = &rt->buffers[i];
        if (!b->host || !(b->flags & flag))
            continue;
        cl_int err = flag == PERMA_READ
                         ? clEnqueueWriteBuffer(rt->queue, b->mem, CL_TRUE, 0, b->bytes, b->host, 0, NULL, NULL)
                         : clEnqueueReadBuffer(rt->queue, b->mem, CL_TRUE, 0, b->bytes, b->host, 0, NULL, NULL);
        if (err != CL_SUCCESS)
            return perma_set_error(rt, PERMA_ERR_OPENCL, "%s (buffer '%s') failed: %s (%d)",
                                   flag == PERMA_READ ? "clEnqueueWriteBuffer" : "clEnqueueReadBuffer",
                                   b->name, perma_cl_error_name(err), (int)err);
    }
    return PERMA_OK;
}

static perma_status emit_limit_error(perma_runtime *rt, uint32_t proc, uint32_t code)
{
    if (proc >= rt->proc_count)
        return perma_set_error(rt, PERMA_ERR_EMIT_LIMIT, "a procedure emitted more than it declared");
    const perma_proc_info *p = &rt->procs[proc];
    if (code & PERMA_EMIT_ERROR_UNDECLARED) {
        uint32_t t = code & 0xffffu;
        return perma_set_error(rt, PERMA_ERR_EMIT_LIMIT,
                               "procedure '%s' emitted into '%s', which is not listed in its .emits",
                               p->name, t < rt->proc_count ? rt->procs[t].name : "?");
    }
    uint32_t e = code & 0xffffu;
    if (e >= p->emit_count)
        return perma_set_error(rt, PERMA_ERR_EMIT_LIMIT, "procedure '%s' emitted more than it declared", p->name);
    return perma_set_error(rt, PERMA_ERR_EMIT_LIMIT,
                           "procedure '%s' emitted more than its declared maximum of %u item(s) into '%s' "
                           "for one input item", p->name, p->emit_max[e], p->emit_target_name[e]);
}

/* The error for a failure status of a kernel (not DONE or NEEDS_ROOM). */
perma_status perma_kernel_status_error(perma_runtime *rt, const uint32_t *ks)
{
    switch (ks[0]) {
    case PERMA_KSTATUS_EMIT_LIMIT:
        return emit_limit_error(rt, ks[1], ks[2]);
    case PERMA_KSTATUS_ABORTED:
        return perma_set_error(rt, PERMA_ERR_TIMEOUT, "the run passed its time limit of %g s and was stopped",
                               rt->config.time_limit > 0 ? rt->config.time_limit : DEFAULT_TIME_LIMIT);
    case PERMA_KSTATUS_NEEDS_ROOM:
        return perma_set_error(rt, PERMA_ERR_DEVICE, "a step kernel found a queue without the room the host reserved");
    }
    return perma_set_error(rt, PERMA_ERR_DEVICE, "the kernel ended with unknown status %u", ks[0]);
}

/* Turn the status a launch ended with into the next step or an error. */
static perma_status interpret(perma_runtime *rt, const uint32_t *ks, bool *again)
{
    *again = false;
    switch (ks[0]) {
    case PERMA_KSTATUS_DONE:
        if (ks[3] != 0)
            return perma_set_error(rt, PERMA_ERR_DEVICE, "the kernel stopped with %d items outstanding",
                                   (int)ks[3]);
        return PERMA_OK;
    case PERMA_KSTATUS_NEEDS_ROOM: {
        perma_status st = perma_queues_download(rt);
        bool starved = ks[1] == PERMA_DETAIL_STARVED;
        if (st == PERMA_OK)
            st = perma_queues_grow(rt, starved ? ks[2] : UINT32_MAX);
        if (starved && st == PERMA_ERR_CAPACITY) {
            /* Growing for full batches is an optimisation: past the memory
             * limit the run goes on with the queues it has, and no group
             * stops it for that again. */
            rt->grow_starved = false;
            st = PERMA_OK;
        }
        *again = st == PERMA_OK;
        return st;
    }
    }
    return perma_kernel_status_error(rt, ks);
}

perma_status perma_run(perma_runtime *rt)
{
    if (!rt)
        return PERMA_ERR_ARGUMENT;
    if (rt->hung)
        return perma_set_error(rt, PERMA_ERR_STATE, "a previous run did not stop; this runtime cannot run again");
    perma_status st = perma_build(rt);
    if (st != PERMA_OK) {
        /* A run consumes its seeds whether it succeeds or not. */
        for (unsigned q = 0; q < rt->proc_count; ++q)
            rt->procs[q].seed_count = 0;
        return st;
    }
    perma_stats_reset(rt);
    double start = perma_now();
    rt->trace_count = 0;
    rt->trace_clock_base = 0.0;
    rt->trace_start_time = start;
    double limit = rt->config.time_limit > 0 ? rt->config.time_limit : DEFAULT_TIME_LIMIT;
    double deadline = start + limit;

    rt->grow_starved = true;
    st = perma_queues_prepare(rt);
    if (st == PERMA_OK)
        st = copy_host_buffers(rt, PERMA_READ);
    bool again = st == PERMA_OK;
    if (again && rt->config.technique != PERMA_TECHNIQUE_MEGAKERNEL) {
        again = false;
        st = perma_run_steps(rt, deadline);
    }
    while (again) {
        uint32_t ks[4];
        st = perma_queues_upload(rt);
        if (st == PERMA_OK)
            st = perma_launch_megakernel(rt, deadline, ks);
        if (st != PERMA_OK)
            break;
        rt->stats.launches++;
        st = perma_stats_collect(rt);
        if (st == PERMA_OK)
            st = perma_trace_collect(rt);
        if (st == PERMA_OK)
            st = interpret(rt, ks, &again);
        if (st != PERMA_OK)
            break;
    }
    if (st == PERMA_OK)
        st = copy_host_buffers(rt, PERMA_WRITE);
    rt->stats.seconds = perma_now() - start;
    if (rt->config.trace_path && !rt->hung) {
        /* Written after a failure too: it shows what ran before it. */
        char kept[PERMA_MESSAGE_MAX];
        memcpy(kept, rt->message, sizeof kept);
        perma_status trace_st = perma_trace_write(rt);
        if (st == PERMA_OK)
            st = trace_st;
        else
            memcpy(rt->message, kept, sizeof kept);
    }
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        rt->procs[q].stats.queue_capacity = 0;
        rt->procs[q].stats.regrowths = 0;
    }
    for (unsigned qi = 0; qi < rt->image_count; ++qi) {
        perma_procedure_stats *ps = &rt->procs[qi % rt->proc_count].stats;
        ps->queue_capacity += rt->images[qi].capacity;
        if (rt->images[qi].regrowths > ps->regrowths)
            ps->regrowths = rt->images[qi].regrowths;
    }
    if (st == PERMA_OK)
        rt->message[0] = '\0';
    return st;
}
