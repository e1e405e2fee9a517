/*
 * One batch, executed by a whole work-group: copy the items into __local
 * memory, run the procedure, reserve the targets' positions with one atomic
 * each, copy the emits out and publish each target's range with one update.
 * Shared by the persistent megakernel and the host-driven step kernel.
 * Every barrier in here is reached by every work-item on every call,
 * whatever the batch (a batch of 0 items runs the same code): PoCL
 * mishandles continue/break between barriers, and barriers must be in
 * uniform control flow anyway.
 */

#define PERMA_CMD_RUN 0u
#define PERMA_CMD_IDLE 1u
#define PERMA_CMD_EXIT 2u
#define PERMA_CMD_DONATE 3u
#define PERMA_CMD_RUN_LOCAL 4u /* run items from the group's local stack */

/* The batch work-item 0 hands to the group (perma_group_mem.batch).  The
 * batch code reads these words where it needs them rather than keeping
 * copies in private variables: PoCL saves and restores a private variable
 * that lives across a barrier for every work-item, a __local word costs a
 * load where it is used. */
#define PERMA_B_PROC 0
#define PERMA_B_START 1
#define PERMA_B_COUNT 2      /* items moved: 0 for IDLE and EXIT */
#define PERMA_B_COMMAND 3    /* PERMA_CMD_* (RUN also for items from the local stack) */
#define PERMA_B_SOURCE 4     /* queue index the items come from (or whose ROOM they hold) */
#define PERMA_B_DEST 5       /* donation: queue index they go to */
#define PERMA_B_KIND 6       /* PERMA_TRACE_* */
#define PERMA_B_FROM_LOCAL 7 /* 1: the items are on the group's local stack at START */
#define PERMA_B_WF_RAN 8     /* work-first: items the batch ran from the work-items' stacks */
#define PERMA_BATCH_WORDS 9

#define PERMA_QINDEX(set, proc) ((set) * PERMA_NUM_PROCS + (proc))

/* __local memory of one group: one struct, declared in the kernel, whose
 * address is passed down.  (A struct of pointers passed by value would be a
 * private copy per work-item that PoCL saves and restores around every
 * barrier; the address of a kernel-scope __local variable is the same for
 * all work-items.) */
typedef struct perma_group_mem {
    /* Items lie in place for their procedures at offsets that are multiples
     * of their size, from a base aligned for any OpenCL type (double16). */
    uint arena[PERMA_ARENA_WORDS] __attribute__((aligned(128))); /* items, scratch, emit counters, staging */
    uint lq[PERMA_LQ_WORDS] __attribute__((aligned(128)));       /* local front queue: a stack per procedure */
    uint edge_counts[PERMA_MAX_EDGES];     /* per edge: items the batch emitted */
    uint edge_base[2 * PERMA_MAX_EDGES];   /* per edge: first local, then first global position */
    uint edge_keep[PERMA_MAX_EDGES];       /* per edge: emits kept on the local stack */
    uint edge_reserved[PERMA_MAX_EDGES];   /* per edge: ROOM the batch holds in the target */
    uint edge_overflow[PERMA_MAX_EDGES];   /* per edge: 1 if its emits go to the overflow data */
    uint lq_count[PERMA_NUM_PROCS];        /* items on each procedure's stack */
    uint stats[PERMA_STAT_GROUP_WORDS];    /* the group's statistics record */
    uint batch[PERMA_BATCH_WORDS];         /* what the group does next (PERMA_B_*) */
    uint error_code;                       /* emit errors of the batch */
#if PERMA_WORK_FIRST
    /* Work-first (kernels/perma_work_first.cl): work-item l's stack is
     * slots [l * PERMA_WORK_FIRST, (l + 1) * PERMA_WORK_FIRST), aligned as
     * the arena for any item type, wf_procs says whose item each holds. */
    uint wf_slots[PERMA_GROUP_SIZE * PERMA_WORK_FIRST * PERMA_WF_SLOT_WORDS] __attribute__((aligned(128)));
    uint wf_procs[PERMA_GROUP_SIZE * PERMA_WORK_FIRST];
    uint wf_sp[PERMA_GROUP_SIZE];                      /* each stack's next free slot */
    uint wf_own[PERMA_GROUP_SIZE * PERMA_MAX_EDGES];   /* each work-item's running item's emits, per edge */
    uint wf_ran[PERMA_NUM_PROCS];                      /* this batch: items run from the stacks */
    uint wf_pushed[PERMA_NUM_PROCS * PERMA_MAX_EDGES]; /* this batch: items pushed, per edge */
    uint wf_total;                                     /* items waiting on the group's stacks */
    uint wf_given;                                     /* items the stacks gave another group, not yet traced */
#endif
} perma_group_mem;

#if PERMA_WORK_FIRST
/* Work-item 0 after a batch ran: fold what the work-items' stacks did
 * (perma_run_simple's counts) into the group's statistics; returns how
 * many more items wait on the stacks than before the batch (pushed less
 * run), for OUTSTANDING. */
inline int perma_wf_count_batch(__local perma_group_mem *mem)
{
    int more = 0;
    uint ran = 0;
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q) {
        __local uint *stats = mem->stats + q * PERMA_STAT_PROC_WORDS;
        stats[PERMA_STAT_ITEMS] += mem->wf_ran[q];
        stats[PERMA_STAT_STACKED] += mem->wf_ran[q];
        ran += mem->wf_ran[q];
        for (uint e = 0; e < perma_edge_count[q]; ++e) {
            stats[PERMA_STAT_EMITTED + e] += mem->wf_pushed[q * PERMA_MAX_EDGES + e];
            more += (int)mem->wf_pushed[q * PERMA_MAX_EDGES + e];
        }
    }
    more -= (int)ran;
    mem->wf_total = (uint)((int)mem->wf_total + more);
    mem->stats[PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS + PERMA_GSTAT_WF_RUNS] += ran;
    mem->batch[PERMA_B_WF_RAN] = ran;
    return more;
}

/* Work-item 0 after the batch's copies: the progress counts of what the
 * stacks ran and pushed (kernels/perma_abi.h, watch page), and the
 * counters cleared for the next batch. */
inline void perma_wf_watch_counts(volatile __global uint *watch, __local perma_group_mem *mem)
{
    for (uint q = 0; q < PERMA_NUM_PROCS; ++q) {
        if (mem->wf_ran[q])
            watch[PERMA_WATCH_COUNTS + q] += mem->wf_ran[q];
        mem->wf_ran[q] = 0;
        for (uint e = 0; e < perma_edge_count[q]; ++e) {
            uint k = mem->wf_pushed[q * PERMA_MAX_EDGES + e];
            if (k)
                watch[PERMA_WATCH_COUNTS + PERMA_NUM_PROCS + perma_edge_target[q * PERMA_MAX_EDGES + e]] += k;
            mem->wf_pushed[q * PERMA_MAX_EDGES + e] = 0;
        }
    }
}
#else
inline int perma_wf_count_batch(__local perma_group_mem *mem)
{
    mem->batch[PERMA_B_WF_RAN] = 0;
    return 0;
}
inline void perma_wf_watch_counts(volatile __global uint *watch, __local perma_group_mem *mem)
{
    (void)watch;
    (void)mem;
}
#endif

/* Whether a batch of q, reserving by its expected emits, expects them all
 * on the work-first stacks (q is stackable), so none in the queues. */
inline int perma_emits_onto_stacks(uint q, uint expected)
{
#if PERMA_WORK_FIRST
    return expected && perma_wf_need[q] != PERMA_WF_NEVER;
#else
    (void)q;
    (void)expected;
    return 0;
#endif
}

/* The ROOM a batch of `items` items of q reserves in the target of edge e
 * before it runs.  `expected`: what the group's batches of q emitted per
 * item into e so far in this launch (its statistics), rounded up, so an
 * item that declares up to N emits and makes k pays for k; before the
 * group's first batch of q, and for the host-driven steps (whose targets
 * the host sized for the worst case), the declared maximum.  A batch that
 * emits more than it reserved takes the rest after it ran
 * (perma_reserve_emits), or, if the target has no room for it, moves the
 * edge's emits to the overflow data of the group's emit area and stops the
 * launch so that the host grows the queue (perma_overflow_edge).  A
 * procedure whose items run from work-first stacks expects none: its
 * items push their emits onto the stack, and stage them only when it is
 * full (its statistics count the pushes too). */
inline uint perma_batch_room(__local const perma_group_mem *mem, uint q, uint e, uint items, uint expected)
{
    const uint max = perma_edge_max[q * PERMA_MAX_EDGES + e];
    if (perma_emits_onto_stacks(q, expected))
        return 0u;
    const uint ran = expected ? mem->stats[q * PERMA_STAT_PROC_WORDS + PERMA_STAT_ITEMS] : 0u;
    if (ran == 0)
        return items * max;
    const ulong emitted = mem->stats[q * PERMA_STAT_PROC_WORDS + PERMA_STAT_EMITTED + e];
    return (uint)min(((ulong)items * emitted + ran - 1u) / ran, (ulong)items * max);
}

/* How many of `want` items of procedure q fit into the room of its targets
 * in queue set `set` (perma_batch_room each). */
inline uint perma_admissible(__global uint *ctl, __local const perma_group_mem *mem, uint set, uint q, uint want,
                             uint expected)
{
    if (perma_emits_onto_stacks(q, expected))
        return want; /* it expects no emits in the queues (perma_batch_room) */
    for (uint e = 0; e < perma_edge_count[q]; ++e) {
        uint t = perma_edge_target[q * PERMA_MAX_EDGES + e];
        int room = perma_load_int(PERMA_QUEUE(ctl, PERMA_QINDEX(set, t)) + PERMA_Q_ROOM);
        const uint ran = expected ? mem->stats[q * PERMA_STAT_PROC_WORDS + PERMA_STAT_ITEMS] : 0u;
        /* items n fit while n * per / den <= room, rounded up */
        const ulong per = ran ? mem->stats[q * PERMA_STAT_PROC_WORDS + PERMA_STAT_EMITTED + e]
                              : perma_edge_max[q * PERMA_MAX_EDGES + e];
        const ulong den = ran ? ran : 1u;
        ulong fit = room <= 0 ? 0ul : per ? (ulong)room * den / per : (ulong)want;
        want = (uint)min((ulong)want, fit);
    }
    return want;
}

/* Give back the ROOM the batch holds beyond what `items` items of q
 * reserve (its claim took fewer than it reserved for). */
inline void perma_shrink_batch_room(__global uint *ctl, __local perma_group_mem *mem, uint set, uint q, uint items,
                                    uint expected)
{
    for (uint e = 0; e < perma_edge_count[q]; ++e) {
        uint t = perma_edge_target[q * PERMA_MAX_EDGES + e];
        uint keep = perma_batch_room(mem, q, e, items, expected);
        perma_queue_return_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(set, t)), (int)(mem->edge_reserved[e] - keep));
        mem->edge_reserved[e] = keep;
    }
}

/* Reserve the room of `items` items of q (perma_batch_room) in every
 * target, recorded in mem->edge_reserved; 0 and nothing held if a target
 * lacks it. */
inline int perma_reserve_batch_room(__global uint *ctl, __local perma_group_mem *mem, uint set, uint q, uint items,
                                    uint expected)
{
    uint edges = perma_edge_count[q];
    for (uint e = 0; e < edges; ++e) {
        uint t = perma_edge_target[q * PERMA_MAX_EDGES + e];
        mem->edge_reserved[e] = perma_batch_room(mem, q, e, items, expected);
        if (!perma_queue_reserve_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(set, t)), (int)mem->edge_reserved[e])) {
            for (uint f = 0; f < e; ++f)
                perma_queue_return_room(ctl, PERMA_QUEUE(ctl, PERMA_QINDEX(set, perma_edge_target[q * PERMA_MAX_EDGES + f])),
                                        (int)mem->edge_reserved[f]);
            return 0;
        }
    }
    return 1;
}

/* Items of the batch to run (0 unless RUN). */
inline uint perma_batch_run(__local const perma_group_mem *mem)
{
    return mem->batch[PERMA_B_COMMAND] == PERMA_CMD_RUN ? mem->batch[PERMA_B_COUNT] : 0u;
}

/* Where the batch's items are: in the arena, or, for items from the local
 * stack, where they lie on it (they run in place; the emits the batch keeps
 * overwrite them only after it ran). */
inline __local uint *perma_batch_items(__local perma_group_mem *mem)
{
    const uint proc = mem->batch[PERMA_B_PROC];
    return mem->batch[PERMA_B_FROM_LOCAL]
               ? mem->lq + perma_lq_off[proc] + mem->batch[PERMA_B_START] * perma_item_words[proc]
               : mem->arena + perma_items_off[proc];
}

/* Move a procedure's whole local stack to its global queue (work-item 0
 * only; the items hold the ROOM reserved when they were emitted). */
inline uint perma_local_flush(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq, __local perma_group_mem *mem, uint own, uint q)
{
    uint n = mem->lq_count[q];
    if (n == 0)
        return 0;
    __global uint *queue = PERMA_QUEUE(ctl, PERMA_QINDEX(own, q));
    uint words = perma_item_words[q];
    uint base = perma_queue_reserve(queue, n);
    __global uint *marks = perma_queue_marks(queue, queue_seq, 0u);
    for (uint i = 0; i < n; ++i) {
        __global uint *dst = perma_queue_slot(queue, queue_data, base + i, words);
        for (uint w = 0; w < words; ++w)
            dst[w] = mem->lq[perma_lq_off[q] + i * words + w];
        if (i)
            perma_queue_clear_mark(marks, queue[PERMA_Q_CAP], base + i);
    }
    perma_queue_complete(queue, queue_seq, 0u, base, n);
    mem->lq_count[q] = 0;
    return n;
}

/* Copy items [lid, lid + group size, ...) of a batch of `count` from the
 * queue slots at position `start` into `items`, marking each position but
 * the first as read (perma_queue_clear_mark); or, from `input`, the
 * host-driven step's items.  `words` is a constant in each caller
 * (PERMA_SWITCH_WORDS), so the copy is a few vector moves, not a loop. */
PERMA_INLINE void perma_copy_items_in(uint lid, uint count, uint start, __global uint *source,
                                      __global const uint *queue_data, __global uint *marks,
                                      __global const uint *input, __local perma_item_word *items, const uint words)
{
    if (input) {
        __global const uint *in = input + start * words;
        for (uint i = lid; i < count; i += PERMA_GROUP_SIZE)
            for (uint w = 0; w < words; ++w)
                items[i * words + w] = in[i * words + w];
        return;
    }
    const uint mask = source[PERMA_Q_CAP] - 1u;
    __global const uint *slots = queue_data + source[PERMA_Q_DATA];
    for (uint i = lid; i < count; i += PERMA_GROUP_SIZE) {
        const uint pos = start + i;
        __global const uint *src = slots + (pos & mask) * words;
        for (uint w = 0; w < words; ++w)
            items[i * words + w] = src[w];
        if (i) /* the first position's mark is the range's (perma_queue_clear_mark) */
            marks[pos & mask] = pos;
    }
}

/* Phase "read": copy the batch into local memory (items from the local stack
 * stay where they are), item i by work-item i % group size, the one that
 * runs it (perma_dispatch), so without procedures of several threads per
 * item no barrier is needed before they run; and clear each item's emit
 * counters.  Work-item 0 read PUBLISHED before the barrier that brought the
 * batch here; the fence orders the item reads after it. */
PERMA_PHASE void perma_read_items(uint lid, __global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                                  __local perma_group_mem *mem, __global const uint *input)
{
    const uint proc = mem->batch[PERMA_B_PROC];
    const uint start = mem->batch[PERMA_B_START];
    const uint count = mem->batch[PERMA_B_COUNT];
    const uint run = perma_batch_run(mem);
    const uint from_local = mem->batch[PERMA_B_FROM_LOCAL];
    __global uint *source = PERMA_QUEUE(ctl, mem->batch[PERMA_B_SOURCE]);
    const uint words = perma_item_words[proc];
    const uint edges = run ? perma_edge_count[proc] : 0u;
    /* Written as perma_item_word: the procedure reads them by its own type. */
    __local perma_item_word *items = (__local perma_item_word *)(mem->arena + perma_items_off[proc]);
    __local uint *counts = mem->arena + perma_counters_off[proc]; /* [slot * edges + edge] */
    read_mem_fence(CLK_GLOBAL_MEM_FENCE);
    if (input || !from_local) {
        __global uint *marks = perma_queue_marks(source, queue_seq, 1u);
        PERMA_SWITCH_WORDS(words, perma_copy_items_in(lid, count, start, source, queue_data, marks, input, items,
                                                      PERMA_WORDS));
    }
    for (uint s = lid; s < run; s += PERMA_GROUP_SIZE)
        for (uint e = 0; e < edges; ++e)
            counts[s * edges + e] = 0;
    if (perma_lane_items[proc]) {
        __local uint *lane_counts = mem->arena + perma_lane_counts_off[proc] + lid * edges;
        for (uint e = 0; e < edges; ++e)
            lane_counts[e] = 0;
    }
}

/* Where the next record's items start in a group's overflow data: after
 * the last record's items, counted in that record's item size (0 when
 * there is none).  Records of different item sizes follow each other: a
 * batch's overflowed edges, then the stacks' items (perma_wf_flush). */
inline uint perma_overflow_end(__global const uint *area)
{
    uint n = area[PERMA_OVERFLOW_RECORDS];
    if (n == 0u)
        return 0u;
    __global const uint *last = area + PERMA_OVERFLOW_RECORD(n - 1u);
    return last[PERMA_OVERFLOW_AT] + last[PERMA_OVERFLOW_COUNT] * perma_item_words[last[PERMA_OVERFLOW_QUEUE] %
                                                                                   PERMA_NUM_PROCS];
}

/* Edge e of the batch emitted k items into queue `qi` that has no room for
 * them: they go to the overflow data of the group's emit area instead
 * (perma_write_emits copies them there), recorded for the host, which
 * grows the queue and appends them to it before the next launch
 * (runtime/src/state.c).  Their ROOM is given back.  Work-item 0; the
 * caller stops the launch. */
inline void perma_overflow_edge(__global uint *ctl, __global uint *emit_areas, __local perma_group_mem *mem, uint e,
                                uint qi, uint k)
{
    __global uint *area = perma_emit_area(emit_areas);
    uint n = area[PERMA_OVERFLOW_RECORDS];
    uint at = perma_overflow_end(area);
    area[PERMA_OVERFLOW_RECORD(n) + PERMA_OVERFLOW_QUEUE] = qi;
    area[PERMA_OVERFLOW_RECORD(n) + PERMA_OVERFLOW_COUNT] = k;
    area[PERMA_OVERFLOW_RECORD(n) + PERMA_OVERFLOW_AT] = at;
    area[PERMA_OVERFLOW_RECORDS] = n + 1u;
    perma_queue_return_room(ctl, PERMA_QUEUE(ctl, qi), (int)mem->edge_reserved[e]);
    mem->edge_reserved[e] = 0;
    mem->edge_overflow[e] = 1u;
    mem->edge_keep[e] = 0;
    mem->edge_base[PERMA_MAX_EDGES + e] = at; /* words into the area's data */
}

/* Phase "publish", work-item 0, after the batch ran: release the source's
 * slots (every copy is done; their room goes back once RELEASED passes
 * them; stacked items give back the room they held at once).  Then turn
 * each edge's per-item counts into offsets, take the ROOM of the emits
 * beyond what the batch reserved (or send the edge's emits to the overflow
 * area when the target has none), keep what fits on the local stack and
 * reserve the rest of each target with one atomic; count the emits before
 * they become visible. */
PERMA_PHASE void perma_reserve_emits(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                                     __global uint *emit_areas, __local perma_group_mem *mem,
                                     __global const uint *input, uint own)
{
    const uint command = mem->batch[PERMA_B_COMMAND];
    const uint proc = mem->batch[PERMA_B_PROC];
    const uint start = mem->batch[PERMA_B_START];
    const uint count = mem->batch[PERMA_B_COUNT];
    const uint from_local = mem->batch[PERMA_B_FROM_LOCAL];
    __global uint *source = PERMA_QUEUE(ctl, mem->batch[PERMA_B_SOURCE]);
    __global uint *donee = PERMA_QUEUE(ctl, mem->batch[PERMA_B_DEST]);
    const uint run = perma_batch_run(mem);
    const uint edges = run ? perma_edge_count[proc] : 0u;
    __local uint *counts = mem->arena + perma_counters_off[proc];
    __local uint *stats = mem->stats;
    if (from_local)
        perma_queue_give_room(source, (int)count);
    else if (!input)
        perma_queue_complete(source, queue_seq, 1u, start, count);
    int emitted = 0;
    uint overflowed = 0;
    for (uint e = 0; e < edges; ++e) {
        uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
        uint max = perma_edge_max[proc * PERMA_MAX_EDGES + e];
        uint k = 0;
        if (perma_lane_items[proc]) {
            /* Lane staging: offsets of each work-item's block. */
            __local uint *lane_counts = mem->arena + perma_lane_counts_off[proc];
            for (uint l = 0; l < PERMA_GROUP_SIZE; ++l) {
                uint c = lane_counts[l * edges + e];
                lane_counts[l * edges + e] = k;
                k += c;
            }
        } else {
            for (uint s = 0; s < run; ++s) {
                uint c = min(counts[s * edges + e], max); /* an item over its limit failed the run */
                counts[s * edges + e] = k;
                k += c;
            }
        }
        mem->edge_counts[e] = k;
        emitted += (int)k;
        stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_EMITTED + e] += k;
        __global uint *target = PERMA_QUEUE(ctl, PERMA_QINDEX(own, t));
        mem->edge_overflow[e] = 0;
        if (k > mem->edge_reserved[e]) {
            if (perma_queue_reserve_room(ctl, target, (int)(k - mem->edge_reserved[e]))) {
                mem->edge_reserved[e] = k;
            } else {
                perma_overflow_edge(ctl, emit_areas, mem, e, PERMA_QINDEX(own, t), k);
                overflowed = 1u;
                continue;
            }
        }
        /* Keep what fits on the local stack (those keep their ROOM in the
         * global queue); the rest goes to the global queue.  edge_base[e]:
         * first local position, [MAX_EDGES + e]: first global position. */
        uint keep = 0;
#if PERMA_LOCAL_QUEUE
        keep = min(k, (uint)PERMA_LOCAL_QUEUE - mem->lq_count[t]);
        mem->edge_base[e] = mem->lq_count[t];
        mem->lq_count[t] += keep;
        stats[PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS + PERMA_GSTAT_SPILLS] += k - keep;
#endif
        mem->edge_keep[e] = keep;
        mem->edge_base[PERMA_MAX_EDGES + e] = k > keep ? perma_queue_reserve(target, k - keep) : 0u;
    }
    int outstanding = 0;
    if (run) {
        stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_ITEMS] += run;
        stats[proc * PERMA_STAT_PROC_WORDS + PERMA_STAT_BATCHES] += 1u;
        outstanding = emitted - (int)run;
    }
    /* Items pushed onto the stacks wait like queued ones until they ran. */
    outstanding += perma_wf_count_batch(mem);
    /* Count the emits before they become visible, and retire the batch. */
    if (outstanding)
        atomic_add((volatile __global int *)(ctl + PERMA_CTL_OUTSTANDING), outstanding);
    if (command == PERMA_CMD_DONATE)
        mem->edge_base[0] = perma_queue_reserve(donee, count);
    /* Emits in the overflow area: every group stops after its batch, the
     * host grows the queues and appends them. */
    if (overflowed)
        perma_fail(ctl, PERMA_KSTATUS_NEEDS_ROOM, PERMA_DETAIL_OVERFLOW, 0);
    /* Read and cleared here, between the batches' procedures (the group's
     * code clears it once before the first batch). */
    if (mem->error_code)
        perma_fail(ctl, PERMA_KSTATUS_EMIT_LIMIT, proc, mem->error_code);
    mem->error_code = 0;
}

/* Move emits [first, end) of one edge (logical indexes; emit i at src +
 * i * words): those below `split` onto the local stack, the others into
 * queue positions pos0 + i, marking each position but the range's first
 * (index keep) as written; with no marks (the overflow area), into
 * slots[(pos0 + i) * words] unmasked.  `words` is a constant in each caller
 * (PERMA_SWITCH_WORDS). */
PERMA_INLINE void perma_copy_emits_out(uint first, uint split, uint end, uint keep, __global const uint *src,
                                       __local perma_item_word *stack, __global uint *slots, uint mask,
                                       __global uint *marks, uint pos0, const uint words)
{
    if (!marks) {
        for (uint i = first; i < end; ++i)
            for (uint w = 0; w < words; ++w)
                slots[(pos0 + i) * words + w] = src[i * words + w];
        return;
    }
    for (uint i = first; i < split; ++i)
        for (uint w = 0; w < words; ++w)
            stack[i * words + w] = src[i * words + w];
    for (uint i = split; i < end; ++i) {
        const uint pos = pos0 + i;
        __global uint *dst = slots + (pos & mask) * words;
        for (uint w = 0; w < words; ++w)
            dst[w] = src[i * words + w];
        if (i > keep) /* the first position's mark is the range's */
            marks[pos & mask] = pos;
    }
}

/* Phase "publish", every work-item: move the emits of its items, the first
 * edge_keep of each edge onto the local stack, the rest into the reserved
 * slots; or, for a donation, the batch itself into the other group's
 * queue.  Nobody waits here. */
PERMA_PHASE void perma_write_emits(uint lid, __global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                                   __global uint *emit_areas, __local perma_group_mem *mem, uint own)
{
    const uint command = mem->batch[PERMA_B_COMMAND];
    const uint proc = mem->batch[PERMA_B_PROC];
    const uint count = mem->batch[PERMA_B_COUNT];
    __global uint *donee = PERMA_QUEUE(ctl, mem->batch[PERMA_B_DEST]);
    const uint run = perma_batch_run(mem);
    const uint edges = run ? perma_edge_count[proc] : 0u;
    __local const uint *counts = mem->arena + perma_counters_off[proc];
    for (uint e = 0; e < edges; ++e) {
        const uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
        const uint max = perma_edge_max[proc * PERMA_MAX_EDGES + e];
        const uint tw = perma_item_words[t];
        const uint k = mem->edge_counts[e];
        const uint keep = mem->edge_keep[e];
        __global uint *target = PERMA_QUEUE(ctl, PERMA_QINDEX(own, t));
        const uint mask = target[PERMA_Q_CAP] - 1u;
        /* Emit i goes to stack[i] below keep, else to position pos0 + i;
         * an overflowed edge's to item i of its run of the overflow data
         * (edge_base: the run's first word). */
        const uint over = mem->edge_overflow[e];
        const uint pos0 = over ? 0u : mem->edge_base[PERMA_MAX_EDGES + e] - keep;
        __global uint *slots = over ? perma_emit_area(emit_areas) + PERMA_EMIT_AREA_OVERFLOW +
                                          mem->edge_base[PERMA_MAX_EDGES + e]
                                    : queue_data + target[PERMA_Q_DATA];
        __global uint *marks = over ? (__global uint *)0 : perma_queue_marks(target, queue_seq, 0u);
        __global const uint *stage = perma_emit_area(emit_areas) + PERMA_EMIT_AREA_STAGE +
                                     perma_edge_stage[proc * PERMA_MAX_EDGES + e];
        /* Stacked items run in place: written as perma_item_word. */
        __local perma_item_word *stack = (__local perma_item_word *)(mem->lq + perma_lq_off[t]) + mem->edge_base[e] * tw;
        /* Emits [first, end) of logical index i lie at src + i * tw: one
         * block of this work-item (lane staging) or one per item. */
        const uint lanes = perma_lane_items[proc];
        __local const uint *lane_counts = mem->arena + perma_lane_counts_off[proc];
        for (uint s = lid; s < (lanes ? lid + 1u : run); s += PERMA_GROUP_SIZE) {
            const uint first = lanes ? lane_counts[lid * edges + e] : counts[s * edges + e];
            const uint end = lanes ? (lid + 1u < PERMA_GROUP_SIZE ? lane_counts[(lid + 1u) * edges + e] : k)
                                   : (s + 1u < run ? counts[(s + 1u) * edges + e] : k);
            __global const uint *src = stage + (lanes ? lid * lanes : s) * max * tw - first * tw;
            const uint split = clamp(keep, first, end);
            PERMA_SWITCH_WORDS(tw, perma_copy_emits_out(first, split, end, keep, src, stack, slots, mask, marks, pos0,
                                                        PERMA_WORDS));
        }
    }
    const uint donated = command == PERMA_CMD_DONATE ? count : 0u;
    const uint words = perma_item_words[proc];
    __local const uint *items = mem->arena + perma_items_off[proc];
    __global uint *donee_marks = perma_queue_marks(donee, queue_seq, 0u);
    for (uint i = lid; i < donated; i += PERMA_GROUP_SIZE) {
        __global uint *dst = perma_queue_slot(donee, queue_data, mem->edge_base[0] + i, words);
        for (uint w = 0; w < words; ++w)
            dst[w] = items[i * words + w];
        if (i)
            perma_queue_clear_mark(donee_marks, donee[PERMA_Q_CAP], mem->edge_base[0] + i);
    }
}

/* Phase "publish", work-item 0, after every copy: publish every target's
 * range (and a donation's), then give back the room the batch reserved
 * and did not use (none for an edge that overflowed). */
PERMA_PHASE void perma_publish_emits(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq, __local perma_group_mem *mem,
                                     uint own)
{
    const uint command = mem->batch[PERMA_B_COMMAND];
    const uint proc = mem->batch[PERMA_B_PROC];
    const uint count = mem->batch[PERMA_B_COUNT];
    __global uint *donee = PERMA_QUEUE(ctl, mem->batch[PERMA_B_DEST]);
    const uint run = perma_batch_run(mem);
    const uint edges = run ? perma_edge_count[proc] : 0u;
    for (uint e = 0; e < edges; ++e) {
        uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
        if (!mem->edge_overflow[e])
            perma_queue_complete(PERMA_QUEUE(ctl, PERMA_QINDEX(own, t)), queue_seq, 0u,
                                 mem->edge_base[PERMA_MAX_EDGES + e], mem->edge_counts[e] - mem->edge_keep[e]);
    }
    if (command == PERMA_CMD_DONATE)
        perma_queue_complete(donee, queue_seq, 0u, mem->edge_base[0], count);
    for (uint e = 0; e < edges; ++e) {
        uint t = perma_edge_target[proc * PERMA_MAX_EDGES + e];
        if (!mem->edge_overflow[e])
            perma_queue_give_room(PERMA_QUEUE(ctl, PERMA_QINDEX(own, t)),
                                  (int)(mem->edge_reserved[e] - mem->edge_counts[e]));
    }
    if (count) {
        mem_fence(CLK_GLOBAL_MEM_FENCE);
        atomic_inc(ctl + PERMA_CTL_PROGRESS); /* stalled groups must look again */
    }
}

/* Phase "dispatch": run each item of the batch with its procedure
 * (generated after this file, since it follows the batch layout above). */
PERMA_PHASE void perma_dispatch(uint lid, __global uint *ctl, __local perma_group_mem *mem, __global uint *stage,
                                ulong *lane, perma_buffers buf);

/* Work-item 0 after a batch it ran: the progress counts in the group's
 * watch page record (kernels/perma_abi.h), its items and what it emitted
 * into each target. */
inline void perma_watch_counts(volatile __global uint *watch, __local const perma_group_mem *mem)
{
    const uint proc = mem->batch[PERMA_B_PROC];
    if (!perma_batch_run(mem))
        return;
    watch[PERMA_WATCH_COUNTS + proc] += perma_batch_run(mem);
    for (uint e = 0; e < perma_edge_count[proc]; ++e)
        watch[PERMA_WATCH_COUNTS + PERMA_NUM_PROCS + perma_edge_target[proc * PERMA_MAX_EDGES + e]] +=
            mem->edge_counts[e];
}

/* Run the batch in mem->batch: `count` items of `proc` (command RUN) or
 * move them to the donee (command DONATE).  The items come from the source
 * queue at `start`, from input[start..] when `input` is not null (the
 * host-driven step kernel), or from the group's local stack at `start`
 * (FROM_LOCAL; then the source is the global queue whose ROOM they hold).
 * Emits go to queue set `own`, first onto the local stack when
 * PERMA_LOCAL_QUEUE is on.  mem->batch may be rewritten only after the
 * last barrier in here. */
inline void perma_run_batch(__global uint *ctl, __global uint *queue_data, __global uint *queue_seq,
                            __global uint *emit_areas, volatile __global uint *abort_flag, __local perma_group_mem *mem,
                            ulong *lane, perma_buffers buf, __global const uint *input, uint own)
{
    /* The group's record in the watch page: the host's watchdog names the
     * procedure running if it never returns, and sees progress in DONE. */
    volatile __global uint *watch = abort_flag + PERMA_WATCH_RECORDS + get_group_id(0) * PERMA_WATCH_GROUP_WORDS;
    /* An atomic store: the work-items running stacks name theirs too
     * (perma_run_simple). */
    if (get_local_id(0) == 0 && perma_batch_run(mem))
        atomic_xchg(watch + PERMA_WATCH_RUNNING, mem->batch[PERMA_B_PROC] + 1u);
    /* The phases take the local id as an argument: PoCL inlines every
     * function that asks for it, which would hide them from a profile. */
    perma_read_items(get_local_id(0), ctl, queue_data, queue_seq, mem, input);
#if PERMA_ITEM_BARRIER
    /* The threads of an item (or a cooperative group) read what others copied. */
    barrier(CLK_LOCAL_MEM_FENCE);
#endif

    /* Run the procedure (the generated dispatch). */
    perma_dispatch(get_local_id(0), ctl, mem, perma_emit_area(emit_areas) + PERMA_EMIT_AREA_STAGE, lane, buf);
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);

    if (get_local_id(0) == 0)
        perma_reserve_emits(ctl, queue_data, queue_seq, emit_areas, mem, input, own);
    barrier(CLK_LOCAL_MEM_FENCE);
    perma_write_emits(get_local_id(0), ctl, queue_data, queue_seq, emit_areas, mem, own);
    barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE);
    if (get_local_id(0) == 0) {
        perma_publish_emits(ctl, queue_data, queue_seq, mem, own);
        if (perma_batch_run(mem) || mem->batch[PERMA_B_WF_RAN]) {
            atomic_xchg(watch + PERMA_WATCH_RUNNING, 0u);
            watch[PERMA_WATCH_DONE] += 1u;
            perma_watch_counts(watch, mem);
        }
        perma_wf_watch_counts(watch, mem);
    }
}
