/*
 * perma device prelude: the layout of the control block shared with the
 * host, and small helpers.  Included first in every generated program, after
 * the generated #defines (PERMA_GROUP_SIZE, PERMA_NUM_PROCS, ...).
 *
 * The control block `ctl` is an array of uint:
 *   header words (PERMA_CTL_*), then one record of PERMA_QUEUE_WORDS per
 *   queue (PERMA_Q_*; queue index = set * PERMA_NUM_PROCS + procedure),
 *   then per-group words (PERMA_G_*).
 * Keep in sync with runtime/src/control.h.
 */
#pragma OPENCL EXTENSION cl_khr_global_int32_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_local_int32_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_global_int32_extended_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

#define PERMA_CTL_OUTSTANDING 0 /* items queued or being processed (int) */
#define PERMA_CTL_STATUS 1      /* PERMA_KSTATUS_* */
#define PERMA_CTL_EXIT 2        /* nonzero: every group leaves the loop */
#define PERMA_CTL_DETAIL_PROC 3 /* procedure that caused a failure status */
#define PERMA_CTL_DETAIL_EDGE 4 /* edge index for PERMA_KSTATUS_EMIT_LIMIT */
#define PERMA_CTL_PROGRESS 5    /* epoch, bumped whenever queue room grows */
#define PERMA_CTL_CLOCK 6       /* logical clock of the trace */
#define PERMA_CTL_GROW_STARVED 7 /* nonzero: a group starved of room may stop the launch to grow queues */
#define PERMA_CTL_HEADER_WORDS 16

#define PERMA_Q_HEAD 0      /* next position to claim */
#define PERMA_Q_TAIL 1      /* next position to reserve for writing */
#define PERMA_Q_ROOM 2      /* free slots not promised to any batch (int) */
#define PERMA_Q_CAP 3       /* capacity, a power of two */
#define PERMA_Q_DATA 4      /* offset of slot 0 in queue_data, in words */
#define PERMA_Q_PUBLISHED 5 /* positions below are written and may be claimed */
#define PERMA_Q_PEAK 6      /* most items queued at once */
#define PERMA_Q_RELEASED 7  /* positions below are read: their slots are free */
#define PERMA_QUEUE_WORDS 8

#define PERMA_G_STATE 0    /* 0 not started, 1 running, 2 finished */
#define PERMA_G_BLOCKED 1  /* progress epoch + 1 when blocked on room, else 0 */
#define PERMA_GROUP_WORDS 2

#define PERMA_KSTATUS_DONE 0
#define PERMA_KSTATUS_NEEDS_ROOM 1 /* no group could reserve room: grow and relaunch */
/* DETAIL_PROC of NEEDS_ROOM: every group stalled, or one was starved. */
#define PERMA_DETAIL_STALLED 0xffffffffu
#define PERMA_DETAIL_STARVED 0xfffffffeu
#define PERMA_KSTATUS_EMIT_LIMIT 2 /* a procedure emitted more than declared */
/* 3 was a bounded wait that ran out: the queues no longer wait. */
#define PERMA_KSTATUS_ABORTED 4    /* the host watchdog asked us to stop */

/* Per-group statistics record, written once when the group leaves. */
#define PERMA_STAT_ITEMS 0
#define PERMA_STAT_BATCHES 1
#define PERMA_STAT_EMITTED 2 /* then PERMA_MAX_EDGES words */
#define PERMA_STAT_PROC_WORDS (2 + PERMA_MAX_EDGES)
/* After the per-procedure records: the group's load-balancing counters. */
#define PERMA_GSTAT_STEALS 0
#define PERMA_GSTAT_DONATIONS 1
#define PERMA_GSTAT_DONATED 2
#define PERMA_GSTAT_SPILLS 3
#define PERMA_GSTAT_IDLE_POLLS 4
#define PERMA_GSTAT_WORDS 8
#define PERMA_STAT_GROUP_WORDS (PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS + PERMA_GSTAT_WORDS)

/* Trace (PERMA_TRACE_EVENTS > 0): per group one count word, then
 * PERMA_TRACE_EVENTS records of 4 words: procedure | kind << 8, items,
 * logical start, logical end. */
#define PERMA_TRACE_RUN 0u
#define PERMA_TRACE_STEAL 1u
#define PERMA_TRACE_LOCAL 2u
#define PERMA_TRACE_DONATE 3u
#define PERMA_TRACE_GROUP_WORDS (1u + 4u * PERMA_TRACE_EVENTS)

#define PERMA_QUEUE(ctl, q) ((ctl) + PERMA_CTL_HEADER_WORDS + (q) * PERMA_QUEUE_WORDS)
#define PERMA_GROUP(ctl, g) \
    ((ctl) + PERMA_CTL_HEADER_WORDS + PERMA_QUEUE_SETS * PERMA_NUM_PROCS * PERMA_QUEUE_WORDS + \
     (g) * PERMA_GROUP_WORDS)

/* The phases of a batch (perma_schedule, perma_read_items, perma_dispatch,
 * perma_emit, perma_reserve_emits, perma_write_emits, perma_publish_emits)
 * are inline; built with -DPERMA_PROFILE_PHASES (e.g. through PoCL's
 * POCL_EXTRA_BUILD_FLAGS) they and the procedures stay separate functions,
 * so a profile shows what each costs (docs/benchmarks.md). */
#ifdef PERMA_PROFILE_PHASES
#define PERMA_PHASE __attribute__((noinline))
#else
#define PERMA_PHASE inline __attribute__((always_inline))
#endif

/* A read that always goes to memory (another group may have written it). */
inline uint perma_load(__global uint *p)
{
    return *(volatile __global uint *)p;
}

inline int perma_load_int(__global uint *p)
{
    return (int)perma_load(p);
}

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
