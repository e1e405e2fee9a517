/* `perma-bench plain`: the command, and the rows and perma helpers that
 * every plain workload shares (plain.h). */
#include "plain.h"

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

#define GROUP_SUFFIX " [group lines]"

static void perma_row(const plain_options *o, const bench_variant *v, plain_count count, bench_report *report,
                      const char *title, const char *unit, double units, const plain_perma *w)
{
    bench_row row;
    char name[96];
    snprintf(name, sizeof name, "%s%s", v->name, count == PLAIN_COUNT_GROUP ? GROUP_SUFFIX : "");
    bench_row_init(&row, title, name, unit);
    row.group_size = o->group_size;
    row.work_groups = o->common->groups;
    row.units = units;
    perma_runtime *rt = bench_perma_create(v, o->group_size, o->common->groups, &row);
    if (rt) {
        unsigned groups = 0, group_size = 0;
        perma_status st = perma_get_work_groups(rt, &groups, &group_size);
        if (st == PERMA_OK)
            st = w->setup(w->run.state, rt, groups, count);
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
    for (unsigned i = 0; i < bench_variant_count; ++i) {
        bench_variant v;
        if (!bench_variant_select(o->common, bench_variants[i], &v))
            continue;
        for (unsigned d = 0; d < bench_device_passes(o->common); ++d) {
            bench_variant_use_device(o->common, d, &v);
            for (unsigned count = PLAIN_COUNT_ATOMIC; count <= PLAIN_COUNT_GROUP; count <<= 1)
                if (o->counts & count)
                    perma_row(o, &v, (plain_count)count, report, title, unit, units, w);
        }
    }
}

/* ---- perma helpers ---- */

perma_status plain_add_sources(perma_runtime *rt, plain_count count, const char *defines)
{
    perma_status st = perma_add_source(rt, plain_work_source, "plain_work.h");
    if (st == PERMA_OK && count == PLAIN_COUNT_GROUP)
        st = perma_add_source(rt, "#define PLAIN_COUNT_GROUP 1\n", "plain_count_group.cl");
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

enum { LINE_BYTES = 64 };

perma_status plain_lines_bind(perma_runtime *rt, plain_lines *lines, unsigned groups, const char *name,
                              const char *type)
{
    if (groups > lines->groups) {
        unsigned char *grown = realloc(lines->bytes, (size_t)groups * LINE_BYTES);
        if (!grown)
            return PERMA_ERR_NO_MEMORY;
        lines->bytes = grown;
    }
    lines->groups = groups;
    plain_lines_clear(lines);
    return perma_bind_host(rt, name, type, lines->bytes, (size_t)groups * LINE_BYTES, PERMA_READ_WRITE);
}

void plain_lines_clear(plain_lines *lines)
{
    if (lines->bytes)
        memset(lines->bytes, 0, (size_t)lines->groups * LINE_BYTES);
}

void plain_lines_free(plain_lines *lines)
{
    free(lines->bytes);
    lines->bytes = NULL;
    lines->groups = 0;
}

uint64_t plain_lines_sum_u32(const plain_lines *lines)
{
    uint64_t sum = 0;
    for (unsigned g = 0; g < lines->groups; ++g) {
        uint32_t v;
        memcpy(&v, lines->bytes + (size_t)g * LINE_BYTES, sizeof v);
        sum += v;
    }
    return sum;
}

uint64_t plain_lines_sum_u64(const plain_lines *lines)
{
    uint64_t sum = 0;
    for (unsigned g = 0; g < lines->groups; ++g) {
        uint64_t v;
        memcpy(&v, lines->bytes + (size_t)g * LINE_BYTES, sizeof v);
        sum += v;
    }
    return sum;
}

double plain_lines_sum_double(const plain_lines *lines)
{
    double sum = 0.0;
    for (unsigned g = 0; g < lines->groups; ++g) {
        double v;
        memcpy(&v, lines->bytes + (size_t)g * LINE_BYTES, sizeof v);
        sum += v;
    }
    return sum;
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
};
enum { WORKLOAD_COUNT = sizeof workloads / sizeof workloads[0] };

static void plain_usage(FILE *out)
{
    fprintf(out,
            "usage: perma-bench plain [common options] [--workload LIST] [--count atomic|group|both]\n"
            "                         [--group-size N] [--cutoff D]\n"
            "  --workload LIST  comma-separated: uts-geometric, uts-binomial, simpson, queens,\n"
            "                   sort (default: all)\n"
            "  --count HOW      how the procedures add to their results: atomic (a global atomic\n"
            "                   per result per item, as README.md does; default), group (one\n"
            "                   64-byte line per work-group) or both (a row for each)\n"
            "  --group-size N   perma work-items per group (default 64)\n"
            "  --cutoff D       OpenMP: spawn tasks only above depth D, in every workload\n"
            "                   (default: each workload's own, shown in its row)\n");
}

/* Which workloads LIST names, as bits of `workloads`; 0 on a bad name. */
static unsigned parse_workloads(const char *list)
{
    unsigned selected = 0;
    char copy[128];
    snprintf(copy, sizeof copy, "%s", list);
    for (char *name = strtok(copy, ","); name; name = strtok(NULL, ",")) {
        unsigned i = 0;
        while (i < WORKLOAD_COUNT && strcmp(name, workloads[i].name) != 0)
            ++i;
        if (i == WORKLOAD_COUNT) {
            fprintf(stderr, "perma-bench plain: unknown workload '%s' (uts-geometric, uts-binomial, simpson, queens, sort)\n", name);
            return 0;
        }
        selected |= 1u << i;
    }
    return selected;
}

static int parse_number(const char *option, const char *text, unsigned min, unsigned max, unsigned *out)
{
    char *end;
    unsigned long value = strtoul(text, &end, 10);
    if (!*text || *end || value < min || value > max) {
        fprintf(stderr, "perma-bench plain: %s needs a number in %u..%u, got '%s'\n", option, min, max, text);
        return -1;
    }
    *out = (unsigned)value;
    return 0;
}

int bench_plain(const bench_options *common, int argc, char **argv)
{
    plain_options o = { .common = common, .counts = PLAIN_COUNT_ATOMIC, .group_size = 64 };
    unsigned selected = (1u << WORKLOAD_COUNT) - 1u;
    for (int i = 1; i < argc; ++i) {
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(argv[i], "--help") == 0) {
            plain_usage(stdout);
            return 0;
        }
        if (!next) {
            fprintf(stderr, "perma-bench plain: unknown or incomplete option '%s'\n", argv[i]);
            plain_usage(stderr);
            return 2;
        }
        if (strcmp(argv[i], "--workload") == 0) {
            if (!(selected = parse_workloads(next)))
                return 2;
        } else if (strcmp(argv[i], "--count") == 0) {
            o.counts = strcmp(next, "atomic") == 0 ? PLAIN_COUNT_ATOMIC
                     : strcmp(next, "group") == 0  ? PLAIN_COUNT_GROUP
                     : strcmp(next, "both") == 0   ? PLAIN_COUNT_ATOMIC | PLAIN_COUNT_GROUP
                                                   : 0;
            if (!o.counts) {
                fprintf(stderr, "perma-bench plain: --count must be atomic, group or both, got '%s'\n", next);
                return 2;
            }
        } else if (strcmp(argv[i], "--group-size") == 0) {
            if (parse_number(argv[i], next, 1, 4096, &o.group_size))
                return 2;
        } else if (strcmp(argv[i], "--cutoff") == 0) {
            if (parse_number(argv[i], next, 1, 4096, &o.cutoff))
                return 2;
        } else {
            fprintf(stderr, "perma-bench plain: unknown option '%s'\n", argv[i]);
            plain_usage(stderr);
            return 2;
        }
        ++i;
    }

    bench_report *report;
    if (bench_report_open(&report, "plain", common))
        return 1;
    bench_report_show_cpu(report);
    if (o.counts & PLAIN_COUNT_GROUP)
        bench_report_widen(report, (int)strlen(GROUP_SUFFIX));
    int failed = 0;
    for (unsigned i = 0; i < WORKLOAD_COUNT && !failed; ++i)
        if (selected & (1u << i))
            failed = workloads[i].run(&o, report);
    unsigned wrong = bench_report_failures(report);
    failed |= bench_report_close(report);
    return failed || wrong ? 1 : 0;
}
