/* The perma variants every benchmark measures: one row per schedule of the
 * runtime (perma_schedule_all, the victims under one stealing strategy),
 * plus a local front queue under two of them, as schedule labels
 * (perma_schedule_parse).  A variant the runtime does not implement yet
 * fails in perma_create or perma_run and prints as n/a, so entries simply
 * start working when the runtime does. */
#include "bench.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* The bounded batches' default limit (perma.h), named in their rows'
 * label so that the rows say what they measured. */
#define BOUNDED_BATCH_LIMIT 4096

unsigned bench_schedule_labels(perma_schedule_set set, char (*labels)[BENCH_LABEL_SIZE], unsigned max)
{
    perma_schedule s;
    unsigned n = 0;
    for (; n < max && perma_schedule_all(set, n, &s) == PERMA_OK; ++n) {
        if (s.technique == PERMA_TECHNIQUE_BOUNDED_BATCHES)
            s.batch_limit = BOUNDED_BATCH_LIMIT;
        perma_schedule_format(&s, labels[n], BENCH_LABEL_SIZE);
    }
    return n;
}

/* After the megakernel's rows: its local front queue (+localN) and
 * work-first stacks (+wfN) under the shared queues and under stealing. */
static const char *const local_queue_rows[] = { "megakernel/shared+local256", "megakernel/stealing/random+local256",
                                                "megakernel/shared+wf64", "megakernel/stealing/random+wf64" };
#define LOCAL_QUEUE_ROWS (sizeof local_queue_rows / sizeof local_queue_rows[0])
#define MAX_VARIANTS 32

static char labels[MAX_VARIANTS][BENCH_LABEL_SIZE];
static unsigned count;

static void list_variants(void)
{
    char schedules[MAX_VARIANTS - LOCAL_QUEUE_ROWS][BENCH_LABEL_SIZE];
    unsigned n = bench_schedule_labels(PERMA_SCHEDULES_VICTIMS_ONCE, schedules, MAX_VARIANTS - LOCAL_QUEUE_ROWS);
    bool local_rows_listed = false;
    for (unsigned i = 0; i < n; ++i) {
        if (!local_rows_listed && strncmp(schedules[i], "megakernel", strlen("megakernel")) != 0) {
            for (unsigned r = 0; r < LOCAL_QUEUE_ROWS; ++r)
                snprintf(labels[count++], BENCH_LABEL_SIZE, "%s", local_queue_rows[r]);
            local_rows_listed = true;
        }
        memcpy(labels[count++], schedules[i], BENCH_LABEL_SIZE);
    }
}

unsigned bench_variant_count(void)
{
    if (!count)
        list_variants();
    return count;
}

void bench_variant_add(const char *label)
{
    unsigned n = bench_variant_count();
    for (unsigned i = 0; i < n; ++i)
        if (strcmp(labels[i], label) == 0)
            return;
    if (n < MAX_VARIANTS)
        snprintf(labels[count++], BENCH_LABEL_SIZE, "%s", label);
}

const char *bench_variant_label(unsigned index)
{
    return index < bench_variant_count() ? labels[index] : NULL;
}

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

/* Whether `label` is one --only names: any of its comma-separated
 * entries, each TEXT (contained in the label) or =LABEL (the label). */
static int only_names(const char *only, const char *label)
{
    for (const char *entry = only; entry;) {
        const char *comma = strchr(entry, ',');
        size_t length = comma ? (size_t)(comma - entry) : strlen(entry);
        char text[128];
        if (length > 0 && length < sizeof text) {
            memcpy(text, entry, length);
            text[length] = '\0';
            if (text[0] == '=' ? !strcmp(label, text + 1) : strstr(label, text) != NULL)
                return 1;
        }
        entry = comma ? comma + 1 : NULL;
    }
    return 0;
}

int bench_variant_select(const bench_options *options, const char *label, bench_variant *out)
{
    if (options->only && !only_names(options->only, label))
        return 0;
    perma_error error;
    if (bench_variant_parse(label, out, &error) != PERMA_OK) {
        printf("%s: n/a: %s\n", label, error.message);
        return 0;
    }
    return 1;
}
