/* perma_run: one loop for every technique.
 *
 *     build -> upload the seeds -> prepare
 *     -> launch -> collect statistics and trace -> interpret:
 *          DONE        the run is over
 *          NEEDS_ROOM  grow the queues, launch again
 *          otherwise   the error the status words stand for
 *     -> copy the user buffers back, write the trace
 *
 * The technique is the executor's business (executor.h); the queues' sizes
 * are queues.c's. */
#include "buffers.h"
#include "clock.h"
#include "executor.h"
#include "outcome.h"
#include "program.h"
#include "progress.h"
#include "reductions.h"
#include "run.h"
#include "state.h"
#include "stats.h"
#include "trace.h"
#include "trace_file.h"

#include <stdlib.h>
#include <string.h>

/* Grow the queues a launch stopped for, as the outcome says, on the
 * device: for the items groups left in their overflow areas (which the
 * growth appends to the queues), a starved group's target, the targets of
 * a stall, or what a host-driven step needs. */
static perma_status grow_queues(perma_runtime *rt, const perma_launch_outcome *outcome)
{
    const perma_queue_layout *layout = &rt->build.queue_layout;
    unsigned queues = layout->count;
    size_t *capacities = malloc(queues * sizeof *capacities), *current = malloc(queues * sizeof *current);
    size_t *queued = malloc(queues * sizeof *queued), *overflow = malloc(queues * sizeof *overflow);
    perma_status st = capacities && current && queued && overflow
                          ? perma_state_read_queues(rt, rt->executor->persistent, current, queued, overflow)
                          : perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory growing queues");
    for (unsigned qi = 0; st == PERMA_OK && qi < queues; ++qi)
        rt->stats.overflowed_items += overflow[qi];
    uint32_t detail = outcome->header.detail_proc;
    bool starved = detail == PERMA_DETAIL_STARVED;
    perma_error error = { PERMA_OK, "" };
    if (st == PERMA_OK && outcome->needed_given)
        st = perma_queues_grow_to_fit(layout, current, queued, outcome->needed, capacities, &error);
    else if (st == PERMA_OK && detail == PERMA_DETAIL_OVERFLOW)
        st = perma_queues_grow_to_fit(layout, current, queued, overflow, capacities, &error);
    else if (st == PERMA_OK)
        st = perma_queues_grow_stalled(layout, current, queued, starved ? outcome->header.detail_edge : UINT32_MAX,
                                       overflow, capacities, &error);
    bool grows = st == PERMA_OK;
    if (starved && st == PERMA_ERR_CAPACITY) {
        /* Growing for full batches is an optimisation: past the memory
         * limit the run goes on with the queues it has (laid out again with
         * a fresh control block), and no group stops it for that again. */
        rt->grow_starved = false;
        memcpy(capacities, current, queues * sizeof *capacities);
        st = PERMA_OK;
    }
    /* Whatever the launch stopped for, the overflowed items must fit. */
    if (st == PERMA_OK && detail != PERMA_DETAIL_OVERFLOW)
        st = perma_queues_fit_more(layout, current, queued, overflow, capacities, &error);
    size_t bytes = st == PERMA_OK ? perma_queues_bytes(layout, capacities) : 0;
    if (st != PERMA_OK && st == error.status)
        st = perma_take_error(rt, &error);
    if (st == PERMA_OK)
        st = perma_state_grow(rt, capacities, bytes);
    if (st == PERMA_OK && grows)
        rt->stats.regrowths++;
    free(capacities);
    free(current);
    free(queued);
    free(overflow);
    return st;
}

/* The first launch state: the seeds in queues of their initial capacities
 * (or what the last run learned).  The seeds are consumed whether the run
 * succeeds or not. */
static perma_status upload_seeds(perma_runtime *rt)
{
    const perma_queue_layout *layout = &rt->build.queue_layout;
    unsigned queues = layout->count;
    size_t seeds[PERMA_MAX_PROCEDURES];
    for (unsigned q = 0; q < rt->proc_count; ++q)
        seeds[q] = rt->procs[q].seed_count;
    size_t *capacities = malloc(queues * sizeof *capacities), *first = malloc(queues * sizeof *first);
    size_t *count = malloc(queues * sizeof *count);
    perma_status st = capacities && first && count
                          ? PERMA_OK
                          : perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for %u queues", queues);
    const size_t *learned = rt->build.learned_capacities && rt->build.learned_build == rt->build.serial &&
                                    rt->build.learned_count == queues
                                ? rt->build.learned_capacities
                                : NULL;
    perma_error error;
    if (st == PERMA_OK &&
        perma_queues_initial(layout, seeds, learned, capacities, &rt->stats.queues_kept, &error) != PERMA_OK)
        st = perma_take_error(rt, &error);
    size_t bytes = 0;
    if (st == PERMA_OK) {
        bytes = perma_queues_bytes(layout, capacities);
        perma_queues_seed_shares(layout, seeds, first, count);
    }
    if (st == PERMA_OK)
        st = perma_state_upload(rt, capacities, bytes, first, count);
    free(capacities);
    free(first);
    free(count);
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        perma_proc_info *p = &rt->procs[q];
        if (st == PERMA_OK) {
            p->stats.seeded = p->seed_count;
            p->stats.peak_queue_items = p->seed_count;
        }
        p->seed_count = 0;
    }
    return st;
}

/* Turn how a launch ended into the next step (*again: launch again) or an
 * error. */
static perma_status interpret(perma_runtime *rt, const perma_launch_outcome *outcome, bool *again)
{
    *again = false;
    switch (outcome->header.status) {
    case PERMA_KSTATUS_DONE:
        if (outcome->header.outstanding != 0)
            return perma_set_error(rt, PERMA_ERR_DEVICE, "the kernel stopped with %d items outstanding",
                                   (int)outcome->header.outstanding);
        return PERMA_OK;
    case PERMA_KSTATUS_NEEDS_ROOM: {
        /* A group stops the launch for room against the groups it sees
         * running (kernels/perma_scheduler.cl, perma_all_blocked); a group
         * it did not see (not started yet, or adopting the set of one that
         * left) may still run batches before it sees the stop, up to the
         * last item.  Then nothing waits for room: the run is done. */
        if (!outcome->needed_given && outcome->header.outstanding == 0)
            return PERMA_OK;
        perma_status st = grow_queues(rt, outcome);
        *again = st == PERMA_OK;
        return st;
    }
    }
    return perma_outcome_error(rt, &outcome->header);
}

/* Launch until the work is done or something fails. */
static perma_status launch_until_done(perma_runtime *rt, double deadline)
{
    const perma_executor *executor = rt->executor;
    perma_status st = executor->prepare(rt);
    bool again = st == PERMA_OK;
    while (again) {
        perma_launch_outcome outcome;
        memset(&outcome, 0, sizeof outcome);
        st = perma_state_begin_launch(rt);
        if (st == PERMA_OK) {
            perma_progress_launch_begins(rt);
            st = executor->launch(rt, deadline, &outcome);
        }
        if (st != PERMA_OK)
            break;
        rt->stats.launches += outcome.launches;
        st = perma_stats_collect(rt);
        if (st == PERMA_OK)
            perma_progress_launch_ends(rt);
        if (st == PERMA_OK)
            st = perma_trace_collect(rt);
        if (st == PERMA_OK)
            st = interpret(rt, &outcome, &again);
        if (st != PERMA_OK)
            break;
    }
    return st;
}

/* The trace is written after a failure too (it shows what ran before it),
 * keeping the failure's message. */
static perma_status write_trace(perma_runtime *rt, perma_status st)
{
    if (!rt->config.trace_path || rt->hung)
        return st;
    char kept[PERMA_MESSAGE_MAX];
    memcpy(kept, rt->message, sizeof kept);
    perma_status trace_st = perma_trace_write(rt);
    if (st == PERMA_OK)
        return trace_st;
    memcpy(rt->message, kept, sizeof kept);
    return st;
}

/* Keep what the queues grew to (the run succeeded), or nothing. */
static void learn_capacities(perma_runtime *rt, const perma_queue_state *queues, unsigned count, bool succeeded)
{
    perma_run_release(rt);
    if (!succeeded || !count)
        return;
    rt->build.learned_capacities = malloc(count * sizeof *rt->build.learned_capacities);
    if (!rt->build.learned_capacities)
        return; /* an optimisation only */
    for (unsigned qi = 0; qi < count; ++qi)
        rt->build.learned_capacities[qi] = queues[qi].capacity;
    rt->build.learned_count = count;
    rt->build.learned_build = rt->build.serial;
}

void perma_run_release(perma_runtime *rt)
{
    free(rt->build.learned_capacities);
    rt->build.learned_capacities = NULL;
    rt->build.learned_count = 0;
}

static perma_status forget_capacities_call(perma_runtime *rt)
{
    perma_call_begin(rt, "perma_forget_capacities", false);
    perma_run_release(rt);
    return PERMA_OK;
}

perma_status perma_forget_capacities(perma_runtime *rt)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_forget_capacities", forget_capacities_call(rt));
}

static perma_status run_call(perma_runtime *rt)
{
    perma_status st = perma_call_begin(rt, "perma_run", true);
    /* A trace that cannot be written fails the run before it starts, not
     * after all its work. */
    perma_error error;
    if (st == PERMA_OK && rt->config.trace_path && perma_output_check(rt->config.trace_path, &error) != PERMA_OK)
        st = perma_set_error(rt, error.status, "cannot write the trace: %s", error.message);
    if (st == PERMA_OK)
        perma_reductions_invalidate(rt);
    if (st == PERMA_OK)
        st = perma_build_program(rt);
    if (st != PERMA_OK) {
        /* A run consumes its seeds whether it succeeds or not. */
        for (unsigned q = 0; q < rt->proc_count; ++q)
            rt->procs[q].seed_count = 0;
        return st;
    }
    perma_stats_reset(rt);
    double start = perma_now();
    perma_trace_reset(rt, start);
    if (rt->config.trace_path)
        perma_trace_file_run_begins(start);
    double deadline = start + perma_time_limit(&rt->config);
    rt->grow_starved = true;

    /* The launch state: the queues with the seeds, and the reductions'
     * slots at their identities. */
    uint64_t *slots;
    size_t slot_words;
    perma_status reduce_st = perma_reductions_identities(rt, &slots, &slot_words);
    st = upload_seeds(rt);
    if (st == PERMA_OK)
        st = reduce_st;
    if (st == PERMA_OK && slots)
        st = perma_state_write_reductions(rt, slots, slot_words);
    free(slots);
    perma_progress_run_begins(rt, start);
    if (st == PERMA_OK)
        st = perma_buffers_copy(rt, PERMA_READ);
    if (st == PERMA_OK)
        st = launch_until_done(rt, deadline);
    if (st == PERMA_OK)
        st = perma_buffers_copy(rt, PERMA_WRITE);
    if (st == PERMA_OK)
        st = perma_reductions_collect(rt);
    rt->stats.seconds = perma_progress_stop_clock(rt);
    unsigned queue_count;
    const perma_queue_state *queues = perma_state_queues(rt, &queue_count);
    learn_capacities(rt, queues, queue_count, st == PERMA_OK);
    st = write_trace(rt, st);
    perma_stats_finish(rt, queues, queue_count);
    perma_progress_run_ends(rt);
    if (st == PERMA_OK)
        rt->message[0] = '\0';
    return st;
}

perma_status perma_run(perma_runtime *rt)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_run", run_call(rt));
}
