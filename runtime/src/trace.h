#ifndef PERMA_TRACE_H
#define PERMA_TRACE_H

#include "perma.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct perma_trace_event {
    uint32_t group;     /* track; UINT32_MAX for host steps */
    uint32_t proc;      /* or PERMA_TRACE_STACKS: the work-first stacks, items of any procedure */
    uint32_t kind;      /* PERMA_TRACE_RUN ... PERMA_TRACE_STACK */
    uint32_t items;
    double start, end;  /* host time (perma_now) */
} perma_trace_event;

/* At host time `time` the trace clock (PERMA_WATCH_CLOCK) showed `tick`. */
typedef struct perma_trace_sample {
    double time;
    uint32_t tick;
} perma_trace_sample;

/* trace.c: the run's batches in host time.  Its state (the events, the
 * clock's samples) is opaque outside trace.c and exists only for a runtime
 * that writes a trace file (config.trace_path or PERMA_TRACE). */
typedef struct perma_trace_state perma_trace_state;
/* At perma_create, when a trace file is named. */
perma_status perma_trace_open(perma_runtime *rt);
bool perma_trace_on_device(const perma_runtime *rt);     /* the megakernel records batches */
void perma_trace_reset(perma_runtime *rt, double start); /* at the start of a run */
void perma_trace_launch_begins(perma_runtime *rt, double now); /* the megakernel is enqueued */
void perma_trace_read_clock(perma_runtime *rt, double now); /* while it runs */
void perma_trace_launch_ends(perma_runtime *rt, double now); /* it ended */
perma_status perma_trace_collect(perma_runtime *rt);       /* after each launch */
perma_status perma_trace_host_step(perma_runtime *rt, unsigned proc, uint32_t items, double start, double end);
void perma_trace_release(perma_runtime *rt);
/* The run's events (trace_file.c writes them) and its start in host time. */
const perma_trace_event *perma_trace_events(const perma_runtime *rt, size_t *count, double *start);
/* Most seconds between two readings of the trace clock while the
 * megakernel runs (the watchdog's loop wakes that often). */
#define PERMA_TRACE_SAMPLE_SECONDS 0.001

#endif
