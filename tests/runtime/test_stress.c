/*
 * Randomized stress: 200 procedure graphs, each run under every technique
 * and strategy and compared with a sequential host simulation of the same
 * graph.  A graph is a *shape* (procedures with their item sizes, threads
 * per item and emit edges; compiled once per variant) plus *data* (depth
 * limit, fan-out per edge, roots) drawn from a fixed seed, so a failure
 * names the graph and reproduces.  Every item carries a payload derived
 * from its id that its consumer verifies, so a torn or mixed-up item is
 * caught, not only a lost one.
 */
#include "perma_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { GRAPHS = 200, MAX_PROCS = 4, MAX_EDGES = 6, MAX_ROOTS = 8, ITEM_BUDGET = 6000 };

typedef struct shape {
    unsigned procs;
    unsigned words[MAX_PROCS];  /* item size in words (>= 2: id, depth, payload) */
    unsigned tpi[MAX_PROCS];
    unsigned edges;
    unsigned from[MAX_EDGES], to[MAX_EDGES], max[MAX_EDGES];
    size_t capacity;            /* initial queue capacity */
} shape;

static const shape shapes[] = {
    { 2, { 2, 4 }, { 1, 2 }, 3, { 0, 0, 1 }, { 0, 1, 0 }, { 2, 3, 1 }, 2 },
    { 3, { 4, 8, 3 }, { 1, 4, 1 }, 4, { 0, 1, 1, 2 }, { 1, 2, 0, 2 }, { 3, 2, 1, 2 }, 16 },
    { 4, { 16, 2, 6, 5 }, { 8, 1, 2, 1 }, 5, { 0, 1, 2, 3, 3 }, { 1, 2, 3, 0, 3 }, { 2, 3, 2, 1, 2 }, 256 },
    { 1, { 7 }, { 3 }, 1, { 0 }, { 0 }, { 3 }, 4096 },
};
enum { SHAPES = sizeof shapes / sizeof shapes[0] };

/* The schedules: every one (perma_schedule_all, the victims under one
 * stealing strategy), then every megakernel one of those with a local
 * front queue of 32 items, then with work-first stacks of 6 items.  Failure messages name them by label and
 * PERMA_STRESS_VARIANT=N indexes this list. */
#define MAX_VARIANTS 32
static perma_schedule variants[MAX_VARIANTS];
static char variant_labels[MAX_VARIANTS][64];
static unsigned variant_count;

static void list_variants(void)
{
    perma_schedule s;
    while (variant_count < MAX_VARIANTS &&
           perma_schedule_all(PERMA_SCHEDULES_VICTIMS_ONCE, variant_count, &s) == PERMA_OK)
        variants[variant_count++] = s;
    for (unsigned i = 0, plain = variant_count; i < plain && variant_count < MAX_VARIANTS; ++i) {
        if (variants[i].technique != PERMA_TECHNIQUE_MEGAKERNEL)
            continue;
        variants[variant_count] = variants[i];
        variants[variant_count++].local_queue_items = 32;
    }
    /* Work-first with stacks of 6 items: full stacks spill, and stacks are
     * flushed at every stall of the tiny queues. */
    for (unsigned i = 0, plain = variant_count; i < plain && variant_count < MAX_VARIANTS; ++i) {
        if (variants[i].technique != PERMA_TECHNIQUE_MEGAKERNEL || variants[i].local_queue_items)
            continue;
        variants[variant_count] = variants[i];
        variants[variant_count++].work_first_items = 6;
    }
    for (unsigned i = 0; i < variant_count; ++i)
        perma_schedule_format(&variants[i], variant_labels[i], sizeof variant_labels[i]);
}

static perma_schedule variant_schedule(unsigned variant)
{
    ck_assert_uint_lt(variant, variant_count);
    return variants[variant];
}

/* The variant of a label; fails the test if there is none. */
static unsigned variant_of(const char *label)
{
    for (unsigned i = 0; i < variant_count; ++i)
        if (strcmp(variant_labels[i], label) == 0)
            return i;
    ck_abort_msg("no stress variant %s", label);
    return 0;
}

/* The hash both sides use; kept in sync with MIX_SOURCE. */
static uint32_t mix(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

#define MIX_SOURCE                                                                          \
    "uint stress_mix(uint x)\n{\n    x ^= x >> 16;\n    x *= 0x7feb352du;\n    x ^= x >> 15;\n" \
    "    x *= 0x846ca68bu;\n    x ^= x >> 16;\n    return x;\n}\n"

/* Graph data: params[0] depth limit, params[1 + e] fan-out of edge e. */
typedef struct graph {
    unsigned shape;
    uint32_t params[1 + MAX_EDGES];
    unsigned roots;
    unsigned root_proc[MAX_ROOTS];
    uint32_t root_id[MAX_ROOTS];
} graph;

typedef struct totals {
    uint32_t counts[MAX_PROCS];
    uint64_t sums[MAX_PROCS];
    uint64_t items;
} totals;

static uint32_t child_count(const shape *sh, const uint32_t *params, unsigned e, uint32_t id)
{
    (void)sh;
    return mix(id ^ (e * 0x9e37u)) % (params[1 + e] + 1);
}

static uint32_t child_id(uint32_t id, unsigned e, uint32_t j)
{
    return mix(id * 31u + e * 7u + j);
}

/* The sequential host simulation (depth-first recursion). */
static void simulate(const shape *sh, const uint32_t *params, unsigned p, uint32_t id, uint32_t depth, totals *t)
{
    t->counts[p]++;
    t->sums[p] += id;
    t->items++;
    if (depth >= params[0] || t->items > 10 * ITEM_BUDGET)
        return;
    for (unsigned e = 0; e < sh->edges; ++e) {
        if (sh->from[e] != p)
            continue;
        uint32_t n = child_count(sh, params, e, id);
        for (uint32_t j = 0; j < n; ++j)
            simulate(sh, params, sh->to[e], child_id(id, e, j), depth + 1, t);
    }
}

static void simulate_graph(const graph *g, totals *t)
{
    memset(t, 0, sizeof *t);
    for (unsigned r = 0; r < g->roots; ++r)
        simulate(&shapes[g->shape], g->params, g->root_proc[r], g->root_id[r], 0, t);
}

/* Graph number `index` from a fixed seed; its depth is lowered until the
 * simulation stays within the item budget. */
static void make_graph(unsigned index, graph *g)
{
    uint32_t state = mix(0x5eed0000u + index);
#define NEXT(n) ((state = mix(state + 0x9e3779b9u)) % (n))
    memset(g, 0, sizeof *g);
    g->shape = index % SHAPES;
    const shape *sh = &shapes[g->shape];
    g->params[0] = 2 + NEXT(6);
    for (unsigned e = 0; e < sh->edges; ++e)
        g->params[1 + e] = NEXT(sh->max[e] + 1);
    g->roots = 1 + NEXT(MAX_ROOTS);
    for (unsigned r = 0; r < g->roots; ++r) {
        g->root_proc[r] = NEXT(sh->procs);
        g->root_id[r] = mix(index * 1000u + r);
    }
#undef NEXT
    totals t;
    for (simulate_graph(g, &t); t.items > ITEM_BUDGET && g->params[0] > 0; simulate_graph(g, &t))
        g->params[0]--;
}

/* OpenCL C for a shape: item types, then one procedure per shape procedure. */
static void shape_sources(const shape *sh, char *types, size_t types_size, char *procs, size_t procs_size)
{
    size_t n = (size_t)snprintf(types, types_size, MIX_SOURCE);
    for (unsigned p = 0; p < sh->procs; ++p) {
        if (sh->words[p] > 2)
            n += (size_t)snprintf(types + n, types_size - n,
                                  "struct item%u { uint id; uint depth; uint payload[%u]; };\n", p, sh->words[p] - 2);
        else
            n += (size_t)snprintf(types + n, types_size - n, "struct item%u { uint id; uint depth; };\n", p);
    }
    n = 0;
    for (unsigned p = 0; p < sh->procs; ++p) {
        n += (size_t)snprintf(procs + n, procs_size - n,
                              "void stress%u(perma_ctx *ctx, __local const struct item%u *it)\n{\n"
                              "    uint t = ctx->thread;\n"
                              "    if (t == 0) {\n"
                              "        atomic_inc(&ctx->buf.counts[%u]);\n"
                              "        atom_add(&ctx->buf.sums[%u], (ulong)it->id);\n",
                              p, p, p, p);
        for (unsigned k = 0; k + 2 < sh->words[p]; ++k)
            n += (size_t)snprintf(procs + n, procs_size - n,
                                  "        if (it->payload[%u] != stress_mix(it->id + %uu)) atomic_inc(&ctx->buf.errors[0]);\n",
                                  k, k);
        n += (size_t)snprintf(procs + n, procs_size - n,
                              "    }\n    if (it->depth >= ctx->buf.params[0])\n        return;\n");
        for (unsigned e = 0; e < sh->edges; ++e) {
            if (sh->from[e] != p)
                continue;
            unsigned q = sh->to[e];
            n += (size_t)snprintf(procs + n, procs_size - n,
                                  "    {\n        uint n = stress_mix(it->id ^ (%uu * 0x9e37u)) %% (ctx->buf.params[%u] + 1u);\n"
                                  "        for (uint j = t; j < n; j += ctx->threads) {\n"
                                  "            struct item%u c;\n"
                                  "            c.id = stress_mix(it->id * 31u + %uu * 7u + j);\n"
                                  "            c.depth = it->depth + 1u;\n",
                                  e, 1 + e, q, e);
            for (unsigned k = 0; k + 2 < sh->words[q]; ++k)
                n += (size_t)snprintf(procs + n, procs_size - n, "            c.payload[%u] = stress_mix(c.id + %uu);\n",
                                      k, k);
            n += (size_t)snprintf(procs + n, procs_size - n, "            emit_stress%u(ctx, &c);\n        }\n    }\n", q);
        }
        n += (size_t)snprintf(procs + n, procs_size - n, "}\n");
    }
}

typedef struct stress_runtime {
    perma_runtime *rt;
    perma_proc ids[MAX_PROCS];
    uint32_t params[1 + MAX_EDGES];
    uint32_t counts[MAX_PROCS];
    uint64_t sums[MAX_PROCS];
    uint32_t errors[1];
} stress_runtime;

static void open_shape(stress_runtime *s, unsigned shape_index, unsigned variant)
{
    const shape *sh = &shapes[shape_index];
    perma_config config;
    perma_config_init(&config);
    perma_schedule schedule = variant_schedule(variant);
    config.schedule = schedule;
    config.queue_capacity = sh->capacity;
    config.schedule.batch_limit = 50;
    config.time_limit = 60;
    s->rt = test_runtime_config(&config);
    static char types[4096], procs[16384];
    shape_sources(sh, types, sizeof types, procs, sizeof procs);
    ck_assert_perma_ok(s->rt, perma_add_source(s->rt, types, "stress_types.cl"));
    for (unsigned p = 0; p < sh->procs; ++p) {
        char name[16], type[32];
        snprintf(name, sizeof name, "stress%u", p);
        snprintf(type, sizeof type, "struct item%u", p);
        perma_procedure d = { .name = name, .item_type = type, .item_size = 4 * sh->words[p],
                              .threads_per_item = sh->tpi[p], .source = procs, .source_file = "stress.cl",
                              .function = name, .priority = (int)p /* the shapes have cycles */ };
        unsigned k = 0;
        char targets[MAX_EDGES][16];
        for (unsigned e = 0; e < sh->edges; ++e) {
            if (sh->from[e] != p)
                continue;
            snprintf(targets[k], sizeof targets[k], "stress%u", sh->to[e]);
            d.emits[k] = (perma_emit){ targets[k], sh->max[e] };
            ++k;
        }
        ck_assert_perma_ok(s->rt, perma_register(s->rt, &d, &s->ids[p]));
    }
    ck_assert_perma_ok(s->rt, perma_bind_host(s->rt, "params", "__global const uint *", s->params, sizeof s->params, PERMA_READ));
    ck_assert_perma_ok(s->rt, perma_bind_host(s->rt, "counts", "__global uint *", s->counts, sizeof s->counts, PERMA_READ_WRITE));
    ck_assert_perma_ok(s->rt, perma_bind_host(s->rt, "sums", "__global ulong *", s->sums, sizeof s->sums, PERMA_READ_WRITE));
    ck_assert_perma_ok(s->rt, perma_bind_host(s->rt, "errors", "__global uint *", s->errors, sizeof s->errors, PERMA_READ_WRITE));
}

static void run_graph(stress_runtime *s, unsigned index, const graph *g, unsigned variant)
{
    const shape *sh = &shapes[g->shape];
    memcpy(s->params, g->params, sizeof s->params);
    memset(s->counts, 0, sizeof s->counts);
    memset(s->sums, 0, sizeof s->sums);
    s->errors[0] = 0;
    for (unsigned r = 0; r < g->roots; ++r) {
        uint32_t item[16] = { g->root_id[r], 0 };
        for (unsigned k = 0; k + 2 < sh->words[g->root_proc[r]]; ++k)
            item[2 + k] = mix(g->root_id[r] + k);
        ck_assert_perma_ok(s->rt, perma_seed(s->rt, s->ids[g->root_proc[r]], item, 1));
    }
    /* Every graph grows its queues from the shape's capacity: the stalls
     * are the point. */
    ck_assert_perma_ok(s->rt, perma_forget_capacities(s->rt));
    perma_status st = perma_run(s->rt);
    ck_assert_msg(st == PERMA_OK, "graph %u (shape %u) under %s: %s", index, g->shape, variant_labels[variant],
                  perma_errmsg(s->rt));
    totals expected;
    simulate_graph(g, &expected);
    ck_assert_msg(s->errors[0] == 0, "graph %u under %s: %u items arrived corrupted", index, variant_labels[variant],
                  s->errors[0]);
    for (unsigned p = 0; p < sh->procs; ++p) {
        ck_assert_msg(s->counts[p] == expected.counts[p] && s->sums[p] == expected.sums[p],
                      "graph %u (shape %u) under %s: procedure %u ran %u items (id sum %llu), the simulation %u (%llu)",
                      index, g->shape, variant_labels[variant], p, s->counts[p], (unsigned long long)s->sums[p],
                      expected.counts[p], (unsigned long long)expected.sums[p]);
    }
}

START_TEST(random_graphs_match_the_simulation)
{
    unsigned variant = (unsigned)_i;
    stress_runtime runtimes[SHAPES];
    for (unsigned sh = 0; sh < SHAPES; ++sh)
        open_shape(&runtimes[sh], sh, variant);
    uint64_t items = 0;
    for (unsigned index = 0; index < GRAPHS; ++index) {
        graph g;
        make_graph(index, &g);
        totals t;
        simulate_graph(&g, &t);
        items += t.items;
        run_graph(&runtimes[g.shape], index, &g, variant);
    }
    ck_assert_uint_gt(items, GRAPHS * 10); /* the graphs are not trivial */
    for (unsigned sh = 0; sh < SHAPES; ++sh)
        perma_destroy(runtimes[sh].rt);
}
END_TEST

/* Regression: with a local front queue, a launch stopped for bigger queues
 * while a group held items on its local stacks lost those items (a
 * group's flush before its stall did not count as progress, so the other
 * group could call the stall while the flushed items were being run).  The
 * graphs of shape 0 start with 2-item queues and stall several times each;
 * repeating them makes the race likely enough to catch (before the fix one
 * pass of all 200 graphs failed about 6 times in 10). */
START_TEST(local_queue_stalls_lose_nothing)
{
    const char *const local_variants[] = { "megakernel/shared+local32", "megakernel/stealing/random+local32" };
    enum { REPEATS = 12 };
    unsigned variant = variant_of(local_variants[_i]);
    ck_assert_uint_eq(variant_schedule(variant).local_queue_items, 32);
    stress_runtime s;
    open_shape(&s, 0, variant);
    unsigned runs = 0, launches = 0;
    for (unsigned repeat = 0; repeat < REPEATS; ++repeat) {
        for (unsigned index = 0; index < GRAPHS; index += SHAPES) {
            graph g;
            make_graph(index, &g);
            ck_assert_uint_eq(g.shape, 0);
            run_graph(&s, index, &g, variant);
            perma_stats stats;
            ck_assert_perma_ok(s.rt, perma_get_stats(s.rt, &stats));
            launches += stats.launches;
            ++runs;
        }
    }
    /* The stalls this test is about did happen (each one is a relaunch). */
    ck_assert_uint_gt(launches, runs);
    perma_destroy(s.rt);
}
END_TEST

/* PERMA_STRESS_VARIANT=N runs variant N only (0-based, in the order of the
 * list above): to repeat one variant many times while hunting a race. */
static void variant_range(int *first, int *end)
{
    *first = 0;
    *end = (int)variant_count;
    const char *only = getenv("PERMA_STRESS_VARIANT");
    if (only && *only) {
        char *rest;
        long v = strtol(only, &rest, 10);
        if (*rest || v < 0 || v >= *end) {
            fprintf(stderr, "PERMA_STRESS_VARIANT=%s: not a variant number 0..%d\n", only, *end - 1);
            exit(EXIT_FAILURE);
        }
        *first = (int)v;
        *end = (int)v + 1;
    }
}

int main(void)
{
    int first, end;
    list_variants();
    variant_range(&first, &end);
    Suite *s = suite_create("stress");
    TCase *tc = tcase_create("stress");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_loop_test(tc, random_graphs_match_the_simulation, first, end);
    if (!getenv("PERMA_STRESS_VARIANT"))
        tcase_add_loop_test(tc, local_queue_stalls_lose_nothing, 0, 2);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
