/* Host-driven steps (steps.h): the loop, the take and step kernels, and
 * checking the targets' room before each step.  A launch runs steps until
 * every queue is empty, a step needs more room than its targets have
 * (NEEDS_ROOM with the room each queue needs), a kernel fails or the
 * deadline passes.
 *
 * A step takes what the policy asks for only if the worst-case emits of all
 * of it fit in the targets' room; otherwise it takes as many as fit, and
 * only when not even STEP_MIN_BATCHES batches per work-group fit (or what a
 * quarter of the memory limit can reserve) do the queues grow, and only for
 * those.  So a breadth-first level is split into
 * launches that fit rather than reserving its whole worst case at once
 * (which failed at the memory limit where the other techniques succeed). */
#include "clock.h"
#include "layout.h"
#include "state.h"
#include "steps.h"
#include "trace.h"
#include "watchdog.h"

#include <stdlib.h>
#include <string.h>

/* Batches per work-group below which a step grows the queues rather than
 * run with fewer items: fewer would mostly pay launch overhead. */
#define STEP_MIN_BATCHES 16

/* The most of `want` items of q whose worst-case emits fit in the targets'
 * room now (taken items free their slots in q's own queue). */
static uint32_t items_that_fit(const perma_runtime *rt, const perma_ctl_block *ctl, unsigned q, uint32_t want)
{
    const perma_proc_info *p = &rt->procs[q];
    uint64_t fit = want;
    for (unsigned e = 0; e < p->emit_count; ++e) {
        unsigned t = (unsigned)p->emit_target[e];
        int64_t room = (int32_t)ctl->queues[t].room;
        uint64_t per_item = p->emit_max[e] - (t == q ? 1u : 0u);
        if (per_item > 0 && (uint64_t)(room > 0 ? room : 0) / per_item < fit)
            fit = (uint64_t)(room > 0 ? room : 0) / per_item;
    }
    return (uint32_t)fit;
}

/* The fewest items of q worth a launch, of `want`: STEP_MIN_BATCHES
 * batches per work-group, but no more than a quarter of the queue memory
 * limit can reserve room for (at least one item). */
static uint32_t least_worth_a_launch(const perma_runtime *rt, unsigned q, uint32_t want)
{
    const perma_proc_info *p = &rt->procs[q];
    uint64_t least = (uint64_t)rt->work_groups * p->max_batch * STEP_MIN_BATCHES, reserved = 0;
    for (unsigned e = 0; e < p->emit_count; ++e)
        reserved += (uint64_t)p->emit_max[e] * (rt->procs[p->emit_target[e]].item_size + PERMA_QUEUE_SLOT_OVERHEAD);
    uint64_t affordable = reserved ? perma_queue_memory_limit(rt) / 4 / reserved : least;
    if (least > affordable)
        least = affordable > 0 ? affordable : 1;
    return want < least ? want : (uint32_t)least;
}

/* How many free slots each queue needs (needed[]) before `take` items of q
 * can run: their worst-case emits, counting that the taken items are still
 * in q's queue. */
static void room_needed(const perma_runtime *rt, unsigned q, uint32_t take, size_t *needed)
{
    const perma_proc_info *p = &rt->procs[q];
    memset(needed, 0, rt->proc_count * sizeof *needed);
    for (unsigned e = 0; e < p->emit_count; ++e) {
        unsigned t = (unsigned)p->emit_target[e];
        needed[t] += (size_t)take * p->emit_max[e] - (t == q ? take : 0);
    }
}

static perma_status set_take_args(perma_runtime *rt, cl_uint qi, cl_uint first, cl_uint take)
{
    const struct {
        cl_uint index;
        size_t size;
        const void *value;
    } args[] = {
        { PERMA_TAKE_ARG_QUEUE, sizeof qi, &qi },
        { PERMA_TAKE_ARG_FIRST, sizeof first, &first },
        { PERMA_TAKE_ARG_COUNT, sizeof take, &take },
    };
    _Static_assert(sizeof args / sizeof args[0] + 4 == PERMA_TAKE_ARG_TOTAL,
                   "every argument of perma_take_kernel (four are the state's)");
    perma_status st = perma_state_bind_take(rt);
    if (st != PERMA_OK)
        return st;
    for (size_t i = 0; i < sizeof args / sizeof args[0]; ++i)
        PERMA_CL_CHECK(rt, "clSetKernelArg (take)",
                       clSetKernelArg(rt->build.take_kernel, args[i].index, args[i].size, args[i].value));
    return PERMA_OK;
}

static perma_status set_step_args(perma_runtime *rt, cl_uint proc, cl_uint count)
{
    perma_status st = perma_state_bind_step(rt);
    if (st != PERMA_OK)
        return st;
    PERMA_CL_CHECK(rt, "clSetKernelArg (step)",
                   clSetKernelArg(rt->build.step_kernel, PERMA_STEP_ARG_PROC, sizeof proc, &proc));
    PERMA_CL_CHECK(rt, "clSetKernelArg (step)",
                   clSetKernelArg(rt->build.step_kernel, PERMA_STEP_ARG_COUNT, sizeof count, &count));
    return PERMA_OK;
}

/* Enqueue the take and step kernels; *done: the step's event. */
static perma_status launch_step(perma_runtime *rt, unsigned q, uint32_t first, uint32_t take, cl_event *done)
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
                   clEnqueueNDRangeKernel(rt->queue, rt->build.take_kernel, 1, NULL, &take_global, NULL, 0, NULL,
                                          NULL));
    st = set_step_args(rt, q, take);
    if (st != PERMA_OK)
        return st;
    /* At most work_groups groups, each running every work_groups-th batch
     * (kernels/perma_host_steps.cl): ctx->group stays below work_groups. */
    size_t local = rt->group_size, batches = ((size_t)take + p->max_batch - 1) / p->max_batch;
    size_t global = (batches < rt->work_groups ? batches : rt->work_groups) * local;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (step)",
                   clEnqueueNDRangeKernel(rt->queue, rt->build.step_kernel, 1, NULL, &global, &local, 0, NULL, done));
    clFlush(rt->queue);
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
                   clEnqueueNDRangeKernel(rt->queue, rt->build.take_kernel, 1, NULL, &take_global, NULL, 0, NULL,
                                          NULL));
    st = set_step_args(rt, 0, 0);
    if (st != PERMA_OK)
        return st;
    size_t local = rt->group_size;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (step warm-up)",
                   clEnqueueNDRangeKernel(rt->queue, rt->build.step_kernel, 1, NULL, &local, &local, 0, NULL, NULL));
    return PERMA_OK;
}

struct perma_steps_state {
    unsigned cursor;         /* the policy's: kernel-per-procedure's round-robin goes on there */
    int traced_proc;         /* the step in flight, for the trace; -1: none */
    cl_event running;        /* the step kernel in flight; NULL: none */
    uint32_t traced_items;
    double traced_start;
};

perma_status perma_steps_prepare(perma_runtime *rt)
{
    if (!rt->steps) {
        rt->steps = calloc(1, sizeof *rt->steps);
        if (!rt->steps)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the host-driven steps");
    }
    rt->steps->cursor = 0;
    rt->steps->traced_proc = -1;
    rt->steps->running = NULL;
    return PERMA_OK;
}

void perma_steps_release(perma_runtime *rt)
{
    free(rt->steps);
    rt->steps = NULL;
}

/* Wait for the step in flight, if any, under the watchdog. */
static perma_status wait_for_step(perma_runtime *rt, double deadline)
{
    perma_steps_state *s = rt->steps;
    if (!s->running)
        return PERMA_OK;
    perma_status st = perma_watch_event(rt, s->running, deadline);
    if (!rt->hung) {
        clReleaseEvent(s->running);
        s->running = NULL;
    }
    return st;
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
    perma_steps_state *s = rt->steps;
    for (;;) {
        perma_status st = wait_for_step(rt, deadline);
        if (st == PERMA_OK)
            st = perma_state_read_control(rt, ctl, rt->proc_count);
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
        if (perma_now() > deadline || perma_state_abort_raised(rt)) {
            outcome->header.status = PERMA_KSTATUS_ABORTED;
            return PERMA_OK;
        }
        int chosen = policy->choose(rt, ctl, &s->cursor);
        if (chosen < 0)
            return PERMA_OK;
        unsigned q = (unsigned)chosen;
        uint32_t want = policy->take(rt, perma_steps_queued(ctl, q));
        uint32_t take = items_that_fit(rt, ctl, q, want), least = least_worth_a_launch(rt, q, want);
        if (take < least) {
            room_needed(rt, q, least, outcome->needed);
            outcome->header.status = PERMA_KSTATUS_NEEDS_ROOM;
            outcome->needed_given = true;
            return PERMA_OK;
        }
        uint32_t first;
        st = take_items(rt, ctl, q, take, policy->from_tail, &first);
        if (st != PERMA_OK)
            return st;
        s->traced_start = perma_now();
        st = launch_step(rt, q, first, take, &s->running);
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
    if (st != PERMA_OK && !rt->hung) {
        clFinish(rt->queue); /* a queue record write may still read *ctl */
        if (rt->steps->running)
            clReleaseEvent(rt->steps->running);
        rt->steps->running = NULL;
    }
    free(ctl);
    return st;
}
