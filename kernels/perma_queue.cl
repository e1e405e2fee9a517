/*
 * Global work queues: one bounded ring per procedure.
 *
 * Positions are 32-bit counters that wrap; a slot is position & (cap - 1),
 * which stays consistent across the wrap because cap is a power of two.
 * Each slot has a sequence word (after Vyukov's bounded MPMC queue):
 *   seq == pos          the slot is free for the writer of position pos
 *   seq == pos + 1      position pos is written and may be read
 *   seq == pos + cap    read; free for the writer of position pos + cap
 * Writers and readers reserve ranges of positions with one atomic per group
 * (TAIL for writers, HEAD for readers) and then wait only on the sequence
 * word of their own slots, i.e. only on a group that already holds the
 * neighbouring position and is inside a wait-free copy: never on a group
 * that may not have started.
 *
 * ROOM counts the slots that no batch has been promised.  A batch may start
 * only after it subtracted its worst-case emits from ROOM of every target,
 * so a started batch can always write everything it emits.
 */

/* Items that are queued (reserved for writing but not yet claimed). */
inline int perma_queue_available(__global uint *queue)
{
    return (int)(perma_load(queue + PERMA_Q_TAIL) - perma_load(queue + PERMA_Q_HEAD));
}

/* Take `count` slots of ROOM if that many are free; returns 1 on success.
 * A failed attempt dents ROOM for a moment; giving it back counts as
 * progress, because another group may have been refused during the dent
 * and must not take its refusal for a stall. */
inline int perma_queue_reserve_room(__global uint *ctl, __global uint *queue, int count)
{
    if (count <= 0)
        return 1;
    if (perma_load_int(queue + PERMA_Q_ROOM) < count)
        return 0; /* do not dent ROOM for others when it cannot succeed */
    int before = atomic_sub((volatile __global int *)(queue + PERMA_Q_ROOM), count);
    if (before >= count)
        return 1;
    atomic_add((volatile __global int *)(queue + PERMA_Q_ROOM), count);
    atomic_inc(ctl + PERMA_CTL_PROGRESS);
    return 0;
}

inline void perma_queue_return_room(__global uint *ctl, __global uint *queue, int count)
{
    if (count <= 0)
        return;
    atomic_add((volatile __global int *)(queue + PERMA_Q_ROOM), count);
    atomic_inc(ctl + PERMA_CTL_PROGRESS);
}

/* Claim up to `wanted` queued positions; returns how many, first in *start. */
inline uint perma_queue_claim(__global uint *queue, uint wanted, uint *start)
{
    for (;;) {
        uint head = perma_load(queue + PERMA_Q_HEAD);
        int available = (int)(perma_load(queue + PERMA_Q_TAIL) - head);
        if (available <= 0)
            return 0;
        uint count = min((uint)available, wanted);
        if (atomic_cmpxchg(queue + PERMA_Q_HEAD, head, head + count) == head) {
            *start = head;
            return count;
        }
    }
}

/* Whether the launch has failed for good (not merely stopped for bigger
 * queues, after which the batches still running must finish). */
inline int perma_launch_failed(__global uint *ctl)
{
    uint status = perma_load(ctl + PERMA_CTL_STATUS);
    return status != PERMA_KSTATUS_DONE && status != PERMA_KSTATUS_NEEDS_ROOM;
}

/* Wait until the sequence word of a slot reaches `expected`.  Returns 0 if the
 * wait ran out, the host asked to abort or the launch failed meanwhile (so
 * after one wait runs out the group's other waits do not each spin to the
 * limit too). */
inline int perma_wait_seq(__global uint *ctl, __global uint *seq, uint expected,
                          volatile __global uint *abort_flag)
{
    for (ulong spins = 0; spins < PERMA_SPIN_LIMIT; ++spins) {
        if (perma_load(seq) == expected)
            return 1;
        if ((spins & 1023u) == 1023u && (*abort_flag || perma_launch_failed(ctl)))
            return 0;
    }
    return 0;
}

/* A wait on a slot of `queue` gave up: report the abort, or which queue,
 * which position and which side waited (the first failure wins, so a wait
 * that gave up because the launch had already failed changes nothing). */
inline void perma_queue_wait_failed(__global uint *ctl, __global uint *queue, uint pos, uint writing,
                                    volatile __global uint *abort_flag)
{
    if (*abort_flag) {
        perma_fail(ctl, PERMA_KSTATUS_ABORTED, PERMA_DETAIL_NONE, 0);
        return;
    }
    uint index = (uint)(queue - (ctl + PERMA_CTL_HEADER_WORDS)) / PERMA_QUEUE_WORDS;
    perma_fail(ctl, PERMA_KSTATUS_SPIN_LIMIT, index | (writing ? PERMA_WAIT_WRITING : 0u), pos);
}

/* Copy the item at position `pos` into `dst` and free its slot. */
inline int perma_queue_read_item(__global uint *ctl, __global uint *queue, __global uint *data,
                                 __global uint *seqs, uint pos, uint words, __local uint *dst,
                                 volatile __global uint *abort_flag)
{
    uint cap = queue[PERMA_Q_CAP];
    uint slot = pos & (cap - 1u);
    __global uint *seq = seqs + queue[PERMA_Q_SEQ] + slot;
    if (!perma_wait_seq(ctl, seq, pos + 1u, abort_flag)) {
        perma_queue_wait_failed(ctl, queue, pos, 0u, abort_flag);
        return 0;
    }
    read_mem_fence(CLK_GLOBAL_MEM_FENCE); /* payload after the published flag */
    __global uint *src = data + queue[PERMA_Q_DATA] + slot * words;
    for (uint w = 0; w < words; ++w)
        dst[w] = src[w];
    mem_fence(CLK_GLOBAL_MEM_FENCE | CLK_LOCAL_MEM_FENCE); /* reads done before the slot is freed */
    atomic_xchg(seq, pos + cap);
    return 1;
}

/* Write the item at position `pos` from `src` and publish it. */
inline int perma_queue_write_item(__global uint *ctl, __global uint *queue, __global uint *data,
                                  __global uint *seqs, uint pos, uint words, __local const uint *src,
                                  volatile __global uint *abort_flag)
{
    uint cap = queue[PERMA_Q_CAP];
    uint slot = pos & (cap - 1u);
    __global uint *seq = seqs + queue[PERMA_Q_SEQ] + slot;
    if (!perma_wait_seq(ctl, seq, pos, abort_flag)) {
        perma_queue_wait_failed(ctl, queue, pos, 1u, abort_flag);
        return 0;
    }
    __global uint *dst = data + queue[PERMA_Q_DATA] + slot * words;
    for (uint w = 0; w < words; ++w)
        dst[w] = src[w];
    write_mem_fence(CLK_GLOBAL_MEM_FENCE); /* payload before the published flag */
    atomic_xchg(seq, pos + 1u);
    return 1;
}

/* Record the queue's occupancy after `end` positions were reserved. */
inline void perma_queue_note_peak(__global uint *queue, uint end)
{
    int occupancy = (int)(end - perma_load(queue + PERMA_Q_HEAD));
    if (occupancy > 0) /* consumers may already have claimed past `end` */
        atomic_max(queue + PERMA_Q_PEAK, (uint)occupancy);
}
