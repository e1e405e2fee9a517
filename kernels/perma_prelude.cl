/*
 * perma device prelude: addressing the control block, and small helpers.
 * Included in every generated program after the generated #defines
 * (PERMA_GROUP_SIZE, PERMA_NUM_PROCS, ...) and kernels/perma_abi.h, which
 * defines the layout of the buffers shared with the host: the control
 * block `ctl` is an array of uint, header words (PERMA_CTL_*), then one
 * record of PERMA_QUEUE_WORDS per queue (PERMA_Q_*; queue index = set *
 * PERMA_NUM_PROCS + procedure), then per-group words (PERMA_G_*).
 */
#pragma OPENCL EXTENSION cl_khr_global_int32_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_local_int32_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_global_int32_extended_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

/* Item memory.  The runtime moves items it knows only by their size (the
 * queues, the emit staging, the batch's copy in __local memory, the local
 * stacks) as 32-bit words, while procedures read and write them as their
 * own types (a struct with double fields, a float4, ...).  OpenCL C keeps
 * C's aliasing rules and PoCL's LLVM applies them: a load through a
 * `uint *` is taken not to read what a store to a `double` field wrote, so
 * the copy of an item that a procedure has just changed could be moved
 * before the change.  So every access of the runtime to memory that a
 * procedure also touches by its own type goes through perma_item_word, a
 * uint that may alias anything (as a char may): the emit's read of the
 * procedure's item (through a copy in a union when the item type is
 * aligned to less than 4 bytes: the generated emit helpers), and the writes of the items that a procedure
 * reads in place in __local memory (perma_copy_items_in,
 * perma_copy_emits_out).  Copies between the runtime's own buffers, which
 * no procedure reads by type, stay plain uint.  docs/design.md, *Item
 * memory and aliasing*. */
typedef uint __attribute__((may_alias)) perma_item_word;

/* Statistics and trace records of this program (kernels/perma_abi.h). */
#define PERMA_STAT_PROC_WORDS PERMA_STAT_PROC_WORDS_FOR(PERMA_MAX_EDGES)
#define PERMA_STAT_GROUP_WORDS PERMA_STAT_GROUP_WORDS_FOR(PERMA_NUM_PROCS, PERMA_MAX_EDGES)
#define PERMA_TRACE_GROUP_WORDS PERMA_TRACE_GROUP_WORDS_FOR(PERMA_TRACE_EVENTS)
#define PERMA_EMIT_AREA_WORDS PERMA_EMIT_AREA_WORDS_FOR(PERMA_STAGE_WORDS)
#define PERMA_EMIT_AREA_OVERFLOW PERMA_EMIT_AREA_OVERFLOW_FOR(PERMA_STAGE_WORDS)
#define PERMA_WATCH_GROUP_WORDS PERMA_WATCH_RECORD_WORDS_FOR(PERMA_NUM_PROCS)

#define PERMA_QUEUE(ctl, q) ((ctl) + PERMA_CTL_HEADER_WORDS + (q) * PERMA_QUEUE_WORDS)
#define PERMA_GROUP(ctl, g) \
    ((ctl) + PERMA_CTL_HEADER_WORDS + PERMA_QUEUE_SETS * PERMA_NUM_PROCS * PERMA_QUEUE_WORDS + \
     (g) * PERMA_GROUP_WORDS)

/* The phases of a batch (perma_pick_batch, perma_read_items, perma_dispatch,
 * perma_emit, perma_reserve_emits, perma_write_emits, perma_publish_emits)
 * are inline; built with -DPERMA_PROFILE_PHASES (e.g. through PoCL's
 * POCL_EXTRA_BUILD_FLAGS) they and the procedures stay separate functions,
 * so a profile shows what each costs (docs/benchmarks.md). */
#ifdef PERMA_PROFILE_PHASES
#define PERMA_PHASE __attribute__((noinline))
#else
#define PERMA_PHASE inline __attribute__((always_inline))
#endif
/* Inlined into every caller, so a caller's constant arguments (an item's
 * word count under PERMA_SWITCH_WORDS) fold into its code. */
#define PERMA_INLINE inline __attribute__((always_inline))

/* A read that always goes to memory (another group may have written it).
 * A word that other groups update with atomics is read with a plain
 * volatile load: OpenCL 1.2 has no atomic load, an aligned 32-bit load is
 * not torn, and every reader tolerates a stale value (it polls again, or
 * the protocol re-checks with an atomic).  Oclgrind's race detector counts
 * such a load against a concurrent atomic as a data race; under it
 * (tests/portability/run_on.sh defines PERMA_RACE_CHECK) the load is an
 * atomic that changes nothing, so the races it still reports are real. */
inline uint perma_load(__global uint *p)
{
#ifdef PERMA_RACE_CHECK
    return atomic_or(p, 0u);
#else
    return *(volatile __global uint *)p;
#endif
}

inline int perma_load_int(__global uint *p)
{
    return (int)perma_load(p);
}

/* The group's emit area (kernels/perma_abi.h): overflow records, the
 * staging of its emits, the overflow data. */
inline __global uint *perma_emit_area(__global uint *emit_areas)
{
    return emit_areas + get_group_id(0) * PERMA_EMIT_AREA_WORDS;
}
/* For a procedure with a long or unbounded loop: nonzero once the host's
 * watchdog has asked the run to stop (its time or stall limit passed,
 * config.time_limit, config.stall_limit).  The scheduler polls the same
 * flag between batches, but a procedure that never returns never gets
 * there, and OpenCL cannot cancel a running kernel: such a kernel runs on
 * until the process exits.  A loop that tests this flag ends instead, the
 * run fails with the watchdog's error and the runtime stays usable
 * (docs/writing-procedures.md). */
#define perma_stop_requested(ctx) ((ctx)->buf.perma_watch_page[PERMA_WATCH_ABORT] != 0u)

/* Record a failure status once (the first one wins) and stop all groups. */
inline void perma_fail(__global uint *ctl, uint status, uint proc, uint edge)
{
    if (atomic_cmpxchg(ctl + PERMA_CTL_STATUS, PERMA_KSTATUS_DONE, status) == PERMA_KSTATUS_DONE) {
        ctl[PERMA_CTL_DETAIL_PROC] = proc;
        ctl[PERMA_CTL_DETAIL_EDGE] = edge;
    }
    mem_fence(CLK_GLOBAL_MEM_FENCE);
    atomic_xchg(ctl + PERMA_CTL_EXIT, 1u);
}
