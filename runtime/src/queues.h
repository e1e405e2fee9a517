/* queues.h: the queue planner, how big the queues are.  Only numbers: it
 * sees no runtime and no device, just the build's queue layout and the
 * capacities and counts it is given (the device state, state.c, lays the
 * queues out; tests/runtime/test_queue_plan.c tests it alone). */
#ifndef PERMA_QUEUES_H
#define PERMA_QUEUES_H

#include "perma.h"

#include <stddef.h>

/* Bytes a queue slot costs beside its item: two completion marks
 * (kernels/perma_queue.cl). */
#define PERMA_QUEUE_SLOT_OVERHEAD 8
/* A queue's capacity when config.queue_capacity is 0. */
#define PERMA_DEFAULT_QUEUE_CAPACITY 1024

/* What the planner needs of one procedure. */
typedef struct perma_queue_proc {
    const char *name;
    size_t item_size;
    unsigned emit_count;
    unsigned emit_target[PERMA_MAX_EMITS]; /* procedure ids (after the build) */
    unsigned emit_max[PERMA_MAX_EMITS];
} perma_queue_proc;

/* The queues of a build: queue qi holds the items of procedure qi % procs
 * in queue set qi / procs.  Fixed once per build (layout.c fills it). */
typedef struct perma_queue_layout {
    unsigned procs;
    unsigned sets;             /* 1 (shared) or one per persistent group (distributed) */
    unsigned count;            /* queues: sets * procs */
    size_t initial_capacity;   /* items: config.queue_capacity or the default */
    size_t memory_limit;       /* bytes all queues may take */
    perma_queue_proc proc[PERMA_MAX_PROCEDURES];
} perma_queue_layout;

/* Bytes of the queues (items and completion marks) at these capacities. */
size_t perma_queues_bytes(const perma_queue_layout *layout, const size_t *capacities);
/* Whether `count` more seeds of procedure `proc`, which has `seeded`
 * already, stay within PERMA_MAX_QUEUED_ITEMS and the memory limit in the
 * queues they start in. */
perma_status perma_queues_check_seeds(const perma_queue_layout *layout, unsigned proc, size_t seeded, size_t count,
                                      perma_error *error);
/* The seeds each queue starts with, of seeds[proc] of its procedure:
 * items [first[qi], first[qi] + count[qi]) (with one queue set per group
 * they are dealt out in contiguous shares). */
void perma_queues_seed_shares(const perma_queue_layout *layout, const size_t *seeds, size_t *first, size_t *count);
/* Before a run: what the seeds (seeds[proc]) and any producer's one item
 * need; or, where `learned` (NULL: none) is more and all queues then fit
 * the memory limit, what the last successful run grew them to (*kept: how
 * many queues start higher for that). */
perma_status perma_queues_initial(const perma_queue_layout *layout, const size_t *seeds, const size_t *learned,
                                  size_t *capacities, unsigned *kept, perma_error *error);
/* After a launch stalled, from the `current` capacities and the items
 * queued[qi] in each: every target that lacks room for one waiting item's
 * emits doubles; or, when starved_queue is below the queue count (a
 * group's batches kept being cut by its room), only that queue.
 * overflow[qi]: items the groups left in their overflow areas for queue qi
 * (the relayout appends them); with some there, nothing needs to grow. */
perma_status perma_queues_grow_stalled(const perma_queue_layout *layout, const size_t *current, const size_t *queued,
                                       unsigned starved_queue, const size_t *overflow, size_t *capacities,
                                       perma_error *error);
/* Every queue with fewer free slots than needed[qi] grows to fit
 * (doubling), from the capacities already in capacities[]; the growth is
 * checked against the `current` ones. */
perma_status perma_queues_fit_more(const perma_queue_layout *layout, const size_t *current, const size_t *queued,
                                   const size_t *needed, size_t *capacities, perma_error *error);
/* The same from the current capacities. */
perma_status perma_queues_grow_to_fit(const perma_queue_layout *layout, const size_t *current, const size_t *queued,
                                      const size_t *needed, size_t *capacities, perma_error *error);

#endif
