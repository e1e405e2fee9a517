/*
 * Work-first execution (perma_schedule.work_first_items, "+wfN"): each
 * work-item keeps a stack of PERMA_WORK_FIRST items in the group's __local
 * memory.  While an item of a stackable procedure runs (one thread per
 * item, no scratch, emitting only into stackable procedures: layout.c) and
 * its stack has room for everything it may emit, its emits go onto the
 * stack instead of the staging (perma_wf_push), and the work-item runs them
 * right after it, last in first out, in place in their slots, in a loop
 * without barriers (perma_run_simple, generated: runtime/src/codegen.c).
 * So an item costs about a function call, and a depth-first search needs
 * a stack as deep as its tree, not a queue as wide as it.
 *
 * A slot stays taken while its item runs and its children lie above it;
 * the item's procedure word gets PERMA_WF_DONE and the slot is freed when
 * the children are done.  The stacks live as long as the launch: a batch
 * runs at most PERMA_WF_BUDGET items from a work-item's stack and leaves
 * the rest for the next one (perma_take_stacks), so batches stay short for
 * the watchdog, progress, priorities and the other procedures.  What
 * leaves a stack goes through the global queues, moved by work-item 0
 * between batches (perma_wf_spill):
 *   - a stack whose top item lacks room for its emits: its bottom half;
 *   - when another group is idle (PERMA_CTL_HUNGRY): the bottom half of
 *     every stack, the oldest items, whose subtrees are the largest;
 *   - when the launch stops for room: every stack, into the group's
 *     overflow area (perma_wf_flush), which the host appends to the queues
 *     as it does a batch's overflowed emits.
 * Items on the stacks count in OUTSTANDING (perma_wf_count_batch), so no
 * group leaves while any wait.
 */

#if PERMA_WORK_FIRST
inline __local uint *perma_wf_procs(__local perma_group_mem *mem, uint l)
{
    return mem->wf_procs + l * PERMA_WORK_FIRST;
}

inline __local perma_item_word *perma_wf_slot(__local perma_group_mem *mem, uint l, uint i)
{
    return (__local perma_item_word *)mem->wf_slots + (l * PERMA_WORK_FIRST + i) * PERMA_WF_SLOT_WORDS;
}

/* Whether work-item l's top item cannot run: it is not done and the stack
 * lacks the room a stack item runs with (PERMA_WF_NEED). */
inline int perma_wf_stuck(__local perma_group_mem *mem, uint l)
{
    uint sp = mem->wf_sp[l];
    if (sp == 0)
        return 0;
    uint top = perma_wf_procs(mem, l)[sp - 1u];
    return !(top & PERMA_WF_DONE) && PERMA_WORK_FIRST - sp < PERMA_WF_NEED;
}

/* Work-item 0: move the items in slots [0, count) of work-item l's stack
 * to the global queues of set `set` (finished items there are dropped),
 * and the rest of the stack down; returns the items moved, 0 (nothing
 * moved) if a queue lacks the room.  The queues' ranges are published
 * (perma_queue_complete) before this returns. */
inline uint perma_wf_spill(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                           __local perma_group_mem *mem, uint l, uint count, uint set)
{
    __local uint *procs = perma_wf_procs(mem, l);
    uint per[PERMA_NUM_PROCS], base[PERMA_NUM_PROCS], moved = 0;
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q)
        per[q] = 0;
    for (uint i = 0; i < count; ++i)
        if (!(procs[i] & PERMA_WF_DONE))
            per[procs[i]] += 1u;
    /* Look before taking: a queue without room ends the spill before any
     * room is taken, so a spill that keeps failing (the group waits for
     * bigger queues) gives none back and counts no progress.  Counted, it
     * would keep every group from agreeing that only bigger queues help
     * (perma_all_blocked), and they would spin until the watchdog. */
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q)
        if (per[q] && perma_load_int(PERMA_QUEUE(ctl, PERMA_QINDEX(set, q)) + PERMA_Q_ROOM) < (int)per[q])
            return 0;
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q) {
        if (per[q] && !perma_queue_reserve_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(set, q)), (int)per[q])) {
            /* Another group took the room since the look: that is progress. */
            for (uint r = 0; r < q; ++r)
                perma_queue_return_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(set, r)), (int)per[r]);
            return 0;
        }
    }
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q) {
        base[q] = per[q] ? perma_queue_reserve(PERMA_QUEUE(ctl, PERMA_QINDEX(set, q)), per[q]) : 0u;
        moved += per[q];
        per[q] = 0; /* from here: how many of q are written */
    }
    for (uint i = 0; i < count; ++i) {
        uint q = procs[i];
        if (q & PERMA_WF_DONE)
            continue;
        __global uint *queue = PERMA_QUEUE(ctl, PERMA_QINDEX(set, q));
        uint words = perma_item_words[q], pos = base[q] + per[q]++;
        __global uint *dst = perma_queue_slot(queue, queue_data, pos, words);
        __local const perma_item_word *src = perma_wf_slot(mem, l, i);
        for (uint w = 0; w < words; ++w)
            dst[w] = src[w];
        if (pos != base[q]) /* the first position's mark is the range's */
            perma_queue_clear_mark(perma_queue_marks(queue, queue_seq, 0u), queue[PERMA_Q_CAP], pos);
    }
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q)
        if (per[q])
            perma_queue_complete(PERMA_QUEUE(ctl, PERMA_QINDEX(set, q)), queue_seq, 0u, base[q], per[q]);
    /* The rest of the stack down, in order (slots and procedure words). */
    uint sp = mem->wf_sp[l];
    for (uint i = count; i < sp; ++i) {
        __local perma_item_word *to = perma_wf_slot(mem, l, i - count);
        __local const perma_item_word *from = perma_wf_slot(mem, l, i);
        for (uint w = 0; w < PERMA_WF_SLOT_WORDS; ++w)
            to[w] = from[w];
        procs[i - count] = procs[i];
    }
    mem->wf_sp[l] = sp - count;
    mem->wf_total -= moved;
    mem->stats[PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS + PERMA_GSTAT_WF_SPILLS] += moved;
    if (moved) {
        mem_fence(CLK_GLOBAL_MEM_FENCE);
        atomic_inc(ctl + PERMA_CTL_PROGRESS); /* published work: groups that looked must look again */
    }
    return moved;
}

/* Work-item 0 between batches, when the stacks hold items: spill the bottom
 * half of every stuck stack, and of every stack when another group is idle
 * (into `give`, the set that group takes from).  Returns whether some
 * stack can run an item now. */
inline int perma_wf_relieve(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                            __local perma_group_mem *mem, uint own, uint give)
{
    int hungry = mem->wf_total > 1u && perma_load_int(ctl + PERMA_CTL_HUNGRY) > 0;
    int runnable = 0;
    uint given = 0;
    for (uint l = 0; l < PERMA_GROUP_SIZE; ++l) {
        uint sp = mem->wf_sp[l];
        if (perma_wf_stuck(mem, l))
            perma_wf_spill(ctl, queue_data, queue_seq, mem, l, (sp + 1u) / 2u, own);
        else if (hungry && sp > 1u)
            given += perma_wf_spill(ctl, queue_data, queue_seq, mem, l, sp / 2u, give);
        runnable = runnable || (mem->wf_sp[l] && !perma_wf_stuck(mem, l));
    }
    /* Items put into another group's set are a donation. */
    if (given && give != own) {
        __local uint *group_stat = mem->stats + PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS;
        group_stat[PERMA_GSTAT_DONATIONS] += 1u;
        group_stat[PERMA_GSTAT_DONATED] += given;
        mem->wf_given += given;
    }
    return runnable;
}

/* Work-item 0, when the launch stops for room: every item on the stacks to
 * the group's overflow area, a record per procedure after the records of
 * the last batch's overflowed emits (the host appends them to the queues
 * of set `own`, kernels/perma_abi.h, Emit areas). */
inline void perma_wf_flush(__global uint *emit_areas, __local perma_group_mem *mem, uint own)
{
    __global uint *area = perma_emit_area(emit_areas);
    uint n = area[PERMA_OVERFLOW_RECORDS];
    uint at = perma_overflow_end(area);
    __global uint *data = area + PERMA_EMIT_AREA_OVERFLOW;
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q) {
        uint words = perma_item_words[q], count = 0;
        for (uint l = 0; l < PERMA_GROUP_SIZE; ++l) {
            __local const uint *procs = perma_wf_procs(mem, l);
            for (uint i = 0; i < mem->wf_sp[l]; ++i) {
                if (procs[i] != q)
                    continue;
                __local const perma_item_word *src = perma_wf_slot(mem, l, i);
                for (uint w = 0; w < words; ++w)
                    data[at + count * words + w] = src[w];
                ++count;
            }
        }
        if (!count)
            continue;
        area[PERMA_OVERFLOW_RECORD(n) + PERMA_OVERFLOW_QUEUE] = PERMA_QINDEX(own, q);
        area[PERMA_OVERFLOW_RECORD(n) + PERMA_OVERFLOW_COUNT] = count;
        area[PERMA_OVERFLOW_RECORD(n) + PERMA_OVERFLOW_AT] = at;
        at += count * words;
        ++n;
    }
    area[PERMA_OVERFLOW_RECORDS] = n;
    for (uint l = 0; l < PERMA_GROUP_SIZE; ++l)
        mem->wf_sp[l] = 0;
    mem->wf_total = 0;
}
#endif
