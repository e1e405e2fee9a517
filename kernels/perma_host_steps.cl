/*
 * Kernels of the host-driven techniques (kernel-per-procedure, bounded
 * batches).  The host moves items out of a queue into a plain input array
 * with perma_take_kernel, then runs perma_step_kernel: one ordinary NDRange
 * of at most work_groups groups, whose group g executes the batches g,
 * g + groups, ... of the input (batch b: items [b * batch, (b + 1) * batch))
 * with the same batch code as the megakernel, emitting into the queues.  So
 * ctx->group is below work_groups and no two groups with the same ctx->group
 * run at once, as in the megakernel.  The host makes sure every target has
 * room before it launches.
 */

/* Copy `count` items of queue `qi` from position `first` into input[] and
 * clear the completion marks of their slots (positions taken from the tail
 * are written again).  The host moves the queue's counters itself (HEAD and
 * RELEASED past items taken from the head, TAIL and PUBLISHED back before
 * items taken from the tail). */
__kernel void perma_take_kernel(PERMA_TAKE_ARGS(PERMA_ARG_PARAM))
{
    uint i = get_global_id(0);
    if (i >= count)
        return;
    __global uint *queue = PERMA_QUEUE(ctl, qi);
    uint words = perma_item_words[qi % PERMA_NUM_PROCS];
    __global uint *src = perma_queue_slot(queue, queue_data, first + i, words);
    for (uint w = 0; w < words; ++w)
        input[i * words + w] = src[w];
    perma_queue_clear_mark(perma_queue_marks(queue, queue_seq, 0u), queue[PERMA_Q_CAP], first + i);
    perma_queue_clear_mark(perma_queue_marks(queue, queue_seq, 1u), queue[PERMA_Q_CAP], first + i);
}

__kernel __attribute__((reqd_work_group_size(PERMA_GROUP_SIZE, 1, 1)))
void perma_step_kernel(PERMA_COMMON_ARGS(PERMA_ARG_PARAM), PERMA_STEP_ARGS(PERMA_ARG_PARAM)
                       PERMA_BUFFER_PARAMS)
{
    PERMA_GROUP_LOCALS(mem);
    const uint lid = get_local_id(0);
    (void)trace;      /* the host records the steps of host-driven techniques */
    perma_buffers buf;
    PERMA_BIND_BUFFERS(buf);
    PERMA_LANE_BEGIN(lane);
    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        mem->stats[i] = 0;
    if (lid == 0) {
        mem->error_code = 0;
        perma_emit_area(emit_areas)[PERMA_OVERFLOW_RECORDS] = 0;
    }
    /* Group g runs the batches g, g + groups, ... (batch b: input items
     * [b * batch, (b + 1) * batch)).  Shaped like the megakernel's loop:
     * work-item 0 decides, a barrier, everyone reads the decision, and the
     * last iteration runs the batch code with 0 items (PoCL 3.1 lost the
     * global writes of a counted loop around the batch's barriers). */
    const uint batch = perma_max_batch[proc];
    const uint batches = (count + batch - 1u) / batch;
    uint b = get_group_id(0), more = 1u;
    while (more) {
        if (lid == 0) {
            const uint n = b < batches ? min(count - b * batch, batch) : 0u;
            perma_set_batch(mem->batch, PERMA_CMD_RUN, proc, b * batch, n, proc, proc);
            if (n && !perma_reserve_batch_room(ctl, mem, 0, proc, n, 0u))
                perma_fail(ctl, PERMA_KSTATUS_NEEDS_ROOM, proc, 0); /* the host sized the queues wrongly */
        }
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        more = b < batches;
        perma_run_batch(ctl, queue_data, queue_seq, emit_areas, abort_flag, mem, lane, buf, input, 0);
        b += get_num_groups(0);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Many groups per launch: add to group 0's record. */
    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        if (mem->stats[i])
            atomic_add(group_stats + i, mem->stats[i]);
    PERMA_LANE_END(lane, reductions);
}
