/* The host-driven techniques.  Each step moves items of one queue into a
 * plain input array (perma_take_kernel) and runs them with one ordinary
 * NDRange (perma_step_kernel), which emits into the queues.
 *   kernel-per-procedure: take every queued item of the next non-empty queue,
 *     visiting the queues round-robin: breadth-first, level by level.
 *   bounded batches: take at most batch_limit items from the tail of the
 *     highest-priority non-empty queue (last in, first out), so the queues
 *     hold O(N + p * k) items. */
#include "internal.h"

#include <string.h>

#define DEFAULT_BATCH_LIMIT 4096

static perma_status read_control(perma_runtime *rt, uint32_t *ctl, size_t words)
{
    PERMA_CL_CHECK(rt, "clEnqueueReadBuffer (control block)",
                   clEnqueueReadBuffer(rt->queue, rt->ctl_mem, CL_TRUE, 0, words * 4, ctl, 0, NULL, NULL));
    return PERMA_OK;
}

static uint32_t queued(const uint32_t *ctl, unsigned q)
{
    const uint32_t *rec = ctl + PERMA_CTL_HEADER_WORDS + q * PERMA_QUEUE_WORDS;
    return rec[PERMA_Q_TAIL] - rec[PERMA_Q_HEAD];
}

/* The queue to serve next, or -1 when all are empty. */
static int choose_queue(perma_runtime *rt, const uint32_t *ctl, unsigned *cursor)
{
    unsigned n = rt->proc_count;
    for (unsigned i = 0; i < n; ++i) {
        unsigned q = rt->config.technique == PERMA_TECHNIQUE_BOUNDED_BATCHES ? rt->order[i] : (*cursor + i) % n;
        if (queued(ctl, q) > 0) {
            *cursor = (q + 1) % n;
            return (int)q;
        }
    }
    return -1;
}

/* Grow the targets of q if a step over `take` of its items could overflow them. */
static perma_status ensure_room(perma_runtime *rt, const uint32_t *ctl, unsigned q, uint32_t take, bool *grew)
{
    const perma_proc_info *p = &rt->procs[q];
    size_t needed[PERMA_MAX_PROCEDURES] = { 0 };
    *grew = false;
    for (unsigned e = 0; e < p->emit_count; ++e) {
        unsigned t = (unsigned)p->emit_target[e];
        const uint32_t *rec = ctl + PERMA_CTL_HEADER_WORDS + t * PERMA_QUEUE_WORDS;
        int64_t room = (int32_t)rec[PERMA_Q_ROOM] + (t == q ? (int64_t)take : 0);
        needed[t] += (size_t)take * p->emit_max[e];
        if ((int64_t)needed[t] > room)
            *grew = true;
    }
    if (!*grew)
        return PERMA_OK;
    /* The taken items are still in q's queue: make room for them too. */
    perma_status st = perma_stats_collect(rt); /* the relayout zeroes the statistics buffer */
    return st != PERMA_OK ? st : perma_queues_make_room(rt, needed);
}

static perma_status set_take_args(perma_runtime *rt, cl_uint qi, cl_uint first, cl_uint take)
{
    cl_mem fixed[] = { rt->ctl_mem, rt->data_mem, rt->input_mem };
    for (cl_uint i = 0; i < 3; ++i)
        PERMA_CL_CHECK(rt, "clSetKernelArg (take)", clSetKernelArg(rt->take_kernel, i, sizeof(cl_mem), &fixed[i]));
    cl_uint values[] = { qi, first, take };
    for (cl_uint i = 0; i < 3; ++i)
        PERMA_CL_CHECK(rt, "clSetKernelArg (take)", clSetKernelArg(rt->take_kernel, 3 + i, sizeof values[i], &values[i]));
    return PERMA_OK;
}

static perma_status set_step_args(perma_runtime *rt, cl_uint proc, cl_uint count)
{
    perma_status st = perma_set_common_args(rt, rt->step_kernel, PERMA_STEP_USER_ARG);
    if (st != PERMA_OK)
        return st;
    PERMA_CL_CHECK(rt, "clSetKernelArg (step)", clSetKernelArg(rt->step_kernel, 5, sizeof(cl_mem), &rt->input_mem));
    PERMA_CL_CHECK(rt, "clSetKernelArg (step)", clSetKernelArg(rt->step_kernel, 6, sizeof proc, &proc));
    PERMA_CL_CHECK(rt, "clSetKernelArg (step)", clSetKernelArg(rt->step_kernel, 7, sizeof count, &count));
    return PERMA_OK;
}

static perma_status launch_step(perma_runtime *rt, unsigned q, uint32_t first, uint32_t take)
{
    const perma_proc_info *p = &rt->procs[q];
    size_t words = (size_t)take * (p->item_size / 4);
    perma_status st = perma_ensure_buffer(rt, &rt->input_mem, &rt->input_mem_words, words, "step input");
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
    rt->stats.launches++;
    return PERMA_OK;
}

/* Launch the take and step kernels once with no items (see warm_up in
 * program.c): a step with count 0 runs one empty batch. */
perma_status perma_warm_up_steps(perma_runtime *rt)
{
    perma_status st = perma_ensure_buffer(rt, &rt->input_mem, &rt->input_mem_words, 1, "step input");
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

perma_status perma_run_steps(perma_runtime *rt, double deadline)
{
    unsigned n = rt->proc_count;
    size_t ctl_words = PERMA_CTL_HEADER_WORDS + (size_t)n * PERMA_QUEUE_WORDS;
    uint32_t ctl[PERMA_CTL_HEADER_WORDS + PERMA_MAX_PROCEDURES * PERMA_QUEUE_WORDS];
    uint32_t limit = rt->config.batch_limit ? rt->config.batch_limit : DEFAULT_BATCH_LIMIT;
    bool bounded = rt->config.technique == PERMA_TECHNIQUE_BOUNDED_BATCHES;
    unsigned cursor = 0;
    int traced_proc = -1;          /* the step in flight, for the trace */
    uint32_t traced_items = 0;
    double traced_start = 0.0;
    __atomic_store_n(rt->abort_flag, 0u, __ATOMIC_SEQ_CST);
    perma_status st = perma_queues_upload(rt);
    while (st == PERMA_OK) {
        st = read_control(rt, ctl, ctl_words); /* waits for the previous step */
        if (st == PERMA_OK && traced_proc >= 0 && rt->config.trace_path)
            st = perma_trace_host_step(rt, (unsigned)traced_proc, traced_items, traced_start, perma_now());
        traced_proc = -1;
        if (st != PERMA_OK)
            break;
        if (ctl[PERMA_CTL_STATUS] != PERMA_KSTATUS_DONE) {
            uint32_t ks[4] = { ctl[PERMA_CTL_STATUS], ctl[PERMA_CTL_DETAIL_PROC], ctl[PERMA_CTL_DETAIL_EDGE], 0 };
            st = perma_kernel_status_error(rt, ks);
            break;
        }
        if (perma_now() > deadline) {
            st = perma_set_error(rt, PERMA_ERR_TIMEOUT, "the run passed its time limit of %g s and was stopped",
                                 rt->config.time_limit > 0 ? rt->config.time_limit : 600.0);
            break;
        }
        int chosen = choose_queue(rt, ctl, &cursor);
        if (chosen < 0)
            break;
        unsigned q = (unsigned)chosen;
        uint32_t available = queued(ctl, q);
        uint32_t take = bounded && available > limit ? limit : available;
        bool grew;
        st = ensure_room(rt, ctl, q, take, &grew);
        if (st != PERMA_OK || grew)
            continue; /* re-read the relaid-out queues */

        /* Move HEAD and RELEASED (breadth-first) or TAIL and PUBLISHED
         * (LIFO) past the taken items. */
        uint32_t *rec = ctl + PERMA_CTL_HEADER_WORDS + q * PERMA_QUEUE_WORDS;
        uint32_t first;
        if (bounded) {
            first = rec[PERMA_Q_TAIL] - take;
            rec[PERMA_Q_TAIL] = first;
        } else {
            first = rec[PERMA_Q_HEAD];
            rec[PERMA_Q_HEAD] += take;
        }
        rec[PERMA_Q_ROOM] += take;
        rec[PERMA_Q_PUBLISHED] = rec[PERMA_Q_TAIL];
        rec[PERMA_Q_RELEASED] = rec[PERMA_Q_HEAD];
        size_t offset = (PERMA_CTL_HEADER_WORDS + (size_t)q * PERMA_QUEUE_WORDS) * 4;
        cl_int err = clEnqueueWriteBuffer(rt->queue, rt->ctl_mem, CL_FALSE, offset, PERMA_QUEUE_WORDS * 4, rec, 0,
                                          NULL, NULL);
        if (err != CL_SUCCESS) {
            st = perma_set_error(rt, PERMA_ERR_OPENCL, "clEnqueueWriteBuffer (queue record) failed: %s (%d)",
                                 perma_cl_error_name(err), (int)err);
            break;
        }
        traced_start = perma_now();
        st = launch_step(rt, q, first, take);
        traced_proc = (int)q;
        traced_items = take;
    }
    if (st == PERMA_OK)
        st = perma_stats_collect(rt);
    return st;
}
