/* `perma-bench pipeline`: producer -> transform -> consumer with skewed
 * fan-out (pipeline.h), measured twice: with perma's default order, where
 * downstream procedures are served first, and with explicit priorities
 * that serve upstream first.  Besides time it reports the peak memory of
 * waiting items: perma's queue allocation (peak q.B) and the sum over
 * procedures of peak queued items times item size (peak items B). */
#include "bench.h"
#include "pipeline.h"

#include <stdlib.h>
#include <string.h>

static const char *device_types =
    "#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable\n"
    "struct pipe_producer { uint index; uint pad; };\n"
    "struct pipe_record { uint source; uint k; uint payload[6]; };\n"
    "struct pipe_result { uint source; uint value; uint pad[2]; };\n"
    PIPE_DEVICE_CODE "\n";

static const char *producer_source =
    "void producer(perma_ctx *ctx, __local const struct pipe_producer *p)\n"
    "{\n"
    "    uint fan = pipe_fan(p->index);\n"
    "    struct pipe_record rec = { p->index, 0u, { p->index, 0u, 0u, 0u, 0u, 0u } };\n"
    "    for (uint k = 0; k < fan; ++k) {\n"
    "        rec.k = k;\n"
    "        rec.payload[1] = k;\n"
    "        emit_transform(ctx, &rec);\n"
    "    }\n"
    "}\n";

static const char *transform_source =
    "void transform(perma_ctx *ctx, __local const struct pipe_record *rec)\n"
    "{\n"
    "    struct pipe_result res = { rec->source, pipe_value(rec->source, rec->k, PIPE_ROUNDS), { 0u, 0u } };\n"
    "    emit_consumer(ctx, &res);\n"
    "}\n";

/* The consumed count and the checksum are reductions. */
static const char *consumer_source =
    "void consumer(perma_ctx *ctx, __local const struct pipe_result *res)\n"
    "{\n"
    "    reduce_consumed(ctx, 1ul);\n"
    "    reduce_checksum(ctx, (ulong)res->value);\n"
    "}\n";

typedef struct pipe_state {
    pipe_params params;
    pipe_result_sum expected;
    perma_proc procs[3];
    pipe_producer *seeds;
    uint64_t consumed, checksum; /* the reductions of the last run */
} pipe_state;

static perma_status pipe_prepare(void *state, perma_runtime *rt)
{
    pipe_state *s = state;
    return perma_seed(rt, s->procs[0], s->seeds, s->params.producers);
}

static int pipe_verify(void *state, perma_runtime *rt, bench_row *row)
{
    pipe_state *s = state;
    uint64_t consumed = s->consumed, checksum = s->checksum;
    perma_stats st;
    row->count = consumed;
    row->expected = s->expected.consumed;
    return consumed == s->expected.consumed && checksum == s->expected.checksum &&
           perma_get_stats(rt, &st) == PERMA_OK && st.items == s->expected.items;
}

static void run_perma(const bench_options *o, const bench_variant *v, pipe_state *s, int upstream_first,
                      unsigned group_size, const char *title, bench_report *report)
{
    bench_row row;
    bench_row_init(&row, title, v->name, "items");
    row.group_size = group_size;
    row.work_groups = o->groups;
    row.units = (double)s->expected.items;
    perma_runtime *rt = bench_perma_create(o, v, group_size, o->groups, &row);
    if (rt) {
        /* Upstream first: explicit priorities producer > transform > consumer;
         * 0 everywhere keeps the runtime's default (deepest first). */
        perma_procedure procs[3] = {
            { .name = "producer", .item_type = "struct pipe_producer", .item_size = sizeof(pipe_producer),
              .source = producer_source, .source_file = "pipe_producer.cl", .function = "producer",
              .emits = { { "transform", 64 } }, .priority = upstream_first ? 3 : 0 },
            { .name = "transform", .item_type = "struct pipe_record", .item_size = sizeof(pipe_record),
              .source = transform_source, .source_file = "pipe_transform.cl", .function = "transform",
              .emits = { { "consumer", 1 } }, .priority = upstream_first ? 2 : 0 },
            { .name = "consumer", .item_type = "struct pipe_result", .item_size = sizeof(pipe_result),
              .source = consumer_source, .source_file = "pipe_consumer.cl", .function = "consumer",
              .priority = upstream_first ? 1 : 0 },
        };
        size_t sizes[3] = { sizeof(pipe_producer), sizeof(pipe_record), sizeof(pipe_result) };
        bench_workload w = { pipe_prepare, pipe_verify, s, 3, s->procs, sizes };
        char defines[160];
        snprintf(defines, sizeof defines, "#define PIPE_ROUNDS %uu\n", s->params.rounds);
        perma_status st = perma_add_source(rt, defines, "pipe_defines.cl");
        if (st == PERMA_OK)
            st = perma_add_source(rt, device_types, "pipe_types.cl");
        for (int i = 0; i < 3 && st == PERMA_OK; ++i)
            st = perma_register(rt, &procs[i], &s->procs[i]);
        if (st == PERMA_OK)
            st = perma_declare_reduction(rt, "consumed", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &s->consumed);
        if (st == PERMA_OK)
            st = perma_declare_reduction(rt, "checksum", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &s->checksum);
        if (st != PERMA_OK)
            snprintf(row.message, sizeof row.message, "setup: %s", perma_errmsg(rt));
        else
            bench_perma_measure(rt, v, o, &w, &row);
        bench_perma_verbose(rt, o);
        perma_destroy(rt);
    }
    bench_report_add(report, &row, 0);
}

/* ---- baselines ---- */

typedef struct baseline_arg {
    const pipe_params *params;
    int downstream_first;
    unsigned threads;
    pipe_result_sum result;
    int failed;
} baseline_arg;

static void sequential_once(void *p)
{
    baseline_arg *a = p;
    if (pipe_run_sequential(a->params, a->downstream_first, &a->result) != 0)
        a->failed = 1;
}

static void openmp_once(void *p)
{
    baseline_arg *a = p;
    pipe_run_openmp(a->params, a->threads, &a->result);
}

static int run_order(const bench_options *o, pipe_state *s, int upstream_first, unsigned group_size,
                     bench_report *report)
{
    char title[128];
    snprintf(title, sizeof title, "%u producers, %s", s->params.producers,
             upstream_first ? "upstream first (priorities 3/2/1)" : "downstream first (default order)");
    bench_report_workload(report, title);

    baseline_arg seq = { .params = &s->params, .downstream_first = !upstream_first };
    bench_row row;
    bench_row_init(&row, title, upstream_first ? "sequential C (upstream first)" : "sequential C (downstream first)",
                   "items");
    row.seconds = bench_time_baseline(o, sequential_once, &seq);
    if (seq.failed) {
        fprintf(stderr, "perma-bench pipeline: out of memory in the sequential run\n");
        return 1;
    }
    row.ran = 1;
    row.units = (double)seq.result.items;
    row.count = row.expected = seq.result.consumed;
    row.peak_item_bytes = seq.result.peak_item_bytes;
    snprintf(row.message, sizeof row.message, "%llu items, %llu consumed", (unsigned long long)seq.result.items,
             (unsigned long long)seq.result.consumed);
    bench_report_add(report, &row, 1);
    s->expected = seq.result;

    if (!upstream_first) {
        baseline_arg omp = { .params = &s->params, .threads = bench_threads(o) };
        bench_row_init(&row, title, "openmp tasks", "items");
        row.work_groups = omp.threads;
        row.seconds = bench_time_baseline(o, openmp_once, &omp);
        row.ran = 1;
        row.units = (double)omp.result.items;
        row.count = omp.result.consumed;
        row.expected = seq.result.consumed;
        row.peak_item_bytes = omp.result.peak_item_bytes;
        row.check = omp.result.consumed == seq.result.consumed && omp.result.checksum == seq.result.checksum &&
                            omp.result.items == seq.result.items
                        ? BENCH_CHECK_PASS
                        : BENCH_CHECK_FAIL;
        bench_report_add(report, &row, 0);
    }

    for (unsigned i = 0; i < bench_variant_count(); ++i) {
        bench_variant v;
        if (!bench_variant_select(o, bench_variant_label(i), &v))
            continue;
        for (unsigned d = 0; d < bench_device_passes(o); ++d) {
            bench_variant_use_device(o, d, &v);
            run_perma(o, &v, s, upstream_first, group_size, title, report);
        }
    }
    return 0;
}

int bench_pipeline(bench_options *o, int argc, char **argv)
{
    pipe_params params = { 0, 16 }; /* producers: 0 = 262144, quick 4096 */
    unsigned group_size = 64;
    const perma_cli_option rows[] = {
        { PERMA_CLI_WHOLE("producers", "N", &params.producers, 1, 1u << 24,
                          "seeded producer items (default 262144, quick 4096)") },
        { PERMA_CLI_WHOLE("rounds", "R", &params.rounds, 1, 4096, "hash rounds per transform (default 16)") },
        { PERMA_CLI_WHOLE("group-size", "N", &group_size, 1, 4096, "perma work-items per group (default 64)") },
    };
    perma_cli_status parsed = bench_parse(o, "[options]",
                                          NULL, rows, sizeof rows / sizeof rows[0], argc, argv);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    if (!params.producers)
        params.producers = o->quick ? 4096 : 262144;

    pipe_state *s = calloc(1, sizeof *s);
    if (s)
        s->seeds = malloc(params.producers * sizeof *s->seeds);
    if (!s || !s->seeds) {
        fprintf(stderr, "perma-bench pipeline: out of memory\n");
        free(s);
        return 1;
    }
    s->params = params;
    for (uint i = 0; i < params.producers; ++i)
        s->seeds[i] = (pipe_producer){ i, 0 };

    bench_report *report;
    int failed = bench_report_open(&report, "pipeline", o);
    if (!failed) {
        failed = run_order(o, s, 0, group_size, report);
        if (!failed)
            failed = run_order(o, s, 1, group_size, report);
        unsigned wrong = bench_report_failures(report);
        failed |= bench_report_close(report) | (wrong > 0);
    }
    free(s->seeds);
    free(s);
    return failed ? 1 : 0;
}
