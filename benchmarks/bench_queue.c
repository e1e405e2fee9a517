/* `perma-bench queue`: throughput of empty tasks.
 *
 * G generator items each emit K empty items into a procedure that does
 * nothing, so the time is the scheduler's own cost per task: taking a
 * batch, dispatching, reserving and publishing emits.  With --emits
 * random:A..B generator g emits A + hash(g) % (B - A + 1) items instead,
 * declaring B as its maximum: what variable fan-out costs (an item that
 * declares up to B emits and makes fewer).  With --count MODE the empty
 * procedure counts itself: `atomic` one global atomic_inc on one counter
 * (what contention costs), `group` an atomic_inc on a 64-byte line per
 * work-group, `reduce` a reduction (perma_declare_reduction).  Measured for every
 * perma variant, group size (= batch size of the empty procedure) and
 * work-group count, against a sequential FIFO loop and OpenMP tasks.
 * Rate = (G + G*K) executed items per second.  Each row's note gives the
 * cost of an item to one work-group (or thread): seconds * groups / items,
 * for the empty procedure the runtime's own overhead per item (claim,
 * read, dispatch, emit, publish); a summary compares the fastest perma row
 * with OpenMP's generator tasks. */
#include "bench.h"

#include <stdlib.h>
#include <string.h>

/* The emit count of generator g: a 32-bit integer hash (lowbias32), the
 * same text in C and OpenCL C. */
#define QUEUE_HASH_CODE                                   \
    "uint queue_hash(uint x)\n"                           \
    "{\n"                                                 \
    "    x ^= x >> 16; x *= 0x7feb352dU;\n"               \
    "    x ^= x >> 15; x *= 0x846ca68bU;\n"               \
    "    return x ^ (x >> 16);\n"                         \
    "}\n"

static const char *device_types =
    "struct generator_item { uint index; };\n"
    "struct empty_item { uint value; };\n" QUEUE_HASH_CODE;

/* EMITS_MIN and EMITS_SPAN (0: always EMITS_MIN) are defined in front of
 * the shared source. */
static const char *generate_source =
    "void generate(perma_ctx *ctx, __local const struct generator_item *g)\n"
    "{\n"
    "    uint k = EMITS_SPAN ? EMITS_MIN + queue_hash(g->index) % EMITS_SPAN : EMITS_MIN;\n"
    "    struct empty_item e;\n"
    "    for (uint i = 0; i < k; ++i) {\n"
    "        e.value = g->index + i;\n"
    "        emit_empty(ctx, &e);\n"
    "    }\n"
    "}\n";

/* QUEUE_COUNT (0 none, 1 atomic, 2 group, 3 reduce) is defined in the
 * shared source. */
static const char *empty_source =
    "void empty(perma_ctx *ctx, __local const struct empty_item *e)\n"
    "{\n"
    "    (void)e;\n"
    "#if QUEUE_COUNT == 1\n"
    "    atomic_inc(&ctx->buf.queue_count[0]);\n"
    "#elif QUEUE_COUNT == 2\n"
    "    atomic_inc(&ctx->buf.queue_count[16u * ctx->group]);\n"
    "#elif QUEUE_COUNT == 3\n"
    "    reduce_count(ctx, 1u);\n"
    "#else\n"
    "    (void)ctx;\n"
    "#endif\n"
    "}\n";

/* How the empty procedure counts itself (--count). */
typedef enum queue_count { COUNT_NONE = 0, COUNT_ATOMIC, COUNT_GROUP, COUNT_REDUCE } queue_count;
static const char *const count_names[] = { "none", "atomic", "group", "reduce", NULL };
enum { COUNT_LINES = 1024 }; /* 64-byte lines: one per work-group (--groups is at most 1024) */

typedef struct queue_params {
    unsigned generators, per_generator; /* G, and K: the most one generator emits (declared) */
    unsigned min_emits;                 /* random: the fewest one emits; else K */
    int random;                         /* each emits min_emits + hash(g) % (K - min_emits + 1) */
    queue_count count;                  /* how the empty procedure counts itself */
} queue_params;

static uint32_t queue_hash(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    return x ^ (x >> 16);
}

/* Items generator g emits. */
static uint32_t emits_of(const queue_params *p, uint32_t g)
{
    if (!p->random)
        return p->per_generator;
    return p->min_emits + queue_hash(g) % (p->per_generator - p->min_emits + 1u);
}

/* Empty items all generators emit together. */
static uint64_t total_emits(const queue_params *p)
{
    uint64_t total = 0;
    for (uint32_t g = 0; g < p->generators; ++g)
        total += emits_of(p, g);
    return total;
}

static double total_items(const queue_params *p)
{
    return (double)p->generators + (double)total_emits(p);
}

/* ---- perma ---- */

typedef struct queue_state {
    queue_params params;
    perma_proc procs[2]; /* generate, empty */
    uint32_t *seeds;
    uint32_t counters[16 * COUNT_LINES]; /* --count atomic, group */
    uint32_t counted;                    /* --count reduce */
} queue_state;

static perma_status queue_prepare(void *state, perma_runtime *rt)
{
    queue_state *s = state;
    memset(s->counters, 0, sizeof s->counters);
    return perma_seed(rt, s->procs[0], s->seeds, s->params.generators);
}

/* The runtime's per-procedure item counts, and what the empty procedure
 * counted if it counts. */
static int queue_verify(void *state, perma_runtime *rt, bench_row *row)
{
    queue_state *s = state;
    perma_procedure_stats gen, empty;
    if (perma_get_procedure_stats(rt, s->procs[0], &gen) != PERMA_OK ||
        perma_get_procedure_stats(rt, s->procs[1], &empty) != PERMA_OK)
        return 0;
    uint64_t expected = total_emits(&s->params), counted = expected;
    if (s->params.count == COUNT_REDUCE)
        counted = s->counted;
    else if (s->params.count != COUNT_NONE)
        for (unsigned l = counted = 0; l < COUNT_LINES; ++l)
            counted += s->counters[16 * l];
    row->count = gen.items + empty.items;
    row->expected = s->params.generators + expected;
    return gen.items == s->params.generators && empty.items == expected && counted == (uint32_t)expected;
}

/* What an item costs one work-group (thread) in nanoseconds: seconds *
 * groups / items; 0 for a row without a time. */
static double ns_per_item_per_group(const bench_row *row)
{
    if (!row->ran || row->seconds <= 0 || row->units <= 0)
        return 0.0;
    return row->seconds * 1e9 * (row->work_groups ? row->work_groups : 1) / row->units;
}

/* The note of a row that ran: its ns_per_item_per_group. */
static void note_overhead(bench_row *row, double ns)
{
    if (ns > 0 && !row->message[0])
        snprintf(row->message, sizeof row->message, "%.1f ns/item/group", ns);
}

/* Fastest rows so far, for the summary. */
typedef struct queue_best {
    double perma_rate, openmp_rate;
    char perma_variant[64], cheapest_variant[64];
    unsigned perma_gs, perma_wg, cheapest_gs, cheapest_wg;
    double perma_ns, cheapest_ns;
} queue_best;

static void run_perma(const bench_options *o, const bench_variant *v, queue_state *s, unsigned group_size,
                      unsigned groups, const char *title, bench_report *report, queue_best *best)
{
    bench_row row;
    bench_row_init(&row, title, v->name, "items");
    row.group_size = group_size;
    row.work_groups = groups;
    row.units = total_items(&s->params);
    perma_runtime *rt = bench_perma_create(o, v, group_size, groups, &row);
    if (rt) {
        perma_procedure generate = {
            .name = "generate", .item_type = "struct generator_item", .item_size = 4,
            .source = generate_source, .source_file = "queue_generate.cl", .function = "generate",
            .emits = { { "empty", s->params.per_generator } },
        };
        perma_procedure empty = {
            .name = "empty", .item_type = "struct empty_item", .item_size = 4,
            .source = empty_source, .source_file = "queue_empty.cl", .function = "empty",
        };
        /* EMITS_MIN, EMITS_SPAN and QUEUE_COUNT are defined in the shared source. */
        char *types = malloc(strlen(device_types) + 128);
        size_t sizes[2] = { 4, 4 };
        bench_workload w = { queue_prepare, queue_verify, s, 2, s->procs, sizes };
        if (!types) {
            snprintf(row.message, sizeof row.message, "out of memory");
        } else {
            const queue_params *p = &s->params;
            sprintf(types, "#define EMITS_MIN %uu\n#define EMITS_SPAN %uu\n#define QUEUE_COUNT %d\n%s",
                    p->random ? p->min_emits : p->per_generator, p->random ? p->per_generator - p->min_emits + 1u : 0u,
                    (int)p->count, device_types);
            if (perma_add_source(rt, types, "queue_types.cl") != PERMA_OK ||
                perma_register(rt, &generate, &s->procs[0]) != PERMA_OK ||
                perma_register(rt, &empty, &s->procs[1]) != PERMA_OK ||
                (p->count == COUNT_REDUCE &&
                 perma_declare_reduction(rt, "count", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &s->counted) != PERMA_OK) ||
                ((p->count == COUNT_ATOMIC || p->count == COUNT_GROUP) &&
                 perma_bind_host(rt, "queue_count", "__global uint *", s->counters, sizeof s->counters,
                                 PERMA_READ_WRITE) != PERMA_OK))
                snprintf(row.message, sizeof row.message, "setup: %s", perma_errmsg(rt));
            else
                bench_perma_measure(rt, v, o, &w, &row);
        }
        free(types);
        bench_perma_verbose(rt, o);
        perma_destroy(rt);
    }
    double ns = ns_per_item_per_group(&row);
    note_overhead(&row, ns);
    bench_report_add(report, &row, 0);
    double rate = row.ran && row.seconds > 0 && row.check != BENCH_CHECK_FAIL ? row.units / row.seconds : 0.0;
    if (rate > best->perma_rate) {
        best->perma_rate = rate;
        snprintf(best->perma_variant, sizeof best->perma_variant, "%s", row.variant);
        best->perma_gs = row.group_size;
        best->perma_wg = row.work_groups;
        best->perma_ns = ns;
    }
    if (rate > 0 && ns > 0 && (best->cheapest_ns == 0 || ns < best->cheapest_ns)) {
        best->cheapest_ns = ns;
        snprintf(best->cheapest_variant, sizeof best->cheapest_variant, "%s", row.variant);
        best->cheapest_gs = row.group_size;
        best->cheapest_wg = row.work_groups;
    }
}

/* ---- baselines ---- */

typedef struct baseline_arg {
    queue_params params;
    unsigned threads;
    uint32_t *ring; /* sequential FIFO storage */
    size_t ring_size;
    uint64_t executed;
} baseline_arg;

/* The task bodies, called through pointers so the loops cannot vanish. */
static void empty_task(uint32_t value)
{
    (void)value;
}
static void (*volatile run_empty)(uint32_t) = empty_task;

/* A plain FIFO of tagged items: the top bit marks a generator. */
static void sequential_once(void *p)
{
    baseline_arg *a = p;
    const uint32_t generator_bit = 0x80000000u;
    size_t mask = a->ring_size - 1, head = 0, tail = 0;
    for (uint32_t g = 0; g < a->params.generators; ++g)
        a->ring[tail++ & mask] = generator_bit | g;
    uint64_t executed = 0;
    while (head != tail) {
        uint32_t item = a->ring[head++ & mask];
        ++executed;
        if (item & generator_bit) {
            uint32_t base = item & ~generator_bit;
            for (uint32_t i = 0, k = emits_of(&a->params, base); i < k; ++i)
                a->ring[tail++ & mask] = base + i;
        } else {
            run_empty(item);
        }
    }
    a->executed = executed;
}

/* OpenMP, the common pattern: one thread creates every empty task. */
static void openmp_single_producer_once(void *p)
{
    baseline_arg *a = p;
#pragma omp parallel num_threads(a->threads)
#pragma omp single
    for (uint32_t g = 0; g < a->params.generators; ++g)
        for (uint32_t i = 0, k = emits_of(&a->params, g); i < k; ++i) {
#pragma omp task firstprivate(g, i)
            run_empty(g + i);
        }
    /* Every created task runs before the parallel region's barrier. */
    a->executed = total_emits(&a->params);
}

/* OpenMP with the same shape as the perma workload: generator tasks that
 * each create K empty tasks. */
static void openmp_generators_once(void *p)
{
    baseline_arg *a = p;
#pragma omp parallel num_threads(a->threads)
#pragma omp single
    for (uint32_t g = 0; g < a->params.generators; ++g) {
#pragma omp task firstprivate(g)
        for (uint32_t i = 0, k = emits_of(&a->params, g); i < k; ++i) {
#pragma omp task firstprivate(i)
            run_empty(g + i);
        }
    }
    a->executed = a->params.generators + total_emits(&a->params);
}

static double add_baseline(const bench_options *o, baseline_arg *a, const char *variant, void (*fn)(void *),
                         unsigned threads, int is_baseline, const char *title, bench_report *report)
{
    bench_row row;
    bench_row_init(&row, title, variant, "items");
    row.work_groups = threads;
    row.seconds = bench_time_baseline(o, fn, a);
    row.ran = 1;
    /* Rate counts the tasks each implementation executed. */
    row.units = (double)a->executed;
    note_overhead(&row, ns_per_item_per_group(&row));
    bench_report_add(report, &row, is_baseline);
    return row.seconds > 0 ? row.units / row.seconds : 0.0;
}

/* --emits K or --emits random:A..B into the queue_params. */
static int parse_emits(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    queue_params *p = option->target;
    unsigned a, b;
    int used = 0;
    if (strncmp(value, "random:", 7) == 0) {
        if (sscanf(value + 7, "%u..%u%n", &a, &b, &used) != 2 || value[7 + used] || a > b || b < 1 ||
            b > PERMA_MAX_EMIT_ITEMS) {
            snprintf(complaint, size, "expected random:A..B with 0 <= A <= B, 1 <= B <= %d", PERMA_MAX_EMIT_ITEMS);
            return 1;
        }
        p->random = 1;
        p->min_emits = a;
        p->per_generator = b;
        return 0;
    }
    if (sscanf(value, "%u%n", &b, &used) != 1 || value[used] || b < 1 || b > PERMA_MAX_EMIT_ITEMS) {
        snprintf(complaint, size, "expected a number in 1..%d or random:A..B", PERMA_MAX_EMIT_ITEMS);
        return 1;
    }
    p->random = 0;
    p->per_generator = b;
    return 0;
}

int bench_queue(bench_options *o, int argc, char **argv)
{
    queue_params params = { 0, 256, 0, 0, COUNT_NONE }; /* generators: 0 = the default */
    const perma_cli_option rows[] = {
        { PERMA_CLI_WHOLE("generators", "G", &params.generators, 1, 1u << 20,
                          "generator items (default 8192, quick 256; with random emits 131072, quick 4096)") },
        { PERMA_CLI_CUSTOM("emits", "K|random:A..B", parse_emits, &params,
                           "what each generator emits: K empty items (default 256), or A + hash(g) % (B-A+1) "
                           "declaring B as its maximum") },
        { PERMA_CLI_WHOLE("per-generator", "K", &params.per_generator, 1, PERMA_MAX_EMIT_ITEMS,
                          "the same as --emits K") },
        { PERMA_CLI_CHOICE("count", "MODE", &params.count, count_names,
                           "how the empty procedure counts itself: not at all, one global atomic, an atomic on a "
                           "64-byte line per work-group, or a reduction (default none)") },
    };
    perma_cli_status parsed = bench_parse(o, "[options]",
                                          "Group sizes 32, 64, 128 and work-groups 1, 2 (--groups N: only N; "
                                          "quick: 64 and 2).",
                                          rows, sizeof rows / sizeof rows[0], argc, argv);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    if (!params.random)
        params.min_emits = params.per_generator;
    if (!params.generators)
        params.generators = params.random ? (o->quick ? 4096 : 131072) : (o->quick ? 256 : 8192);

    static const unsigned all_sizes[] = { 32, 64, 128 }, quick_sizes[] = { 64 };
    static const unsigned all_groups[] = { 1, 2 }, quick_groups[] = { 2 };
    const unsigned *sizes = o->quick ? quick_sizes : all_sizes;
    unsigned size_count = o->quick ? 1 : 3;
    const unsigned *group_list = o->quick ? quick_groups : all_groups;
    unsigned group_count = o->quick ? 1 : 2;
    if (o->groups) {
        group_list = &o->groups;
        group_count = 1;
    }

    char title[96];
    char counting[32] = "";
    if (params.count != COUNT_NONE)
        snprintf(counting, sizeof counting, ", counted: %s", count_names[params.count]);
    if (params.random)
        snprintf(title, sizeof title, "%u generators x %u..%u empty tasks%s", params.generators, params.min_emits,
                 params.per_generator, counting);
    else
        snprintf(title, sizeof title, "%u generators x %u empty tasks%s", params.generators, params.per_generator,
                 counting);
    bench_report *report;
    if (bench_report_open(&report, "queue", o))
        return 1;
    bench_report_workload(report, title);

    baseline_arg a = { .params = params, .threads = bench_threads(o) };
    /* The FIFO holds at most all items at once. */
    size_t needed = (size_t)params.generators + (size_t)total_emits(&params);
    a.ring_size = 1;
    while (a.ring_size < needed)
        a.ring_size *= 2;
    a.ring = malloc(a.ring_size * sizeof *a.ring);
    queue_state *s = calloc(1, sizeof *s);
    if (s)
        s->seeds = malloc(params.generators * sizeof *s->seeds);
    if (!a.ring || !s || !s->seeds) {
        fprintf(stderr, "perma-bench queue: out of memory\n");
        free(a.ring);
        if (s)
            free(s->seeds);
        free(s);
        bench_report_close(report);
        return 1;
    }
    add_baseline(o, &a, "sequential C (FIFO loop)", sequential_once, 1, 1, title, report);
    free(a.ring);
    a.ring = NULL;
    add_baseline(o, &a, "openmp tasks (one producer)", openmp_single_producer_once, a.threads, 0, title, report);
    queue_best best = { 0 };
    best.openmp_rate =
        add_baseline(o, &a, "openmp tasks (generator tasks)", openmp_generators_once, a.threads, 0, title, report);

    s->params = params;
    for (uint32_t g = 0; g < params.generators; ++g)
        s->seeds[g] = g;
    for (unsigned gi = 0; gi < group_count; ++gi)
        for (unsigned si = 0; si < size_count; ++si)
            for (unsigned i = 0; i < bench_variant_count(); ++i) {
                bench_variant v;
                if (!bench_variant_select(o, bench_variant_label(i), &v))
                    continue;
                for (unsigned d = 0; d < bench_device_passes(o); ++d) {
                    bench_variant_use_device(o, d, &v);
                    run_perma(o, &v, s, sizes[si], group_list[gi], title, report, &best);
                }
            }
    if (best.perma_rate > 0 && best.openmp_rate > 0)
        printf("\nlowest runtime overhead: %s, %u work-items x %u group(s): %.1f ns per item per group\n"
               "fastest perma row: %s, %u work-items x %u group(s): %.1f ns per item per group; "
               "empty-task throughput %.2fx OpenMP generator tasks\n",
               best.cheapest_variant, best.cheapest_gs, best.cheapest_wg, best.cheapest_ns, best.perma_variant,
               best.perma_gs, best.perma_wg, best.perma_ns, best.perma_rate / best.openmp_rate);
    free(s->seeds);
    free(s);

    unsigned wrong = bench_report_failures(report);
    int failed = bench_report_close(report);
    return failed || wrong ? 1 : 0;
}
