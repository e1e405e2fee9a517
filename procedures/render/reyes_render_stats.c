/* Statistics of a render: the runtime's per-run numbers summed over the
 * buckets' runs (peaks and capacities: the largest). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "reyes_render_stats.h"

void reyes_stats_free(reyes_stats *stats)
{
    if (!stats)
        return;
    free(stats->bucket_peak_queue_bytes);
    stats->bucket_peak_queue_bytes = NULL;
}

static uint64_t max_u64(uint64_t a, uint64_t b)
{
    return a > b ? a : b;
}

static size_t max_size(size_t a, size_t b)
{
    return a > b ? a : b;
}

static void add_procedure(perma_procedure_stats *total, const perma_procedure_stats *run)
{
    total->name = run->name;
    total->items += run->items;
    total->batches += run->batches;
    total->emit_count = run->emit_count;
    for (unsigned e = 0; e < PERMA_MAX_EMITS; ++e)
        total->emitted[e] += run->emitted[e];
    total->seeded += run->seeded;
    total->peak_queue_items = max_u64(total->peak_queue_items, run->peak_queue_items);
    total->queue_capacity = max_size(total->queue_capacity, run->queue_capacity);
    total->regrowths += run->regrowths;
    total->batch_size = total->batch_size > run->batch_size ? total->batch_size : run->batch_size;
    total->stacked_items += run->stacked_items;
}

void reyes_stats_add_run(reyes_stats *total, const perma_stats *run,
                         const perma_procedure_stats procedures[REYES_PROC_COUNT])
{
    perma_stats *t = &total->run;
    t->seconds += run->seconds;
    t->launches += run->launches;
    t->regrowths += run->regrowths;
    t->work_groups = run->work_groups;
    t->resident_groups = run->resident_groups;
    t->kernel_local_bytes = run->kernel_local_bytes;
    if (run->work_groups_reason)
        snprintf(total->work_groups_reason, sizeof total->work_groups_reason, "%s", run->work_groups_reason);
    t->group_size = run->group_size;
    t->procedure_count = run->procedure_count;
    t->peak_queue_bytes = max_size(t->peak_queue_bytes, run->peak_queue_bytes);
    t->items += run->items;
    t->steals += run->steals;
    t->donations += run->donations;
    t->spills += run->spills;
    t->idle_polls += run->idle_polls;
    t->stack_items = run->stack_items;
    t->stacked_items += run->stacked_items;
    t->stack_spills += run->stack_spills;
    t->stack_peak = t->stack_peak > run->stack_peak ? t->stack_peak : run->stack_peak;
    t->technique = run->technique;
    t->strategy = run->strategy;
    for (int p = 0; p < REYES_PROC_COUNT; ++p)
        add_procedure(&total->procedures[p], &procedures[p]);
    total->peak_queue_bytes = t->peak_queue_bytes;
    total->seconds = t->seconds;
}

double reyes_area_bin_lower(unsigned bin)
{
    if (bin == 0)
        return 0.0;
    return ldexp((bin - 1) % 2 ? 1.5 : 1.0, (int)((bin - 1) / 2) - 10);
}

double reyes_stats_area_mean(const reyes_stats *stats)
{
    return stats->micropolygons ? stats->micropolygon_area / (double)stats->micropolygons : 0.0;
}

double reyes_stats_area_percentile(const reyes_stats *stats, double fraction)
{
    uint64_t total = 0;
    for (unsigned b = 0; b < REYES_AREA_BINS; ++b)
        total += stats->micropolygon_area_bins[b];
    if (total == 0)
        return 0.0;
    double rank = fraction * (double)total, below = 0.0;
    for (unsigned b = 0; b < REYES_AREA_BINS; ++b) {
        double count = (double)stats->micropolygon_area_bins[b];
        if (count > 0.0 && below + count >= rank) {
            double lo = reyes_area_bin_lower(b), hi = reyes_area_bin_lower(b + 1);
            double t = (rank - below) / count;
            if (b == 0)
                return hi * t;
            if (b + 1 >= REYES_AREA_BINS)
                return lo;
            return lo * pow(hi / lo, t);
        }
        below += count;
    }
    return reyes_area_bin_lower(REYES_AREA_BINS - 1);
}
