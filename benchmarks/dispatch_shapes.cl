/* Dispatch shapes (perma-dispatch-shapes, docs/writing-procedures.md
 * section "Code the compiler can vectorise").  Each kernel runs the same
 * one-item "procedure" over its group's share of the keys, in batches of
 * SHAPES_BATCH items as perma's dispatch does, shaped one way: whether an
 * OpenCL CPU compiler (PoCL, Intel's) runs it several work-items per
 * vector instruction depends on the shape, not on the procedure.
 * SHAPES_GROUP (the local size) and SHAPES_BATCH are defined by the host. */
/* benchmarks/plain_work.h and dispatch_shapes_work.h come first (the
 * items: shapes_item, shapes_item_loop, shapes_item_double). */

/* shapes_item, never inlined: what a procedure too large for the inliner is. */
__attribute__((noinline)) ulong shapes_item_call(ulong key) { return shapes_item(key); }

#define SHAPES_FIRST (get_group_id(0) * per)

/* perma's dispatch: work-item lid runs items lid, lid + group size, ... of
 * each batch in a loop of its own. */
#define SHAPES_STRIDED(name, work)                                                     \
    __kernel void name(__global const ulong *in, __global ulong *out, uint per)       \
    {                                                                                  \
        for (uint b = 0; b < per / SHAPES_BATCH; ++b) {                                \
            const uint base = SHAPES_FIRST + b * SHAPES_BATCH;                         \
            for (uint s = get_local_id(0); s < SHAPES_BATCH; s += SHAPES_GROUP)        \
                out[base + s] = work(in[base + s]);                                    \
            barrier(CLK_GLOBAL_MEM_FENCE);                                             \
        }                                                                              \
    }

/* Rounds: one item per work-item between two barriers, so the compiler's
 * loop over the work-items is the innermost loop around the work.  ACC:
 * what else each work-item does with the item's value v (kept across the
 * barriers), SUM its total, stored after the items. */
#define SHAPES_ROUNDS(name, work, DECLARE, ACC, SUM)                                   \
    __kernel void name(__global const ulong *in, __global ulong *out, uint per)       \
    {                                                                                  \
        DECLARE;                                                                       \
        for (uint r = 0; r < per / SHAPES_GROUP; ++r) {                                \
            const uint i = SHAPES_FIRST + r * SHAPES_GROUP + get_local_id(0);          \
            const ulong v = work(in[i]);                                               \
            ACC;                                                                       \
            out[i] = v;                                                                \
            barrier(CLK_GLOBAL_MEM_FENCE);                                             \
        }                                                                              \
        SUM;                                                                           \
    }
#define SHAPES_NOTHING (void)0
#define SHAPES_STORE(total) out[get_num_groups(0) * per + get_global_id(0)] = (total)

SHAPES_STRIDED(strided, shapes_item)
SHAPES_STRIDED(strided_call, shapes_item_call)
SHAPES_STRIDED(strided_loop, shapes_item_loop)
SHAPES_STRIDED(strided_double, shapes_item_double)
SHAPES_ROUNDS(rounds, shapes_item, SHAPES_NOTHING, SHAPES_NOTHING, SHAPES_NOTHING)
SHAPES_ROUNDS(rounds_call, shapes_item_call, SHAPES_NOTHING, SHAPES_NOTHING, SHAPES_NOTHING)
SHAPES_ROUNDS(rounds_loop, shapes_item_loop, SHAPES_NOTHING, SHAPES_NOTHING, SHAPES_NOTHING)
SHAPES_ROUNDS(rounds_double, shapes_item_double, SHAPES_NOTHING, SHAPES_NOTHING, SHAPES_NOTHING)
/* A scalar accumulator, and an array indexed by data (a reduction lane's
 * shape), each kept across the barriers. */
SHAPES_ROUNDS(rounds_sum, shapes_item, ulong sum = 0, sum += v, SHAPES_STORE(sum))
SHAPES_ROUNDS(rounds_lane, shapes_item, ulong lane[4] = { 0 }, lane[v & 3u] += v,
              SHAPES_STORE(lane[0] + lane[1] + lane[2] + lane[3]))
