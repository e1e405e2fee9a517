/* Trace mode: each work-group's batches, in host time (trace_file.c writes
 * them as Chrome trace events).
 *
 * The megakernel's groups record each batch's start and end as ticks of a
 * clock on the watch page (PERMA_WATCH_CLOCK, one atomic_inc per batch
 * start or end): OpenCL 1.2 gives a kernel no clock of its own.  The host
 * reads that word with its own clock while the kernel runs (from the
 * watchdog's loop, at least every SAMPLE_SECONDS) and keeps the samples
 * where it moved: "at host time h the clock showed k".  A tick v then
 * happened after the last sample showing at most v and before the first
 * showing more, and gets the time interpolated between the two; the
 * launch's start (tick 0) and end (its last tick) close the list.  So
 * every event lies within its launch and in the order of its ticks, with
 * an error below the interval between samples.  On a device whose watch
 * page the host cannot see during a kernel only the start and end remain,
 * and the ticks spread evenly over the launch.  Host-driven steps are
 * timed on the host. */
#include "internal.h"
#include "state.h"
#include "trace.h"

#include <stdlib.h>
#include <string.h>

struct perma_trace_state {
    perma_trace_event *events;  /* the current run's */
    size_t count, alloc;
    double start_time;          /* host time of the run's start */
    /* The launch's trace clock as the host saw it. */
    perma_trace_sample *samples;
    size_t sample_count, sample_alloc;
    bool pending;               /* the clock showed the last sample's tick still at: */
    double pending_time;
};

perma_status perma_trace_open(perma_runtime *rt)
{
    rt->trace = calloc(1, sizeof *rt->trace);
    if (!rt->trace)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory recording the trace");
    return PERMA_OK;
}

/* Persistent groups record their own batches (the build decides:
 * build.device_trace_events); the host records the steps of the others. */
bool perma_trace_on_device(const perma_runtime *rt)
{
    return rt->build.device_trace_events > 0;
}

void perma_trace_reset(perma_runtime *rt, double start)
{
    if (!rt->trace)
        return;
    rt->trace->count = 0;
    rt->trace->start_time = start;
}

void perma_trace_release(perma_runtime *rt)
{
    if (!rt->trace)
        return;
    free(rt->trace->events);
    free(rt->trace->samples);
    free(rt->trace);
    rt->trace = NULL;
}

const perma_trace_event *perma_trace_events(const perma_runtime *rt, size_t *count, double *start)
{
    *count = rt->trace ? rt->trace->count : 0;
    *start = rt->trace ? rt->trace->start_time : 0.0;
    return rt->trace ? rt->trace->events : NULL;
}

static perma_status push_event(perma_runtime *rt, const perma_trace_event *event)
{
    perma_trace_state *t = rt->trace;
    if (t->count == t->alloc) {
        size_t alloc = t->alloc ? t->alloc * 2 : 4096;
        perma_trace_event *events = realloc(t->events, alloc * sizeof *events);
        if (!events)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory recording the trace");
        t->events = events;
        t->alloc = alloc;
    }
    t->events[t->count++] = *event;
    return PERMA_OK;
}

/* Keep a sample (a failed allocation loses it: the interpolation is then
 * coarser, never wrong). */
static void push_sample(perma_trace_state *t, double time, uint32_t tick)
{
    if (t->sample_count == t->sample_alloc) {
        size_t alloc = t->sample_alloc ? t->sample_alloc * 2 : 1024;
        perma_trace_sample *samples = realloc(t->samples, alloc * sizeof *samples);
        if (!samples)
            return;
        t->samples = samples;
        t->sample_alloc = alloc;
    }
    t->samples[t->sample_count++] = (perma_trace_sample){ time, tick };
}


void perma_trace_launch_begins(perma_runtime *rt, double now)
{
    perma_trace_state *t = rt->trace;
    if (!perma_trace_on_device(rt))
        return;
    t->sample_count = 0;
    t->pending = false;
    push_sample(t, now, 0); /* the page was cleared: tick 0 */
}

void perma_trace_read_clock(perma_runtime *rt, double now)
{
    perma_trace_state *t = rt->trace;
    if (!perma_trace_on_device(rt) || t->sample_count == 0)
        return;
    uint32_t tick = perma_state_watch_clock(rt);
    if (tick == t->samples[t->sample_count - 1].tick) {
        /* Not moved: remember the latest time it still showed this. */
        t->pending = true;
        t->pending_time = now;
        return;
    }
    if (t->pending)
        push_sample(t, t->pending_time, t->samples[t->sample_count - 1].tick);
    t->pending = false;
    push_sample(t, now, tick);
}

void perma_trace_launch_ends(perma_runtime *rt, double now)
{
    perma_trace_state *t = rt->trace;
    if (!perma_trace_on_device(rt) || t->sample_count == 0)
        return;
    perma_trace_read_clock(rt, now);
    if (t->pending)
        push_sample(t, t->pending_time, t->samples[t->sample_count - 1].tick);
    t->pending = false;
}

/* The host time of tick v (the batch start or end whose atomic_inc
 * returned v, so the clock moved from v to v + 1 then): between the last
 * sample showing at most v and the next one, in proportion. */
static double tick_time(const perma_trace_sample *samples, size_t count, uint32_t v)
{
    size_t lo = 0, hi = count; /* the first sample showing more than v is in [lo, hi] */
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (samples[mid].tick <= v)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo == 0)
        return samples[0].time;
    if (lo == count)
        return samples[count - 1].time;
    const perma_trace_sample *a = &samples[lo - 1], *b = &samples[lo];
    double share = ((double)(v - a->tick) + 0.5) / (double)(b->tick - a->tick);
    return a->time + share * (b->time - a->time);
}

/* The records group g kept in the trace buffer read back (count word,
 * then the records; kernels/perma_abi.h). */
static uint32_t records(const perma_runtime *rt, const uint32_t *buffer, unsigned g)
{
    uint32_t count = buffer[g * PERMA_TRACE_GROUP_WORDS_FOR((size_t)rt->build.device_trace_events)];
    return count < rt->build.device_trace_events ? count : rt->build.device_trace_events;
}

static perma_trace_record record(const uint32_t *buffer, unsigned g, uint32_t i, size_t per_group)
{
    perma_trace_record r;
    memcpy(&r, buffer + g * per_group + 1 + PERMA_TRACE_RECORD_WORDS * i, sizeof r);
    return r;
}

perma_status perma_trace_collect(perma_runtime *rt)
{
    perma_trace_state *t = rt->trace;
    if (!perma_trace_on_device(rt))
        return PERMA_OK;
    size_t per_group = PERMA_TRACE_GROUP_WORDS_FOR((size_t)rt->build.device_trace_events);
    size_t words = rt->work_groups * per_group;
    uint32_t *buffer = malloc(words * 4);
    if (!buffer)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory reading the trace");
    perma_status st = perma_state_read_trace(rt, buffer, words);
    if (st != PERMA_OK || t->sample_count == 0) {
        free(buffer);
        return st;
    }
    /* The launch's last tick closes the samples, even where the host saw
     * the clock only at the start. */
    uint32_t last = 0;
    for (unsigned g = 0; g < rt->work_groups; ++g)
        for (uint32_t i = 0, count = records(rt, buffer, g); i < count; ++i) {
            perma_trace_record r = record(buffer, g, i, per_group);
            if (r.end + 1 > last)
                last = r.end + 1;
        }
    perma_trace_sample *end = &t->samples[t->sample_count - 1];
    if (end->tick < last)
        end->tick = last;
    for (unsigned g = 0; g < rt->work_groups && st == PERMA_OK; ++g) {
        for (uint32_t i = 0, count = records(rt, buffer, g); i < count && st == PERMA_OK; ++i) {
            perma_trace_record r = record(buffer, g, i, per_group);
            perma_trace_event event = { g, r.proc_kind & 0xffu, (r.proc_kind >> 8) & 0xffu, r.items,
                                        tick_time(t->samples, t->sample_count, r.start),
                                        tick_time(t->samples, t->sample_count, r.end) };
            if ((event.proc >= rt->proc_count && event.proc != PERMA_TRACE_STACKS) || event.kind >= PERMA_TRACE_KINDS)
                continue;
            st = push_event(rt, &event);
        }
    }
    free(buffer);
    return st;
}

perma_status perma_trace_host_step(perma_runtime *rt, unsigned proc, uint32_t items, double start, double end)
{
    if (!rt->trace)
        return PERMA_OK;
    perma_trace_event event = { UINT32_MAX, proc, 0, items, start, end };
    return push_event(rt, &event);
}
