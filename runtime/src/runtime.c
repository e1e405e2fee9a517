/* Creating and destroying a runtime. */
#include "device.h"
#include "executor.h"
#include "program.h"
#include "progress.h"
#include "reductions.h"
#include "run.h"
#include "state.h"
#include "stats.h"
#include "steps.h"
#include "trace.h"
#include "watchdog.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

void perma_config_init(perma_config *config)
{
    memset(config, 0, sizeof *config);
    config->platform_index = -1;
    config->device_index = -1;
    config->schedule.technique = PERMA_TECHNIQUE_MEGAKERNEL;
}

static perma_status check_config(perma_runtime *rt, const perma_config *c)
{
    if (c->group_size > 4096)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.group_size %u is above 4096", c->group_size);
    if (c->work_groups > 65536)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.work_groups %u is above 65536", c->work_groups);
    if (!(c->time_limit >= 0.0) || c->time_limit > 1e7)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "config.time_limit %g is not a number of seconds in 0..1e7", c->time_limit);
    if (!(c->stall_limit >= 0.0) || c->stall_limit > 1e7)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "config.stall_limit %g is not a number of seconds in 0..1e7", c->stall_limit);
    if (c->queue_capacity > ((size_t)1 << 30))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.queue_capacity %zu is above 2^30 items",
                               c->queue_capacity);
    if (!perma_executor_for(c->schedule.technique))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.schedule.technique %d is not a known technique",
                               (int)c->schedule.technique);
    if (!perma_strategy_name(c->schedule.strategy))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.schedule.strategy %d is not a known strategy",
                               (int)c->schedule.strategy);
    if (!perma_victim_name(c->schedule.victim))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.schedule.victim %d is not a known victim policy",
                               (int)c->schedule.victim);
    if (!(c->progress_interval >= 0.0) || c->progress_interval > 1e6)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "config.progress_interval %g is not a number of seconds in 0..1e6",
                               c->progress_interval);
    if (c->trace_events > (1u << 24))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.trace_events %u is above 2^24", c->trace_events);
    if (c->items_per_work_item > 64)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.items_per_work_item %u is above 64",
                               c->items_per_work_item);
    if (c->schedule.local_queue_items > PERMA_MAX_LOCAL_QUEUE_ITEMS)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.schedule.local_queue_items %u is above %u",
                               c->schedule.local_queue_items, (unsigned)PERMA_MAX_LOCAL_QUEUE_ITEMS);
    if (c->schedule.work_first_items > PERMA_MAX_WORK_FIRST_ITEMS && c->schedule.work_first_items != PERMA_WORK_FIRST_OFF)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.schedule.work_first_items %u is above %u",
                               c->schedule.work_first_items, (unsigned)PERMA_MAX_WORK_FIRST_ITEMS);
    return PERMA_OK;
}

perma_status perma_create(const perma_config *config, perma_runtime **out, perma_error *error)
{
    perma_config defaults;
    if (!config) {
        perma_config_init(&defaults);
        config = &defaults;
    }
    if (out)
        *out = NULL;
    perma_runtime *rt = calloc(1, sizeof *rt);
    if (!rt) {
        if (error) {
            error->status = PERMA_ERR_NO_MEMORY;
            snprintf(error->message, sizeof error->message, "out of memory creating the runtime");
        }
        return PERMA_ERR_NO_MEMORY;
    }
    rt->config = *config;
    /* Debug mode: one work-group, so printf output of a procedure comes in
     * order, and PERMA_DEBUG defined for the procedures. */
    perma_settings_read(&rt->settings);
    rt->debug = rt->settings.debug;
    if (rt->debug)
        rt->config.work_groups = 1;
    rt->config.build_options = NULL; /* copied below */
    rt->config.trace_path = NULL;
    rt->group_size = config->group_size ? config->group_size : 64;
    rt->executor = perma_executor_for(config->schedule.technique);
    perma_status st = out ? check_config(rt, config)
                          : perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_create: out is NULL");
    if (st == PERMA_OK && config->build_options) {
        rt->config.build_options = strdup(config->build_options);
        if (!rt->config.build_options)
            st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory copying build options");
    }
    const char *trace = config->trace_path ? config->trace_path : rt->settings.trace;
    if (st == PERMA_OK && trace && *trace) {
        rt->config.trace_path = strdup(trace);
        if (!rt->config.trace_path)
            st = perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory copying the trace path");
        rt->config.trace_events = config->trace_events ? config->trace_events : 65536;
        if (st == PERMA_OK)
            st = perma_trace_open(rt);
    }
    if (st == PERMA_OK && !config->local_memory_limit) {
        rt->config.local_memory_limit = rt->settings.local_memory_limit;
        if (rt->settings.local_memory_error.status != PERMA_OK)
            st = perma_take_error(rt, &rt->settings.local_memory_error);
    }
    if (st == PERMA_OK)
        st = perma_device_open(rt);
    if (st == PERMA_OK)
        st = perma_reductions_open(rt);
    if (st == PERMA_OK)
        st = perma_state_open(rt);
    if (st == PERMA_OK)
        st = perma_watchdog_open(rt);
    if (st == PERMA_OK)
        st = perma_progress_open(rt);
    if (error) {
        error->status = st;
        snprintf(error->message, sizeof error->message, "%s", st == PERMA_OK ? "" : rt->message);
    }
    if (st != PERMA_OK) {
        perma_destroy(rt);
        return st;
    }
    *out = rt;
    return PERMA_OK;
}

static void free_proc(perma_proc_info *p)
{
    free(p->name);
    free(p->item_type);
    free(p->function);
    free(p->source.text);
    free(p->source.name);
    for (unsigned e = 0; e < p->emit_count; ++e)
        free(p->emit_target_name[e]);
    free(p->seeds);
}

/* Runtimes whose kernel never ended (rt->hung): kept, not freed, since
 * that kernel still uses their buffers, and kept reachable, so that a leak
 * checker at exit (the sanitize suite's) does not report them: the
 * process exits normally after a hang. */
static pthread_mutex_t hung_lock = PTHREAD_MUTEX_INITIALIZER;
static perma_runtime *hung_runtimes;

static void keep_hung(perma_runtime *rt)
{
    pthread_mutex_lock(&hung_lock);
    rt->next_hung = hung_runtimes;
    hung_runtimes = rt;
    pthread_mutex_unlock(&hung_lock);
}

void perma_destroy(perma_runtime *rt)
{
    if (!rt)
        return;
    /* The watchdog's waiter thread is idle between launches, so it is
     * stopped and joined before the queue is finished; the waiter of a
     * kernel that never ended (rt->hung) is blocked on it and detached. */
    perma_watchdog_close(rt);
    if (rt->hung) {
        /* A kernel is still running and would make every release block:
         * leak the OpenCL objects rather than hang the caller. */
        keep_hung(rt);
        return;
    }
    if (rt->queue)
        clFinish(rt->queue);
    perma_state_close(rt);
    perma_run_release(rt);
    perma_steps_release(rt);
    perma_release_program(rt);
    for (unsigned i = 0; i < rt->buffer_count; ++i) {
        if (rt->buffers[i].mem)
            clReleaseMemObject(rt->buffers[i].mem);
        free(rt->buffers[i].name);
        free(rt->buffers[i].type);
        free(rt->buffers[i].element_type);
    }
    for (unsigned i = 0; i < rt->source_count; ++i) {
        free(rt->sources[i].text);
        free(rt->sources[i].name);
    }
    perma_reductions_release(rt);
    for (unsigned i = 0; i < rt->proc_count; ++i)
        free_proc(&rt->procs[i]);
    perma_device_close(rt);
    free((char *)rt->config.build_options);
    free((char *)rt->config.trace_path);
    perma_trace_release(rt);
    perma_progress_close(rt);
    perma_stats_release(rt);
    free(rt);
}

cl_context perma_cl_context(const perma_runtime *rt) { return rt ? rt->context : NULL; }
cl_device_id perma_cl_device(const perma_runtime *rt) { return rt ? rt->device : NULL; }
cl_command_queue perma_cl_queue(const perma_runtime *rt) { return rt ? rt->queue : NULL; }
