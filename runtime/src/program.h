#ifndef PERMA_PROGRAM_H
#define PERMA_PROGRAM_H

#include "perma.h"
#include "queues.h"

#include <stddef.h>

struct perma_strategy_info;

/* What a build fixes, the same until the next build: the layout
 * (layout.c), the reductions' lane (reductions.c) and the program and its
 * kernels (program.c) fill it at perma_build, and the run loop (run.c)
 * what the runs of this build learned; the code generator, the executors,
 * the device state and the statistics only read it. */
typedef struct perma_build_products {
    unsigned serial;               /* builds so far */
    perma_build_info info;         /* how the last build got its program */
    cl_program program;
    cl_kernel kernel;              /* perma_megakernel */
    cl_kernel step_kernel;         /* perma_step_kernel (host-driven techniques) */
    cl_kernel take_kernel;         /* perma_take_kernel */
    cl_kernel relayout_kernel;     /* perma_relayout_kernel (queue growth) */
    unsigned max_edges;
    unsigned arena_words;
    unsigned stage_words;          /* a group's staging area for emits (global memory), words */
    unsigned local_queue_items;    /* 0: no local front queue */
    unsigned lq_words;
    /* Work-first (layout.c, perma_schedule.work_first_items): items on a
     * work-item's stack (0: off, also when no procedure can be stacked),
     * words of a stack slot, items a work-item runs from its stack in one
     * batch, the room a stack item runs with, and the __local words of the
     * stacks and their counters. */
    unsigned wf_items;
    unsigned wf_slot_words;
    unsigned wf_budget;
    unsigned wf_need;              /* the most stack room an item of a stackable procedure needs */
    unsigned wf_words;
    size_t local_bytes;            /* the layout's figure of a group's __local memory (arena and the rest) */
    unsigned order[PERMA_MAX_PROCEDURES];
    unsigned queue_sets;           /* 1 (shared) or one per group (distributed) */
    const struct perma_strategy_info *strategy; /* the schedule table's row (schedule_table.h) */
    perma_queue_layout queue_layout; /* what the queue planner knows of the build (queues.h) */
    unsigned device_trace_events;  /* trace records per group the device keeps; 0: none */
    unsigned reduce_words;         /* words of a work-item's lane, all reductions */
    /* What the last run grew the queues to, when it succeeded (run.c): the
     * next run of the same build starts from them, memory permitting. */
    size_t *learned_capacities;    /* learned_count entries; NULL: none */
    unsigned learned_count, learned_build;
} perma_build_products;

/* program.c: perma_build after the call's start (perma_call_begin): build
 * unless built; let go of the program and its kernels. */
perma_status perma_build_program(perma_runtime *rt);
void perma_release_program(perma_runtime *rt);

#endif
