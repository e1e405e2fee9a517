/* How big the queues are: their capacities at the start of a run, how they
 * grow when a launch runs out of room, and the cap on their memory.  Only
 * numbers: the device state (state.c) lays the queues out. */
#include "executor.h"
#include "schedule_table.h"

#include <stdlib.h>
#include <string.h>

#define DEFAULT_CAPACITY 1024

static size_t next_pow2(size_t v)
{
    size_t p = 1;
    while (p < v)
        p <<= 1;
    return p;
}

/* config.queue_memory_limit, or half the device's largest allocation: a
 * regrowth holds the old and the new queue buffers at once. */
size_t perma_queues_memory_limit(const perma_runtime *rt)
{
    if (rt->config.queue_memory_limit)
        return rt->config.queue_memory_limit;
    return rt->max_alloc ? (size_t)(rt->max_alloc / 2) : ((size_t)1 << 30);
}

unsigned perma_queues_sets(const perma_runtime *rt)
{
    const perma_strategy_info *strategy = perma_strategy_row((int)rt->config.schedule.strategy);
    return rt->executor->persistent && strategy && strategy->per_group_queue_sets ? rt->work_groups : 1;
}

static size_t initial_capacity(const perma_runtime *rt)
{
    return rt->config.queue_capacity ? rt->config.queue_capacity : DEFAULT_CAPACITY;
}

/* The seeds each of `sets` queue sets starts with, rounded up (the last
 * sets may get fewer, or none). */
static size_t seed_share(size_t seeds, unsigned sets)
{
    return (seeds + sets - 1) / sets;
}

/* The capacity a queue starts with for its share of `seeds`: at least
 * initial_capacity, a power of two. */
static size_t starting_capacity(const perma_runtime *rt, size_t seeds, unsigned sets)
{
    size_t share = seed_share(seeds, sets), base = initial_capacity(rt);
    return next_pow2(share > base ? share : base);
}

perma_status perma_queues_check_seeds(perma_runtime *rt, unsigned proc, size_t count)
{
    const perma_proc_info *p = &rt->procs[proc];
    size_t total = p->seed_count + count;
    if (count > PERMA_MAX_QUEUED_ITEMS - p->seed_count)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "perma_seed('%s'): %zu more items would make %zu queued, more than a queue holds "
                               "(PERMA_MAX_QUEUED_ITEMS, 2^30)", p->name, count, total);
    unsigned sets = perma_queues_sets(rt);
    size_t cap = starting_capacity(rt, total, sets);
    size_t slot = p->item_size + PERMA_QUEUE_SLOT_OVERHEAD, bytes = sets * cap * slot;
    if (bytes > perma_queues_memory_limit(rt))
        return perma_set_error(rt, PERMA_ERR_CAPACITY,
                               "perma_seed('%s'): %zu items seeded would need %s%zu items of %zu bytes (with its "
                               "completion marks), %zu bytes, more than the queue memory limit of %zu bytes "
                               "(config.queue_memory_limit; 0: half the device's largest allocation)",
                               p->name, total, sets > 1 ? "a queue per group of " : "a queue of ", cap,
                               slot, bytes, perma_queues_memory_limit(rt));
    return PERMA_OK;
}

/* The procedure whose items queue `qi` holds. */
static const perma_proc_info *proc_of(const perma_runtime *rt, unsigned qi)
{
    return &rt->procs[qi % rt->proc_count];
}

static size_t queued(const perma_ctl_block *ctl, unsigned qi)
{
    return (uint32_t)(ctl->queues[qi].tail - ctl->queues[qi].head);
}

unsigned perma_queues_count(const perma_runtime *rt)
{
    return rt->queue_sets * rt->proc_count;
}

size_t perma_queues_bytes(const perma_runtime *rt, const size_t *capacities)
{
    size_t total = 0;
    for (unsigned qi = 0; qi < perma_queues_count(rt); ++qi)
        total += capacities[qi] * (proc_of(rt, qi)->item_size + PERMA_QUEUE_SLOT_OVERHEAD);
    return total;
}

void perma_queues_seed_share(const perma_runtime *rt, unsigned qi, size_t *first, size_t *count)
{
    unsigned sets = rt->queue_sets, set = qi / rt->proc_count;
    const perma_proc_info *p = proc_of(rt, qi);
    size_t share = seed_share(p->seed_count, sets);
    *first = (size_t)set * share;
    *count = *first < p->seed_count ? p->seed_count - *first : 0;
    if (*count > share)
        *count = share;
}

/* Start from what the last successful run of this build grew the queues
 * to, if that is more and all queues then fit the memory limit: a runtime
 * that runs similar work again does not pay the same regrowths every time.
 * Counts the queues that start higher in the statistics. */
static void keep_learned_capacities(perma_runtime *rt, size_t *capacities)
{
    const perma_device_state *s = &rt->state;
    unsigned count = perma_queues_count(rt);
    rt->stats.queues_kept = 0;
    if (!s->capacities_learned || s->queue_count != count)
        return;
    size_t *learned = malloc(count * sizeof *learned);
    if (!learned)
        return; /* an optimisation only */
    unsigned kept = 0;
    for (unsigned qi = 0; qi < count; ++qi) {
        learned[qi] = capacities[qi];
        if (s->queues[qi].capacity > capacities[qi]) {
            learned[qi] = s->queues[qi].capacity;
            kept++;
        }
    }
    if (kept && perma_queues_bytes(rt, learned) <= perma_queues_memory_limit(rt)) {
        memcpy(capacities, learned, count * sizeof *learned);
        rt->stats.queues_kept = kept;
    }
    free(learned);
}

perma_status perma_queues_initial(perma_runtime *rt, size_t *capacities)
{
    unsigned n = rt->proc_count;
    for (unsigned qi = 0; qi < perma_queues_count(rt); ++qi) {
        unsigned q = qi % n;
        size_t cap = starting_capacity(rt, rt->procs[q].seed_count, rt->queue_sets);
        /* One item of any producer must fit, or nothing could ever run. */
        for (unsigned i = 0; i < n; ++i)
            for (unsigned e = 0; e < rt->procs[i].emit_count; ++e)
                if ((unsigned)rt->procs[i].emit_target[e] == q && rt->procs[i].emit_max[e] > cap)
                    cap = rt->procs[i].emit_max[e];
        capacities[qi] = next_pow2(cap);
    }
    keep_learned_capacities(rt, capacities);
    size_t bytes = perma_queues_bytes(rt, capacities);
    if (bytes > perma_queues_memory_limit(rt))
        return perma_set_error(rt, PERMA_ERR_CAPACITY,
                               "the initial queues need %zu bytes, more than the queue memory limit of %zu bytes",
                               bytes, perma_queues_memory_limit(rt));
    return PERMA_OK;
}

/* New capacities for a growth step: refused, naming the first queue that
 * grows, if all queues together would pass the memory limit or one would
 * pass 2^31 items. */
static perma_status check_growth(perma_runtime *rt, const size_t *capacities)
{
    size_t bytes = perma_queues_bytes(rt, capacities);
    for (unsigned qi = 0; qi < perma_queues_count(rt); ++qi) {
        size_t before = rt->state.queues[qi].capacity;
        if (capacities[qi] == before)
            continue;
        if (bytes > perma_queues_memory_limit(rt))
            return perma_set_error(rt, PERMA_ERR_CAPACITY,
                                   "queue '%s' is full (%zu items of %zu bytes) and cannot grow to %zu items: "
                                   "all queues would need %zu bytes, more than the queue memory limit of %zu bytes",
                                   proc_of(rt, qi)->name, before, proc_of(rt, qi)->item_size, capacities[qi], bytes,
                                   perma_queues_memory_limit(rt));
        if (capacities[qi] > PERMA_MAX_QUEUED_ITEMS)
            return perma_set_error(rt, PERMA_ERR_CAPACITY, "queue '%s' would need more than 2^30 items "
                                   "(PERMA_MAX_QUEUED_ITEMS)", proc_of(rt, qi)->name);
    }
    return PERMA_OK;
}

perma_status perma_queues_grow_stalled(perma_runtime *rt, const perma_ctl_block *ctl, unsigned starved_queue,
                                       const size_t *overflow, size_t *capacities)
{
    unsigned n = rt->proc_count, count = perma_queues_count(rt);
    bool *grows = calloc(count, sizeof *grows);
    if (!grows)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory growing queues");
    bool any = false;
    if (starved_queue < count)
        grows[starved_queue] = any = true;
    for (int relaxed = 0; relaxed < 2 && !any; ++relaxed) {
        for (unsigned qi = 0; qi < count; ++qi) {
            if (queued(ctl, qi) == 0)
                continue;
            const perma_proc_info *p = proc_of(rt, qi);
            /* A stolen batch emits into the thief's set: consider every set. */
            for (unsigned set = 0; set < rt->queue_sets; ++set) {
                for (unsigned e = 0; e < p->emit_count; ++e) {
                    unsigned ti = set * n + (unsigned)p->emit_target[e];
                    size_t room = rt->state.queues[ti].capacity - queued(ctl, ti);
                    /* relaxed: the kernel saw no room where we see some (a
                     * race between groups); grow the targets of all waiting work. */
                    if (relaxed || room < p->emit_max[e]) {
                        grows[ti] = true;
                        any = true;
                    }
                }
            }
        }
    }
    /* The initial capacity is at least any emit_max, so doubling leaves
     * room for at least one item's emits. */
    for (unsigned qi = 0; qi < count; ++qi)
        capacities[qi] = rt->state.queues[qi].capacity * (grows[qi] ? 2 : 1);
    free(grows);
    /* A group calls a stall against the groups it sees running; a group
     * it did not see (not started yet, or adopting the set of one that
     * left) may still run batches before it sees the launch stop, and
     * leave their emits in its overflow area rather than in the queues
     * (kernels/perma_scheduler.cl, perma_all_blocked).  Those items are
     * what waits: the relayout appends them, nothing else needs to grow. */
    for (unsigned qi = 0; qi < count && !any; ++qi)
        any = overflow[qi] != 0;
    if (!any)
        return perma_set_error(rt, PERMA_ERR_DEVICE, "the kernel reported no room, but no queued item emits anything");
    return check_growth(rt, capacities);
}

perma_status perma_queues_fit_more(perma_runtime *rt, const perma_ctl_block *ctl, const size_t *needed,
                                   size_t *capacities)
{
    for (unsigned qi = 0; qi < perma_queues_count(rt); ++qi)
        while (capacities[qi] - queued(ctl, qi) < needed[qi])
            capacities[qi] *= 2;
    return check_growth(rt, capacities);
}

perma_status perma_queues_grow_to_fit(perma_runtime *rt, const perma_ctl_block *ctl, const size_t *needed,
                                      size_t *capacities)
{
    for (unsigned qi = 0; qi < perma_queues_count(rt); ++qi)
        capacities[qi] = rt->state.queues[qi].capacity;
    return perma_queues_fit_more(rt, ctl, needed, capacities);
}
