/*
 * The persistent megakernel: every work-group loops
 *   schedule (work-item 0) -> copy the batch in -> run the procedure
 *   -> reserve target positions (work-item 0) -> copy emits out
 * until the outstanding-item count is zero or a status stops the run.
 *
 * Queue sets: with the shared strategy there is one set of queues (one per
 * procedure); with the distributed strategies each group owns a set, emits
 * into its own set, steals batches from other sets when its own is empty
 * (PERMA_STEALING) and moves items to the emptiest set when its own queue
 * passes a threshold (PERMA_DONATION).  Which of these a strategy does is
 * its row of the schedule table (runtime/src/schedules.def), which codegen
 * turns into the PERMA_STEALING / PERMA_DONATION constants.
 *
 * perma_pick_batch tries the ways to find a batch in order, each a small
 * function that is a no-op when the schedule does not use it:
 *   perma_take_local   the group's local front queue (+localN)
 *   perma_donate       give items away (donation)
 *   perma_take_own     the group's own queue set (every strategy)
 *   perma_steal        another group's set (stealing)
 *   perma_adopt        the set of a group that is not running (donation
 *                      without stealing)
 * and each that finds one starts it with perma_begin_batch.
 *
 * Uses the generated tables (perma_order, perma_max_batch, ...), the
 * generated perma_dispatch(), PERMA_BUFFER_PARAMS and PERMA_BIND_BUFFERS.
 * Every barrier is reached by all work-items on every iteration.
 */

/* Scheduler polls in work-item 0 before the group goes round its loop once. */
#define PERMA_IDLE_POLLS 64u
/* Schedules in a row that room, not work, cut to under half a
 * batch (or to nothing) before a group asks the host for bigger queues. */
#define PERMA_STARVE_LIMIT 64u

/* How many of `want` items of q the group can start: as many as the room
 * of its targets admits for their expected emits (perma_batch_room), with
 * that room reserved (0: none).  Sets *starved to q if the room cut the
 * batch to under half of `want`, else to -1. */
inline uint perma_fit_batch(__global uint *ctl, __local perma_group_mem *mem, uint own, uint q, uint want,
                            int *starved)
{
    uint fit = perma_admissible(ctl, mem, own, q, want, 1u);
    *starved = 2u * fit < want ? (int)q : -1;
    if (fit == 0 || !perma_reserve_batch_room(ctl, mem, own, q, fit, 1u))
        return 0;
    return fit;
}

/* Take a batch of procedure q from queue set `from` for a group whose emits
 * go to set `own`.  Returns the item count (0: none), first position in
 * *start; when the queue had items, sets *starved to q if the room of the
 * targets cut the batch to under half of what there was to take, else
 * to -1. */
inline uint perma_try_take(__global uint *ctl, __local perma_group_mem *mem, uint own, uint from, uint q,
                           int full_only, uint *start, int *starved)
{
    __global uint *queue = PERMA_QUEUE(ctl, PERMA_QINDEX(from, q));
    int available = perma_queue_available(queue);
    if (available <= 0)
        return 0;
    uint want = min((uint)available, perma_max_batch[q]);
    if (full_only && want < perma_max_batch[q])
        return 0;
    want = perma_fit_batch(ctl, mem, own, q, want, starved);
    if (want == 0)
        return 0;
    uint got = perma_queue_claim(queue, want, start);
    if (got < want)
        perma_shrink_batch_room(ctl, mem, own, q, got, 1u);
    return got;
}

/* Whether group g is inside its loop (started, not left). */
inline int perma_group_running(__global uint *ctl, uint g)
{
    return perma_load(PERMA_GROUP(ctl, g) + PERMA_G_STATE) == 1u;
}

/* Donation: if the own queue of a procedure holds more than the threshold,
 * claim up to a batch of it for the running group's set that has the
 * fewest. */
inline uint perma_try_donate(__global uint *ctl, uint own, uint *proc, uint *dest, uint *start)
{
    for (uint i = 0; i < PERMA_NUM_PROCS; ++i) {
        uint q = perma_order[i];
        __global uint *queue = PERMA_QUEUE(ctl, PERMA_QINDEX(own, q));
        int mine = perma_queue_available(queue);
        uint threshold = PERMA_DONATION_THRESHOLD ? PERMA_DONATION_THRESHOLD : 4u * perma_max_batch[q];
        if (mine <= (int)threshold)
            continue;
        uint poorest = own;
        int fewest = mine;
        for (uint s = 0; s < PERMA_QUEUE_SETS; ++s) {
            if (s == own || !perma_group_running(ctl, s))
                continue; /* nobody serves it now (perma_adopt) */
            int theirs = perma_queue_available(PERMA_QUEUE(ctl, PERMA_QINDEX(s, q)));
            if (theirs < fewest) {
                fewest = theirs;
                poorest = s;
            }
        }
        if (poorest == own || fewest + (int)perma_max_batch[q] >= mine)
            continue;
        uint share = min(perma_max_batch[q], (uint)(mine - fewest) / 2u);
        __global uint *target = PERMA_QUEUE(ctl, PERMA_QINDEX(poorest, q));
        if (share == 0 || !perma_queue_reserve_room(ctl, target, (int)share))
            continue;
        uint got = perma_queue_claim(queue, share, start);
        if (got < share)
            perma_queue_return_room(ctl, target, (int)(share - got));
        if (got == 0)
            continue;
        *proc = q;
        *dest = PERMA_QINDEX(poorest, q);
        return got;
    }
    return 0;
}

/* True when every running group found nothing to start since `epoch` and
 * no batch finished since: nobody can make progress until the host grows
 * queues.  Groups that are not running count for nothing: every strategy
 * lets the running groups take their items (stealing, or perma_adopt). */
inline int perma_all_blocked(__global uint *ctl, uint epoch, uint groups)
{
    for (uint g = 0; g < groups; ++g) {
        if (perma_group_running(ctl, g) && perma_load(PERMA_GROUP(ctl, g) + PERMA_G_BLOCKED) != epoch + 1u)
            return 0;
    }
    return perma_load(ctl + PERMA_CTL_PROGRESS) == epoch;
}

/* Mark the group stalled since an epoch (epoch + 1) or running (0); the
 * word is written only when it changes, not once per batch. */
inline void perma_set_blocked(__global uint *group_words, uint value)
{
    if (perma_load(group_words + PERMA_G_BLOCKED) != value)
        atomic_xchg(group_words + PERMA_G_BLOCKED, value);
}

#if PERMA_STEALING
/* Where a stealing group starts looking: a random other group, or the one
 * after the last start (round-robin).  The scan then visits every other
 * group from there, so a group only calls itself stalled after looking at
 * all of them (random picks with repetition could miss the one set that has
 * work, and a false stall makes the host grow queues for nothing). */
inline uint perma_first_victim(uint own, uint *state)
{
#if PERMA_VICTIM_ROUND_ROBIN
    *state = (*state + 1u) % PERMA_QUEUE_SETS;
    if (*state == own)
        *state = (*state + 1u) % PERMA_QUEUE_SETS;
    return *state;
#else
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    uint v = *state % (PERMA_QUEUE_SETS - 1u);
    return v >= own ? v + 1u : v;
#endif
}
#endif

/* Describe the group's next batch (IDLE and EXIT with count 0: their
 * iteration runs the batch code with no items). */
inline void perma_set_batch(__local uint *batch, uint command, uint proc, uint start, uint count,
                            uint source, uint dest)
{
    batch[PERMA_B_KIND] = command == PERMA_CMD_DONATE ? PERMA_TRACE_DONATE
                        : command == PERMA_CMD_RUN_LOCAL ? PERMA_TRACE_LOCAL : PERMA_TRACE_RUN;
    batch[PERMA_B_PROC] = proc;
    batch[PERMA_B_START] = start;
    batch[PERMA_B_COUNT] = count;
    batch[PERMA_B_COMMAND] = command == PERMA_CMD_RUN_LOCAL ? PERMA_CMD_RUN : command;
    batch[PERMA_B_FROM_LOCAL] = command == PERMA_CMD_RUN_LOCAL;
    batch[PERMA_B_SOURCE] = source;
    batch[PERMA_B_DEST] = dest;
}

/* Count a schedule that room cut short for procedure `starved` (-1: the
 * batch of procedure `taken` was not cut, which resets the count if the
 * count is that procedure's; batches of other procedures in between, such
 * as the consumers of its emits, do not).  *count holds the procedure + 1
 * in its high half and the count in its low half.  After
 * PERMA_STARVE_LIMIT, if the host allows it and a target of that procedure
 * in set `own` is smaller than its occupancy plus a full batch of expected
 * emits for every group, stop the launch so the host doubles that queue
 * (named in DETAIL_EDGE): batches of a few items cost nearly as much as
 * full ones, and a group that sees work but can start none is idle.
 * Returns 1 when it stopped the launch. */
inline int perma_note_starved(__global uint *ctl, __local const perma_group_mem *mem, uint groups, uint own,
                              int starved, uint taken, uint *count)
{
    if (starved < 0) {
        if (*count >> 16 == taken + 1u)
            *count = 0;
        return 0;
    }
    *count = *count >> 16 == (uint)starved + 1u ? *count + 1u : ((uint)starved + 1u) << 16 | 1u;
    if ((*count & 0xffffu) < PERMA_STARVE_LIMIT || !perma_load(ctl + PERMA_CTL_GROW_STARVED))
        return 0;
    *count = 0;
    uint q = (uint)starved;
    for (uint e = 0; e < perma_edge_count[q]; ++e) {
        uint ti = PERMA_QINDEX(own, perma_edge_target[q * PERMA_MAX_EDGES + e]);
        __global uint *target = PERMA_QUEUE(ctl, ti);
        uint occupancy = perma_load(target + PERMA_Q_TAIL) - perma_load(target + PERMA_Q_RELEASED);
        ulong needed = (ulong)occupancy + (ulong)groups * perma_batch_room(mem, q, e, perma_max_batch[q], 1u);
        if ((ulong)target[PERMA_Q_CAP] < needed) {
            perma_fail(ctl, PERMA_KSTATUS_NEEDS_ROOM, PERMA_DETAIL_STARVED, ti);
            return 1;
        }
    }
    return 0;
}

/* What work-item 0 of a group needs to pick its next batch. */
typedef struct perma_picker {
    __global uint *ctl;
    __global uint *queue_data; /* the local front queue's flush, the stacks' spills */
    __global uint *queue_seq;
    __global uint *group_words;
    __local perma_group_mem *mem;
    __local uint *group_stat;
    uint groups;
    uint own;           /* the group's queue set */
    uint *victim_state; /* stealing only: perma_first_victim's state */
    uint *starve_count; /* perma_note_starved's count */
    uint *hungry;       /* 1 while the group counts itself in PERMA_CTL_HUNGRY */
    int starved;        /* the procedure room last cut short (perma_fit_batch), -1: none */
} perma_picker;

/* How a batch was found: what it counts in the group's statistics and the
 * trace, and whether it counts toward the starve limit. */
#define PERMA_FOUND_OWN 0u      /* the own queue set */
#define PERMA_FOUND_LOCAL 1u    /* the local front queue */
#define PERMA_FOUND_STOLEN 2u   /* another group's set */
#define PERMA_FOUND_ADOPTED 3u  /* the set of a group that is not running */
#define PERMA_FOUND_DONATED 4u  /* own items to give to set `dest` */
#define PERMA_FOUND_STACKS 5u   /* no new items: the work-items run their stacks */

/* Start the batch of `count` items of q at `start` in queue `source`
 * (`dest`: the queue a donation goes to): count it toward the starve limit
 * unless adopted or donated, count steals and donations, mark the group
 * running and describe the batch. */
inline void perma_begin_batch(perma_picker *p, uint found, uint q, uint start, uint count, uint source, uint dest)
{
    __local uint *batch = p->mem->batch;
    if (found != PERMA_FOUND_ADOPTED && found != PERMA_FOUND_DONATED && found != PERMA_FOUND_STACKS)
        perma_note_starved(p->ctl, p->mem, p->groups, p->own, p->starved, q, p->starve_count);
    if (found == PERMA_FOUND_STOLEN || found == PERMA_FOUND_ADOPTED)
        p->group_stat[PERMA_GSTAT_STEALS] += 1u;
    if (found == PERMA_FOUND_DONATED) {
        p->group_stat[PERMA_GSTAT_DONATIONS] += 1u;
        p->group_stat[PERMA_GSTAT_DONATED] += count;
    }
    perma_set_blocked(p->group_words, 0u);
    uint command = found == PERMA_FOUND_DONATED ? PERMA_CMD_DONATE
                 : found == PERMA_FOUND_LOCAL ? PERMA_CMD_RUN_LOCAL : PERMA_CMD_RUN;
    perma_set_batch(batch, command, q, start, count, source, dest);
    if (found == PERMA_FOUND_STOLEN || found == PERMA_FOUND_ADOPTED)
        batch[PERMA_B_KIND] = PERMA_TRACE_STEAL;
    if (found == PERMA_FOUND_STACKS)
        batch[PERMA_B_KIND] = PERMA_TRACE_STACK;
}

/* Take a batch of q from queue set `from` and start it as `found`; 0 when
 * there was none.  An adopted take leaves p->starved as it was: it does
 * not count toward the starve limit. */
inline int perma_take_from(perma_picker *p, uint found, uint from, uint q, int full_only)
{
    uint start = 0;
    int starved = p->starved;
    uint got = perma_try_take(p->ctl, p->mem, p->own, from, q, full_only, &start, &starved);
    if (found != PERMA_FOUND_ADOPTED)
        p->starved = starved;
    if (got)
        perma_begin_batch(p, found, q, start, got, PERMA_QINDEX(from, q), 0);
    return got != 0;
}

/* The own queue set: pass 0 takes only queues that fill a whole batch
 * (Whippletree's rule); pass 1 takes any.  Within a pass, priority order.
 * `unstacked`: only procedures whose items cannot run from a stack (the
 * group's stacks hold work: perma_take_stacks). */
inline int perma_take_own_of(perma_picker *p, int unstacked)
{
    for (uint pass = 0; pass < 2; ++pass)
        for (uint i = 0; i < PERMA_NUM_PROCS; ++i)
            if ((!unstacked || perma_wf_need[perma_order[i]] == PERMA_WF_NEVER) &&
                perma_take_from(p, PERMA_FOUND_OWN, p->own, perma_order[i], pass == 0))
                return 1;
    return 0;
}

inline int perma_take_own(perma_picker *p)
{
    return perma_take_own_of(p, 0);
}

/* Every other group's set from set `first` on (adopted: only the sets of
 * groups that are not running), each in priority order. */
inline int perma_take_from_others(perma_picker *p, uint found, uint first)
{
    for (uint attempt = 0; attempt < PERMA_QUEUE_SETS; ++attempt) {
        uint s = (first + attempt) % PERMA_QUEUE_SETS;
        if (s == p->own || (found == PERMA_FOUND_ADOPTED && perma_group_running(p->ctl, s)))
            continue;
        for (uint i = 0; i < PERMA_NUM_PROCS; ++i)
            if (perma_take_from(p, found, s, perma_order[i], 0))
                return 1;
    }
    return 0;
}

#if PERMA_STEALING
/* Every other group's set, from the victim policy's first pick on. */
inline int perma_steal(perma_picker *p)
{
    return perma_take_from_others(p, PERMA_FOUND_STOLEN, perma_first_victim(p->own, p->victim_state));
}
#else
inline int perma_steal(perma_picker *p) { (void)p; return 0; }
#endif

#if PERMA_DONATION
/* Give up to a batch of an overfull own queue to the emptiest running set. */
inline int perma_donate(perma_picker *p)
{
    uint q = 0, dest = 0, start = 0;
    uint got = perma_try_donate(p->ctl, p->own, &q, &dest, &start);
    if (got)
        perma_begin_batch(p, PERMA_FOUND_DONATED, q, start, got, PERMA_QINDEX(p->own, q), dest);
    return got != 0;
}
#else
inline int perma_donate(perma_picker *p) { (void)p; return 0; }
#endif

#if PERMA_DONATION && !PERMA_STEALING
/* Take a batch from the set of a group that is not running (not started
 * yet, or left).  OpenCL does not promise that the groups of a launch run
 * at the same time, and Intel's CPU runtime starts a launch's second group
 * only when its first one has left (or a host thread waits for the launch):
 * without stealing, items in such a set would wait for a group that waits
 * for them.  So whoever runs serves it, as a thief would.  An adopted batch
 * does not count toward the starve limit. */
inline int perma_adopt(perma_picker *p)
{
    return perma_take_from_others(p, PERMA_FOUND_ADOPTED, 0);
}
#else
inline int perma_adopt(perma_picker *p) { (void)p; return 0; }
#endif

#if PERMA_LOCAL_QUEUE
/* Flush every local stack to the global queues (work-item 0); returns the
 * items moved, and counts a flush that moved any as progress. */
inline uint perma_flush_local(perma_picker *p)
{
    uint moved = 0;
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q)
        moved += perma_local_flush(p->ctl, p->queue_data, p->queue_seq, p->mem, p->own, q);
    p->group_stat[PERMA_GSTAT_SPILLS] += moved;
    if (moved) {
        mem_fence(CLK_GLOBAL_MEM_FENCE); /* the items are published before the progress is seen */
        atomic_inc(p->ctl + PERMA_CTL_PROGRESS);
    }
    return moved;
}

/* A batch from the local stack of a procedure (top first, priority order)
 * whose targets have room; the items already hold ROOM in the global queue
 * of their procedure. */
inline int perma_take_local(perma_picker *p)
{
    __local perma_group_mem *mem = p->mem;
    for (uint i = 0; i < PERMA_NUM_PROCS; ++i) {
        uint q = perma_order[i];
        uint n = min(mem->lq_count[q], perma_max_batch[q]);
        if (n == 0)
            continue;
        n = perma_fit_batch(p->ctl, mem, p->own, q, n, &p->starved);
        if (n == 0)
            continue;
        mem->lq_count[q] -= n;
        perma_begin_batch(p, PERMA_FOUND_LOCAL, q, mem->lq_count[q], n, PERMA_QINDEX(p->own, q), 0);
        return 1;
    }
    return 0;
}
#else
inline uint perma_flush_local(perma_picker *p) { (void)p; return 0; }
inline int perma_take_local(perma_picker *p) { (void)p; return 0; }
#endif

#if PERMA_WORK_FIRST
/* While the group's stacks hold items, work first: a batch of the queued
 * items no stack can run, else a batch that runs the stacks
 * (kernels/perma_work_first.cl), after spilling what the stacks cannot run
 * or another group should get.  A group without stealing gives to a group
 * that found nothing, whose set it can take from. */
inline int perma_take_stacks(perma_picker *p)
{
    if (perma_take_own_of(p, 1))
        return 1;
    uint give = p->own;
#if PERMA_QUEUE_SETS > 1 && !PERMA_STEALING
    for (uint g = 0; g < p->groups; ++g)
        if (g != p->own && perma_group_running(p->ctl, g) && perma_load(PERMA_GROUP(p->ctl, g) + PERMA_G_BLOCKED))
            give = g;
#endif
    if (!perma_wf_relieve(p->ctl, p->queue_data, p->queue_seq, p->mem, p->own, give))
        return 0;
    perma_begin_batch(p, PERMA_FOUND_STACKS, 0, 0, 0, PERMA_QINDEX(p->own, 0), 0);
    return 1;
}

/* A group that finds nothing to run counts itself in PERMA_CTL_HUNGRY,
 * once, so that groups with full stacks give it some (perma_wf_relieve);
 * it leaves the count when it finds work or leaves the launch. */
inline void perma_set_hungry(perma_picker *p, uint hungry)
{
    if (*p->hungry == hungry || (hungry && p->mem->wf_total))
        return;
    *p->hungry = hungry;
    if (hungry)
        atomic_inc(p->ctl + PERMA_CTL_HUNGRY);
    else
        atomic_dec(p->ctl + PERMA_CTL_HUNGRY);
}
#endif

/* The ways to a batch, in order; 1 when one was found (and begun). */
inline int perma_find_batch(perma_picker *p)
{
    if (perma_take_local(p) || perma_donate(p))
        return 1;
#if PERMA_WORK_FIRST
    /* Stacks whose items cannot run (no room to spill them) must not keep
     * the group from other work: it takes and steals as without them. */
    if (p->mem->wf_total && perma_take_stacks(p))
        return 1;
#endif
    return perma_take_own(p) || perma_steal(p) || perma_adopt(p);
}

/* Work-item 0: choose what the group does next and write it to batch[]. */
PERMA_PHASE void perma_pick_batch(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                                  __global uint *emit_areas, __global uint *group_words, uint groups, uint own,
                                  volatile __global uint *abort_flag, __local perma_group_mem *mem,
                                  uint *victim_state, uint *starve_count, uint *hungry)
{
    perma_picker picker = { ctl, queue_data, queue_seq, group_words, mem,
                            mem->stats + PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS, groups, own,
                            victim_state, starve_count, hungry, -1 };
    perma_picker *p = &picker;
    for (uint poll = 0;; ++poll) {
        if (perma_load(ctl + PERMA_CTL_EXIT))
            break;
        if (*abort_flag) {
            perma_fail(ctl, PERMA_KSTATUS_ABORTED, PERMA_DETAIL_NONE, 0);
            break;
        }
        if (perma_load_int(ctl + PERMA_CTL_OUTSTANDING) <= 0)
            break;

        uint epoch = perma_load(ctl + PERMA_CTL_PROGRESS);
        p->starved = -1;
        if (perma_find_batch(p)) {
#if PERMA_WORK_FIRST
            perma_set_hungry(p, 0u);
#endif
            return;
        }
        /* Local items that cannot run now go where other groups and the
         * host can see them before this group calls itself stalled.  That
         * publishes work, so it is progress: a group that looked at this
         * set before the flush must not take this group's stall for a
         * deadlock (and stop the launch while the items are taken). */
        if (perma_flush_local(p))
            continue;
        p->group_stat[PERMA_GSTAT_IDLE_POLLS] += 1u;
#if PERMA_WORK_FIRST
        perma_set_hungry(p, 1u);
#endif
        /* Nothing this group can start: either no room for the work it sees,
         * or no work it may take (another group's set, without stealing).
         * If every running group is in that state since the same epoch while
         * items are outstanding, only bigger queues can help. */
        perma_set_blocked(group_words, epoch + 1u);
        if (perma_all_blocked(ctl, epoch, groups) && perma_load_int(ctl + PERMA_CTL_OUTSTANDING) > 0) {
            perma_fail(ctl, PERMA_KSTATUS_NEEDS_ROOM, PERMA_DETAIL_NONE, 0);
            break;
        }
        /* Work in sight but no room to start any of it. */
        if (p->starved >= 0 && perma_note_starved(ctl, mem, groups, own, p->starved, 0, starve_count))
            break;
        if (poll >= PERMA_IDLE_POLLS) {
            perma_set_batch(mem->batch, PERMA_CMD_IDLE, 0, 0, 0, 0, 0);
            return;
        }
    }
    /* Another group stopped the launch for bigger queues while this one
     * held items on its local stacks (it ran a batch after the stall was
     * called): they must reach the global queues, which the host carries
     * over to the next launch.  After any other status the run is over. */
    if (PERMA_LOCAL_QUEUE && perma_load(ctl + PERMA_CTL_STATUS) == PERMA_KSTATUS_NEEDS_ROOM)
        perma_flush_local(p);
#if PERMA_WORK_FIRST
    /* The stacks' items to the overflow area, which the host appends to
     * the queues it grows. */
    if (perma_load(ctl + PERMA_CTL_STATUS) == PERMA_KSTATUS_NEEDS_ROOM)
        perma_wf_flush(emit_areas, mem, own);
    perma_set_hungry(p, 0u);
#endif
    perma_set_batch(mem->batch, PERMA_CMD_EXIT, 0, 0, 0, 0, 0);
}

/* Declare a group's __local memory and `mem`, its address. */
#define PERMA_GROUP_LOCALS(mem)                       \
    __local perma_group_mem perma_group_state;        \
    __local perma_group_mem *const mem = &perma_group_state

#if PERMA_TRACE_EVENTS
/* Work-item 0: the group's next trace record, while there is room. */
inline void perma_trace_add(__global uint *group_trace, uint *trace_count, uint proc, uint kind, uint items,
                            uint start, uint end)
{
    if (*trace_count >= PERMA_TRACE_EVENTS)
        return;
    __global uint *record = group_trace + 1u + PERMA_TRACE_RECORD_WORDS * (*trace_count)++;
    record[0] = proc | kind << 8;
    record[1] = items;
    record[2] = start;
    record[3] = end;
}
#endif

__kernel __attribute__((reqd_work_group_size(PERMA_GROUP_SIZE, 1, 1)))
void perma_megakernel(PERMA_COMMON_ARGS(PERMA_ARG_PARAM) PERMA_BUFFER_PARAMS)
{
    PERMA_GROUP_LOCALS(mem);

    const uint lid = get_local_id(0);
    const uint group = get_group_id(0);
    const uint own = PERMA_QUEUE_SETS > 1 ? group : 0u;
    __global uint *group_words = PERMA_GROUP(ctl, group);
    uint victim_state = group * 2654435761u + 12345u; /* used by work-item 0 only */
    uint starve_count = 0;                            /* likewise */
    uint hungry = 0;                                  /* likewise */
#if PERMA_TRACE_EVENTS
    uint trace_count = 0, trace_start = 0;            /* likewise */
    __global uint *group_trace = trace + group * PERMA_TRACE_GROUP_WORDS;
#else
    (void)trace;
#endif
    perma_buffers buf;
    PERMA_BIND_BUFFERS(buf);
    PERMA_LANE_BEGIN(lane);

    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        mem->stats[i] = 0;
    for (uint i = lid; i < PERMA_NUM_PROCS; i += PERMA_GROUP_SIZE)
        mem->lq_count[i] = 0;
#if PERMA_WORK_FIRST
    mem->wf_sp[lid] = 0;
    for (uint e = 0; e < PERMA_MAX_EDGES; ++e)
        mem->wf_own[lid * PERMA_MAX_EDGES + e] = 0;
    for (uint i = lid; i < PERMA_NUM_PROCS * PERMA_MAX_EDGES; i += PERMA_GROUP_SIZE)
        mem->wf_pushed[i] = 0;
    for (uint i = lid; i < PERMA_NUM_PROCS; i += PERMA_GROUP_SIZE)
        mem->wf_ran[i] = 0;
    if (lid == 0) {
        mem->wf_total = 0;
        mem->wf_given = 0;
    }
#endif
    if (lid == 0) {
        mem->error_code = 0;
        perma_emit_area(emit_areas)[PERMA_OVERFLOW_RECORDS] = 0;
        perma_set_batch(mem->batch, PERMA_CMD_IDLE, 0, 0, 0, 0, 0);
        atomic_xchg(group_words + PERMA_G_STATE, 1u);
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    /* An idle or final iteration runs the batch code with 0 items rather
     * than branching around its barriers. */
    uint command = PERMA_CMD_IDLE;
    while (command != PERMA_CMD_EXIT) {
        if (lid == 0)
            perma_pick_batch(ctl, queue_data, queue_seq, emit_areas, group_words, get_num_groups(0), own, abort_flag,
                             mem, &victim_state, &starve_count, &hungry);
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        command = mem->batch[PERMA_B_COMMAND];
#if PERMA_TRACE_EVENTS
#if PERMA_WORK_FIRST
        /* What the stacks gave another group while the batch was picked: a
         * donation, as the statistics count it. */
        if (lid == 0 && mem->wf_given) {
            uint now = atomic_inc(abort_flag + PERMA_WATCH_CLOCK);
            perma_trace_add(group_trace, &trace_count, PERMA_TRACE_STACKS, PERMA_TRACE_DONATE, mem->wf_given, now, now);
            mem->wf_given = 0;
        }
#endif
        if (lid == 0 && (mem->batch[PERMA_B_COUNT] || mem->batch[PERMA_B_KIND] == PERMA_TRACE_STACK))
            trace_start = atomic_inc(abort_flag + PERMA_WATCH_CLOCK);
#endif
        perma_run_batch(ctl, queue_data, queue_seq, emit_areas, abort_flag, mem, lane, buf, (__global const uint *)0,
                        own);
#if PERMA_TRACE_EVENTS
        /* Before work-item 0 schedules the next batch. */
        if (lid == 0 && (mem->batch[PERMA_B_COUNT] || mem->batch[PERMA_B_WF_RAN])) {
            uint kind = mem->batch[PERMA_B_KIND];
            perma_trace_add(group_trace, &trace_count, kind == PERMA_TRACE_STACK ? PERMA_TRACE_STACKS
                            : mem->batch[PERMA_B_PROC], kind, mem->batch[PERMA_B_COUNT] + mem->batch[PERMA_B_WF_RAN],
                            trace_start, atomic_inc(abort_flag + PERMA_WATCH_CLOCK));
        }
#endif
    }
#if PERMA_TRACE_EVENTS
    if (lid == 0)
        group_trace[0] = trace_count;
#endif

    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        group_stats[group * PERMA_STAT_GROUP_WORDS + i] = mem->stats[i];
    PERMA_LANE_END(lane, reductions);
    if (lid == 0)
        atomic_xchg(group_words + PERMA_G_STATE, 2u);
}
