/* Host-driven steps (steps.h): the loop, the take and step kernels, and
 * checking the targets' room before each step.  A launch runs steps until
 * every queue is empty, a step needs more room than its targets have
 * (NEEDS_ROOM with the room each queue needs), a kernel fails or the
 * deadline passes. */
#include "steps.h"

#include <stdlib.h>
#include <string.h>

/* Whether the targets of q have room for the worst-case emits of `take` of
 * its items; if not, needed[] says how many free slots each queue needs.
 * The taken items are still in q's queue: q needs room for them too. */
static bool targets_have_room(const perma_runtime *rt, const perma_ctl_block *ctl, unsigned q, uint32_t take,
                              size_t *needed)
{
    const perma_proc_info *p = &rt->procs[q];
    bool room_for_all = true;
    memset(needed, 0, rt->proc_count * sizeof *needed);
    for (unsigned e = 0; e < p->emit_count; ++e) {
        unsigned t = (unsigned)p->emit_target[e];
        int64_t room = (int32_t)ctl->queues[t].room + (t == q ? (int64_t)take : 0);
        needed[t] += (size_t)take * p->emit_max[e];
        if ((int64_t)needed[t] > room)
            room_for_all = false;
    }
    return room_for_all;
}

static perma_status set_take_args(perma_runtime *rt, cl_uint qi, cl_uint first, cl_uint take)
{
    const struct {
        cl_uint index;
        size_t size;
        const void *value;
    } args[] = {
        { PERMA_TAKE_ARG_CTL, sizeof(cl_mem), &rt->state.ctl.mem },
        { PERMA_TAKE_ARG_QUEUE_DATA, sizeof(cl_mem), &rt->state.data.mem },
        { PERMA_TAKE_ARG_QUEUE_SEQ, sizeof(cl_mem), &rt->state.seq.mem },
        { PERMA_TAKE_ARG_INPUT, sizeof(cl_mem), &rt->state.input.mem },
        { PERMA_TAKE_ARG_QUEUE, sizeof qi, &qi },
        { PERMA_TAKE_ARG_FIRST, sizeof first, &first },
        { PERMA_TAKE_ARG_COUNT, sizeof take, &take },
    };
    _Static_assert(sizeof args / sizeof args[0] == PERMA_TAKE_ARG_TOTAL, "every argument of perma_take_kernel");
    for (size_t i = 0; i < sizeof args / sizeof args[0]; ++i)
        PERMA_CL_CHECK(rt, "clSetKernelArg (take)",
                       clSetKernelArg(rt->take_kernel, args[i].index, args[i].size, args[i].value));
    return PERMA_OK;
}

static perma_status set_step_args(perma_runtime *rt, cl_uint proc, cl_uint count)
{
    perma_status st = perma_state_bind(rt, rt->step_kernel, PERMA_STEP_USER_ARGS);
    if (st != PERMA_OK)
        return st;
    PERMA_CL_CHECK(rt, "clSetKernelArg (step)",
                   clSetKernelArg(rt->step_kernel, PERMA_STEP_ARG_INPUT, sizeof(cl_mem), &rt->state.input.mem));
    PERMA_CL_CHECK(rt, "clSetKernelArg (step)", clSetKernelArg(rt->step_kernel, PERMA_STEP_ARG_PROC, sizeof proc, &proc));
    PERMA_CL_CHECK(rt, "clSetKernelArg (step)",
                   clSetKernelArg(rt->step_kernel, PERMA_STEP_ARG_COUNT, sizeof count, &count));
    return PERMA_OK;
}

static perma_status launch_step(perma_runtime *rt, unsigned q, uint32_t first, uint32_t take)
{
    const perma_proc_info *p = &rt->procs[q];
    size_t words = (size_t)take * (p->item_size / 4);
    perma_status st = perma_state_ensure_input(rt, words);
    if (st == PERMA_OK)
        st = set_take_args(rt, q, first, take);
    if (st != PERMA_OK)
        return st;
    size_t take_global = ((size_t)take + 63) / 64 * 64;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (take)",
                   clEnqueueNDRangeKernel(rt->queue, rt->take_kernel, 1, NULL, &take_global, NULL, 0, NULL, NULL));
    st = set_step_args(rt, q, take);
    if (st != PERMA_OK)
        return st;
    size_t local = rt->group_size;
    size_t global = ((size_t)take + p->max_batch - 1) / p->max_batch * local;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (step)",
                   clEnqueueNDRangeKernel(rt->queue, rt->step_kernel, 1, NULL, &global, &local, 0, NULL, NULL));
    return PERMA_OK;
}

/* Launch the take and step kernels once with no items: a step with count
 * 0 runs one empty batch. */
perma_status perma_steps_warm_up(perma_runtime *rt)
{
    perma_status st = perma_state_ensure_input(rt, 1);
    if (st == PERMA_OK)
        st = set_take_args(rt, 0, 0, 0);
    if (st != PERMA_OK)
        return st;
    size_t take_global = 64;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (take warm-up)",
                   clEnqueueNDRangeKernel(rt->queue, rt->take_kernel, 1, NULL, &take_global, NULL, 0, NULL, NULL));
    st = set_step_args(rt, 0, 0);
    if (st != PERMA_OK)
        return st;
    size_t local = rt->group_size;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (step warm-up)",
                   clEnqueueNDRangeKernel(rt->queue, rt->step_kernel, 1, NULL, &local, &local, 0, NULL, NULL));
    return PERMA_OK;
}

perma_status perma_steps_prepare(perma_runtime *rt)
{
    rt->steps.cursor = 0;
    rt->steps.traced_proc = -1;
    return PERMA_OK;
}

/* Move HEAD (from the head) or TAIL (from the tail) past the `take` items
 * of queue q and write the record's counters; the first taken
 * position in *first.  Not blocking: the next read of the control block
 * waits for it, and *ctl lives until then. */
static perma_status take_items(perma_runtime *rt, perma_ctl_block *ctl, unsigned q, uint32_t take, bool from_tail,
                               uint32_t *first)
{
    perma_queue_record *rec = &ctl->queues[q];
    if (from_tail) {
        *first = rec->tail - take;
        rec->tail = *first;
    } else {
        *first = rec->head;
        rec->head += take;
    }
    rec->room += take;
    /* The host-driven steps run no batch between launches: every range is
     * published and released. */
    rec->published = rec->tail;
    rec->released = rec->head;
    return perma_state_write_queue_counters(rt, q, rec);
}

static perma_status run_steps(perma_runtime *rt, const perma_step_policy *policy, double deadline,
                              perma_ctl_block *ctl, perma_launch_outcome *outcome)
{
    perma_steps_state *s = &rt->steps;
    for (;;) {
        perma_status st = perma_state_read_control(rt, ctl, rt->proc_count); /* waits for the previous step */
        if (st == PERMA_OK && s->traced_proc >= 0)
            st = perma_trace_host_step(rt, (unsigned)s->traced_proc, s->traced_items, s->traced_start, perma_now());
        s->traced_proc = -1;
        if (st != PERMA_OK)
            return st;
        outcome->header = ctl->header;
        if (ctl->header.status == PERMA_KSTATUS_NEEDS_ROOM)
            return perma_set_error(rt, PERMA_ERR_DEVICE,
                                   "a step kernel found a queue without the room the host reserved");
        if (ctl->header.status != PERMA_KSTATUS_DONE)
            return PERMA_OK;
        if (perma_now() > deadline) {
            outcome->header.status = PERMA_KSTATUS_ABORTED;
            return PERMA_OK;
        }
        int chosen = policy->choose(rt, ctl);
        if (chosen < 0)
            return PERMA_OK;
        unsigned q = (unsigned)chosen;
        uint32_t take = policy->take(rt, perma_steps_queued(ctl, q));
        if (!targets_have_room(rt, ctl, q, take, outcome->needed)) {
            outcome->header.status = PERMA_KSTATUS_NEEDS_ROOM;
            outcome->needed_given = true;
            return PERMA_OK;
        }
        uint32_t first;
        st = take_items(rt, ctl, q, take, policy->from_tail, &first);
        if (st != PERMA_OK)
            return st;
        s->traced_start = perma_now();
        st = launch_step(rt, q, first, take);
        if (st != PERMA_OK)
            return st;
        outcome->launches++;
        s->traced_proc = (int)q;
        s->traced_items = take;
    }
}

perma_status perma_steps_launch(perma_runtime *rt, double deadline, perma_launch_outcome *outcome)
{
    const perma_step_policy *policy = &((const perma_step_executor *)rt->executor)->policy;
    perma_ctl_block *ctl = malloc(perma_ctl_block_bytes(rt->proc_count));
    if (!ctl)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the control block");
    perma_status st = run_steps(rt, policy, deadline, ctl, outcome);
    if (st != PERMA_OK)
        clFinish(rt->queue); /* a queue record write may still read *ctl */
    free(ctl);
    return st;
}
