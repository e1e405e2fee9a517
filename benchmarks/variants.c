/* The perma variants every benchmark measures: one row per technique and
 * megakernel strategy.  A variant the runtime does not implement yet fails
 * in perma_create or perma_run and prints as n/a, so entries simply start
 * working when the runtime does. */
#include "bench.h"

#include <string.h>

#define MK PERMA_TECHNIQUE_MEGAKERNEL

const bench_variant bench_variants[] = {
    { MK, PERMA_STRATEGY_SHARED, PERMA_VICTIM_RANDOM, 0, 0 },
    { MK, PERMA_STRATEGY_STEALING, PERMA_VICTIM_RANDOM, 0, 0 },
    { MK, PERMA_STRATEGY_STEALING, PERMA_VICTIM_ROUND_ROBIN, 0, 0 },
    { MK, PERMA_STRATEGY_DONATION, PERMA_VICTIM_RANDOM, 0, 0 },
    { MK, PERMA_STRATEGY_STEALING_DONATION, PERMA_VICTIM_RANDOM, 0, 0 },
    { MK, PERMA_STRATEGY_SHARED, PERMA_VICTIM_RANDOM, 256, 0 },
    { MK, PERMA_STRATEGY_STEALING, PERMA_VICTIM_RANDOM, 256, 0 },
    { PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE, PERMA_STRATEGY_SHARED, PERMA_VICTIM_RANDOM, 0, 0 },
    { PERMA_TECHNIQUE_BOUNDED_BATCHES, PERMA_STRATEGY_SHARED, PERMA_VICTIM_RANDOM, 0, 4096 },
};
const unsigned bench_variant_count = sizeof bench_variants / sizeof bench_variants[0];

static const char *or_unknown(const char *name)
{
    return name ? name : "?";
}

void bench_variant_label(const bench_variant *v, char *out, size_t size)
{
    const char *technique = or_unknown(perma_technique_name(v->technique));
    if (v->technique == PERMA_TECHNIQUE_BOUNDED_BATCHES) {
        snprintf(out, size, "%s/p=%u", technique, v->batch_limit);
        return;
    }
    if (v->technique != PERMA_TECHNIQUE_MEGAKERNEL) {
        snprintf(out, size, "%s", technique);
        return;
    }
    int stealing = v->strategy == PERMA_STRATEGY_STEALING || v->strategy == PERMA_STRATEGY_STEALING_DONATION;
    char local[32] = "";
    if (v->local_queue_items)
        snprintf(local, sizeof local, "+local%u", v->local_queue_items);
    snprintf(out, size, "%s/%s%s%s%s", technique, or_unknown(perma_strategy_name(v->strategy)),
             stealing ? "/" : "", stealing ? or_unknown(perma_victim_name(v->victim)) : "", local);
}

int bench_variant_selected(const bench_options *options, const bench_variant *variant)
{
    if (!options->only)
        return 1;
    char label[96];
    bench_variant_label(variant, label, sizeof label);
    return strstr(label, options->only) != NULL;
}
