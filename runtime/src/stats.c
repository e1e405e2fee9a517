/* Run statistics: collected from each launch, summed, printed. */
#include "internal.h"
#include "layout.h"
#include "state.h"
#include "stats.h"

#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

void perma_stats_reset(perma_runtime *rt)
{
    memset(&rt->stats, 0, sizeof rt->stats);
    rt->stats.technique = rt->config.schedule.technique;
    rt->stats.strategy = rt->config.schedule.strategy;
    if (rt->group_stats)
        memset(rt->group_stats, 0, rt->group_stats_count * sizeof *rt->group_stats);
    rt->stats.work_groups = rt->work_groups;
    rt->stats.work_groups_reason = rt->work_groups_reason;
    rt->stats.resident_groups = rt->resident_groups;
    rt->stats.kernel_local_bytes = rt->kernel_local_bytes;
    rt->stats.group_size = rt->group_size;
    rt->stats.procedure_count = rt->proc_count;
    rt->stats.queue_memory_limit = rt->build.queue_layout.memory_limit;
    rt->stats.stack_items = rt->build.wf_items;
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        perma_proc_info *p = &rt->procs[q];
        memset(&p->stats, 0, sizeof p->stats);
        p->stats.name = p->name;
        p->stats.emit_count = p->emit_count;
    }
}

/* Add the per-group counters and queue peaks of the launch that just ended. */
perma_status perma_stats_collect(perma_runtime *rt)
{
    unsigned n = rt->proc_count, stride = PERMA_STAT_PROC_WORDS_FOR(rt->build.max_edges);
    unsigned group_words = PERMA_STAT_GROUP_WORDS_FOR(n, rt->build.max_edges);
    size_t stats_words = (size_t)rt->work_groups * group_words;
    unsigned queues = rt->build.queue_layout.count;
    size_t ctl_bytes = perma_ctl_block_bytes(queues);
    if (rt->group_stats_count < rt->work_groups) {
        /* The build can change the count (device.c). */
        free(rt->group_stats);
        rt->group_stats_count = 0;
        rt->group_stats = calloc(rt->work_groups, sizeof *rt->group_stats);
        if (!rt->group_stats)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for group statistics");
        rt->group_stats_count = rt->work_groups;
    }
    uint32_t *words = malloc(stats_words * 4);
    perma_ctl_block *ctl = malloc(ctl_bytes);
    if (!words || !ctl) {
        free(words);
        free(ctl);
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory reading statistics");
    }
    perma_status st = perma_state_read_stats(rt, words, stats_words);
    if (st == PERMA_OK)
        st = perma_state_read_control(rt, ctl, queues);
    if (st != PERMA_OK) {
        free(words);
        free(ctl);
        return st;
    }
    for (unsigned g = 0; g < rt->work_groups; ++g) {
        const uint32_t *record = words + (size_t)g * group_words;
        perma_group_stats *gs = &rt->group_stats[g];
        for (unsigned q = 0; q < n; ++q) {
            const uint32_t *s = record + q * stride;
            perma_procedure_stats *ps = &rt->procs[q].stats;
            ps->items += s[PERMA_STAT_ITEMS];
            ps->batches += s[PERMA_STAT_BATCHES];
            ps->stacked_items += s[PERMA_STAT_STACKED];
            for (unsigned e = 0; e < rt->procs[q].emit_count; ++e)
                ps->emitted[e] += s[PERMA_STAT_EMITTED + e];
            rt->stats.items += s[PERMA_STAT_ITEMS];
            gs->items += s[PERMA_STAT_ITEMS];
            gs->batches += s[PERMA_STAT_BATCHES];
        }
        perma_group_counters gw;
        memcpy(&gw, record + n * stride, sizeof gw);
        gs->steals += gw.steals;
        gs->donations += gw.donations;
        gs->donated_items += gw.donated;
        gs->spills += gw.spills;
        gs->idle_polls += gw.idle_polls;
        gs->stacked_items += gw.wf_runs;
        gs->stack_spills += gw.wf_spills;
        if (gw.wf_peak > gs->stack_peak)
            gs->stack_peak = gw.wf_peak;
        rt->stats.stacked_items += gw.wf_runs;
        rt->stats.stack_spills += gw.wf_spills;
        if (gw.wf_peak > rt->stats.stack_peak)
            rt->stats.stack_peak = gw.wf_peak;
        rt->stats.steals += gw.steals;
        rt->stats.donations += gw.donations;
        rt->stats.spills += gw.spills;
        rt->stats.idle_polls += gw.idle_polls;
    }
    /* A procedure's peak: the sum over queue sets of each queue's peak. */
    for (unsigned q = 0; q < n; ++q) {
        uint64_t peak = 0;
        for (unsigned set = 0; set < rt->build.queue_sets; ++set)
            peak += ctl->queues[set * n + q].peak;
        if (peak > rt->procs[q].stats.peak_queue_items)
            rt->procs[q].stats.peak_queue_items = peak;
    }
    free(words);
    free(ctl);
    return PERMA_OK;
}

/* The largest capacity of target t's queues (one per queue set) among
 * the `count` queues. */
static size_t target_capacity(const perma_runtime *rt, const perma_queue_state *queues, unsigned count, unsigned t)
{
    size_t cap = 0;
    for (unsigned qi = t; qi < count; qi += rt->proc_count)
        if (queues[qi].capacity > cap)
            cap = queues[qi].capacity;
    return cap;
}

/* Why q's batches held fewer items than a group runs at once, if it
 * mattered (more items were queued at once than a batch took): the layout
 * gave it a smaller batch for lack of __local memory, or of staging for the
 * declared maximum of emits, or (the batches averaging under half of it)
 * the expected emits of a full batch, batch_size times the mean emits per
 * item, did not fit the target's queue, so a batch could only reserve room
 * for a few items.  The .emits entry responsible: the one staging the most
 * bytes, or reserving the most for its target's capacity. */
static void explain_batches(perma_runtime *rt, const perma_queue_state *queues, unsigned count, unsigned q)
{
    const perma_proc_info *p = &rt->procs[q];
    perma_procedure_stats *ps = &rt->procs[q].stats;
    ps->batch_size = p->max_batch;
    ps->batch_cut = PERMA_BATCH_FULL;
    ps->batch_cut_emit = -1;
    if (ps->peak_queue_items <= p->max_batch)
        return;
    if (p->max_batch_local < p->full_batch) {
        ps->batch_cut = PERMA_BATCH_CUT_LOCAL_MEMORY;
        return;
    }
    if (p->max_batch < p->max_batch_local) {
        ps->batch_cut = PERMA_BATCH_CUT_STAGING;
        size_t most = 0;
        for (unsigned e = 0; e < p->emit_count; ++e) {
            size_t staged = (size_t)p->emit_max[e] * rt->procs[p->emit_target[e]].item_size;
            if (staged > most) {
                most = staged;
                ps->batch_cut_emit = (int)e;
            }
        }
        return;
    }
    if (ps->batches == 0 || ps->items * 2 >= ps->batches * p->max_batch)
        return;
    double worst = 1.0;
    for (unsigned e = 0; e < p->emit_count; ++e) {
        size_t cap = target_capacity(rt, queues, count, (unsigned)p->emit_target[e]);
        double mean = (double)ps->emitted[e] / (double)ps->items;
        double over = cap ? (double)p->max_batch * mean / (double)cap : 0.0;
        if (over > worst) {
            worst = over;
            ps->batch_cut = PERMA_BATCH_CUT_ROOM;
            ps->batch_cut_emit = (int)e;
        }
    }
}

/* Each procedure's final queue capacity (summed over queue sets), most
 * regrowths of one of its queues, and its batches. */
void perma_stats_finish(perma_runtime *rt, const perma_queue_state *queues, unsigned count)
{
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        rt->procs[q].stats.initial_capacity = 0;
        rt->procs[q].stats.queue_capacity = 0;
        rt->procs[q].stats.regrowths = 0;
    }
    for (unsigned qi = 0; qi < count; ++qi) {
        perma_procedure_stats *ps = &rt->procs[qi % rt->proc_count].stats;
        ps->initial_capacity += queues[qi].initial;
        ps->queue_capacity += queues[qi].capacity;
        if (queues[qi].regrowths > ps->regrowths)
            ps->regrowths = queues[qi].regrowths;
    }
    if (rt->built)
        for (unsigned q = 0; q < rt->proc_count; ++q)
            explain_batches(rt, queues, count, q);
}

static perma_status get_stats_call(perma_runtime *rt, perma_stats *out)
{
    perma_call_begin(rt, "perma_get_stats", false);
    if (!out)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_get_stats: out is NULL");
    *out = rt->stats;
    return PERMA_OK;
}

perma_status perma_get_stats(perma_runtime *rt, perma_stats *out)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_get_stats", get_stats_call(rt, out));
}

static perma_status get_procedure_stats_call(perma_runtime *rt, perma_proc proc, perma_procedure_stats *out)
{
    perma_call_begin(rt, "perma_get_procedure_stats", false);
    if (proc < 0 || (unsigned)proc >= rt->proc_count || !out)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_get_procedure_stats: %d is not a registered procedure",
                               proc);
    *out = rt->procs[proc].stats;
    out->name = rt->procs[proc].name;
    out->emit_count = rt->procs[proc].emit_count;
    return PERMA_OK;
}

perma_status perma_get_procedure_stats(perma_runtime *rt, perma_proc proc, perma_procedure_stats *out)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_get_procedure_stats", get_procedure_stats_call(rt, proc, out));
}

static perma_status get_work_groups_call(perma_runtime *rt, unsigned *work_groups, unsigned *group_size)
{
    perma_call_begin(rt, "perma_get_work_groups", false);
    if (!work_groups && !group_size)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_get_work_groups: both out pointers are NULL");
    if (work_groups)
        *work_groups = rt->work_groups;
    if (group_size)
        *group_size = rt->group_size;
    return PERMA_OK;
}

perma_status perma_get_work_groups(perma_runtime *rt, unsigned *work_groups, unsigned *group_size)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_get_work_groups", get_work_groups_call(rt, work_groups, group_size));
}

static perma_status get_local_memory_call(perma_runtime *rt, size_t *bytes)
{
    perma_call_begin(rt, "perma_get_local_memory", false);
    if (!bytes)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_get_local_memory: bytes is NULL");
    *bytes = perma_local_memory(rt);
    return PERMA_OK;
}

perma_status perma_get_local_memory(perma_runtime *rt, size_t *bytes)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_get_local_memory", get_local_memory_call(rt, bytes));
}

void perma_stats_release(perma_runtime *rt)
{
    free(rt->group_stats);
    rt->group_stats = NULL;
    rt->group_stats_count = 0;
}

static perma_status get_group_stats_call(perma_runtime *rt, unsigned group, perma_group_stats *out)
{
    perma_call_begin(rt, "perma_get_group_stats", false);
    if (group >= rt->work_groups || !out)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_get_group_stats: group %u is not in 0..%u",
                               group, rt->work_groups - 1);
    if (rt->group_stats)
        *out = rt->group_stats[group];
    else
        memset(out, 0, sizeof *out);
    return PERMA_OK;
}

perma_status perma_get_group_stats(perma_runtime *rt, unsigned group, perma_group_stats *out)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_get_group_stats", get_group_stats_call(rt, group, out));
}

/* The warning for a procedure whose batches were cut, naming the
 * declaration responsible and the fix. */
static void print_batch_warning(const perma_runtime *rt, unsigned q, FILE *out)
{
    unsigned count;
    const perma_queue_state *queues = perma_state_queues(rt, &count);
    const perma_proc_info *p = &rt->procs[q];
    const perma_procedure_stats *ps = &p->stats;
    unsigned full = p->full_batch;
    int e = ps->batch_cut_emit;
    const char *target = e >= 0 ? p->emit_target_name[e] : "";
    if (ps->batch_cut == PERMA_BATCH_CUT_STAGING && e >= 0)
        fprintf(out, "warning: procedure '%s' runs at most %u items per batch instead of %u: .emits[%d] (up to %u "
                     "items of %zu bytes into '%s' per item) needs %zu bytes of staging per item, and a work-group "
                     "stages at most %zu bytes; declare fewer, or emit them from a separate procedure "
                     "(docs/writing-procedures.md, section 6)\n", p->name, ps->batch_size, full, e, p->emit_max[e],
                rt->procs[p->emit_target[e]].item_size, target,
                (size_t)p->emit_max[e] * rt->procs[p->emit_target[e]].item_size, 4 * (size_t)rt->build.stage_words);
    else if (ps->batch_cut == PERMA_BATCH_CUT_LOCAL_MEMORY)
        fprintf(out, "warning: procedure '%s' runs at most %u items per batch instead of %u: its items and scratch "
                     "(.local_bytes_per_item) do not fit more in __local memory\n",
                p->name, ps->batch_size, full);
    else if (ps->batch_cut == PERMA_BATCH_CUT_ROOM)
        fprintf(out, "warning: procedure '%s' ran batches of %.1f items on average instead of up to %u: a full "
                     "batch reserves room for the emits it is expected to make (%.1f per item into '%s', its mean "
                     "so far), more than the queue of %zu holds (a queue grows when a group's batches keep being "
                     "cut, up to config.queue_memory_limit, %zu bytes); raise the limit, or let fewer items wait "
                     "(docs/writing-procedures.md, section 6)\n",
                p->name, (double)(ps->items - ps->stacked_items) / (double)ps->batches, ps->batch_size,
                (double)ps->emitted[e] / (double)ps->items, target, target_capacity(rt, queues, count, (unsigned)p->emit_target[e]),
                perma_queue_memory_limit(rt));
}

static void print_stats(perma_runtime *rt, FILE *out)
{
    const perma_stats *s = &rt->stats;
    fprintf(out, "perma run (%s, %s): %.3f s, %u launch(es), %u regrowth(s), %u group(s) x %u work-items, "
                 "peak queue memory %zu bytes (limit %zu)\n",
            perma_technique_name(s->technique), perma_strategy_name(s->strategy), s->seconds, s->launches,
            s->regrowths, s->work_groups, s->group_size, s->peak_queue_bytes, s->queue_memory_limit);
    char resident[96] = "on a CPU any number: a group that cannot start waits for one that ends";
    if (s->resident_groups)
        snprintf(resident, sizeof resident, "the device holds %u at once", s->resident_groups);
    fprintf(out, "work-groups: %s; %s; the megakernel uses %zu bytes of __local memory per group\n",
            s->work_groups_reason ? s->work_groups_reason : "", resident, s->kernel_local_bytes);
    if (s->queues_kept)
        fprintf(out, "%u queue(s) started at the capacity an earlier run grew them to\n", s->queues_kept);
    if (s->overflowed_items)
        fprintf(out, "%" PRIu64 " emitted item(s) overflowed a queue and were appended when it grew\n",
                s->overflowed_items);
    if (s->steals || s->donations || s->spills)
        fprintf(out, "load balancing: %" PRIu64 " steal(s), %" PRIu64 " donation(s), %" PRIu64
                     " spill(s), %" PRIu64 " idle poll(s)\n",
                s->steals, s->donations, s->spills, s->idle_polls);
    if (s->stack_items)
        fprintf(out, "work-first: stacks of %u items; %" PRIu64 " item(s) ran from them (deepest %u), %" PRIu64
                     " moved from them to the queues\n",
                s->stack_items, s->stacked_items, s->stack_peak, s->stack_spills);
    fprintf(out, "%-20s %12s %10s %10s %10s %12s %10s  %s\n", "procedure", "items", "batches", "batch",
            "seeded", "peak queued", "capacity", "emitted");
    for (unsigned q = 0; q < rt->proc_count; ++q) {
        const perma_proc_info *p = &rt->procs[q];
        const perma_procedure_stats *ps = &p->stats;
        /* Items per batch: those that ran from stacks took no batch. */
        char batch[32];
        snprintf(batch, sizeof batch, "%.1f/%u",
                 ps->batches ? (double)(ps->items - ps->stacked_items) / (double)ps->batches : 0.0, ps->batch_size);
        fprintf(out, "%-20s %12" PRIu64 " %10" PRIu64 " %10s %10" PRIu64 " %12" PRIu64 " %10zu ", p->name,
                ps->items, ps->batches, batch, ps->seeded, ps->peak_queue_items, ps->queue_capacity);
        for (unsigned e = 0; e < p->emit_count; ++e)
            fprintf(out, " %s:%" PRIu64, p->emit_target_name[e], ps->emitted[e]);
        fputc('\n', out);
    }
    for (unsigned q = 0; q < rt->proc_count; ++q)
        print_batch_warning(rt, q, out);
}

void perma_print_stats(perma_runtime *rt, FILE *out)
{
    if (!rt || !out)
        return;
    if (perma_call_claim(rt, "perma_print_stats") != PERMA_OK) {
        fprintf(out, "perma: no statistics: %s\n", perma_errmsg(rt));
        return;
    }
    print_stats(rt, out);
    perma_call_release(rt);
}
