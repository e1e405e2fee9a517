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
 * passes a threshold (PERMA_DONATION).
 *
 * Uses the generated tables (perma_order, perma_max_batch, ...), the
 * generated perma_dispatch(), PERMA_BUFFER_PARAMS and PERMA_BIND_BUFFERS.
 * Every barrier is reached by all work-items on every iteration.
 */

#define PERMA_CMD_RUN 0u
#define PERMA_CMD_IDLE 1u
#define PERMA_CMD_EXIT 2u
#define PERMA_CMD_DONATE 3u

/* Words work-item 0 broadcasts to the group. */
#define PERMA_B_PROC 0
#define PERMA_B_START 1
#define PERMA_B_COUNT 2
#define PERMA_B_COMMAND 3
#define PERMA_B_SOURCE 4 /* queue index the items come from */
#define PERMA_B_DEST 5   /* donation: queue index they go to */
#define PERMA_BATCH_WORDS 8

/* Scheduler polls in work-item 0 before the group goes round its loop once. */
#define PERMA_IDLE_POLLS 64u

#define PERMA_QINDEX(set, proc) ((set) * PERMA_NUM_PROCS + (proc))

/* How many of `want` items of procedure q fit into the room of its targets
 * in queue set `set`. */
inline uint perma_admissible(__global uint *ctl, uint set, uint q, uint want)
{
    for (uint e = 0; e < perma_edge_count[q]; ++e) {
        uint t = perma_edge_target[q * PERMA_MAX_EDGES + e];
        int room = perma_load_int(PERMA_QUEUE(ctl, PERMA_QINDEX(set, t)) + PERMA_Q_ROOM);
        uint fit = room > 0 ? (uint)room / perma_edge_max[q * PERMA_MAX_EDGES + e] : 0u;
        want = min(want, fit);
    }
    return want;
}

inline void perma_release_batch_room(__global uint *ctl, uint set, uint q, uint items, uint edges)
{
    for (uint e = 0; e < edges; ++e) {
        uint t = perma_edge_target[q * PERMA_MAX_EDGES + e];
        perma_queue_return_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(set, t)),
                                (int)(items * perma_edge_max[q * PERMA_MAX_EDGES + e]));
    }
}

/* Reserve the worst-case emits of `items` items of q in every target. */
inline int perma_reserve_batch_room(__global uint *ctl, uint set, uint q, uint items)
{
    uint edges = perma_edge_count[q];
    for (uint e = 0; e < edges; ++e) {
        uint t = perma_edge_target[q * PERMA_MAX_EDGES + e];
        if (!perma_queue_reserve_room(PERMA_QUEUE(ctl, PERMA_QINDEX(set, t)),
                                      (int)(items * perma_edge_max[q * PERMA_MAX_EDGES + e]))) {
            perma_release_batch_room(ctl, set, q, items, e);
            return 0;
        }
    }
    return 1;
}

/* Take a batch of procedure q from queue set `from` for a group whose emits
 * go to set `own`.  Returns the item count (0: none), first position in
 * *start; sets *found when the queue had items at all. */
inline uint perma_try_take(__global uint *ctl, uint own, uint from, uint q, int full_only,
                           uint *start, int *found)
{
    __global uint *queue = PERMA_QUEUE(ctl, PERMA_QINDEX(from, q));
    int available = perma_queue_available(queue);
    if (available <= 0)
        return 0;
    *found = 1;
    uint want = min((uint)available, perma_max_batch[q]);
    if (full_only && want < perma_max_batch[q])
        return 0;
    want = perma_admissible(ctl, own, q, want);
    if (want == 0 || !perma_reserve_batch_room(ctl, own, q, want))
        return 0;
    uint got = perma_queue_claim(queue, want, start);
    if (got < want)
        perma_release_batch_room(ctl, own, q, want - got, perma_edge_count[q]);
    return got;
}

/* Donation: if the own queue of a procedure holds more than the threshold,
 * claim up to a batch of it for the set that has the fewest. */
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
            int theirs = perma_queue_available(PERMA_QUEUE(ctl, PERMA_QINDEX(s, q)));
            if (s != own && theirs < fewest) {
                fewest = theirs;
                poorest = s;
            }
        }
        if (poorest == own || fewest + (int)perma_max_batch[q] >= mine)
            continue;
        uint share = min(perma_max_batch[q], (uint)(mine - fewest) / 2u);
        __global uint *target = PERMA_QUEUE(ctl, PERMA_QINDEX(poorest, q));
        if (share == 0 || !perma_queue_reserve_room(target, (int)share))
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

/* True when every running group is blocked on room since `epoch` and no room
 * appeared since: nobody can make progress until the host grows queues. */
inline int perma_all_blocked(__global uint *ctl, uint epoch)
{
    for (uint g = 0; g < get_num_groups(0); ++g) {
        __global uint *gw = PERMA_GROUP(ctl, g);
        if (perma_load(gw + PERMA_G_STATE) == 1u && perma_load(gw + PERMA_G_BLOCKED) != epoch + 1u)
            return 0;
    }
    return perma_load(ctl + PERMA_CTL_PROGRESS) == epoch;
}

inline void perma_set_blocked(__global uint *group_words, uint value)
{
    atomic_xchg(group_words + PERMA_G_BLOCKED, value);
}

/* The next victim of a stealing group (never itself). */
inline uint perma_next_victim(uint own, uint *state)
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

inline void perma_set_batch(__local uint *batch, uint command, uint proc, uint start, uint count,
                            uint source, uint dest)
{
    batch[PERMA_B_PROC] = proc;
    batch[PERMA_B_START] = start;
    batch[PERMA_B_COUNT] = count;
    batch[PERMA_B_COMMAND] = command;
    batch[PERMA_B_SOURCE] = source;
    batch[PERMA_B_DEST] = dest;
}

/* Work-item 0: choose what the group does next and write it to batch[]. */
inline void perma_schedule(__global uint *ctl, __global uint *group_words, uint own,
                           volatile __global uint *abort_flag, __local uint *batch,
                           __local uint *group_stat, uint *victim_state)
{
    for (uint poll = 0;; ++poll) {
        if (perma_load(ctl + PERMA_CTL_EXIT))
            break;
        if (*abort_flag) {
            perma_fail(ctl, PERMA_KSTATUS_ABORTED, 0xffffffffu, 0);
            break;
        }
        if (perma_load_int(ctl + PERMA_CTL_OUTSTANDING) <= 0)
            break;

        uint epoch = perma_load(ctl + PERMA_CTL_PROGRESS);
        int found = 0;
        uint start = 0, q = 0, dest = 0, got;
#if PERMA_DONATION
        got = perma_try_donate(ctl, own, &q, &dest, &start);
        if (got) {
            group_stat[PERMA_GSTAT_DONATIONS] += 1u;
            group_stat[PERMA_GSTAT_DONATED] += got;
            perma_set_batch(batch, PERMA_CMD_DONATE, q, start, got, PERMA_QINDEX(own, q), dest);
            return;
        }
#endif
        /* Pass 0 takes only queues that fill a whole batch (Whippletree's
         * rule); pass 1 takes any.  Within a pass, priority order. */
        for (uint pass = 0; pass < 2; ++pass) {
            for (uint i = 0; i < PERMA_NUM_PROCS; ++i) {
                q = perma_order[i];
                got = perma_try_take(ctl, own, own, q, pass == 0, &start, &found);
                if (got) {
                    perma_set_blocked(group_words, 0u);
                    perma_set_batch(batch, PERMA_CMD_RUN, q, start, got, PERMA_QINDEX(own, q), 0);
                    return;
                }
            }
        }
#if PERMA_STEALING
        for (uint attempt = 0; attempt + 1u < PERMA_QUEUE_SETS; ++attempt) {
            uint victim = perma_next_victim(own, victim_state);
            for (uint i = 0; i < PERMA_NUM_PROCS; ++i) {
                q = perma_order[i];
                got = perma_try_take(ctl, own, victim, q, 0, &start, &found);
                if (got) {
                    group_stat[PERMA_GSTAT_STEALS] += 1u;
                    perma_set_blocked(group_words, 0u);
                    perma_set_batch(batch, PERMA_CMD_RUN, q, start, got, PERMA_QINDEX(victim, q), 0);
                    return;
                }
            }
        }
#endif
        group_stat[PERMA_GSTAT_IDLE_POLLS] += 1u;
        if (found) {
            /* Work exists but no target has room for it. */
            perma_set_blocked(group_words, epoch + 1u);
            if (perma_all_blocked(ctl, epoch)) {
                perma_fail(ctl, PERMA_KSTATUS_NEEDS_ROOM, 0xffffffffu, 0);
                break;
            }
        } else {
            perma_set_blocked(group_words, 0u);
        }
        if (poll >= PERMA_IDLE_POLLS) {
            batch[PERMA_B_COMMAND] = PERMA_CMD_IDLE;
            return;
        }
    }
    batch[PERMA_B_COMMAND] = PERMA_CMD_EXIT;
}

__kernel __attribute__((reqd_work_group_size(PERMA_GROUP_SIZE, 1, 1)))
void perma_megakernel(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                      __global uint *group_stats, volatile __global uint *abort_flag
                      PERMA_BUFFER_PARAMS)
{
    /* One arena; each procedure has its own layout of items, scratch, emit
     * counters and staging inside it (perma_*_off tables). */
    __local uint arena[PERMA_ARENA_WORDS] __attribute__((aligned(64)));
    __local uint edge_counts[PERMA_MAX_EDGES];
    __local uint edge_base[PERMA_MAX_EDGES];
    __local uint stats[PERMA_STAT_GROUP_WORDS];
    __local uint batch[PERMA_BATCH_WORDS];
    __local uint error_code;
    __local uint copy_failed;

    const uint lid = get_local_id(0);
    const uint group = get_group_id(0);
    const uint own = PERMA_QUEUE_SETS > 1 ? group : 0u;
    __global uint *group_words = PERMA_GROUP(ctl, group);
    __local uint *group_stat = stats + PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS;
    uint victim_state = group * 2654435761u + 12345u; /* used by work-item 0 only */

    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        stats[i] = 0;
    if (lid == 0) {
        copy_failed = 0;
        perma_set_batch(batch, PERMA_CMD_IDLE, 0, 0, 0, 0, 0);
        atomic_xchg(group_words + PERMA_G_STATE, 1u);
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    /* The body is straight-line code with a uniform trip count: an idle or
     * final iteration runs it with count = 0 rather than branching around
     * barriers (PoCL mishandles continue/break between barriers). */
    uint command = PERMA_CMD_IDLE;
    while (command != PERMA_CMD_EXIT) {
        if (lid == 0)
            perma_schedule(ctl, group_words, own, abort_flag, batch, group_stat, &victim_state);
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        command = batch[PERMA_B_COMMAND];
        const uint proc = batch[PERMA_B_PROC];
        const uint start = batch[PERMA_B_START];
        const uint moving = command == PERMA_CMD_RUN || command == PERMA_CMD_DONATE;
        const uint count = moving ? batch[PERMA_B_COUNT] : 0u;
        const uint run = command == PERMA_CMD_RUN ? count : 0u; /* items to execute */
        __global uint *queue = PERMA_QUEUE(ctl, batch[PERMA_B_SOURCE]);
        __global uint *donee = PERMA_QUEUE(ctl, batch[PERMA_B_DEST]);
        barrier(CLK_LOCAL_MEM_FENCE); /* all have read batch[] before it is rewritten */

        /* Copy the batch into local memory, freeing its queue slots. */
        const uint words = perma_item_words[proc];
        const uint edges = command == PERMA_CMD_RUN ? perma_edge_count[proc] : 0u;
        __local uint *items = arena + perma_items_off[proc];
        __local uint *item_emit_counts = arena + perma_counters_off[proc];
        for (uint i = lid; i < count; i += PERMA_GROUP_SIZE) {
            if (!perma_queue_read_item(queue, queue_data, queue_seq, start + i, words,
                                       items + i * words, abort_flag))
                copy_failed = 1;
        }
        for (uint i = lid; i < run * edges; i += PERMA_GROUP_SIZE)
            item_emit_counts[i] = 0;
        for (uint i = lid; i < PERMA_MAX_EDGES; i += PERMA_GROUP_SIZE)
            edge_counts[i] = 0;
        if (lid == 0)
            error_code = 0;
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        if (lid == 0)
            perma_queue_return_room(ctl, queue, (int)count);

        /* Run the procedure (not on items that failed to arrive). */
        perma_ctx ctx;
        const uint tpi = perma_tpi[proc];
        const uint slot = lid / tpi;
        ctx.proc = proc;
        ctx.thread = lid % tpi;
        ctx.threads = tpi;
        ctx.active = (slot < run && !copy_failed) ? 1u : 0u;
        ctx.slot = ctx.active ? slot : 0u;
        ctx.group = group;
        ctx.scratch = (__local void *)(arena + perma_scratch_off[proc] +
                                       ctx.slot * perma_scratch_words[proc]);
        ctx.item_emit_counts = item_emit_counts + ctx.slot * perma_edge_count[proc];
        ctx.edge_counts = edge_counts;
        ctx.stage = arena;
        ctx.error_code = &error_code;
        PERMA_BIND_BUFFERS(ctx.buf);
        perma_dispatch(proc, &ctx, items);
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);

        /* Reserve positions in the targets: one atomic per target. */
        if (lid == 0) {
            int emitted = 0;
            for (uint e = 0; e < edges; ++e) {
                uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
                __global uint *target = PERMA_QUEUE(ctl, PERMA_QINDEX(own, t));
                uint k = edge_counts[e];
                edge_base[e] = k ? atomic_add(target + PERMA_Q_TAIL, k) : 0u;
                if (k)
                    perma_queue_note_peak(target, edge_base[e] + k);
                emitted += (int)k;
                stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_EMITTED + e] += k;
            }
            if (run) {
                stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_ITEMS] += run;
                stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_BATCHES] += 1u;
                /* Count the emits before they become visible, and retire the batch. */
                atomic_add((volatile __global int *)(ctl + PERMA_CTL_OUTSTANDING), emitted - (int)run);
            }
            if (command == PERMA_CMD_DONATE) {
                edge_base[0] = atomic_add(donee + PERMA_Q_TAIL, count);
                perma_queue_note_peak(donee, edge_base[0] + count);
            }
            if (error_code)
                perma_fail(ctl, PERMA_KSTATUS_EMIT_LIMIT, proc, error_code);
        }
        barrier(CLK_LOCAL_MEM_FENCE);

        /* Copy the staged items out and publish them. */
        for (uint e = 0; e < edges; ++e) {
            const uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
            __global uint *target = PERMA_QUEUE(ctl, PERMA_QINDEX(own, t));
            const uint k = edge_counts[e];
            const uint target_words = perma_item_words[t];
            __local const uint *src = arena + perma_edge_stage[proc * PERMA_MAX_EDGES + e];
            for (uint i = lid; i < k; i += PERMA_GROUP_SIZE) {
                if (!perma_queue_write_item(target, queue_data, queue_seq, edge_base[e] + i,
                                            target_words, src + i * target_words, abort_flag))
                    copy_failed = 1;
            }
        }
        /* A donation publishes the batch itself in the other group's queue. */
        const uint donated = command == PERMA_CMD_DONATE ? count : 0u;
        for (uint i = lid; i < donated; i += PERMA_GROUP_SIZE) {
            if (!perma_queue_write_item(donee, queue_data, queue_seq, edge_base[0] + i, words,
                                        items + i * words, abort_flag))
                copy_failed = 1;
        }
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        if (lid == 0) {
            for (uint e = 0; e < edges; ++e) {
                uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
                uint promised = run * perma_edge_max[proc * PERMA_MAX_EDGES + e];
                perma_queue_return_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(own, t)),
                                        (int)(promised - edge_counts[e]));
            }
            if (copy_failed)
                perma_fail(ctl, *abort_flag ? PERMA_KSTATUS_ABORTED : PERMA_KSTATUS_SPIN_LIMIT,
                           0xffffffffu, 0);
        }
    }

    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        group_stats[group * PERMA_STAT_GROUP_WORDS + i] = stats[i];
    if (lid == 0)
        atomic_xchg(group_words + PERMA_G_STATE, 2u);
}
