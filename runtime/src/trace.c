/* Trace mode: each work-group's batches as Chrome trace events (JSON),
 * viewable in Perfetto (ui.perfetto.dev) or chrome://tracing. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

static const char *const kind_names[] = { "run", "steal", "local", "donate" };

/* Persistent groups record their own batches (the build decides:
 * device_trace_events); the host records the steps of the others. */
static bool tracing_on_device(const perma_runtime *rt)
{
    return rt->device_trace_events > 0;
}

void perma_trace_reset(perma_runtime *rt, double start)
{
    rt->trace_count = 0;
    rt->trace_clock_base = 0.0;
    rt->trace_start_time = start;
}

void perma_trace_release(perma_runtime *rt)
{
    free(rt->trace);
    rt->trace = NULL;
    rt->trace_count = rt->trace_alloc = 0;
}

static perma_status push_event(perma_runtime *rt, const perma_trace_event *event)
{
    if (rt->trace_count == rt->trace_alloc) {
        size_t alloc = rt->trace_alloc ? rt->trace_alloc * 2 : 4096;
        perma_trace_event *events = realloc(rt->trace, alloc * sizeof *events);
        if (!events)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory recording the trace");
        rt->trace = events;
        rt->trace_alloc = alloc;
    }
    rt->trace[rt->trace_count++] = *event;
    return PERMA_OK;
}

perma_status perma_trace_collect(perma_runtime *rt)
{
    if (!tracing_on_device(rt))
        return PERMA_OK;
    size_t per_group = PERMA_TRACE_GROUP_WORDS_FOR((size_t)rt->device_trace_events);
    size_t words = rt->work_groups * per_group;
    uint32_t *buffer = malloc(words * 4);
    if (!buffer)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory reading the trace");
    perma_status st = perma_state_read_trace(rt, buffer, words);
    if (st != PERMA_OK) {
        free(buffer);
        return st;
    }
    double last = 0.0;
    for (unsigned g = 0; g < rt->work_groups && st == PERMA_OK; ++g) {
        const uint32_t *group = buffer + g * per_group;
        uint32_t count = group[0] < rt->device_trace_events ? group[0] : rt->device_trace_events;
        for (uint32_t i = 0; i < count && st == PERMA_OK; ++i) {
            perma_trace_record r;
            memcpy(&r, group + 1 + PERMA_TRACE_RECORD_WORDS * i, sizeof r);
            perma_trace_event event = { g, r.proc_kind & 0xffu, (r.proc_kind >> 8) & 0xffu, r.items,
                                        rt->trace_clock_base + r.start, rt->trace_clock_base + r.end };
            if (event.proc >= rt->proc_count || event.kind >= PERMA_TRACE_KINDS)
                continue;
            if (event.end > last)
                last = event.end;
            st = push_event(rt, &event);
        }
    }
    free(buffer);
    /* The next launch's clock starts at zero again. */
    if (last >= rt->trace_clock_base)
        rt->trace_clock_base = last + 1.0;
    return st;
}

perma_status perma_trace_host_step(perma_runtime *rt, unsigned proc, uint32_t items, double start, double end)
{
    if (!rt->config.trace_path)
        return PERMA_OK;
    perma_trace_event event = { UINT32_MAX, proc, 0, items, (start - rt->trace_start_time) * 1e6,
                                (end - rt->trace_start_time) * 1e6 };
    return push_event(rt, &event);
}

perma_status perma_trace_write(perma_runtime *rt)
{
    if (!rt->config.trace_path)
        return PERMA_OK;
    perma_output *out;
    perma_error error;
    if (perma_output_open(rt->config.trace_path, &out, &error) != PERMA_OK)
        return perma_set_error(rt, error.status, "cannot write the trace: %s", error.message);
    FILE *f = perma_output_stream(out);
    bool host = !tracing_on_device(rt);
    fprintf(f, "{\"displayTimeUnit\":\"ns\",\"otherData\":{\"runtime\":\"perma %s\",\"technique\":\"%s\","
               "\"strategy\":\"%s\",\"clock\":\"%s\"},\n\"traceEvents\":[\n",
            PERMA_VERSION_STRING, perma_technique_name(rt->config.schedule.technique),
            perma_strategy_name(rt->config.schedule.strategy),
            host ? "host microseconds" : "logical: one tick per batch start or end");
    if (host) {
        fprintf(f, "{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":1,\"tid\":0,\"args\":{\"name\":\"host steps\"}}");
    } else {
        for (unsigned g = 0; g < rt->work_groups; ++g)
            fprintf(f, "%s{\"name\":\"thread_name\",\"ph\":\"M\",\"pid\":1,\"tid\":%u,\"args\":{\"name\":\"group %u\"}}",
                    g ? ",\n" : "", g, g);
    }
    for (size_t i = 0; i < rt->trace_count; ++i) {
        const perma_trace_event *e = &rt->trace[i];
        double duration = e->end > e->start ? e->end - e->start : 0.0;
        fprintf(f, ",\n{\"name\":\"%s\",\"cat\":\"%s\",\"ph\":\"X\",\"pid\":1,\"tid\":%u,\"ts\":%.3f,\"dur\":%.3f,"
                   "\"args\":{\"items\":%u,\"kind\":\"%s\"}}",
                rt->procs[e->proc].name, kind_names[e->kind], e->group == UINT32_MAX ? 0u : e->group, e->start,
                duration, e->items, kind_names[e->kind]);
    }
    fprintf(f, "\n]}\n");
    if (perma_output_commit(out, &error) != PERMA_OK)
        return perma_set_error(rt, error.status, "cannot write the trace: %s", error.message);
    return PERMA_OK;
}
