/* Emits checked while running: beyond an item's declared maximum, into
 * a target not in .emits, and batches cut to leave room for the emits
 * they are expected to make, explained. */
#include "perma_test.h"

#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *limit_source =
    "void greedy(perma_ctx *ctx, __local const uint *x)\n"
    "{\n"
    "    uint v = *x;\n"
    "    if (v == 0u) { uint a = 1u; emit_sink(ctx, &a); emit_sink(ctx, &a); emit_sink(ctx, &a); }\n"
    "}\n"
    "void sink(perma_ctx *ctx, __local const uint *x) { (void)ctx; (void)x; }\n";

START_TEST(emitting_beyond_the_declared_maximum)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure greedy = { .name = "greedy", .item_type = "uint", .item_size = 4, .source = limit_source,
                               .source_file = "limit.cl", .function = "greedy", .emits = { { "sink", 2 } } };
    perma_procedure sink = greedy;
    sink.name = "sink";
    sink.function = "sink";
    memset(sink.emits, 0, sizeof sink.emits);
    perma_proc g, s;
    ck_assert_perma_ok(rt, perma_register(rt, &greedy, &g));
    ck_assert_perma_ok(rt, perma_register(rt, &sink, &s));
    uint32_t zero = 0;
    ck_assert_perma_ok(rt, perma_seed(rt, g, &zero, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_EMIT_LIMIT);
    ck_assert_contains(perma_errmsg(rt),
                       "procedure 'greedy' emitted more than its declared maximum of 2 item(s) into 'sink'");
    perma_destroy(rt);
}
END_TEST

/* Two procedures in one source: `rogue` calls the emit helper of a target
 * that only `a` declares. */
static const char *undeclared_source =
    "void proc_a(perma_ctx *ctx, __local const uint *x) { uint v = *x; if (v) emit_b(ctx, &v); }\n"
    "void proc_b(perma_ctx *ctx, __local const uint *x) { (void)ctx; (void)x; }\n"
    "void rogue(perma_ctx *ctx, __local const uint *x) { uint v = 0; emit_b(ctx, &v); (void)x; }\n";

START_TEST(emitting_into_an_undeclared_target)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure a = { .name = "a", .item_type = "uint", .item_size = 4, .source = undeclared_source,
                          .source_file = "undeclared.cl", .function = "proc_a", .emits = { { "b", 1 } } };
    perma_procedure b = a, rogue = a;
    b.name = "b";
    b.function = "proc_b";
    memset(b.emits, 0, sizeof b.emits);
    rogue.name = "rogue";
    rogue.function = "rogue";
    memset(rogue.emits, 0, sizeof rogue.emits);
    perma_proc ia, ib, ir;
    ck_assert_perma_ok(rt, perma_register(rt, &a, &ia));
    ck_assert_perma_ok(rt, perma_register(rt, &b, &ib));
    ck_assert_perma_ok(rt, perma_register(rt, &rogue, &ir));
    uint32_t one = 1;
    ck_assert_perma_ok(rt, perma_seed(rt, ia, &one, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_perma_ok(rt, perma_seed(rt, ir, &one, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_EMIT_LIMIT);
    ck_assert_contains(perma_errmsg(rt), "procedure 'rogue' emitted into 'b', which is not listed in its .emits");
    perma_destroy(rt);
}
END_TEST

/* A tree whose root has FANOUT children and whose other nodes have 2,
 * down to depth 4: 1 + FANOUT + 2 FANOUT + 4 FANOUT + 8 FANOUT nodes.
 * FANOUT comes from the build options (run_fanout). */
static const char *fanout_types = "struct fan { uint depth; uint pad; };\n";
static const char *fanout_source =
    "void node(perma_ctx *ctx, __local const struct fan *n)\n"
    "{\n"
    "    atomic_inc(&ctx->buf.nodes[0]);\n"
    "    struct fan child = { n->depth + 1u, 0u };\n"
    "    uint children = n->depth == 0u ? FANOUT : n->depth < 4u ? 2u : 0u;\n"
    "    for (uint i = 0; i < children; ++i)\n"
    "        emit_node(ctx, &child);\n"
    "}\n"
    "void root(perma_ctx *ctx, __local const struct fan *n) { node(ctx, n); }\n";

/* How a fan-out run is set up: the root's children (and what the
 * procedure that runs the root declares), items per work-item, and the
 * caps on queue memory and __local memory (0: the defaults). */
typedef struct fanout_case {
    const char *root_name; /* "node": one procedure for all; "root": a separate one */
    unsigned fanout;
    unsigned items_per_work_item;
    size_t queue_capacity;
    size_t queue_memory_limit;
    size_t local_memory_limit;
} fanout_case;

static perma_config fanout_config(const fanout_case *c, char *options, size_t size)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = 64;
    config.time_limit = 120;
    config.items_per_work_item = c->items_per_work_item;
    config.queue_capacity = c->queue_capacity;
    config.queue_memory_limit = c->queue_memory_limit;
    config.local_memory_limit = c->local_memory_limit;
    snprintf(options, size, "-DFANOUT=%uu", c->fanout);
    config.build_options = options;
    return config;
}

/* The __local memory a group of the fan-out runtime may use: the device's,
 * or a lower cap (PERMA_LOCAL_MEMORY_LIMIT, under which the suite also runs
 * this test). */
static size_t fanout_local_memory(void)
{
    fanout_case c = { "node", 2, 0, 0, 0, 0 };
    char options[64];
    perma_config config = fanout_config(&c, options, sizeof options);
    perma_runtime *rt = test_runtime_config(&config);
    size_t bytes = 0;
    ck_assert_perma_ok(rt, perma_get_local_memory(rt, &bytes));
    perma_destroy(rt);
    return bytes;
}

/* Run the fan-out tree of case `c`; the statistics of `node` and what
 * perma_print_stats printed. */
static void run_fanout(const fanout_case *c, perma_procedure_stats *node_stats, char **printed)
{
    char options[64];
    perma_config config = fanout_config(c, options, sizeof options);
    perma_runtime *rt = test_runtime_config(&config);
    bool separate = strcmp(c->root_name, "root") == 0;
    ck_assert_perma_ok(rt, perma_add_source(rt, fanout_types, "fan_types.cl"));
    perma_procedure node = { .name = "node", .item_type = "struct fan", .item_size = 8, .function = "node",
                             .source = fanout_source, .source_file = "fan.cl",
                             .emits = { { "node", separate ? 2 : c->fanout } } };
    perma_proc node_id, root_id;
    ck_assert_perma_ok(rt, perma_register(rt, &node, &node_id));
    root_id = node_id;
    if (separate) {
        perma_procedure root = node;
        root.name = root.function = "root";
        root.emits[0].max_items = c->fanout;
        ck_assert_perma_ok(rt, perma_register(rt, &root, &root_id));
    }
    uint32_t nodes[1] = { 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "nodes", "__global uint *", nodes, sizeof nodes, PERMA_READ_WRITE));
    struct { uint32_t depth, pad; } top = { 0, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, root_id, &top, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(nodes[0], 1 + 15 * c->fanout);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, node_id, node_stats));
    size_t size;
    FILE *out = open_memstream(printed, &size);
    perma_print_stats(rt, out);
    fclose(out);
    perma_destroy(rt);
}

/* `wide` items (8 bytes) each emit `emits` leaves of `leaf_size` bytes into
 * `leaf`, declaring `declared`; `count` of them seeded, a queue memory
 * limit (0: the default), one item per work-item per batch or the default
 * (0).  The statistics of `wide` and what perma_print_stats printed. */
#define WIDE_SOURCE                                                          \
    "struct wide { uint emits; uint pad; };\n"                               \
    "void wide(perma_ctx *ctx, __local const struct wide *w)\n"              \
    "{\n"                                                                    \
    "    struct leaf l = { 0 };\n"                                           \
    "    for (uint i = 0; i < w->emits; ++i)\n"                              \
    "        emit_leaf(ctx, &l);\n"                                          \
    "}\n"                                                                    \
    "void leaf(perma_ctx *ctx, __local const struct leaf *l) { atomic_inc(&ctx->buf.leaves[0]); }\n"
static void run_wide(unsigned declared, unsigned leaf_size, unsigned emits, unsigned count, size_t memory_limit,
                     unsigned items_per_work_item, perma_procedure_stats *wide_stats, char **printed)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = 64;
    config.time_limit = 120;
    config.queue_memory_limit = memory_limit;
    config.items_per_work_item = items_per_work_item;
    perma_runtime *rt = test_runtime_config(&config);
    char types[64];
    snprintf(types, sizeof types, "struct leaf { uint w[%u]; };\n", leaf_size / 4);
    ck_assert_perma_ok(rt, perma_add_source(rt, types, "leaf_types.cl"));
    perma_procedure w = { .name = "wide", .item_type = "struct wide", .item_size = 8, .function = "wide",
                          .source = WIDE_SOURCE, .source_file = "wide.cl", .emits = { { "leaf", declared } } };
    perma_procedure l = { .name = "leaf", .item_type = "struct leaf", .item_size = leaf_size, .function = "leaf",
                          .source = WIDE_SOURCE, .source_file = "wide.cl" };
    perma_proc wide_id, leaf_id;
    ck_assert_perma_ok(rt, perma_register(rt, &w, &wide_id));
    ck_assert_perma_ok(rt, perma_register(rt, &l, &leaf_id));
    uint32_t leaves[1] = { 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "leaves", "__global uint *", leaves, sizeof leaves, PERMA_READ_WRITE));
    struct { uint32_t emits, pad; } *seeds = calloc(count, sizeof *seeds);
    for (unsigned i = 0; i < count; ++i)
        seeds[i].emits = emits;
    ck_assert_perma_ok(rt, perma_seed(rt, wide_id, seeds, count));
    free(seeds);
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(leaves[0], count * emits);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, wide_id, wide_stats));
    size_t size;
    FILE *out = open_memstream(printed, &size);
    perma_print_stats(rt, out);
    fclose(out);
    perma_destroy(rt);
}

/* A batch reserves room for the emits its items are expected to make (the
 * mean so far), not for the declared maximum, and stages them in global
 * memory: one procedure for root and nodes that declares the root's 1000
 * children for every node runs full batches, even under a small cap on
 * __local memory.  What still cuts batches is
 * said, naming the declaration: staging the declared maximum of a full
 * batch beyond what a group may stage (4096 emits of 64 bytes per item),
 * and expected emits that do not fit a queue the memory limit keeps small
 * (1000 real emits per item). */
START_TEST(cut_batches_are_explained)
{
    perma_procedure_stats ps;
    char *printed = NULL;
    /* 4 x 64 items of 8 bytes, each declaring 1000 emits (2 MB of staging
     * for a full batch, in global memory), under a cap of 128 KiB of
     * __local memory: full batches. */
    fanout_case by_memory = { "node", 1000, 0, 0, 0, 128 * 1024 };
    ck_assert_uint_ge(fanout_local_memory(), 16 * 1024);
    run_fanout(&by_memory, &ps, &printed);
    ck_assert_int_eq(ps.batch_cut, PERMA_BATCH_FULL);
    ck_assert_uint_eq(ps.batch_size, 4 * 64);
    ck_assert_uint_ge(ps.items, ps.batches * 16);
    ck_assert_msg(strstr(printed, "warning") == NULL, "unexpected warning: %s", printed);
    free(printed);

    printed = NULL;
    run_wide(4096, 64, 1, 1000, 0, 0, &ps, &printed);
    ck_assert_int_eq(ps.batch_cut, PERMA_BATCH_CUT_STAGING);
    ck_assert_int_eq(ps.batch_cut_emit, 0);
    ck_assert_uint_lt(ps.batch_size, 4 * 64);
    ck_assert_contains(printed, "warning: procedure 'wide' runs at most ");
    ck_assert_contains(printed, ".emits[0] (up to 4096 items of 64 bytes into 'leaf' per item) needs 262144 bytes "
                                "of staging per item");
    ck_assert_contains(printed, "a separate procedure");
    free(printed);

    /* The leaf queue may hold at most 16384 items of 8 bytes and two
     * completion marks beside the wide queue's 1024: full batches of 64
     * wide items would need room for 64000. */
    printed = NULL;
    run_wide(1000, 8, 1000, 512, (size_t)16384 * 16 + 1024 * 16, 1, &ps, &printed);
    ck_assert_int_eq(ps.batch_cut_emit, 0);
    ck_assert_int_eq(ps.batch_cut, PERMA_BATCH_CUT_ROOM);
    ck_assert_uint_eq(ps.batch_size, 64);
    ck_assert_uint_lt(ps.items, ps.batches * 32);
    ck_assert_contains(printed, "warning: procedure 'wide' ran batches of ");
    ck_assert_contains(printed, "instead of up to 64: a full batch reserves room for the emits it is expected to "
                                "make (1000.0 per item into 'leaf'");
    ck_assert_contains(printed, "config.queue_memory_limit");
    free(printed);

    /* The fix: only the root promises 1000 children; node's full batches of
     * 4 x 64 items stage 2 emits each (8 KiB). */
    fanout_case separate = { "root", 1000, 0, 0, 0, 0 };
    printed = NULL;
    run_fanout(&separate, &ps, &printed);
    ck_assert_int_eq(ps.batch_cut, PERMA_BATCH_FULL);
    ck_assert_int_eq(ps.batch_cut_emit, -1);
    ck_assert_uint_eq(ps.batch_size, 4 * 64);
    ck_assert_uint_ge(ps.items, ps.batches * 32);
    ck_assert_msg(strstr(printed, "warning") == NULL, "unexpected warning: %s", printed);
    free(printed);
}
END_TEST

PERMA_TEST_MAIN("emits", emitting_beyond_the_declared_maximum, emitting_into_an_undeclared_target, cut_batches_are_explained)
