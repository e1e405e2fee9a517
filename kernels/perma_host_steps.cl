/*
 * Kernels of the host-driven techniques (kernel-per-procedure, bounded
 * batches).  The host moves items out of a queue into a plain input array
 * with perma_take_kernel, then runs perma_step_kernel: one ordinary NDRange
 * whose group g executes items [g * batch, (g + 1) * batch) of the input
 * with the same batch code as the megakernel, emitting into the queues.
 * The host makes sure every target has room before it launches.
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
    (void)abort_flag; /* a step runs one batch per group and never waits */
    (void)trace;      /* the host records the steps of host-driven techniques */
    perma_buffers buf;
    PERMA_BIND_BUFFERS(buf);
    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        mem->stats[i] = 0;
    const uint start = get_group_id(0) * perma_max_batch[proc];
    const uint n = start < count ? min(count - start, perma_max_batch[proc]) : 0u;
    if (lid == 0) {
        mem->error_code = 0;
        perma_set_batch(mem->batch, PERMA_CMD_RUN, proc, start, n, proc, proc);
        if (n && !perma_reserve_batch_room(ctl, 0, proc, n))
            perma_fail(ctl, PERMA_KSTATUS_NEEDS_ROOM, proc, 0); /* the host sized the queues wrongly */
    }
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    perma_run_batch(ctl, queue_data, queue_seq, mem, buf, input, 0);
    barrier(CLK_LOCAL_MEM_FENCE);
    /* Many groups per launch: add to group 0's record. */
    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        if (mem->stats[i])
            atomic_add(group_stats + i, mem->stats[i]);
}
