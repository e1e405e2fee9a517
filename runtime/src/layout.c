/* Resolving the procedure graph and laying out each procedure's __local
 * arena: its batch of items, scratch, per-item emit counters and staging. */
#include "executor.h"
#include "layout.h"
#include "schedule_table.h"

#include <ctype.h>
#include <string.h>

#define DEFAULT_ITEMS_PER_WORK_ITEM 4

static unsigned words_of(size_t bytes)
{
    return (unsigned)((bytes + 3) / 4);
}

static unsigned round_up(unsigned value, unsigned multiple)
{
    return (value + multiple - 1) / multiple * multiple;
}

static perma_status resolve_targets(perma_runtime *rt)
{
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        perma_proc_info *p = &rt->procs[i];
        for (unsigned e = 0; e < p->emit_count; ++e) {
            p->emit_target[e] = -1;
            for (unsigned j = 0; j < rt->proc_count; ++j)
                if (strcmp(rt->procs[j].name, p->emit_target_name[e]) == 0)
                    p->emit_target[e] = (int)j;
            if (p->emit_target[e] < 0)
                return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                                       "procedure '%s' emits into '%s', which is not a registered procedure",
                                       p->name, p->emit_target_name[e]);
        }
    }
    return PERMA_OK;
}

/* True if `text` has `name` as an identifier followed by '('. */
static bool defines_function(const char *text, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = text; (p = strstr(p, name)) != NULL; p += n) {
        bool starts = p == text || !(isalnum((unsigned char)p[-1]) || p[-1] == '_');
        const char *q = p + n;
        while (*q == ' ' || *q == '\t' || *q == '\n' || *q == '\r')
            ++q;
        if (starts && *q == '(')
            return true;
    }
    return false;
}

/* Each procedure's function must appear in its source or a shared source. */
static perma_status check_functions(perma_runtime *rt)
{
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_proc_info *p = &rt->procs[i];
        bool found = defines_function(p->source.text, p->function);
        for (unsigned k = 0; k < rt->source_count && !found; ++k)
            found = defines_function(rt->sources[k].text, p->function);
        if (!found)
            return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                                   "procedure '%s': function '%s' is not defined in '%s' or a shared source",
                                   p->name, p->function, p->source.name);
    }
    return PERMA_OK;
}

/* reach[i][j]: j can be reached from i along emit edges. */
static void transitive_closure(const perma_runtime *rt, bool reach[PERMA_MAX_PROCEDURES][PERMA_MAX_PROCEDURES])
{
    unsigned n = rt->proc_count;
    for (unsigned i = 0; i < n; ++i) {
        for (unsigned j = 0; j < n; ++j)
            reach[i][j] = false;
        for (unsigned e = 0; e < rt->procs[i].emit_count; ++e)
            reach[i][rt->procs[i].emit_target[e]] = true;
    }
    for (unsigned k = 0; k < n; ++k)
        for (unsigned i = 0; i < n; ++i)
            if (reach[i][k])
                for (unsigned j = 0; j < n; ++j)
                    reach[i][j] = reach[i][j] || reach[k][j];
}

/* Procedures that emit into each other in a cycle have no downstream end:
 * their priorities must say which is served first. */
static perma_status check_cycles(perma_runtime *rt)
{
    static bool reach[PERMA_MAX_PROCEDURES][PERMA_MAX_PROCEDURES];
    unsigned n = rt->proc_count;
    transitive_closure(rt, reach);
    for (unsigned i = 0; i < n; ++i) {
        bool cyclic = false, ordered = false;
        for (unsigned j = 0; j < n; ++j) {
            if (j == i || !reach[i][j] || !reach[j][i])
                continue;
            cyclic = true;
            ordered = ordered || rt->procs[j].priority != rt->procs[i].priority;
        }
        if (!cyclic || ordered)
            continue;
        char names[512] = "";
        size_t used = 0;
        for (unsigned j = 0; j < n; ++j)
            if (j == i || (reach[i][j] && reach[j][i]))
                used += (size_t)snprintf(names + used, used < sizeof names ? sizeof names - used : 0, "%s'%s'",
                                         used ? ", " : "", rt->procs[j].name);
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "procedures %s emit into each other in a cycle and all have priority %d: give "
                               "them different .priority values (higher is served first) to order them",
                               names, rt->procs[i].priority);
    }
    return PERMA_OK;
}

/* depth = edges from the nearest root (a procedure nothing else emits into).
 * Deeper procedures are "downstream" and served first by default. */
static void compute_depths(perma_runtime *rt)
{
    unsigned n = rt->proc_count;
    bool has_input[PERMA_MAX_PROCEDURES] = { false };
    bool seen[PERMA_MAX_PROCEDURES] = { false };
    unsigned queue[PERMA_MAX_PROCEDURES];
    unsigned head = 0, tail = 0;
    for (unsigned i = 0; i < n; ++i)
        for (unsigned e = 0; e < rt->procs[i].emit_count; ++e)
            if ((unsigned)rt->procs[i].emit_target[e] != i)
                has_input[rt->procs[i].emit_target[e]] = true;
    for (unsigned i = 0; i < n; ++i) {
        if (!has_input[i]) {
            seen[i] = true;
            rt->procs[i].depth = 0;
            queue[tail++] = i;
        }
    }
    for (;;) {
        while (head < tail) {
            perma_proc_info *p = &rt->procs[queue[head++]];
            for (unsigned e = 0; e < p->emit_count; ++e) {
                unsigned t = (unsigned)p->emit_target[e];
                if (!seen[t]) {
                    seen[t] = true;
                    rt->procs[t].depth = p->depth + 1;
                    queue[tail++] = t;
                }
            }
        }
        /* A cycle with no root: start it at its first registered member. */
        unsigned next = n;
        for (unsigned i = 0; i < n && next == n; ++i)
            if (!seen[i])
                next = i;
        if (next == n)
            break;
        seen[next] = true;
        rt->procs[next].depth = 0;
        queue[tail++] = next;
    }
}

/* True if a should be served before b. */
static bool served_before(const perma_proc_info *a, unsigned ia, const perma_proc_info *b, unsigned ib)
{
    if (a->priority != b->priority)
        return a->priority > b->priority;
    if (a->depth != b->depth)
        return a->depth > b->depth;
    return ia > ib;
}

static void compute_order(perma_runtime *rt)
{
    for (unsigned i = 0; i < rt->proc_count; ++i)
        rt->build.order[i] = i;
    for (unsigned i = 1; i < rt->proc_count; ++i) {
        unsigned v = rt->build.order[i];
        unsigned j = i;
        while (j > 0 && served_before(&rt->procs[v], v, &rt->procs[rt->build.order[j - 1]], rt->build.order[j - 1])) {
            rt->build.order[j] = rt->build.order[j - 1];
            --j;
        }
        rt->build.order[j] = v;
    }
}

size_t perma_local_memory(const perma_runtime *rt)
{
    size_t limit = rt->caps.local_mem_size;
    if (rt->config.local_memory_limit && rt->config.local_memory_limit < limit)
        limit = rt->config.local_memory_limit;
    return limit;
}

static unsigned queue_sets_of(const perma_runtime *rt, const perma_strategy_info *strategy)
{
    return rt->executor->persistent && strategy && strategy->per_group_queue_sets ? rt->work_groups : 1;
}

unsigned perma_queue_sets(const perma_runtime *rt)
{
    return queue_sets_of(rt, perma_strategy_row((int)rt->config.schedule.strategy));
}

size_t perma_queue_memory_limit(const perma_runtime *rt)
{
    if (rt->config.queue_memory_limit)
        return rt->config.queue_memory_limit;
    return rt->caps.max_alloc ? (size_t)(rt->caps.max_alloc / 2) : ((size_t)1 << 30);
}

void perma_queue_layout_fill(const perma_runtime *rt, unsigned sets, perma_queue_layout *out)
{
    out->procs = rt->proc_count;
    out->sets = sets;
    out->count = sets * rt->proc_count;
    out->initial_capacity = rt->config.queue_capacity ? rt->config.queue_capacity : PERMA_DEFAULT_QUEUE_CAPACITY;
    out->memory_limit = perma_queue_memory_limit(rt);
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_proc_info *p = &rt->procs[i];
        perma_queue_proc *q = &out->proc[i];
        q->name = p->name;
        q->item_size = p->item_size;
        q->emit_count = p->emit_count;
        for (unsigned e = 0; e < p->emit_count; ++e) {
            q->emit_target[e] = (unsigned)p->emit_target[e];
            q->emit_max[e] = p->emit_max[e];
        }
    }
}

/* Each procedure's simple flag and full batch (internal.h). */
static void compute_full_batches(perma_runtime *rt)
{
    unsigned items_per_work_item =
        rt->config.items_per_work_item ? rt->config.items_per_work_item : DEFAULT_ITEMS_PER_WORK_ITEM;
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        perma_proc_info *p = &rt->procs[i];
        p->simple = p->threads_per_item == 1 && !p->cooperative;
        p->full_batch = p->simple ? rt->group_size * items_per_work_item : rt->group_size / p->threads_per_item;
    }
}

/* Arena words procedure p needs for a batch of `batch` items: the items,
 * scratch, an emit counter per item and edge, and the lane counters.  A
 * procedure of one thread per item that is not cooperative stages its
 * emits per work-item ("lane"): lane l appends the emits of its items (l,
 * l + group size, ...) to its own block of the group's staging area, room
 * for lane_items items, and counts them per edge in the lane counters; any
 * other stages per item.  The staging is in global memory (stage_cost),
 * so a generous .emits maximum costs no __local memory. */
static unsigned arena_cost(const perma_runtime *rt, perma_proc_info *p, unsigned batch, bool assign)
{
    /* Lanes only for whole rounds of the group, so no lane has room for an
     * item it never gets; always with work-first stacks, whose batches
     * stage per work-item (kernels/perma_batch.cl, perma_run_simple). */
    bool lanes = p->simple && (batch % rt->group_size == 0 || rt->build.wf_items);
    unsigned lane_items = (batch + rt->group_size - 1) / rt->group_size;
    unsigned offset = 0;
    if (assign) {
        p->items_off = offset;
        p->lane_items = lanes ? lane_items : 0;
    }
    offset += round_up(batch * words_of(p->item_size), 16);
    if (assign)
        p->scratch_off = offset;
    offset += round_up(batch * p->scratch_words, 16);
    if (assign)
        p->counters_off = offset;
    offset += batch * p->emit_count;
    if (assign)
        p->lane_counts_off = offset;
    offset += lanes ? rt->group_size * p->emit_count : 0;
    return offset;
}

/* Words of the group's staging area a batch of `batch` items of p needs:
 * room for every item's declared maximum of emits into each target (lanes
 * as arena_cost says), edge after edge. */
static size_t stage_cost(const perma_runtime *rt, perma_proc_info *p, unsigned batch, bool assign)
{
    bool lanes = p->simple && (batch % rt->group_size == 0 || rt->build.wf_items);
    size_t staged = lanes ? (size_t)rt->group_size * ((batch + rt->group_size - 1) / rt->group_size) : batch;
    size_t offset = 0;
    for (unsigned e = 0; e < p->emit_count; ++e) {
        if (assign)
            p->stage_off[e] = (unsigned)offset;
        offset += staged * p->emit_max[e] * words_of(rt->procs[p->emit_target[e]].item_size);
    }
    return offset;
}

/* Most staging words per group: a quarter of the device's largest
 * allocation holds every group's staging and overflow data, at most
 * PERMA_STAGE_LIMIT_WORDS each. */
#define PERMA_STAGE_LIMIT_WORDS ((size_t)1 << 22)
static size_t stage_limit(const perma_runtime *rt)
{
    size_t limit = rt->caps.max_alloc ? (size_t)(rt->caps.max_alloc / (16 * (cl_ulong)rt->work_groups)) : PERMA_STAGE_LIMIT_WORDS;
    return limit < PERMA_STAGE_LIMIT_WORDS ? limit : PERMA_STAGE_LIMIT_WORDS;
}

/* Items a work-item runs from its stack in one batch: long enough that a
 * batch's own cost is small beside its items, short enough that a batch
 * ends soon for the watchdog, progress, priorities, an idle group's share
 * and, on a GPU, the divergence of the work-items' loops. */
#define WF_BUDGET_CPU 1024
#define WF_BUDGET_GPU 32

/* The largest power of two (at most 128) that divides `bytes`: the most
 * alignment a type of that size can have in OpenCL C. */
static unsigned alignment_of_size(size_t bytes)
{
    unsigned a = 1;
    while (a < 128 && bytes % (2 * a) == 0)
        a *= 2;
    return a;
}

/* The __local words of the stacks of `items` items of `slot_words` words:
 * the slots, a word per slot (its procedure), a stack pointer and a row of
 * emit counters per work-item, counters per procedure and edge, and room
 * to align the slots to 128 bytes. */
static size_t wf_words_of(const perma_runtime *rt, unsigned items, unsigned slot_words)
{
    size_t g = rt->group_size, stacks = g * items;
    return stacks * (slot_words + 1) + g + g * rt->build.max_edges + rt->proc_count * (1 + rt->build.max_edges) + 4 +
           32;
}

/* Stack items when the schedule leaves it to the runtime.  On a CPU 128 (a
 * depth-first search of most trees fits, so few items spill), or fewer
 * when the stacks would take more than half the __local memory `free`
 * words leave.  On other devices at most 32 in at most a quarter of it: a
 * GPU's 48 KiB also decides how many groups a compute unit holds at once
 * (device.c), and its work-items' stacks diverge anyway.  0 when not even
 * 8 fit. */
static unsigned default_work_first_items(const perma_runtime *rt, unsigned slot_words, size_t free)
{
    unsigned items = rt->caps.is_cpu ? 128 : 32;
    size_t share = rt->caps.is_cpu ? free / 2 : free / 4;
    while (items >= 8 && wf_words_of(rt, items, slot_words) > share)
        items /= 2;
    return items >= 8 ? items : 0;
}

/* Work-first (perma_schedule.work_first_items): which procedures' items may
 * run from a work-item's stack, and the stacks' shape.  A procedure is
 * stackable when it runs one thread per item, is neither cooperative nor
 * queue_only, has no scratch (its items run outside the batch's arena),
 * declares at most half a stack of emits (an item runs from the stack only
 * with room for all of them), and emits only into stackable procedures (its
 * items never stage emits, so they may run in any batch).  The stack's
 * slots hold the largest stackable item, aligned for every stackable type. */
static void compute_work_first(perma_runtime *rt, size_t free)
{
    unsigned n = rt->proc_count, items = rt->config.schedule.work_first_items;
    bool on = rt->executor->persistent && items != PERMA_WORK_FIRST_OFF;
    /* The largest slot any procedure would need, for the default size. */
    unsigned widest = 1;
    for (unsigned i = 0; i < n; ++i)
        if (words_of(rt->procs[i].item_size) > widest)
            widest = words_of(rt->procs[i].item_size);
    if (on && items == 0)
        items = default_work_first_items(rt, widest, free);
    for (unsigned i = 0; i < n; ++i) {
        perma_proc_info *p = &rt->procs[i];
        p->wf_need = 0;
        for (unsigned e = 0; e < p->emit_count; ++e)
            p->wf_need += p->emit_max[e];
        p->stackable = on && items && p->simple && !p->queue_only && p->local_bytes_per_item == 0 &&
                       2 * p->wf_need <= items;
    }
    for (bool changed = true; changed;) {
        changed = false;
        for (unsigned i = 0; i < n; ++i)
            for (unsigned e = 0; e < rt->procs[i].emit_count && rt->procs[i].stackable; ++e)
                if (!rt->procs[rt->procs[i].emit_target[e]].stackable) {
                    rt->procs[i].stackable = false;
                    changed = true;
                }
    }
    /* Stacks only where an item can land on one: a stackable procedure
     * that emits into a stackable one. */
    bool pushed = false;
    for (unsigned i = 0; i < n; ++i)
        pushed = pushed || (rt->procs[i].stackable && rt->procs[i].emit_count);
    unsigned slot = 0, align = 1;
    for (unsigned i = 0; i < n; ++i) {
        rt->procs[i].stackable = rt->procs[i].stackable && pushed;
        if (!rt->procs[i].stackable)
            continue;
        if (words_of(rt->procs[i].item_size) > slot)
            slot = words_of(rt->procs[i].item_size);
        if (alignment_of_size(rt->procs[i].item_size) > align)
            align = alignment_of_size(rt->procs[i].item_size);
    }
    rt->build.wf_items = slot ? items : 0;
    rt->build.wf_slot_words = slot ? round_up(slot, align < 4 ? 1 : align / 4) : 0;
    rt->build.wf_budget = rt->caps.is_cpu ? WF_BUDGET_CPU : WF_BUDGET_GPU;
    rt->build.wf_need = 0;
    for (unsigned i = 0; i < n; ++i)
        if (rt->procs[i].stackable && rt->procs[i].wf_need > rt->build.wf_need)
            rt->build.wf_need = rt->procs[i].wf_need;
    rt->build.wf_words =
        rt->build.wf_items ? (unsigned)wf_words_of(rt, rt->build.wf_items, rt->build.wf_slot_words) : 0;
}

perma_status perma_build_layout(perma_runtime *rt)
{
    if (rt->proc_count == 0)
        return perma_set_error(rt, PERMA_ERR_STATE, "no procedure is registered");
    perma_status st = resolve_targets(rt);
    if (st == PERMA_OK)
        st = check_functions(rt);
    if (st == PERMA_OK)
        st = check_cycles(rt);
    if (st != PERMA_OK)
        return st;
    compute_depths(rt);
    compute_order(rt);
    compute_full_batches(rt);
    /* Queues can belong to groups, and groups keep local front queues,
     * only when the groups live for the whole launch. */
    bool persistent = rt->executor->persistent;
    rt->build.strategy = perma_strategy_row((int)rt->config.schedule.strategy);
    rt->build.queue_sets = queue_sets_of(rt, rt->build.strategy);
    perma_queue_layout_fill(rt, rt->build.queue_sets, &rt->build.queue_layout);
    rt->build.device_trace_events = persistent && rt->config.trace_path ? rt->config.trace_events : 0;

    rt->build.max_edges = 1;
    for (unsigned i = 0; i < rt->proc_count; ++i)
        if (rt->procs[i].emit_count > rt->build.max_edges)
            rt->build.max_edges = rt->procs[i].emit_count;

    size_t limit = perma_local_memory(rt);
    /* The local front queue: a stack of local_queue_items per procedure. */
    rt->build.local_queue_items = persistent ? rt->config.schedule.local_queue_items : 0;
    rt->build.lq_words = 0;
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        /* Each stack aligned as the kernel's arena (128 bytes), so items
         * run in place there are aligned for their type. */
        rt->build.lq_words = round_up(rt->build.lq_words, 32);
        rt->procs[i].lq_off = rt->build.lq_words;
        rt->build.lq_words += rt->build.local_queue_items * words_of(rt->procs[i].item_size);
    }
    /* The kernel's other __local words: statistics, edge counters, batch,
     * and the local front queues. */
    size_t fixed = 4 * ((size_t)rt->proc_count * (4 + rt->build.max_edges) + 6 * rt->build.max_edges + 32 +
                        (size_t)rt->build.lq_words);
    if (fixed >= limit)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "config.schedule.local_queue_items %u needs %u bytes of __local memory, more than the "
                               "%zu bytes available", rt->build.local_queue_items, 4 * rt->build.lq_words, limit);
    compute_work_first(rt, (limit - fixed) / 4);
    fixed += 4 * (size_t)rt->build.wf_words;
    if (fixed >= limit)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "config.schedule.work_first_items %u needs %zu bytes of __local memory for the stacks "
                               "of %u work-items (items of up to %u bytes), more than the %zu bytes available: give "
                               "fewer items (+wfN) or a smaller config.group_size",
                               rt->build.wf_items, 4 * (size_t)rt->build.wf_words, rt->group_size,
                               4 * rt->build.wf_slot_words, limit);
    size_t budget_words = (limit - fixed) / 4;

    rt->build.arena_words = 16;
    rt->build.stage_words = 16;
    size_t stage_budget = stage_limit(rt);
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        perma_proc_info *p = &rt->procs[i];
        p->scratch_words = round_up(words_of(p->local_bytes_per_item), 4);
        unsigned batch = p->full_batch;
        while (batch > 0 && arena_cost(rt, p, batch, false) > budget_words)
            --batch;
        if (batch == 0)
            return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                                   "procedure '%s' needs %u bytes of __local memory for one item (item, "
                                   "scratch and emit counters), more than the %zu bytes available",
                                   p->name, 4 * arena_cost(rt, p, 1, false), (size_t)(budget_words * 4));
        p->max_batch_local = batch;
        while (batch > 1 && stage_cost(rt, p, batch, false) > stage_budget)
            --batch;
        if (stage_cost(rt, p, batch, false) > stage_budget)
            return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                                   "procedure '%s' needs %zu bytes to stage the emits of one item (its .emits "
                                   "maxima), more than the %zu bytes of staging a work-group may have",
                                   p->name, 4 * stage_cost(rt, p, 1, false), 4 * stage_budget);
        p->max_batch = batch;
        unsigned cost = arena_cost(rt, p, batch, true);
        if (cost > rt->build.arena_words)
            rt->build.arena_words = cost;
        size_t staged = stage_cost(rt, p, batch, true);
        if (staged > rt->build.stage_words)
            rt->build.stage_words = (unsigned)staged;
    }
    /* A launch that stops for room moves the items on the group's stacks to
     * its overflow data (as large as the staging), after the last batch's
     * overflowed emits: room for both. */
    rt->build.stage_words += rt->group_size * rt->build.wf_items * rt->build.wf_slot_words;
    rt->build.local_bytes = fixed + 4 * (size_t)rt->build.arena_words;
    return PERMA_OK;
}
