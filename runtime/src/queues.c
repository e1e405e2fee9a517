/* How big the queues are: their capacities at the start of a run, how they
 * grow when a launch runs out of room, and the cap on their memory.  A
 * planner (queues.h): numbers in, numbers out. */
#include "queues.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

static perma_status fail(perma_error *error, perma_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static perma_status fail(perma_error *error, perma_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(error->message, sizeof error->message, fmt, ap);
    va_end(ap);
    error->status = status;
    return status;
}

static size_t next_pow2(size_t v)
{
    size_t p = 1;
    while (p < v)
        p <<= 1;
    return p;
}

/* The seeds each of `sets` queue sets starts with, rounded up (the last
 * sets may get fewer, or none). */
static size_t seed_share(size_t seeds, unsigned sets)
{
    return (seeds + sets - 1) / sets;
}

/* The capacity a queue starts with for its share of `seeds`: at least the
 * initial capacity, a power of two. */
static size_t starting_capacity(const perma_queue_layout *layout, size_t seeds)
{
    size_t share = seed_share(seeds, layout->sets), base = layout->initial_capacity;
    return next_pow2(share > base ? share : base);
}

/* The procedure whose items queue `qi` holds. */
static const perma_queue_proc *proc_of(const perma_queue_layout *layout, unsigned qi)
{
    return &layout->proc[qi % layout->procs];
}

static size_t slot_bytes(const perma_queue_proc *p)
{
    return p->item_size + PERMA_QUEUE_SLOT_OVERHEAD;
}

size_t perma_queues_bytes(const perma_queue_layout *layout, const size_t *capacities)
{
    size_t total = 0;
    for (unsigned qi = 0; qi < layout->count; ++qi)
        total += capacities[qi] * slot_bytes(proc_of(layout, qi));
    return total;
}

perma_status perma_queues_check_seeds(const perma_queue_layout *layout, unsigned proc, size_t seeded, size_t count,
                                      perma_error *error)
{
    const perma_queue_proc *p = &layout->proc[proc];
    size_t total = seeded + count;
    if (count > PERMA_MAX_QUEUED_ITEMS - seeded)
        return fail(error, PERMA_ERR_ARGUMENT,
                    "perma_seed('%s'): %zu more items would make %zu queued, more than a queue holds "
                    "(PERMA_MAX_QUEUED_ITEMS, 2^30)", p->name, count, total);
    unsigned sets = layout->sets;
    size_t cap = starting_capacity(layout, total);
    size_t slot = slot_bytes(p), bytes = sets * cap * slot;
    if (bytes > layout->memory_limit)
        return fail(error, PERMA_ERR_CAPACITY,
                    "perma_seed('%s'): %zu items seeded would need %s%zu items of %zu bytes (with its "
                    "completion marks), %zu bytes, more than the queue memory limit of %zu bytes "
                    "(config.queue_memory_limit; 0: half the device's largest allocation)",
                    p->name, total, sets > 1 ? "a queue per group of " : "a queue of ", cap, slot, bytes,
                    layout->memory_limit);
    return PERMA_OK;
}

void perma_queues_seed_shares(const perma_queue_layout *layout, const size_t *seeds, size_t *first, size_t *count)
{
    for (unsigned qi = 0; qi < layout->count; ++qi) {
        size_t total = seeds[qi % layout->procs], share = seed_share(total, layout->sets);
        first[qi] = (size_t)(qi / layout->procs) * share;
        count[qi] = first[qi] < total ? total - first[qi] : 0;
        if (count[qi] > share)
            count[qi] = share;
    }
}

/* Start from what the last successful run of this build grew the queues
 * to, if that is more and all queues then fit the memory limit: a runtime
 * that runs similar work again does not pay the same regrowths every time. */
static unsigned keep_learned_capacities(const perma_queue_layout *layout, const size_t *learned, size_t *capacities)
{
    unsigned count = layout->count, kept = 0;
    size_t bytes = 0;
    for (unsigned qi = 0; qi < count; ++qi) {
        bool more = learned[qi] > capacities[qi];
        kept += more;
        bytes += (more ? learned[qi] : capacities[qi]) * slot_bytes(proc_of(layout, qi));
    }
    if (!kept || bytes > layout->memory_limit)
        return 0;
    for (unsigned qi = 0; qi < count; ++qi)
        if (learned[qi] > capacities[qi])
            capacities[qi] = learned[qi];
    return kept;
}

perma_status perma_queues_initial(const perma_queue_layout *layout, const size_t *seeds, const size_t *learned,
                                  size_t *capacities, unsigned *kept, perma_error *error)
{
    unsigned n = layout->procs;
    for (unsigned qi = 0; qi < layout->count; ++qi) {
        unsigned q = qi % n;
        size_t cap = starting_capacity(layout, seeds[q]);
        /* One item of any producer must fit, or nothing could ever run. */
        for (unsigned i = 0; i < n; ++i)
            for (unsigned e = 0; e < layout->proc[i].emit_count; ++e)
                if (layout->proc[i].emit_target[e] == q && layout->proc[i].emit_max[e] > cap)
                    cap = layout->proc[i].emit_max[e];
        capacities[qi] = next_pow2(cap);
    }
    *kept = learned ? keep_learned_capacities(layout, learned, capacities) : 0;
    size_t bytes = perma_queues_bytes(layout, capacities);
    if (bytes > layout->memory_limit)
        return fail(error, PERMA_ERR_CAPACITY,
                    "the initial queues need %zu bytes, more than the queue memory limit of %zu bytes", bytes,
                    layout->memory_limit);
    return PERMA_OK;
}

/* New capacities for a growth step: refused, naming the first queue that
 * grows, if all queues together would pass the memory limit or one would
 * pass 2^30 items. */
static perma_status check_growth(const perma_queue_layout *layout, const size_t *current, const size_t *capacities,
                                 perma_error *error)
{
    size_t bytes = perma_queues_bytes(layout, capacities);
    for (unsigned qi = 0; qi < layout->count; ++qi) {
        size_t before = current[qi];
        if (capacities[qi] == before)
            continue;
        const perma_queue_proc *p = proc_of(layout, qi);
        if (bytes > layout->memory_limit)
            return fail(error, PERMA_ERR_CAPACITY,
                        "queue '%s' is full (%zu items of %zu bytes) and cannot grow to %zu items: "
                        "all queues would need %zu bytes, more than the queue memory limit of %zu bytes",
                        p->name, before, p->item_size, capacities[qi], bytes, layout->memory_limit);
        if (capacities[qi] > PERMA_MAX_QUEUED_ITEMS)
            return fail(error, PERMA_ERR_CAPACITY, "queue '%s' would need more than 2^30 items "
                        "(PERMA_MAX_QUEUED_ITEMS)", p->name);
    }
    return PERMA_OK;
}

perma_status perma_queues_grow_stalled(const perma_queue_layout *layout, const size_t *current, const size_t *queued,
                                       unsigned starved_queue, const size_t *overflow, size_t *capacities,
                                       perma_error *error)
{
    unsigned n = layout->procs, count = layout->count;
    /* capacities[qi] doubles for every queue that grows. */
    memcpy(capacities, current, count * sizeof *capacities);
    bool any = false;
    if (starved_queue < count) {
        capacities[starved_queue] = 2 * current[starved_queue];
        any = true;
    }
    for (int relaxed = 0; relaxed < 2 && !any; ++relaxed) {
        for (unsigned qi = 0; qi < count; ++qi) {
            if (queued[qi] == 0)
                continue;
            const perma_queue_proc *p = proc_of(layout, qi);
            /* A stolen batch emits into the thief's set: consider every set. */
            for (unsigned set = 0; set < layout->sets; ++set) {
                for (unsigned e = 0; e < p->emit_count; ++e) {
                    unsigned ti = set * n + p->emit_target[e];
                    size_t room = current[ti] - queued[ti];
                    /* relaxed: the kernel saw no room where we see some (a
                     * race between groups); grow the targets of all waiting work. */
                    if (relaxed || room < p->emit_max[e]) {
                        capacities[ti] = 2 * current[ti];
                        any = true;
                    }
                }
            }
        }
    }
    /* The initial capacity is at least any emit_max, so doubling leaves
     * room for at least one item's emits.  A group calls a stall against
     * the groups it sees running; a group it did not see (not started yet,
     * or adopting the set of one that left) may still run batches before
     * it sees the launch stop, and leave their emits in its overflow area
     * rather than in the queues (kernels/perma_scheduler.cl,
     * perma_all_blocked).  Those items are what waits: the relayout
     * appends them, nothing else needs to grow. */
    for (unsigned qi = 0; qi < count && !any; ++qi)
        any = overflow[qi] != 0;
    if (!any)
        return fail(error, PERMA_ERR_DEVICE, "the kernel reported no room, but no queued item emits anything");
    return check_growth(layout, current, capacities, error);
}

perma_status perma_queues_fit_more(const perma_queue_layout *layout, const size_t *current, const size_t *queued,
                                   const size_t *needed, size_t *capacities, perma_error *error)
{
    for (unsigned qi = 0; qi < layout->count; ++qi)
        while (capacities[qi] - queued[qi] < needed[qi])
            capacities[qi] *= 2;
    return check_growth(layout, current, capacities, error);
}

perma_status perma_queues_grow_to_fit(const perma_queue_layout *layout, const size_t *current, const size_t *queued,
                                      const size_t *needed, size_t *capacities, perma_error *error)
{
    memcpy(capacities, current, layout->count * sizeof *capacities);
    return perma_queues_fit_more(layout, current, queued, needed, capacities, error);
}
