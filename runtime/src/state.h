/* state.h: the device state, state.c's alone.  Everything the kernels use
 * on the device (the control block, the queues' items and completion
 * marks, statistics, trace, emit areas, reductions, the watch page) lives
 * in an opaque perma_device_state; no other module touches a cl_mem of it
 * or reads or writes it: they ask these functions. */
#ifndef PERMA_STATE_H
#define PERMA_STATE_H

#include "perma.h"
#include "perma_abi.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The host's view of a control block (kernels/perma_abi.h): the header and
 * the queue records, which follow it without a gap; the group records after
 * them stay the kernels' business. */
typedef struct perma_ctl_block {
    perma_ctl_header header;
    perma_queue_record queues[];
} perma_ctl_block;

/* Bytes of the header and the first `queues` queue records. */
size_t perma_ctl_block_bytes(size_t queues);

/* One queue of the launch state. */
typedef struct perma_queue_state {
    size_t capacity;     /* items, a power of two */
    size_t initial;      /* its capacity when this run started */
    unsigned regrowths;  /* times it grew in this run */
} perma_queue_state;

typedef struct perma_device_state perma_device_state;

perma_status perma_state_open(perma_runtime *rt);
void perma_state_close(perma_runtime *rt);
/* An empty launch state (nothing outstanding) for warming up kernels. */
perma_status perma_state_empty(perma_runtime *rt);
/* The first launch state of a run: queues of these capacities (`bytes` in
 * all, queues.h) holding the seeds: queue qi items [seed_first[qi],
 * seed_first[qi] + seed_count[qi]) of its procedure's seeds. */
perma_status perma_state_upload(perma_runtime *rt, const size_t *capacities, size_t bytes, const size_t *seed_first,
                                const size_t *seed_count);
/* Before each launch: statistics zeroed, watchdog flag down. */
perma_status perma_state_begin_launch(perma_runtime *rt);
/* After a launch that stopped for room, per queue: its capacity, the items
 * queued in it and, `with_overflow`, the items its groups left in their
 * overflow areas (else 0).  The control block and the overflow records
 * are kept for perma_state_grow, which appends the overflowed items to the
 * grown queues. */
perma_status perma_state_read_queues(perma_runtime *rt, bool with_overflow, size_t *capacities, size_t *queued,
                                     size_t *overflow);
/* The header and the first `queues` queue records, read back. */
perma_status perma_state_read_control(perma_runtime *rt, perma_ctl_block *out, unsigned queues);
perma_status perma_state_read_header(perma_runtime *rt, perma_ctl_header *out);
/* Write the record of queue q (its counters; the capacity and offsets are
 * unchanged) without waiting: *record must stay unchanged until the next
 * blocking call on the queue. */
perma_status perma_state_write_queue_counters(perma_runtime *rt, unsigned q, const perma_queue_record *record);
/* Between launches, after perma_state_read_queues: give the queues these
 * capacities (`bytes` in all) on the device, their items moved by
 * perma_relayout_kernel and the overflowed items appended. */
perma_status perma_state_grow(perma_runtime *rt, const size_t *capacities, size_t bytes);
perma_status perma_state_read_stats(perma_runtime *rt, uint32_t *words, size_t count);
perma_status perma_state_read_trace(perma_runtime *rt, uint32_t *words, size_t count);
/* The step kernels' input buffer, at least `words` words. */
perma_status perma_state_ensure_input(perma_runtime *rt, size_t words);
/* Set the arguments PERMA_COMMON_ARGS lists, and the user buffers from
 * `first_user_arg` on. */
perma_status perma_state_bind(perma_runtime *rt, cl_kernel kernel, cl_uint first_user_arg);
/* Ask every group of a running kernel to stop (the watchdog). */
void perma_state_raise_abort(perma_runtime *rt);
/* Whether the watchdog raised it during this launch (a host-driven run
 * checks between its steps: a procedure that polls perma_stop_requested
 * returns and its step completes). */
bool perma_state_abort_raised(const perma_runtime *rt);
/* What the watch page says while a kernel runs: the batches the groups
 * finished so far (a sum that moves while items complete), and in
 * running[0..procs) how many groups run a batch of each procedure. */
uint64_t perma_state_watch(const perma_runtime *rt, unsigned *running, unsigned procs);
/* Group `group`'s record on the watch page (PERMA_WATCH_RUNNING, ...). */
const uint32_t *perma_state_watch_record(const perma_runtime *rt, unsigned group);
/* The queues on the device: *count records, index set * procs + proc. */
const perma_queue_state *perma_state_queues(const perma_runtime *rt, unsigned *count);
/* The reductions' slots (`words` 64-bit words), written before a run and
 * read after it (kernels/perma_reduce.cl). */
perma_status perma_state_write_reductions(perma_runtime *rt, const uint64_t *slots, size_t words);
perma_status perma_state_read_reductions(perma_runtime *rt, uint64_t *slots, size_t words);
/* The host-driven techniques' kernels: the take kernel's queue and input
 * arguments; the step kernel's common arguments, user buffers and input. */
perma_status perma_state_bind_take(perma_runtime *rt);
perma_status perma_state_bind_step(perma_runtime *rt);
/* The trace clock on the watch page (PERMA_WATCH_CLOCK). */
uint32_t perma_state_watch_clock(const perma_runtime *rt);

#endif
