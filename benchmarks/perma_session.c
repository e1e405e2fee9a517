/* Creating a runtime for a variant and measuring a workload on it. */
#include "bench.h"

#include <string.h>

perma_runtime *bench_perma_create(const bench_options *o, const bench_variant *v, unsigned group_size,
                                  unsigned work_groups, bench_row *row)
{
    perma_config config;
    perma_config_init(&config);
    config.trace_path = o->trace_path;
    config.schedule = v->schedule;
    config.group_size = group_size;
    config.work_groups = work_groups;
    config.time_limit = 120; /* a broken variant fails its row, not the whole benchmark */
    perma_runtime *rt = NULL;
    perma_error error;
    if (perma_create(&config, &rt, &error) != PERMA_OK) {
        snprintf(row->message, sizeof row->message, "create: %s", error.message);
        return NULL;
    }
    return rt;
}

static void fail(bench_row *row, perma_runtime *rt, const char *what)
{
    row->ran = 0;
    snprintf(row->message, sizeof row->message, "%s: %s", what, perma_errmsg(rt));
}

/* Sum of per-procedure peak items times item size: the memory the items
 * themselves needed, independent of how the queues were allocated. */
static size_t peak_item_bytes(perma_runtime *rt, const bench_workload *w)
{
    size_t total = 0;
    for (unsigned p = 0; p < w->procedures; ++p) {
        perma_procedure_stats ps;
        if (perma_get_procedure_stats(rt, w->procs[p], &ps) == PERMA_OK)
            total += (size_t)ps.peak_queue_items * w->item_sizes[p];
    }
    return total;
}

void bench_perma_measure(perma_runtime *rt, const bench_variant *variant, const bench_options *options,
                         const bench_workload *w, bench_row *row)
{
    enum { MAX_REPEAT = 1000 };
    static double seconds[MAX_REPEAT], walls[MAX_REPEAT], cpu[MAX_REPEAT];
    unsigned repeat = options->repeat < MAX_REPEAT ? options->repeat : MAX_REPEAT;

    bench_activity("building %s (%s)", variant->name, row->workload);
    if (perma_build(rt) != PERMA_OK) {
        fail(row, rt, "build");
        return;
    }
    row->check = BENCH_CHECK_PASS;
    /* Run 0 is the untimed warm-up (PoCL compiles for the local size at
     * the first launch). */
    for (unsigned i = 0; i <= repeat; ++i) {
        if (w->prepare(w->state, rt) != PERMA_OK) {
            fail(row, rt, "seed");
            return;
        }
        if (i == 0)
            bench_activity("the warm-up run of %s (%s)", variant->name, row->workload);
        else
            bench_activity("timed run %u of %u of %s (%s)", i, repeat, variant->name, row->workload);
        double start = bench_now(), cpu_start = bench_cpu_now();
        if (perma_run(rt) != PERMA_OK) {
            fail(row, rt, "run");
            return;
        }
        double wall = bench_now() - start, cpu_used = bench_cpu_now() - cpu_start;
        if (!w->verify(w->state, rt, row))
            row->check = BENCH_CHECK_FAIL;
        perma_stats st;
        if (perma_get_stats(rt, &st) != PERMA_OK) {
            fail(row, rt, "stats");
            return;
        }
        if (i > 0) {
            seconds[i - 1] = st.seconds;
            walls[i - 1] = wall;
            cpu[i - 1] = cpu_used;
        }
        row->peak_queue_bytes = st.peak_queue_bytes;
        row->steals = st.steals;
        row->donations = st.donations;
        row->spills = st.spills;
        row->group_size = st.group_size;
        row->work_groups = st.work_groups;
        row->peak_item_bytes = peak_item_bytes(rt, w);
        if (st.technique != variant->schedule.technique ||
            (st.technique == PERMA_TECHNIQUE_MEGAKERNEL && st.strategy != variant->schedule.strategy))
            snprintf(row->message, sizeof row->message, "runtime ran %s/%s instead",
                     perma_technique_name(st.technique) ? perma_technique_name(st.technique) : "?",
                     perma_strategy_name(st.strategy) ? perma_strategy_name(st.strategy) : "?");
    }
    row->seconds = bench_summary(options, seconds, repeat);
    row->wall_seconds = bench_summary(options, walls, repeat);
    row->cpu_seconds = bench_summary(options, cpu, repeat);
    row->ran = 1;
}

void bench_perma_verbose(perma_runtime *rt, const bench_options *options)
{
    if (options->verbose)
        perma_print_stats(rt, stdout);
}
