/*
 * One batch, executed by a whole work-group: copy the items into __local
 * memory, run the procedure, reserve the targets' positions with one atomic
 * each, publish the emits.  Shared by the persistent megakernel and the
 * host-driven step kernel.  Every barrier in here is reached by every
 * work-item on every call, whatever the batch (a batch of 0 items runs the
 * same code): PoCL mishandles continue/break between barriers, and
 * barriers must be in uniform control flow anyway.
 */

#define PERMA_CMD_RUN 0u
#define PERMA_CMD_IDLE 1u
#define PERMA_CMD_EXIT 2u
#define PERMA_CMD_DONATE 3u
#define PERMA_CMD_RUN_LOCAL 4u /* run items from the group's local stack */

/* Words work-item 0 broadcasts to the group. */
#define PERMA_B_PROC 0
#define PERMA_B_START 1
#define PERMA_B_COUNT 2
#define PERMA_B_COMMAND 3
#define PERMA_B_SOURCE 4 /* queue index the items come from */
#define PERMA_B_DEST 5   /* donation: queue index they go to */
#define PERMA_B_KIND 6   /* PERMA_TRACE_* */
#define PERMA_BATCH_WORDS 8

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
        if (!perma_queue_reserve_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(set, t)),
                                      (int)(items * perma_edge_max[q * PERMA_MAX_EDGES + e]))) {
            perma_release_batch_room(ctl, set, q, items, e);
            return 0;
        }
    }
    return 1;
}

/* __local memory of one group, declared in the kernel and passed down. */
typedef struct perma_group_mem {
    __local uint *arena;        /* items, scratch, emit counters, staging */
    __local uint *edge_counts;  /* per edge: items the batch staged */
    __local uint *edge_base;    /* per edge: first reserved target position */
    __local uint *stats;        /* the group's statistics record */
    __local uint *error_code;   /* emit errors of the batch */
    __local uint *copy_failed;  /* a copy-in wait gave up: the batch's items are not run */
    __local uint *lq;           /* local front queue: a stack per procedure */
    __local uint *lq_count;     /* items on each procedure's stack */
    __local uint *edge_keep;    /* per edge: emits kept on the local stack */
} perma_group_mem;

/* Move a procedure's whole local stack to its global queue (work-item 0
 * only; the items hold the ROOM reserved when they were emitted). */
inline uint perma_local_flush(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                              volatile __global uint *abort_flag, perma_group_mem mem, uint own, uint q)
{
    uint n = mem.lq_count[q];
    if (n == 0)
        return 0;
    __global uint *queue = PERMA_QUEUE(ctl, PERMA_QINDEX(own, q));
    uint words = perma_item_words[q];
    uint base = atomic_add(queue + PERMA_Q_TAIL, n);
    perma_queue_note_peak(queue, base + n);
    for (uint i = 0; i < n; ++i) /* a failed write has stopped the launch (perma_queue_wait_failed) */
        perma_queue_write_item(ctl, queue, queue_data, queue_seq, base + i, words,
                               mem.lq + perma_lq_off[q] + i * words, abort_flag);
    mem.lq_count[q] = 0;
    return n;
}

/* The part of a batch's copy-out that this work-item does for edge e of
 * proc: the kept items onto the local stack, the rest into the queue. */
inline void perma_publish_edge(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                               volatile __global uint *abort_flag, perma_group_mem mem, uint proc, uint own,
                               uint e)
{
    const uint lid = get_local_id(0);
    const uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
    __global uint *target = PERMA_QUEUE(ctl, PERMA_QINDEX(own, t));
    const uint k = mem.edge_counts[e];
    const uint keep = mem.edge_keep[e];
    const uint target_words = perma_item_words[t];
    __local const uint *src = mem.arena + perma_edge_stage[proc * PERMA_MAX_EDGES + e];
    __local uint *stack = mem.lq + perma_lq_off[t] + mem.edge_base[e] * target_words;
    for (uint i = lid; i < keep; i += PERMA_GROUP_SIZE)
        for (uint w = 0; w < target_words; ++w)
            stack[i * target_words + w] = src[i * target_words + w];
    /* A write that gives up has stopped the launch (perma_queue_wait_failed). */
    for (uint i = keep + lid; i < k; i += PERMA_GROUP_SIZE)
        perma_queue_write_item(ctl, target, queue_data, queue_seq, mem.edge_base[PERMA_MAX_EDGES + e] + i - keep,
                               target_words, src + i * target_words, abort_flag);
}

/* Run `count` items of `proc` (command RUN) or move them to `donee`
 * (command DONATE).  The items come from queue `source` at `start`, from
 * input[start..] when `input` is not null (the host-driven step kernel), or
 * from the group's local stack at `start` when `from_local` (then `source`
 * is the global queue whose ROOM they hold).  Emits go to queue set `own`,
 * first onto the local stack when PERMA_LOCAL_QUEUE is on. */
inline void perma_run_batch(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                            volatile __global uint *abort_flag, perma_group_mem mem, perma_buffers buf,
                            uint command, uint proc, uint start, uint count,
                            __global uint *source, __global uint *donee,
                            __global const uint *input, uint from_local, uint own)
{
    const uint lid = get_local_id(0);
    const uint run = command == PERMA_CMD_RUN ? count : 0u; /* items to execute */

    /* Copy the batch into local memory, freeing its queue slots. */
    const uint words = perma_item_words[proc];
    const uint edges = command == PERMA_CMD_RUN ? perma_edge_count[proc] : 0u;
    __local uint *items = mem.arena + perma_items_off[proc];
    __local uint *item_emit_counts = mem.arena + perma_counters_off[proc];
    for (uint i = lid; i < count; i += PERMA_GROUP_SIZE) {
        if (input) {
            for (uint w = 0; w < words; ++w)
                items[i * words + w] = input[(start + i) * words + w];
        } else if (from_local) {
            for (uint w = 0; w < words; ++w)
                items[i * words + w] = mem.lq[perma_lq_off[proc] + (start + i) * words + w];
        } else if (!perma_queue_read_item(ctl, source, queue_data, queue_seq, start + i, words,
                                          items + i * words, abort_flag)) {
            *mem.copy_failed = 1;
        }
    }
    for (uint i = lid; i < run * edges; i += PERMA_GROUP_SIZE)
        item_emit_counts[i] = 0;
    for (uint i = lid; i < PERMA_MAX_EDGES; i += PERMA_GROUP_SIZE)
        mem.edge_counts[i] = 0;
    if (lid == 0)
        *mem.error_code = 0;
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    volatile __global uint *watch = abort_flag + PERMA_WATCH_RECORDS + get_group_id(0) * PERMA_WATCH_RECORD_WORDS;
    if (lid == 0 && !input)
        perma_queue_return_room(ctl, source, (int)count);
    if (lid == 0 && run)
        watch[PERMA_WATCH_RUNNING] = proc + 1u; /* the host's watchdog names it if it never returns */

    /* Run the procedure (not on items that failed to arrive). */
    perma_ctx ctx;
    const uint tpi = perma_tpi[proc];
    const uint slot = lid / tpi;
    ctx.proc = proc;
    ctx.thread = lid % tpi;
    ctx.threads = tpi;
    ctx.active = (slot < run && !*mem.copy_failed) ? 1u : 0u;
    ctx.slot = ctx.active ? slot : 0u;
    ctx.group = get_group_id(0);
    ctx.scratch = (__local void *)(mem.arena + perma_scratch_off[proc] + ctx.slot * perma_scratch_words[proc]);
    ctx.item_emit_counts = item_emit_counts + ctx.slot * perma_edge_count[proc];
    ctx.edge_counts = mem.edge_counts;
    ctx.stage = mem.arena;
    ctx.error_code = mem.error_code;
    ctx.buf = buf;
    perma_dispatch(proc, &ctx, items);
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);

    /* Reserve positions in the targets: one atomic per target. */
    __local uint *stats = mem.stats;
    if (lid == 0) {
        int emitted = 0;
        for (uint e = 0; e < edges; ++e) {
            uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
            __global uint *target = PERMA_QUEUE(ctl, PERMA_QINDEX(own, t));
            uint k = mem.edge_counts[e];
            /* Keep what fits on the local stack (those keep their ROOM in
             * the global queue); the rest goes to the global queue.
             * edge_base[e]: first local position, [MAX_EDGES + e]: first
             * global position. */
            uint keep = 0;
#if PERMA_LOCAL_QUEUE
            keep = min(k, (uint)PERMA_LOCAL_QUEUE - mem.lq_count[t]);
            mem.edge_base[e] = mem.lq_count[t];
            mem.lq_count[t] += keep;
            stats[PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS + PERMA_GSTAT_SPILLS] += k - keep;
#endif
            mem.edge_keep[e] = keep;
            mem.edge_base[PERMA_MAX_EDGES + e] = k > keep ? atomic_add(target + PERMA_Q_TAIL, k - keep) : 0u;
            if (k > keep)
                perma_queue_note_peak(target, mem.edge_base[PERMA_MAX_EDGES + e] + k - keep);
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
            mem.edge_base[0] = atomic_add(donee + PERMA_Q_TAIL, count);
            perma_queue_note_peak(donee, mem.edge_base[0] + count);
        }
        if (*mem.error_code)
            perma_fail(ctl, PERMA_KSTATUS_EMIT_LIMIT, proc, *mem.error_code);
    }
    barrier(CLK_LOCAL_MEM_FENCE);

    /* Copy the staged items out and publish them, one target queue after
     * another in ascending queue order, with a barrier in between: a group
     * that waits for a slot of one queue has then published everything it
     * owes to the queues before it and nothing of the queues after it,
     * which keeps the waits between groups free of cycles when PoCL runs a
     * group's work-items one after another (docs/design.md, *Queues*).
     * The loop's trip count is a constant, so its barrier is uniform. */
    for (uint o = 0; o < PERMA_MAX_EDGES; ++o) {
        if (o < edges)
            perma_publish_edge(ctl, queue_data, queue_seq, abort_flag, mem, proc, own,
                               perma_edge_write_order[proc * PERMA_MAX_EDGES + o]);
        barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    }
    /* A donation publishes the batch itself in the other group's queue. */
    const uint donated = command == PERMA_CMD_DONATE ? count : 0u;
    for (uint i = lid; i < donated; i += PERMA_GROUP_SIZE)
        perma_queue_write_item(ctl, donee, queue_data, queue_seq, mem.edge_base[0] + i, words, items + i * words,
                               abort_flag);
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    if (lid == 0) {
        for (uint e = 0; e < edges; ++e) {
            uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
            uint promised = run * perma_edge_max[proc * PERMA_MAX_EDGES + e];
            perma_queue_return_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(own, t)),
                                    (int)(promised - mem.edge_counts[e]));
        }
        if (count)
            atomic_inc(ctl + PERMA_CTL_PROGRESS); /* stalled groups must look again */
        if (run) {
            watch[PERMA_WATCH_RUNNING] = 0u;
            watch[PERMA_WATCH_DONE] += 1u;    /* progress the host's watchdog sees */
        }
    }
}
