/* The perma variants every benchmark measures: one row per technique and
 * megakernel strategy, as schedule labels (perma_schedule_parse).  A
 * variant the runtime does not implement yet fails in perma_create or
 * perma_run and prints as n/a, so entries simply start working when the
 * runtime does. */
#include "bench.h"

#include <stdlib.h>
#include <string.h>

const char *const bench_variants[] = {
    "megakernel/shared",
    "megakernel/stealing/random",
    "megakernel/stealing/round-robin",
    "megakernel/donation",
    "megakernel/stealing-donation/random",
    "megakernel/shared+local256",
    "megakernel/stealing/random+local256",
    "kernel-per-procedure",
    "bounded-batches/p=4096",
};
const unsigned bench_variant_count = sizeof bench_variants / sizeof bench_variants[0];

perma_status bench_variant_parse(const char *label, bench_variant *out, perma_error *error)
{
    perma_status status = perma_schedule_parse(label, &out->schedule, error);
    if (status == PERMA_OK) {
        out->label = label;
        snprintf(out->name, sizeof out->name, "%s", label);
    }
    return status;
}

unsigned bench_device_passes(const bench_options *options)
{
    return options->device_count ? options->device_count : 1;
}

void bench_variant_use_device(const bench_options *options, unsigned d, bench_variant *v)
{
    if (!options->device_count)
        return;
    setenv("PERMA_DEVICE", options->devices[d], 1);
    snprintf(v->name, sizeof v->name, "%s @%s", v->label, options->devices[d]);
}

int bench_variant_select(const bench_options *options, const char *label, bench_variant *out)
{
    if (options->only && (options->only[0] == '=' ? strcmp(label, options->only + 1) != 0
                                                  : !strstr(label, options->only)))
        return 0;
    perma_error error;
    if (bench_variant_parse(label, out, &error) != PERMA_OK) {
        printf("%s: n/a: %s\n", label, error.message);
        return 0;
    }
    return 1;
}
