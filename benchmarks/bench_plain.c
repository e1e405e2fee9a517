/* `perma-bench plain`: the command, and the rows and perma helpers that
 * every plain workload shares (plain.h). */
#include "plain.h"
#include "plain_work.h"

#include <stdlib.h>
#include <string.h>

/* ---- rows ---- */

void plain_sequential_row(bench_report *report, const char *title, const char *unit, double units,
                          bench_timing time, const char *note)
{
    bench_row row;
    bench_row_init(&row, title, "sequential C", unit);
    row.seconds = time.seconds;
    row.cpu_seconds = time.cpu_seconds;
    row.ran = 1;
    row.units = units;
    snprintf(row.message, sizeof row.message, "%s", note);
    bench_report_add(report, &row, 1);
}

void plain_openmp_row(bench_report *report, const plain_options *o, const char *title, const char *label,
                      const char *unit, double units, bench_timing time, int ok)
{
    bench_row row;
    char variant[64];
    snprintf(variant, sizeof variant, "openmp tasks %s", label);
    bench_row_init(&row, title, variant, unit);
    row.work_groups = bench_threads(o->common);
    row.seconds = time.seconds;
    row.cpu_seconds = time.cpu_seconds;
    row.ran = 1;
    row.units = units;
    row.check = ok ? BENCH_CHECK_PASS : BENCH_CHECK_FAIL;
    bench_report_add(report, &row, 0);
}

unsigned plain_cutoff(const plain_options *o, unsigned workload_default)
{
    return o->cutoff ? o->cutoff : workload_default;
}

#define ATOMIC_SUFFIX " [atomics]"

static void perma_row(const plain_options *o, const bench_variant *v, plain_count count, bench_report *report,
                      const char *title, const char *unit, double units, const plain_perma *w)
{
    bench_row row;
    char name[96];
    snprintf(name, sizeof name, "%s%s", v->name, count == PLAIN_COUNT_ATOMIC ? ATOMIC_SUFFIX : "");
    bench_row_init(&row, title, name, unit);
    row.group_size = o->group_size;
    row.work_groups = o->common->groups;
    row.units = units;
    perma_runtime *rt = bench_perma_create(o->common, v, o->group_size, o->common->groups, &row);
    if (rt) {
        perma_status st = w->setup(w->run.state, rt, count);
        if (st != PERMA_OK)
            snprintf(row.message, sizeof row.message, "setup: %s", perma_errmsg(rt));
        else
            bench_perma_measure(rt, v, o->common, &w->run, &row);
        bench_perma_verbose(rt, o->common);
        perma_destroy(rt);
    }
    bench_report_add(report, &row, 0);
}

void plain_perma_rows(const plain_options *o, bench_report *report, const char *title, const char *unit,
                      double units, const plain_perma *w)
{
    for (unsigned i = 0; i < bench_variant_count(); ++i) {
        bench_variant v;
        if (!bench_variant_select(o->common, bench_variant_label(i), &v))
            continue;
        for (unsigned d = 0; d < bench_device_passes(o->common); ++d) {
            bench_variant_use_device(o->common, d, &v);
            for (unsigned count = PLAIN_COUNT_REDUCE; count <= PLAIN_COUNT_ATOMIC; count <<= 1)
                if (w->counts_nothing ? count == PLAIN_COUNT_REDUCE : (o->counts & count) != 0)
                    perma_row(o, &v, (plain_count)count, report, title, unit, units, w);
        }
    }
}

/* ---- perma helpers ---- */

perma_status plain_add_sources(perma_runtime *rt, plain_count count, const char *defines)
{
    perma_status st = perma_add_source(rt, plain_work_source, "plain_work.h");
    if (st == PERMA_OK && count == PLAIN_COUNT_ATOMIC)
        st = perma_add_source(rt, "#define PLAIN_COUNT_ATOMIC 1\n", "plain_count_atomic.cl");
    if (st == PERMA_OK)
        st = perma_add_source(rt, defines, "plain_defines.cl");
    return st;
}

perma_status plain_register(perma_runtime *rt, const char *name, const char *item_type, size_t item_size,
                            const char *source, const char *file, const char *target, unsigned max_emits,
                            perma_proc *out)
{
    perma_procedure p = {
        .name = name, .item_type = item_type, .item_size = item_size, .threads_per_item = 1,
        .source = source, .source_file = file, .function = name,
    };
    if (target) {
        p.emits[0].target = target;
        p.emits[0].max_items = max_emits;
    }
    return perma_register(rt, &p, out);
}

perma_status plain_results_declare(perma_runtime *rt, plain_count count, const plain_result *results, unsigned n)
{
    perma_status st = PERMA_OK;
    for (unsigned i = 0; i < n && st == PERMA_OK; ++i) {
        const plain_result *r = &results[i];
        if (count == PLAIN_COUNT_REDUCE)
            st = perma_declare_reduction(rt, r->name, PERMA_REDUCE_SUM, r->type, r->value);
        else
            st = perma_bind_host(rt, r->name, r->type == PERMA_TYPE_DOUBLE ? "__global double *" : "__global ulong *",
                                 r->value, 8, PERMA_READ_WRITE);
    }
    return st;
}

void plain_results_clear(const plain_result *results, unsigned n)
{
    for (unsigned i = 0; i < n; ++i)
        memset(results[i].value, 0, 8);
}

uint64_t plain_items_run(perma_runtime *rt)
{
    perma_stats st;
    return perma_get_stats(rt, &st) == PERMA_OK ? st.items : UINT64_MAX;
}

/* ---- the command ---- */

static const struct {
    const char *name;
    int (*run)(const plain_options *o, bench_report *report);
} workloads[] = {
    { "uts-geometric", plain_uts_geometric },
    { "uts-binomial", plain_uts_binomial },
    { "simpson", plain_simpson },
    { "queens", plain_queens },
    { "sort", plain_sort },
    { "subset", plain_subset },
};
enum { WORKLOAD_COUNT = sizeof workloads / sizeof workloads[0] };

/* --workload LIST: bits of `workloads` for comma-separated names. */
static int parse_workloads(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    unsigned selected = 0, found = 1;
    for (const char *at = value; *at && found;) {
        size_t n = strcspn(at, ",");
        found = 0;
        for (unsigned i = 0; i < WORKLOAD_COUNT; ++i)
            if (strlen(workloads[i].name) == n && strncmp(workloads[i].name, at, n) == 0)
                found = 1u << i;
        selected |= found;
        at += n + (at[n] == ',');
    }
    if (!found || !selected) {
        snprintf(complaint, size, "expected a comma-separated list of uts-geometric, uts-binomial, simpson, "
                                  "queens, sort or subset");
        return 1;
    }
    *(unsigned *)option->target = selected;
    return 0;
}

int bench_plain(bench_options *common, int argc, char **argv)
{
    static const char *const count_names[] = { "reduce", "atomic", "both", NULL };
    static const unsigned count_bits[] = { PLAIN_COUNT_REDUCE, PLAIN_COUNT_ATOMIC,
                                           PLAIN_COUNT_REDUCE | PLAIN_COUNT_ATOMIC };
    plain_options o = { .common = common, .group_size = 64 };
    unsigned selected = (1u << WORKLOAD_COUNT) - 1u, count = 0;
    const perma_cli_option rows[] = {
        { PERMA_CLI_CUSTOM("workload", "LIST", parse_workloads, &selected,
                           "comma-separated: uts-geometric, uts-binomial, simpson, queens, sort, subset (default: "
                           "all)") },
        { PERMA_CLI_CHOICE("count", "HOW", &count, count_names,
                           "how the procedures add to their results: reduce (reduce_NAME, the runtime's "
                           "reductions; default), atomic (a global atomic per result per item, all groups on one "
                           "word; rows marked [atomics]) or both (a row for each)") },
        { PERMA_CLI_WHOLE("group-size", "N", &o.group_size, 1, 4096, "perma work-items per group (default 64)") },
        { PERMA_CLI_WHOLE("weights", "N", &o.weights, 1, SUBSET_MAX_WEIGHTS,
                          "subset: N weights (default 30, 16 with --quick; 34 makes 6.7e9 nodes)") },
        { PERMA_CLI_WHOLE("cutoff", "D", &o.cutoff, 1, 4096,
                          "OpenMP: spawn tasks only above depth D, in every workload (default: each workload's "
                          "own, shown in its row)") },
    };
    perma_cli_status parsed = bench_parse(common, "[options]", NULL, rows, sizeof rows / sizeof rows[0], argc, argv);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    o.counts = count_bits[count];

    bench_report *report;
    if (bench_report_open(&report, "plain", common))
        return 1;
    bench_report_show_cpu(report);
    if (o.counts & PLAIN_COUNT_ATOMIC)
        bench_report_widen(report, (int)strlen(ATOMIC_SUFFIX));
    int failed = 0;
    for (unsigned i = 0; i < WORKLOAD_COUNT && !failed; ++i)
        if (selected & (1u << i))
            failed = workloads[i].run(&o, report);
    unsigned wrong = bench_report_failures(report);
    failed |= bench_report_close(report);
    return failed || wrong ? 1 : 0;
}
