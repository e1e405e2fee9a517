/*
 * The context a procedure receives, and emit staging.
 *
 * Emits are staged without atomics in the group's staging area (global
 * memory, room for every item's declared maximum, so a generous maximum
 * costs no __local memory).  A procedure of one
 * thread per item that is not cooperative stages per work-item ("lane"):
 * the work-item appends the emits of all its items of the batch to its own
 * area and counts them per edge, so its emits leave as one block.  Any other
 * procedure stages per item (the threads of a multi-thread item share a
 * local counter).  Either way each item also counts its emits per edge
 * against its declared maximum.  After the batch work-item 0 turns the
 * counts into offsets and reserves each target's positions with a single
 * global atomic, and every work-item copies its emits out
 * (kernels/perma_batch.cl).  Included after the generated `perma_buffers`
 * struct.
 */

typedef struct perma_ctx {
    uint proc;     /* id of the running procedure */
    uint thread;   /* 0 .. threads-1: this work-item's part of the item */
    uint threads;  /* threads_per_item of the procedure */
    uint slot;     /* index of the item in the batch */
    uint group;    /* persistent work-group id */
    uint active;   /* 1 if this work-item has an item (cooperative procedures) */
    __local void *scratch;            /* local_bytes_per_item for this item */
    __local uint *item_emit_counts;   /* per edge: items this item emitted */
    __local uint *lane_counts;        /* lane staging: per edge, items this work-item staged; else null */
    uint lane;                        /* lane staging: this work-item's local id */
    __global uint *stage;             /* the group's staging area */
#if PERMA_NUM_REDUCTIONS
    ulong *reduce;                    /* this work-item's lane of the reductions (kernels/perma_reduce.cl) */
#endif
    __local uint *error_code;         /* 0, or PERMA_EMIT_ERROR_* | detail (perma_abi.h) */
#if PERMA_WORK_FIRST
    /* Work-first (kernels/perma_work_first.cl): the item's emits into
     * stackable procedures go onto the work-item's stack (wf_room 1, set
     * only when the stack has room for all of them), else to the staging. */
    uint wf_room;
    uint wf_sp;                       /* the stack's next free slot */
    __local uint *wf_slots;           /* the work-item's stack: PERMA_WORK_FIRST slots */
    __local uint *wf_procs;           /* each slot's procedure (| PERMA_WF_DONE) */
#endif
    perma_buffers buf;                /* user buffers, by name */
} perma_ctx;

/* Stage one item emitted into procedure `target` by the running procedure
 * (its words: the emit helper hands them over as perma_item_word, see
 * kernels/perma_prelude.cl).  Returns 1 if staged, 0 if the target is not
 * declared in .emits or the item already emitted its declared maximum
 * there (the run then fails). */
PERMA_PHASE int perma_emit(perma_ctx *ctx, uint target, const perma_item_word *src)
{
    if (!ctx->active)
        return 0;
    int edge = perma_edge_index[ctx->proc * PERMA_NUM_PROCS + target];
    if (edge < 0) {
        atomic_cmpxchg(ctx->error_code, 0u, PERMA_EMIT_ERROR_UNDECLARED | target);
        return 0;
    }
    uint e = ctx->proc * PERMA_MAX_EDGES + (uint)edge;
    /* With one thread per item nobody else counts this item's emits. */
    uint own = ctx->threads == 1 ? ctx->item_emit_counts[edge]++ : atomic_inc(ctx->item_emit_counts + edge);
    uint max = perma_edge_max[e];
    if (own >= max) {
        atomic_cmpxchg(ctx->error_code, 0u, PERMA_EMIT_ERROR_LIMIT | (uint)edge);
        return 0;
    }
    uint words = perma_item_words[target];
    uint at = ctx->lane_counts ? ctx->lane * perma_lane_items[ctx->proc] * max + ctx->lane_counts[edge]++
                               : ctx->slot * max + own;
    __global perma_item_word *dst = (__global perma_item_word *)ctx->stage + perma_edge_stage[e] + at * words;
    for (uint w = 0; w < words; ++w)
        dst[w] = src[w];
    return 1;
}

#if PERMA_WORK_FIRST
/* A slot's procedure word: the procedure, and this bit once its item ran
 * (its children lie above it; the slot is free when they are done). */
#define PERMA_WF_DONE 0x80000000u

/* Push an item of procedure `target` onto the running work-item's stack:
 * the slot to write it to (the emit helper stores it there by its own
 * type, so the procedure that runs it reads the same fields it was
 * written with).  The caller made sure of the room for the item's
 * declared emits (ctx->wf_room); whether it kept to them is checked from
 * the stack when it returns (perma_run_simple), so a push costs no
 * counting.  A target not declared in .emits, or a push past the stack,
 * records the error (the run fails) and gets the stack's last slot to
 * write into, so the caller needs no test. */
PERMA_PHASE __local uint *perma_wf_push(perma_ctx *ctx, uint target)
{
    uint sp = ctx->wf_sp;
    int edge = perma_edge_index[ctx->proc * PERMA_NUM_PROCS + target];
    if (edge < 0 || sp >= PERMA_WORK_FIRST) {
        atomic_cmpxchg(ctx->error_code, 0u,
                       edge < 0 ? PERMA_EMIT_ERROR_UNDECLARED | target : PERMA_EMIT_ERROR_LIMIT | (uint)edge);
        return ctx->wf_slots + (PERMA_WORK_FIRST - 1u) * PERMA_WF_SLOT_WORDS;
    }
    ctx->wf_procs[sp] = target;
    ctx->wf_sp = sp + 1u;
    return ctx->wf_slots + sp * PERMA_WF_SLOT_WORDS;
}
#endif
