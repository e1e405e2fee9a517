/*
 * perma's host/device ABI: the layout of the buffers the host and the
 * kernels share, the status words a launch ends with, and the order of the
 * kernels' arguments.  Defined once, here.
 *
 * This file is compiled as C11 by the runtime's host code (runtime/src) and
 * embedded verbatim at the top of every generated OpenCL C program (after
 * the generated #defines), so it may only use syntax both languages accept.
 * The kernels address the shared buffers as arrays of 32-bit words with the
 * word indices below; the host reads them through the structs below.  The
 * host checks (static assertions in runtime/src/abi.c) that each struct
 * member sits at its word index, and the generated program checks at
 * compile time that the device lays each struct out as the host does
 * (PERMA_ABI_CHECK, emitted by runtime/src/abi.c).
 */
#ifndef PERMA_ABI_H
#define PERMA_ABI_H

#ifdef __OPENCL_VERSION__
typedef uint perma_word;
typedef ulong perma_word64;
#else
#include <stdint.h>
typedef uint32_t perma_word;
typedef uint64_t perma_word64;
#endif

/* ---- Control block ----------------------------------------------------
 * One array of words: the header, then one queue record per queue (queue
 * index = set * procedures + procedure), then one group record per
 * persistent work-group. */

#define PERMA_CTL_OUTSTANDING 0 /* items queued or being processed (int) */
#define PERMA_CTL_STATUS 1      /* PERMA_KSTATUS_* */
#define PERMA_CTL_EXIT 2        /* nonzero: every group leaves the loop */
#define PERMA_CTL_DETAIL_PROC 3 /* procedure (or queue) that caused a failure status */
#define PERMA_CTL_DETAIL_EDGE 4 /* edge or position detail of a failure status */
#define PERMA_CTL_PROGRESS 5    /* epoch, bumped whenever queue room grows */
#define PERMA_CTL_CLOCK 6       /* unused (the trace clock is on the watch page) */
#define PERMA_CTL_GROW_STARVED 7 /* nonzero: a group starved of room may stop the launch to grow queues */
#define PERMA_CTL_HUNGRY 8      /* groups that found nothing to run (work-first stacks give to them) */
#define PERMA_CTL_HEADER_WORDS 16

typedef struct perma_ctl_header {
    perma_word outstanding;
    perma_word status;
    perma_word exit;
    perma_word detail_proc;
    perma_word detail_edge;
    perma_word progress;
    perma_word clock;
    perma_word grow_starved;
    perma_word hungry;
    perma_word reserved[7];
} perma_ctl_header;

/* A queue record fills a 64-byte line, so groups hammering one queue's
 * counters do not also invalidate the next queue's (docs/design.md, Queues). */
#define PERMA_Q_HEAD 0      /* next position to claim */
#define PERMA_Q_TAIL 1      /* next position to reserve for writing */
#define PERMA_Q_ROOM 2      /* free slots not promised to any batch (int) */
#define PERMA_Q_CAP 3       /* capacity, a power of two */
#define PERMA_Q_DATA 4      /* offset of slot 0 in queue_data, in words */
#define PERMA_Q_SEQ 5       /* offset of the completion marks in queue_seq: cap publishing, then cap releasing */
#define PERMA_Q_PEAK 6      /* most items queued at once */
#define PERMA_Q_PUBLISHED 7 /* positions below are written and may be claimed */
#define PERMA_Q_RELEASED 8  /* positions below are read: their slots are free */
#define PERMA_QUEUE_WORDS 16

typedef struct perma_queue_record {
    perma_word head;
    perma_word tail;
    perma_word room;
    perma_word cap;
    perma_word data;
    perma_word seq;
    perma_word peak;
    perma_word published;
    perma_word released;
    perma_word reserved[7];
} perma_queue_record;

#define PERMA_G_STATE 0    /* 0 not started, 1 running, 2 finished */
#define PERMA_G_BLOCKED 1  /* progress epoch + 1 when blocked on room, else 0 */
#define PERMA_GROUP_WORDS 2

typedef struct perma_group_record {
    perma_word state;
    perma_word blocked;
} perma_group_record;

/* Words of the control block for `queues` queues (sets x procedures) and
 * `groups` persistent work-groups. */
#define PERMA_CTL_WORDS_FOR(queues, groups) \
    (PERMA_CTL_HEADER_WORDS + (queues) * PERMA_QUEUE_WORDS + (groups) * PERMA_GROUP_WORDS)

/* ---- Status words ------------------------------------------------------
 * How a launch ended (header word STATUS) and what DETAIL_PROC and
 * DETAIL_EDGE then say. */

#define PERMA_KSTATUS_DONE 0       /* OUTSTANDING reached zero */
#define PERMA_KSTATUS_NEEDS_ROOM 1 /* grow and relaunch: DETAIL_PROC = PERMA_DETAIL_NONE when no group
                                      could reserve room, PERMA_DETAIL_STARVED when a group's batches kept
                                      being cut by the room of queue DETAIL_EDGE */
#define PERMA_KSTATUS_EMIT_LIMIT 2 /* a procedure emitted more than declared:
                                      DETAIL_PROC = procedure, DETAIL_EDGE = PERMA_EMIT_ERROR_* code */
/* 3 was a bounded wait on a queue slot that ran out: the queues no longer wait. */
#define PERMA_KSTATUS_ABORTED 4    /* the host watchdog asked the kernel to stop */
/* 5 was a regrowth that found an unpublished item: the host checks the
 * queue counters before it grows (runtime/src/state.c). */

/* DETAIL_PROC when no procedure or queue is concerned. */
#define PERMA_DETAIL_NONE 0xffffffffu
/* DETAIL_PROC of NEEDS_ROOM when a group was starved of room. */
#define PERMA_DETAIL_STARVED 0xfffffffeu
/* DETAIL_PROC of NEEDS_ROOM when a group put emits in its overflow area
 * (a target had no room for what a batch emitted beyond its reservation). */
#define PERMA_DETAIL_OVERFLOW 0xfffffffdu

/* PERMA_KSTATUS_EMIT_LIMIT codes in DETAIL_EDGE. */
#define PERMA_EMIT_ERROR_LIMIT 0x10000u      /* | edge: over the declared maximum */
#define PERMA_EMIT_ERROR_UNDECLARED 0x20000u /* | target: not in the procedure's .emits */
#define PERMA_EMIT_ERROR_DETAIL 0xffffu      /* the edge or target part */

/* ---- Statistics buffer -------------------------------------------------
 * One record per persistent work-group: per procedure ITEMS, BATCHES,
 * STACKED and one EMITTED word per edge (max_edges of them), then the group's
 * load-balancing counters. */

#define PERMA_STAT_ITEMS 0
#define PERMA_STAT_BATCHES 1
#define PERMA_STAT_STACKED 2 /* of ITEMS, those run from a work-item's stack (work-first) */
#define PERMA_STAT_EMITTED 3 /* then max_edges words */
#define PERMA_STAT_PROC_WORDS_FOR(max_edges) (3u + (max_edges))

#define PERMA_GSTAT_STEALS 0
#define PERMA_GSTAT_DONATIONS 1
#define PERMA_GSTAT_DONATED 2
#define PERMA_GSTAT_SPILLS 3
#define PERMA_GSTAT_IDLE_POLLS 4
#define PERMA_GSTAT_WF_RUNS 5   /* items run from the work-items' stacks (work-first) */
#define PERMA_GSTAT_WF_SPILLS 6 /* items moved from the stacks to the global queues */
#define PERMA_GSTAT_WF_PEAK 7   /* most items one work-item's stack held */
#define PERMA_GSTAT_WORDS 8

typedef struct perma_group_counters {
    perma_word steals;
    perma_word donations;
    perma_word donated;
    perma_word spills;
    perma_word idle_polls;
    perma_word wf_runs;
    perma_word wf_spills;
    perma_word wf_peak;
} perma_group_counters;

#define PERMA_STAT_GROUP_WORDS_FOR(procs, max_edges) \
    ((procs) * PERMA_STAT_PROC_WORDS_FOR(max_edges) + PERMA_GSTAT_WORDS)

/* ---- Trace buffer ------------------------------------------------------
 * Per group one count word, then `events` records (perma_trace_record). */

#define PERMA_TRACE_RUN 0u
#define PERMA_TRACE_STEAL 1u
#define PERMA_TRACE_LOCAL 2u
#define PERMA_TRACE_DONATE 3u
#define PERMA_TRACE_STACK 4u /* items run from the work-items' stacks (the record's items) */
#define PERMA_TRACE_KINDS 5u
/* A record's procedure for work of the stacks as a whole (a batch that only
 * ran stacks, items the stacks gave another group): their items are of any
 * procedure. */
#define PERMA_TRACE_STACKS 0xffu
#define PERMA_TRACE_RECORD_WORDS 4u

typedef struct perma_trace_record {
    perma_word proc_kind; /* procedure | kind << 8 */
    perma_word items;
    perma_word start;     /* ticks of the clock PERMA_WATCH_CLOCK */
    perma_word end;
} perma_trace_record;

#define PERMA_TRACE_GROUP_WORDS_FOR(events) (1u + PERMA_TRACE_RECORD_WORDS * (events))

/* ---- Regrowth ----------------------------------------------------------
 * Between launches the host grows queues on the device: it lays the queues
 * out again in fresh item and completion-mark (queue_seq) buffers and gives
 * perma_relayout_kernel one record per queue saying where its items are
 * and where they go (kernels/perma_relayout.cl), and where the items a
 * launch left in overflow areas are, which follow the queued ones.  The
 * new layout puts the queues one after another: a queue whose first slot is
 * s has its marks at 2 * s. */

typedef struct perma_relayout_record {
    perma_word head;     /* position of the first queued item */
    perma_word count;    /* items queued */
    perma_word old_cap;  /* capacity before, a power of two */
    perma_word old_data; /* offset before, in words */
    perma_word new_cap;  /* capacity after */
    perma_word new_data; /* offsets after: slot i holds the item at head + i */
    perma_word new_seq;  /* = 2 * the queue's first slot */
    perma_word words;    /* words per item */
    perma_word overflow; /* items from overflow areas appended after the queued ones */
    perma_word overflow_segments; /* how many segments they come in */
    perma_word overflow_first; /* word of the first segment in the segment list */
    perma_word reserved;
} perma_relayout_record;

#define PERMA_RELAYOUT_RECORD_WORDS 12
/* A segment of overflowed items in the segment list: where they start in
 * the emit-area buffer (words) and how many there are. */
#define PERMA_RELAYOUT_SEGMENT_WORDS 2

/* ---- Reductions --------------------------------------------------------
 * The exact float and double sums (kernels/perma_reduce.cl): digits of 32
 * bits in signed 64-bit words, then a control word whose high bits say
 * which infinities and NaNs were added. */
#define PERMA_EXACT_FLOAT_DIGITS 9   /* bits 0 .. 287 >= 23 + 253 + carries, in units of 2^-149 */
#define PERMA_EXACT_DOUBLE_DIGITS 66 /* bits 0 .. 2111 >= 52 + 2045 + carries, in units of 2^-1074 */
#define PERMA_EXACT_POS_INF_SEEN ((perma_word64)1 << 32)
#define PERMA_EXACT_NEG_INF_SEEN ((perma_word64)1 << 33)
#define PERMA_EXACT_NAN_SEEN ((perma_word64)1 << 34)

/* ---- Emit areas -------------------------------------------------------
 * One area per persistent work-group in the emit-area buffer, in global
 * memory: a header, the staging of a batch's emits (the procedures write
 * their emits there; room for every item's declared maximum, which costs
 * no __local memory), then the overflow data.  A batch reserves in each
 * target the ROOM of its expected emits before it runs and takes the rest
 * after; when a target has no room for the rest, the edge's emits are
 * copied to the overflow data and the launch ends with NEEDS_ROOM
 * (DETAIL_PROC = PERMA_DETAIL_OVERFLOW).  The host reads the headers,
 * grows the queues and appends the items to them on the device
 * (perma_relayout_kernel).  Header word RECORDS counts the overflow
 * records; record r (at PERMA_OVERFLOW_RECORD(r)) holds the queue index,
 * the item count and where the items start, in words from the overflow
 * data.  A group clears RECORDS when it starts; a batch's emits fit the
 * overflow data because they fit the staging. */
#define PERMA_OVERFLOW_RECORDS 0
#define PERMA_OVERFLOW_RECORD(r) (1u + 3u * (r))
#define PERMA_OVERFLOW_QUEUE 0
#define PERMA_OVERFLOW_COUNT 1
#define PERMA_OVERFLOW_AT 2
/* Records an area holds: a batch's overflowed edges, then (work-first)
 * one per procedure whose items the group's stacks held when the launch
 * stopped. */
#define PERMA_OVERFLOW_MAX_RECORDS (8 + 64) /* PERMA_MAX_EMITS + PERMA_MAX_PROCEDURES */
#define PERMA_EMIT_AREA_HEADER 224 /* the count and the records, rounded up */
#define PERMA_EMIT_AREA_STAGE PERMA_EMIT_AREA_HEADER
#define PERMA_EMIT_AREA_OVERFLOW_FOR(stage_words) (PERMA_EMIT_AREA_HEADER + (stage_words))
#define PERMA_EMIT_AREA_WORDS_FOR(stage_words) (PERMA_EMIT_AREA_HEADER + 2 * (stage_words))

/* ---- Watch page --------------------------------------------------------
 * Host memory the kernels see through a CL_MEM_USE_HOST_PTR buffer (their
 * abort_flag argument), so that the host can watch a running kernel
 * (runtime/src/watchdog.c, progress.c).  Word ABORT is the host's request
 * to stop, which every group polls.  Each work-group has a record of its
 * own, cache lines apart, in which its work-item 0 writes the procedure of
 * the batch it is running and counts the batches it finished (the host
 * tells a stuck run from a slow one by whether the counts move, and names
 * the procedures in flight), and per procedure the items it completed and
 * the items its batches emitted into that procedure (perma_get_progress).
 * Plain stores of words only that group writes; the host reads them
 * while the kernel runs only where the device shares memory with it. */

#define PERMA_WATCH_ABORT 0         /* nonzero: every group stops */
#define PERMA_WATCH_CLOCK 1         /* the trace's clock: ticks of batch starts and ends (atomic_inc),
                                       which the host reads with its own clock (runtime/src/trace.c) */
#define PERMA_WATCH_RECORDS 16      /* word of group 0's record */
#define PERMA_WATCH_RUNNING 0       /* procedure + 1 of the batch running; 0 between batches */
#define PERMA_WATCH_DONE 1          /* batches of items this group finished (wraps) */
#define PERMA_WATCH_COUNTS 16       /* items completed per procedure, then items emitted into each
                                       procedure: 2 * procedures words (wrap) */
#define PERMA_WATCH_RECORD_WORDS_FOR(procs) ((PERMA_WATCH_COUNTS + 2u * (procs) + 15u) / 16u * 16u)
#define PERMA_WATCH_WORDS_FOR(groups, procs) (PERMA_WATCH_RECORDS + (groups) * PERMA_WATCH_RECORD_WORDS_FOR(procs))

/* ---- Kernel arguments --------------------------------------------------
 * Each list gives (host index name, OpenCL C type, parameter name) in
 * argument order.  The host numbers the arguments from the lists
 * (PERMA_ARG_INDEX), the kernels declare their parameters from them
 * (PERMA_ARG_PARAM), so the order exists only here.  The user buffers
 * follow a kernel's own arguments, in binding order. */

/* perma_megakernel's arguments; perma_step_kernel begins with them too. */
#define PERMA_COMMON_ARGS(X)                                       \
    X(PERMA_ARG_CTL, __global uint *, ctl),                        \
    X(PERMA_ARG_QUEUE_DATA, __global uint *, queue_data),          \
    X(PERMA_ARG_QUEUE_SEQ, __global uint *, queue_seq),            \
    X(PERMA_ARG_GROUP_STATS, __global uint *, group_stats),        \
    X(PERMA_ARG_ABORT_FLAG, volatile __global uint *, abort_flag), \
    X(PERMA_ARG_TRACE, __global uint *, trace),                    \
    X(PERMA_ARG_EMIT_AREAS, __global uint *, emit_areas),          \
    X(PERMA_ARG_REDUCTIONS, __global ulong *, reductions)

/* perma_step_kernel's arguments after the common ones. */
#define PERMA_STEP_ARGS(X)                                   \
    X(PERMA_STEP_ARG_INPUT, __global const uint *, input),   \
    X(PERMA_STEP_ARG_PROC, uint, proc),                      \
    X(PERMA_STEP_ARG_COUNT, uint, count)

/* perma_take_kernel's arguments. */
#define PERMA_TAKE_ARGS(X)                                   \
    X(PERMA_TAKE_ARG_CTL, __global uint *, ctl),             \
    X(PERMA_TAKE_ARG_QUEUE_DATA, __global uint *, queue_data), \
    X(PERMA_TAKE_ARG_QUEUE_SEQ, __global uint *, queue_seq), \
    X(PERMA_TAKE_ARG_INPUT, __global uint *, input),         \
    X(PERMA_TAKE_ARG_QUEUE, uint, qi),                       \
    X(PERMA_TAKE_ARG_FIRST, uint, first),                    \
    X(PERMA_TAKE_ARG_COUNT, uint, count)

/* perma_relayout_kernel's arguments: the records, how many, the slots of
 * the new layout, the items before, the items and marks after, the
 * segment list (the same buffer as the records: the segments follow them)
 * and the emit areas (overflowed items). */
#define PERMA_RELAYOUT_ARGS(X)                                                 \
    X(PERMA_RELAYOUT_ARG_MAP, __global const perma_relayout_record *, map),    \
    X(PERMA_RELAYOUT_ARG_QUEUES, uint, queues),                                \
    X(PERMA_RELAYOUT_ARG_SLOTS, uint, slots),                                  \
    X(PERMA_RELAYOUT_ARG_OLD_DATA, __global const uint *, old_data),           \
    X(PERMA_RELAYOUT_ARG_NEW_DATA, __global uint *, new_data),                 \
    X(PERMA_RELAYOUT_ARG_NEW_SEQ, __global uint *, new_seq),                   \
    X(PERMA_RELAYOUT_ARG_SEGMENTS, __global const uint *, segments),           \
    X(PERMA_RELAYOUT_ARG_EMIT_AREAS, __global const uint *, emit_areas)

#define PERMA_ARG_PARAM(index, type, name) type name
#define PERMA_ARG_INDEX(index, type, name) index

#ifndef __OPENCL_VERSION__
enum perma_common_arg { PERMA_COMMON_ARGS(PERMA_ARG_INDEX), PERMA_MEGAKERNEL_USER_ARGS };
enum perma_step_arg {
    PERMA_STEP_ARG_BEFORE = PERMA_MEGAKERNEL_USER_ARGS - 1,
    PERMA_STEP_ARGS(PERMA_ARG_INDEX),
    PERMA_STEP_USER_ARGS
};
enum perma_take_arg { PERMA_TAKE_ARGS(PERMA_ARG_INDEX), PERMA_TAKE_ARG_TOTAL };
enum perma_relayout_arg { PERMA_RELAYOUT_ARGS(PERMA_ARG_INDEX), PERMA_RELAYOUT_ARG_TOTAL };
#endif

/* ---- Layout checks -----------------------------------------------------
 * Every member of a shared struct with the word index the kernels use for
 * it (checked on the host), and every shared struct with its size in words.
 * The generated program repeats each as PERMA_ABI_CHECK with the host's
 * numbers, so a device compiler that lays one out differently fails the
 * build with both numbers in the message. */
#define PERMA_ABI_MEMBERS(X)                                         \
    X(perma_ctl_header, outstanding, PERMA_CTL_OUTSTANDING)          \
    X(perma_ctl_header, status, PERMA_CTL_STATUS)                    \
    X(perma_ctl_header, exit, PERMA_CTL_EXIT)                        \
    X(perma_ctl_header, detail_proc, PERMA_CTL_DETAIL_PROC)          \
    X(perma_ctl_header, detail_edge, PERMA_CTL_DETAIL_EDGE)          \
    X(perma_ctl_header, progress, PERMA_CTL_PROGRESS)                \
    X(perma_ctl_header, clock, PERMA_CTL_CLOCK)                      \
    X(perma_ctl_header, grow_starved, PERMA_CTL_GROW_STARVED)        \
    X(perma_ctl_header, hungry, PERMA_CTL_HUNGRY)                    \
    X(perma_queue_record, head, PERMA_Q_HEAD)                        \
    X(perma_queue_record, tail, PERMA_Q_TAIL)                        \
    X(perma_queue_record, room, PERMA_Q_ROOM)                        \
    X(perma_queue_record, cap, PERMA_Q_CAP)                          \
    X(perma_queue_record, data, PERMA_Q_DATA)                        \
    X(perma_queue_record, seq, PERMA_Q_SEQ)                          \
    X(perma_queue_record, peak, PERMA_Q_PEAK)                        \
    X(perma_queue_record, published, PERMA_Q_PUBLISHED)              \
    X(perma_queue_record, released, PERMA_Q_RELEASED)                \
    X(perma_group_record, state, PERMA_G_STATE)                      \
    X(perma_group_record, blocked, PERMA_G_BLOCKED)                  \
    X(perma_group_counters, steals, PERMA_GSTAT_STEALS)              \
    X(perma_group_counters, donations, PERMA_GSTAT_DONATIONS)        \
    X(perma_group_counters, donated, PERMA_GSTAT_DONATED)            \
    X(perma_group_counters, spills, PERMA_GSTAT_SPILLS)              \
    X(perma_group_counters, idle_polls, PERMA_GSTAT_IDLE_POLLS)      \
    X(perma_group_counters, wf_runs, PERMA_GSTAT_WF_RUNS)            \
    X(perma_group_counters, wf_spills, PERMA_GSTAT_WF_SPILLS)        \
    X(perma_group_counters, wf_peak, PERMA_GSTAT_WF_PEAK)            \
    X(perma_trace_record, proc_kind, 0)                              \
    X(perma_trace_record, items, 1)                                  \
    X(perma_trace_record, start, 2)                                  \
    X(perma_trace_record, end, 3)                                    \
    X(perma_relayout_record, head, 0)                                \
    X(perma_relayout_record, count, 1)                               \
    X(perma_relayout_record, old_cap, 2)                             \
    X(perma_relayout_record, old_data, 3)                            \
    X(perma_relayout_record, new_cap, 4)                             \
    X(perma_relayout_record, new_data, 5)                            \
    X(perma_relayout_record, new_seq, 6)                             \
    X(perma_relayout_record, words, 7)                               \
    X(perma_relayout_record, overflow, 8)                            \
    X(perma_relayout_record, overflow_segments, 9)                   \
    X(perma_relayout_record, overflow_first, 10)

#define PERMA_ABI_STRUCTS(X)                           \
    X(perma_ctl_header, PERMA_CTL_HEADER_WORDS)        \
    X(perma_queue_record, PERMA_QUEUE_WORDS)           \
    X(perma_group_record, PERMA_GROUP_WORDS)           \
    X(perma_group_counters, PERMA_GSTAT_WORDS)         \
    X(perma_trace_record, PERMA_TRACE_RECORD_WORDS)    \
    X(perma_relayout_record, PERMA_RELAYOUT_RECORD_WORDS)

#ifdef __OPENCL_VERSION__
/* Fails the build unless host_bytes == device_bytes; the compiler's message
 * ("typedef redefinition with different types ('char[DEVICE]' vs
 * 'char[HOST]')") carries both numbers, and the host turns it into a
 * sentence (runtime/src/abi.c). */
#define PERMA_ABI_CHECK(name, host_bytes, device_bytes) \
    typedef char name[host_bytes];                      \
    typedef char name[device_bytes];
#ifdef __clang__
#define PERMA_ABI_OFFSETOF(type, member) __builtin_offsetof(type, member)
#else
#define PERMA_ABI_OFFSETOF(type, member) ((size_t) & (((type *)0)->member))
#endif
#endif

#endif
