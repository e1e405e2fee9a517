/*
 * Global work queues: one bounded ring per procedure.
 *
 * Positions are 32-bit counters that wrap; a slot is position & (cap - 1),
 * which stays consistent across the wrap because cap is a power of two.
 * Four counters describe a queue (docs/design.md, *Queues*):
 *
 *   RELEASED <= HEAD <= PUBLISHED <= TAIL <= RELEASED + cap
 *
 * A writer reserves a range of positions with one atomic_add on TAIL and
 * copies its items in; a reader claims a range below PUBLISHED with one
 * cmpxchg on HEAD and copies it out.  PUBLISHED (RELEASED) moves over the
 * written (read) ranges in position order: a group that completes a range
 * marks it done in a per-slot word and moves the counter past every done
 * range at the counter, so a range completed out of order is carried along
 * by the group that completes the range before it (perma_queue_complete).
 * Nobody ever waits for another group, and a batch costs a few atomics
 * whatever its size: no per-item atomics, no per-slot handshakes.
 *
 * ROOM counts the slots that no batch has been promised.  A batch may start
 * only after it subtracted its expected emits from ROOM of every target
 * (perma_batch_room), takes ROOM for any emit beyond them before it
 * reserves positions (or sends them to its overflow area, never into the
 * queue), and released slots go back to ROOM only when RELEASED passes
 * them, so TAIL - RELEASED never exceeds cap: a writer's slots are always
 * free.
 */

/* Items that are published and not yet claimed. */
inline int perma_queue_available(__global uint *queue)
{
    return (int)(perma_load(queue + PERMA_Q_PUBLISHED) - perma_load(queue + PERMA_Q_HEAD));
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

/* Give back `count` slots of ROOM.  The caller counts the progress. */
inline void perma_queue_give_room(__global uint *queue, int count)
{
    if (count > 0)
        atomic_add((volatile __global int *)(queue + PERMA_Q_ROOM), count);
}

inline void perma_queue_return_room(__global uint *ctl, __global uint *queue, int count)
{
    if (count <= 0)
        return;
    perma_queue_give_room(queue, count);
    atomic_inc(ctl + PERMA_CTL_PROGRESS);
}

/* Claim up to `wanted` published positions; returns how many, first in
 * *start.  The claimed items may be read after a read fence (the caller's
 * barrier carries it to the group). */
inline uint perma_queue_claim(__global uint *queue, uint wanted, uint *start)
{
    for (;;) {
        uint head = perma_load(queue + PERMA_Q_HEAD);
        int available = (int)(perma_load(queue + PERMA_Q_PUBLISHED) - head);
        if (available <= 0)
            return 0;
        uint count = min((uint)available, wanted);
        if (atomic_cmpxchg(queue + PERMA_Q_HEAD, head, head + count) == head) {
            *start = head;
            return count;
        }
    }
}

/* Reserve `count` positions for writing; returns the first. */
inline uint perma_queue_reserve(__global uint *queue, uint count)
{
    uint base = atomic_add(queue + PERMA_Q_TAIL, count);
    /* Record the occupancy (consumers may already have claimed past the end). */
    int occupancy = (int)(base + count - perma_load(queue + PERMA_Q_HEAD));
    if (occupancy > 0 && (uint)occupancy > perma_load(queue + PERMA_Q_PEAK))
        atomic_max(queue + PERMA_Q_PEAK, (uint)occupancy);
    return base;
}

/* Where position `pos` of a queue of `words`-word items keeps its item. */
inline __global uint *perma_queue_slot(__global uint *queue, __global uint *data, uint pos, uint words)
{
    return data + queue[PERMA_Q_DATA] + (pos & (queue[PERMA_Q_CAP] - 1u)) * words;
}

/* The completion marks of a queue in queue_seq: one word per slot for
 * publishing (releasing = 0), then one per slot for releasing. */
inline __global uint *perma_queue_marks(__global uint *queue, __global uint *marks, uint releasing)
{
    return marks + queue[PERMA_Q_SEQ] + queue[PERMA_Q_CAP] * releasing;
}

/* Called for every position a group writes (or reads) other than the first
 * of its range: its mark is set to the position itself, which never reads
 * as a completed range, so a mark is never older than one lap and the
 * 32-bit positions cannot wrap onto a stale one. */
inline void perma_queue_clear_mark(__global uint *marks, uint cap, uint pos)
{
    marks[pos & (cap - 1u)] = pos;
}

/* A range [first, first + count) was written (releasing = 0) or read
 * (releasing = 1) completely: mark it done, then move PUBLISHED (RELEASED)
 * past every done range that starts where it stands, whoever owns them.
 * Nobody waits: a range done before the ones ahead of it is carried along
 * by whichever group completes the last of those.  Work-item 0 only,
 * after a barrier that follows the group's copies.  Moving RELEASED gives
 * the released slots back to ROOM; the caller counts the progress.
 *
 * Announce (xchg of the mark) then read the counter, against move (cmpxchg
 * of the counter) then read the mark: with a full fence between each pair
 * at least one side sees the other, so no done range is left behind. */
inline void perma_queue_complete(__global uint *queue, __global uint *queue_seq, uint releasing, uint first,
                                 uint count)
{
    if (count == 0)
        return;
    const uint cap = queue[PERMA_Q_CAP];
    __global uint *marks = perma_queue_marks(queue, queue_seq, releasing);
    __global uint *counter = queue + (releasing ? PERMA_Q_RELEASED : PERMA_Q_PUBLISHED);
    mem_fence(CLK_GLOBAL_MEM_FENCE); /* the items (or the copies out of them) before the mark */
    atomic_xchg(marks + (first & (cap - 1u)), first + count);
    mem_fence(CLK_GLOBAL_MEM_FENCE);
    for (;;) {
        uint at = perma_load(counter);
        uint end = perma_load(marks + (at & (cap - 1u)));
        if (end - at - 1u >= cap) /* not a done range starting at `at` */
            return;
        if (atomic_cmpxchg(counter, at, end) == at && releasing)
            perma_queue_give_room(queue, (int)(end - at));
        mem_fence(CLK_GLOBAL_MEM_FENCE);
    }
}
