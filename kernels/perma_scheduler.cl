/*
 * The persistent megakernel: every work-group loops
 *   schedule (work-item 0) -> copy the batch in -> run the procedure
 *   -> reserve target positions (work-item 0) -> copy emits out
 * until the outstanding-item count is zero or a status stops the run.
 *
 * Uses the generated tables (perma_order, perma_max_batch, ...), the
 * generated perma_dispatch(), PERMA_BUFFER_PARAMS and PERMA_BIND_BUFFERS.
 * Every barrier is in control flow that is uniform across the group: the
 * branch conditions come from __local words written before a barrier.
 */

#define PERMA_CMD_RUN 0u
#define PERMA_CMD_IDLE 1u
#define PERMA_CMD_EXIT 2u

/* Scheduler polls in work-item 0 before the group goes round its loop once. */
#define PERMA_IDLE_POLLS 256u

/* How many of `want` items of procedure q fit into the room of its targets. */
inline uint perma_admissible(__global uint *ctl, uint q, uint want)
{
    for (uint e = 0; e < perma_edge_count[q]; ++e) {
        __global uint *target = PERMA_QUEUE(ctl, perma_edge_target[q * PERMA_MAX_EDGES + e]);
        int room = perma_load_int(target + PERMA_Q_ROOM);
        uint fit = room > 0 ? (uint)room / perma_edge_max[q * PERMA_MAX_EDGES + e] : 0u;
        want = min(want, fit);
    }
    return want;
}

inline void perma_release_batch_room(__global uint *ctl, uint q, uint items, uint edges)
{
    for (uint e = 0; e < edges; ++e) {
        __global uint *target = PERMA_QUEUE(ctl, perma_edge_target[q * PERMA_MAX_EDGES + e]);
        perma_queue_return_room(ctl, target, (int)(items * perma_edge_max[q * PERMA_MAX_EDGES + e]));
    }
}

/* Reserve the worst-case emits of `items` items of q in every target. */
inline int perma_reserve_batch_room(__global uint *ctl, uint q, uint items)
{
    uint edges = perma_edge_count[q];
    for (uint e = 0; e < edges; ++e) {
        __global uint *target = PERMA_QUEUE(ctl, perma_edge_target[q * PERMA_MAX_EDGES + e]);
        if (!perma_queue_reserve_room(target, (int)(items * perma_edge_max[q * PERMA_MAX_EDGES + e]))) {
            perma_release_batch_room(ctl, q, items, e);
            return 0;
        }
    }
    return 1;
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

/* Work-item 0: choose the next batch and write it to batch[0..3]
 * (procedure, first position, count, command). */
inline void perma_schedule(__global uint *ctl, __global uint *group_words,
                           volatile __global uint *abort_flag, __local uint *batch)
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
        int found_items = 0;
        /* Pass 0 takes only queues that fill a whole batch (Whippletree's
         * rule); pass 1 takes any.  Within a pass, priority order. */
        for (uint pass = 0; pass < 2; ++pass) {
            for (uint i = 0; i < PERMA_NUM_PROCS; ++i) {
                uint q = perma_order[i];
                __global uint *queue = PERMA_QUEUE(ctl, q);
                int available = perma_queue_available(queue);
                if (available <= 0)
                    continue;
                found_items = 1;
                uint want = min((uint)available, perma_max_batch[q]);
                if (pass == 0 && want < perma_max_batch[q])
                    continue;
                want = perma_admissible(ctl, q, want);
                if (want == 0 || !perma_reserve_batch_room(ctl, q, want))
                    continue;
                uint start = 0;
                uint got = perma_queue_claim(queue, want, &start);
                if (got < want)
                    perma_release_batch_room(ctl, q, want - got, perma_edge_count[q]);
                if (got == 0)
                    continue;
                perma_set_blocked(group_words, 0u);
                batch[0] = q;
                batch[1] = start;
                batch[2] = got;
                batch[3] = PERMA_CMD_RUN;
                return;
            }
        }
        if (found_items) {
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
            batch[3] = PERMA_CMD_IDLE;
            return;
        }
    }
    batch[3] = PERMA_CMD_EXIT;
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
    __local uint batch[4];
    __local uint error_code;
    __local uint copy_failed;

    const uint lid = get_local_id(0);
    const uint group = get_group_id(0);
    __global uint *group_words = PERMA_GROUP(ctl, group);

    for (uint i = lid; i < PERMA_STAT_GROUP_WORDS; i += PERMA_GROUP_SIZE)
        stats[i] = 0;
    if (lid == 0) {
        copy_failed = 0;
        batch[0] = 0;
        atomic_xchg(group_words + PERMA_G_STATE, 1u);
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    /* The body is straight-line code with a uniform trip count: an idle or
     * final iteration runs it with count = 0 rather than branching around
     * barriers (PoCL mishandles continue/break between barriers). */
    uint command = PERMA_CMD_IDLE;
    while (command != PERMA_CMD_EXIT) {
        if (lid == 0)
            perma_schedule(ctl, group_words, abort_flag, batch);
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        command = batch[3];
        const uint proc = batch[0];
        const uint start = batch[1];
        const uint count = command == PERMA_CMD_RUN ? batch[2] : 0u;
        barrier(CLK_LOCAL_MEM_FENCE); /* all have read batch[] before it is rewritten */

        /* Copy the batch into local memory, freeing its queue slots. */
        __global uint *queue = PERMA_QUEUE(ctl, proc);
        const uint words = perma_item_words[proc];
        const uint edges = perma_edge_count[proc];
        __local uint *items = arena + perma_items_off[proc];
        __local uint *item_emit_counts = arena + perma_counters_off[proc];
        for (uint i = lid; i < count; i += PERMA_GROUP_SIZE) {
            if (!perma_queue_read_item(queue, queue_data, queue_seq, start + i, words,
                                       items + i * words, abort_flag))
                copy_failed = 1;
        }
        for (uint i = lid; i < count * edges; i += PERMA_GROUP_SIZE)
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
        ctx.active = (slot < count && !copy_failed) ? 1u : 0u;
        ctx.slot = ctx.active ? slot : 0u;
        ctx.group = group;
        ctx.scratch = (__local void *)(arena + perma_scratch_off[proc] +
                                       ctx.slot * perma_scratch_words[proc]);
        ctx.item_emit_counts = item_emit_counts + ctx.slot * edges;
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
                __global uint *target = PERMA_QUEUE(ctl, perma_edge_target[proc * PERMA_MAX_EDGES + e]);
                uint k = edge_counts[e];
                edge_base[e] = k ? atomic_add(target + PERMA_Q_TAIL, k) : 0u;
                if (k)
                    perma_queue_note_peak(target, edge_base[e] + k);
                emitted += (int)k;
                stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_EMITTED + e] += k;
            }
            if (count) {
                stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_ITEMS] += count;
                stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_BATCHES] += 1u;
                /* Count the emits before they become visible, and retire the batch. */
                atomic_add((volatile __global int *)(ctl + PERMA_CTL_OUTSTANDING), emitted - (int)count);
            }
            if (error_code)
                perma_fail(ctl, PERMA_KSTATUS_EMIT_LIMIT, proc, error_code);
        }
        barrier(CLK_LOCAL_MEM_FENCE);

        /* Copy the staged items out and publish them. */
        for (uint e = 0; e < edges; ++e) {
            const uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
            __global uint *target = PERMA_QUEUE(ctl, t);
            const uint k = edge_counts[e];
            const uint target_words = perma_item_words[t];
            __local const uint *src = arena + perma_edge_stage[proc * PERMA_MAX_EDGES + e];
            for (uint i = lid; i < k; i += PERMA_GROUP_SIZE) {
                if (!perma_queue_write_item(target, queue_data, queue_seq, edge_base[e] + i,
                                            target_words, src + i * target_words, abort_flag))
                    copy_failed = 1;
            }
        }
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
        if (lid == 0) {
            for (uint e = 0; e < edges; ++e) {
                __global uint *target = PERMA_QUEUE(ctl, perma_edge_target[proc * PERMA_MAX_EDGES + e]);
                uint promised = count * perma_edge_max[proc * PERMA_MAX_EDGES + e];
                perma_queue_return_room(ctl, target, (int)(promised - edge_counts[e]));
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
