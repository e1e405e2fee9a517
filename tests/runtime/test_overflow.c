/* Overflow loses nothing: queues far too small grow and the run completes
 * with the exact result; a memory cap that cannot be met is an error that
 * names the queue, never a hang. */
#include "perma_test.h"
#include "tree_procedure.h"

#include <stdbool.h>

#include <stdlib.h>
#include <string.h>

START_TEST(tiny_queue_regrows_to_exact_result)
{
    perma_runtime *rt = test_runtime_queues(64, 2, 2);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, 1, counts, sums);
    enum { DEPTH = 14 };
    struct tree_node root = { 0, DEPTH, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(counts[0], 1u << DEPTH);
    ck_assert_uint_eq(counts[1], (1u << DEPTH) - 1);
    uint64_t first = 1u << DEPTH, last = (2u << DEPTH) - 1;
    ck_assert_uint_eq(sums[0], (first + last) * (last - first + 1) / 2);

    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_gt(st.regrowths, 0);
    if (st.technique == PERMA_TECHNIQUE_MEGAKERNEL)
        ck_assert_uint_eq(st.launches, st.regrowths + 1); /* one relaunch per growth */
    else
        ck_assert_uint_ge(st.launches, DEPTH + 1);        /* at least one NDRange per tree level */
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
    ck_assert_uint_gt(ps.regrowths, 0);
    ck_assert_uint_le(ps.regrowths, st.regrowths); /* per queue set, at most every step */
    ck_assert_uint_gt(ps.queue_capacity, 2);
    ck_assert_uint_le(ps.peak_queue_items, ps.queue_capacity);
    ck_assert_uint_eq(ps.items, (2u << DEPTH) - 1);

    /* The next run starts from the capacities this one grew to: the same
     * work runs without the regrowths (at most one more).  Where groups
     * share the work differently from run to run (stealing, donation,
     * local queues) a busy machine can make a second run peak higher:
     * there it only grows less than the first. */
    const char *strategy = getenv("PERMA_TEST_STRATEGY"), *local_queue = getenv("PERMA_TEST_LOCAL_QUEUE");
    bool repeatable = !local_queue && (!strategy || strcmp(strategy, "shared") == 0);
    size_t grown = ps.queue_capacity;
    unsigned first_regrowths = st.regrowths;
    memset(counts, 0, sizeof counts);
    sums[0] = 0;
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(counts[0], 1u << DEPTH);
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    if (repeatable)
        ck_assert_uint_le(st.regrowths, 1);
    ck_assert_uint_lt(st.regrowths, first_regrowths);
    ck_assert_uint_ge(st.queues_kept, 1);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
    ck_assert_uint_eq(ps.initial_capacity, grown);
    if (st.technique == PERMA_TECHNIQUE_MEGAKERNEL)
        ck_assert_uint_eq(st.launches, st.regrowths + 1);

    /* perma_forget_capacities, and rebuilding the program (a new buffer),
     * start from the configured capacity again. */
    ck_assert_perma_ok(rt, perma_forget_capacities(rt));
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_eq(st.queues_kept, 0);
    ck_assert_uint_gt(st.regrowths, 0);
    uint32_t unused[1];
    ck_assert_perma_ok(rt, perma_bind_host(rt, "unused", "__global uint *", unused, sizeof unused, PERMA_READ));
    memset(counts, 0, sizeof counts);
    root.target = 3;
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(counts[0], 8);
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_eq(st.queues_kept, 0);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
    ck_assert_uint_lt(ps.initial_capacity, grown);
    perma_destroy(rt);
}
END_TEST

/* Built directly, not through the test variant: depth-first variants (a
 * local front queue, bounded batches, work-first stacks) fit the cap, and
 * the test shows they do. */
START_TEST(memory_cap_is_a_clear_error)
{
    perma_config config;
    perma_config_init(&config);
    config.schedule.work_first_items = PERMA_WORK_FIRST_OFF; /* breadth first */
    config.queue_capacity = 16;
    config.queue_memory_limit = 64 * 1024;
    config.time_limit = 60;
    perma_runtime *rt;
    perma_error error;
    ck_assert_msg(perma_create(&config, &rt, &error) == PERMA_OK, "%s", error.message);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, 1, counts, sums);
    struct tree_node root = { 0, 16, 1, 0 }; /* a level of 65536 nodes: far beyond 64 KiB */
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_CAPACITY);
    ck_assert_contains(perma_errmsg(rt), "queue 'tree'");
    ck_assert_contains(perma_errmsg(rt), "memory limit of 65536 bytes");

    /* The same cap is enough with work-first stacks of 64 items (deeper
     * than the tree, whatever the device's __local memory: 8 work-items):
     * the queue holds the seed, not a tree level. */
    perma_destroy(rt);
    config.schedule.work_first_items = 64;
    config.group_size = 8;
    ck_assert_msg(perma_create(&config, &rt, &error) == PERMA_OK, "%s", error.message);
    id = tree_add(rt, 1, counts, sums);
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    counts[0] = 0;
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(counts[0], 1u << 16);
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_gt(st.stack_items, 0);
    ck_assert_uint_gt(st.stacked_items, (2u << 16) / 2);
    ck_assert_uint_le(st.peak_queue_bytes, config.queue_memory_limit);

    /* And for bounded batches: a stack of batches. */
    perma_destroy(rt);
    counts[0] = 0;
    config.group_size = 0;
    config.schedule.technique = PERMA_TECHNIQUE_BOUNDED_BATCHES;
    config.schedule.batch_limit = 64;
    ck_assert_msg(perma_create(&config, &rt, &error) == PERMA_OK, "%s", error.message);
    id = tree_add(rt, 1, counts, sums);
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(counts[0], 1u << 16);
    perma_destroy(rt);
}
END_TEST

/* A large declared maximum does not make a technique reserve it for all
 * queued items at once: 100000 items that may each emit 64 (and emit 1)
 * would need 51 MB of room in one step, but a host-driven step splits the
 * work into launches that fit the 4 MB cap, like the other techniques. */
START_TEST(large_emit_maximum_fits_the_memory_cap)
{
    perma_config config;
    perma_config_init(&config);
    config.queue_memory_limit = 4 << 20;
    config.time_limit = 120;
    perma_runtime *rt = test_runtime_config(&config);
    const char *source = "void source(perma_ctx *ctx, __local const uint *x) { uint v = *x; emit_sink(ctx, &v); }\n"
                         "void sink(perma_ctx *ctx, __local const uint *x) { atomic_add(&ctx->buf.total[0], *x); }\n";
    perma_procedure producer = { .name = "source", .item_type = "uint", .item_size = 4, .source = source,
                                 .source_file = "fan.cl", .function = "source", .emits = { { "sink", 64 } } };
    perma_procedure sink = producer;
    sink.name = sink.function = "sink";
    memset(sink.emits, 0, sizeof sink.emits);
    perma_proc p, s;
    ck_assert_perma_ok(rt, perma_register(rt, &producer, &p));
    ck_assert_perma_ok(rt, perma_register(rt, &sink, &s));
    uint32_t total[1] = { 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "total", "__global uint *", total, sizeof total, PERMA_READ_WRITE));
    enum { N = 100000 };
    uint32_t *values = malloc(N * sizeof *values);
    for (unsigned i = 0; i < N; ++i)
        values[i] = i % 7;
    ck_assert_perma_ok(rt, perma_seed(rt, p, values, N));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(total[0], (N / 7) * 21 + 0 + 1 + 2 + 3 + 4); /* 100000 = 7 * 14285 + 5 */
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_le(st.peak_queue_bytes, 4 << 20);
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, s, &ps));
    ck_assert_uint_eq(ps.items, N);
    free(values);
    perma_destroy(rt);
}
END_TEST

/* Capacities kept from an earlier run give way when they and the next
 * run's seeds would pass the memory limit together: the run then starts
 * from fresh capacities, and succeeds.  Built directly (megakernel/shared):
 * the sizes are calibrated for it. */
START_TEST(kept_capacities_give_way_to_the_memory_limit)
{
    perma_config config;
    perma_config_init(&config);
    config.schedule.work_first_items = PERMA_WORK_FIRST_OFF; /* its tree grows the queue */
    config.queue_capacity = 16;
    config.queue_memory_limit = 1 << 20;
    config.time_limit = 120;
    perma_runtime *rt;
    perma_error error;
    ck_assert_msg(perma_create(&config, &rt, &error) == PERMA_OK, "%s", error.message);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc tree = tree_add(rt, 1, counts, sums);
    perma_procedure noop = { .name = "noop", .item_type = "uint", .item_size = 4, .function = "noop",
                             .source = "void noop(perma_ctx *ctx, __local const uint *x) { (void)ctx; (void)x; }\n" };
    perma_proc flat;
    ck_assert_perma_ok(rt, perma_register(rt, &noop, &flat));
    struct tree_node root = { 0, 14, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, tree, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, tree, &ps));
    /* A slot costs its item and 8 bytes (perma_config.queue_memory_limit).
     * 2^16 seeds of 4 bytes need 768 KiB: with the learned tree queue (how
     * far it grew depends on the schedule: 16384 items or more, 384 KiB)
     * more than 1 MiB, with a fresh one less. */
    enum { FLAT = 1 << 16, SLOT_OVERHEAD = 8 };
    size_t learned = ps.queue_capacity * (sizeof root + SLOT_OVERHEAD);
    size_t flat_bytes = (size_t)FLAT * (sizeof(uint32_t) + SLOT_OVERHEAD);
    ck_assert_msg(learned + flat_bytes > config.queue_memory_limit, "the tree grew its queue to only %zu bytes",
                  learned);
    uint32_t *items = calloc(FLAT, sizeof *items);
    ck_assert_perma_ok(rt, perma_seed(rt, flat, items, FLAT));
    root.target = 3;
    ck_assert_perma_ok(rt, perma_seed(rt, tree, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_eq(st.queues_kept, 0);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, tree, &ps));
    ck_assert_uint_eq(ps.initial_capacity, 16);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, flat, &ps));
    ck_assert_uint_eq(ps.items, FLAT);
    free(items);
    perma_destroy(rt);
}
END_TEST

/* A procedure that always emits two copies of itself never finishes: the
 * queues grow until the cap, and the run ends with an error. */
START_TEST(unbounded_recursion_hits_the_cap)
{
    perma_config config;
    perma_config_init(&config);
    config.queue_memory_limit = 1 << 20;
    config.time_limit = 60;
    perma_runtime *rt = test_runtime_config(&config);
    perma_procedure forever = {
        .name = "forever", .item_type = "uint", .item_size = 4,
        .source = "void forever(perma_ctx *ctx, __local const uint *x)\n"
                  "{ uint a = *x + 1u; emit_forever(ctx, &a); emit_forever(ctx, &a); }\n",
        .function = "forever", .emits = { { "forever", 2 } },
    };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &forever, &id));
    uint32_t zero = 0;
    ck_assert_perma_ok(rt, perma_seed(rt, id, &zero, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_CAPACITY);
    ck_assert_contains(perma_errmsg(rt), "queue 'forever'");
    perma_destroy(rt);
}
END_TEST

/* Items that declare far more emits than they make (64; these leaves make
 * none): 950 of them in each queue of 1024 (one, or one per group with the
 * distributed strategies).  A batch reserves the room of the emits its
 * procedure made per item so far, not of the declared maximum: only a
 * group's first batch (nothing made yet) reserves 64 per item and runs one
 * item, the others run full batches, with a memory limit that forbids
 * growing the queue, and no queue grows. */
START_TEST(declared_emits_do_not_cut_batches)
{
    enum { LEAVES_PER_SET = 950, GROUPS = 2, DECLARED = 64 };
    unsigned leaves = 1;
    size_t initial_bytes = 0;
    bool megakernel = true;
    for (int run = 0; run < 2 && megakernel; ++run) {
        perma_config config;
        perma_config_init(&config);
        config.time_limit = 120;
        config.work_groups = GROUPS;
        config.queue_memory_limit = initial_bytes;
        perma_runtime *rt = test_runtime_config(&config);
        uint32_t counts[2] = { 0, 0 };
        uint64_t sums[1] = { 0 };
        perma_proc id = tree_add_declaring(rt, 1, DECLARED, counts, sums);
        /* Run 0: a single leaf, to learn the initial queue memory. */
        struct tree_node seeds[GROUPS * LEAVES_PER_SET];
        for (unsigned i = 0; i < leaves; ++i)
            seeds[i] = (struct tree_node){ 0, 0, i, 0 };
        ck_assert_perma_ok(rt, perma_seed(rt, id, seeds, leaves));
        ck_assert_perma_ok(rt, perma_run(rt));
        ck_assert_uint_eq(counts[0], leaves);
        ck_assert_uint_eq(sums[0], (uint64_t)leaves * (leaves - 1) / 2);
        perma_stats st;
        perma_procedure_stats ps;
        ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
        ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
        ck_assert_uint_eq(ps.items, leaves);
        /* The host-driven techniques size the queues for each step. */
        megakernel = st.technique == PERMA_TECHNIQUE_MEGAKERNEL;
        if (run == 0) {
            initial_bytes = st.peak_queue_bytes;
            leaves = LEAVES_PER_SET * (st.strategy == PERMA_STRATEGY_SHARED ? 1 : GROUPS);
        } else if (megakernel) {
            ck_assert_uint_eq(st.regrowths, 0);
            ck_assert_uint_eq(st.peak_queue_bytes, initial_bytes);
            ck_assert_uint_eq(ps.batch_cut, PERMA_BATCH_FULL);
            /* One short first batch per group, the rest full (a local
             * front queue may split a batch more). */
            unsigned full = (leaves + ps.batch_size - 1) / ps.batch_size;
            ck_assert_msg(ps.batches <= full + 2 * GROUPS, "%llu batches for %u leaves in batches of %u",
                          (unsigned long long)ps.batches, leaves, ps.batch_size);
        }
        perma_destroy(rt);
    }
}
END_TEST

/* Generators that each emit a pseudo-random 0..32 items (declared 32) into
 * a sink, seeded so that the first 512 emit nothing: a group's batches then
 * reserve room for no emits at all while the later ones emit up to 32 per
 * item, far more than the 16 slots the queues start with.  What does not
 * fit goes to the group's overflow area, the launch stops, the queue grows
 * and takes those items: the count is exact under every schedule, and on
 * one group of the shared megakernel the overflow path must have been
 * taken. */
#define BURST_TYPES                                                              \
    "struct burst { uint index; };\n"                                            \
    "uint burst_emits(uint i)\n"                                                 \
    "{\n"                                                                        \
    "    if (i < 512u) return 0u;\n"                                             \
    "    i ^= i >> 16; i *= 0x7feb352du; i ^= i >> 15; i *= 0x846ca68bu;\n"      \
    "    return (i ^ (i >> 16)) % 33u;\n"                                        \
    "}\n"
#define BURST_SOURCE                                                             \
    "void burst_generate(perma_ctx *ctx, __local const struct burst *g)\n"       \
    "{\n"                                                                        \
    "    struct burst b;\n"                                                      \
    "    for (uint i = 0; i < burst_emits(g->index); ++i) {\n"                   \
    "        b.index = g->index * 33u + i;\n"                                    \
    "        emit_burst_sink(ctx, &b);\n"                                        \
    "    }\n"                                                                    \
    "}\n"                                                                        \
    "void burst_sink(perma_ctx *ctx, __local const struct burst *b)\n"           \
    "{\n"                                                                        \
    "    atomic_inc(&ctx->buf.sink[0]);\n"                                       \
    "    atomic_add(&ctx->buf.sink[1], b->index);\n"                             \
    "}\n"

static uint32_t burst_emits(uint32_t i)
{
    if (i < 512u)
        return 0;
    i ^= i >> 16;
    i *= 0x7feb352du;
    i ^= i >> 15;
    i *= 0x846ca68bu;
    return (i ^ (i >> 16)) % 33u;
}

static void run_bursts(perma_runtime *rt, uint64_t *overflowed)
{
    enum { GENERATORS = 4096 };
    ck_assert_perma_ok(rt, perma_add_source(rt, BURST_TYPES, "burst_types.cl"));
    perma_procedure generate = { .name = "burst_generate", .item_type = "struct burst", .item_size = 4,
                                 .source = BURST_SOURCE, .source_file = "burst.cl", .function = "burst_generate",
                                 .emits = { { "burst_sink", 32 } } };
    perma_procedure sink = generate;
    sink.name = sink.function = "burst_sink";
    sink.emits[0].target = NULL;
    perma_proc gen_id, sink_id;
    ck_assert_perma_ok(rt, perma_register(rt, &generate, &gen_id));
    ck_assert_perma_ok(rt, perma_register(rt, &sink, &sink_id));
    uint32_t totals[2] = { 0, 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "sink", "__global uint *", totals, sizeof totals, PERMA_READ_WRITE));
    static uint32_t seeds[GENERATORS];
    uint32_t count = 0, sum = 0;
    for (uint32_t g = 0; g < GENERATORS; ++g) {
        seeds[g] = g;
        for (uint32_t i = 0; i < burst_emits(g); ++i, ++count)
            sum += g * 33u + i;
    }
    ck_assert_perma_ok(rt, perma_seed(rt, gen_id, seeds, GENERATORS));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(totals[0], count);
    ck_assert_uint_eq(totals[1], sum);
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, sink_id, &ps));
    ck_assert_uint_eq(ps.items, count);
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_gt(st.regrowths, 0);
    ck_assert_uint_le(st.overflowed_items, count);
    *overflowed = st.overflowed_items;
}

START_TEST(emits_beyond_the_reservation_overflow_and_arrive)
{
    uint64_t overflowed;
    perma_runtime *rt = test_runtime_queues(64, 2, 16);
    run_bursts(rt, &overflowed);
    perma_destroy(rt);
}
END_TEST

START_TEST(overflow_path_taken)
{
    perma_config config;
    perma_config_init(&config);
    config.schedule.work_first_items = PERMA_WORK_FIRST_OFF; /* the bursts go through the queues */
    config.work_groups = 1;
    config.queue_capacity = 16;
    config.time_limit = 120;
    perma_runtime *rt = NULL;
    perma_error error;
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_OK);
    uint64_t overflowed;
    run_bursts(rt, &overflowed);
    ck_assert_uint_gt(overflowed, 0);
    perma_destroy(rt);
}
END_TEST

/* Bounded batches keep the queue at O(N + depth * p * (k - 1)) items where
 * breadth-first needs a whole tree level.  Built directly (not through the
 * test variant) because the technique is the point. */
/* One batch whose emits overflow two queues of different item sizes: each
 * edge's overflowed items lie after the previous edge's, measured in that
 * edge's item size, and arrive intact.  Generators 0..511 emit nothing, so
 * later batches reserve (about) nothing and overflow both edges at once. */
static const char *two_sizes_types = "struct wide { uint word[16]; };\n";
static const char *two_sizes_source =
    "void two_sizes_generate(perma_ctx *ctx, __local const uint *g)\n"
    "{\n"
    "    if (*g < 512u)\n"
    "        return;\n"
    "    struct wide w;\n"
    "    for (uint j = 0; j < 16u; ++j)\n"
    "        w.word[j] = *g * 16u + j;\n"
    "    emit_two_sizes_wide(ctx, &w);\n"
    "    uint n = *g;\n"
    "    emit_two_sizes_narrow(ctx, &n);\n"
    "}\n"
    "void two_sizes_wide(perma_ctx *ctx, __local const struct wide *w)\n"
    "{\n"
    "    uint intact = 1u;\n"
    "    for (uint j = 1; j < 16u; ++j)\n"
    "        intact &= w->word[j] == w->word[0] + j;\n"
    "    atomic_add(&ctx->buf.sink[0], intact);\n"
    "    atomic_add(&ctx->buf.sink[1], w->word[0] / 16u);\n"
    "}\n"
    "void two_sizes_narrow(perma_ctx *ctx, __local const uint *n)\n"
    "{\n"
    "    atomic_inc(&ctx->buf.sink[2]);\n"
    "    atomic_add(&ctx->buf.sink[3], *n);\n"
    "}\n";

START_TEST(overflow_of_two_item_sizes_in_one_batch)
{
    enum { GENERATORS = 4096 };
    perma_runtime *rt = test_runtime_queues(64, 1, 16);
    ck_assert_perma_ok(rt, perma_add_source(rt, two_sizes_types, "wide.cl"));
    perma_procedure generate = { .name = "two_sizes_generate", .item_type = "uint", .item_size = 4,
                                 .source = two_sizes_source, .source_file = "two_sizes.cl",
                                 .function = "two_sizes_generate",
                                 .emits = { { "two_sizes_wide", 1 }, { "two_sizes_narrow", 1 } } };
    perma_procedure wide = generate, narrow = generate;
    wide.name = wide.function = "two_sizes_wide";
    wide.item_type = "struct wide";
    wide.item_size = 64;
    wide.emits[0].target = NULL;
    narrow.name = narrow.function = "two_sizes_narrow";
    narrow.emits[0].target = NULL;
    perma_proc gen_id, id;
    ck_assert_perma_ok(rt, perma_register(rt, &generate, &gen_id));
    ck_assert_perma_ok(rt, perma_register(rt, &wide, &id));
    ck_assert_perma_ok(rt, perma_register(rt, &narrow, &id));
    uint32_t sink[4] = { 0, 0, 0, 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "sink", "__global uint *", sink, sizeof sink, PERMA_READ_WRITE));
    static uint32_t seeds[GENERATORS];
    uint32_t sum = 0;
    for (uint32_t g = 0; g < GENERATORS; ++g) {
        seeds[g] = g;
        sum += g >= 512 ? g : 0;
    }
    ck_assert_perma_ok(rt, perma_seed(rt, gen_id, seeds, GENERATORS));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(sink[0], GENERATORS - 512); /* every wide item intact */
    ck_assert_uint_eq(sink[1], sum);
    ck_assert_uint_eq(sink[2], GENERATORS - 512);
    ck_assert_uint_eq(sink[3], sum);
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    if (st.technique == PERMA_TECHNIQUE_MEGAKERNEL)
        ck_assert_uint_gt(st.overflowed_items, 0);
    perma_destroy(rt);
}
END_TEST

START_TEST(bounded_batches_bound_memory)
{
    enum { DEPTH = 16, LIMIT = 64 };
    uint64_t peaks[2];
    perma_technique techniques[2] = { PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE, PERMA_TECHNIQUE_BOUNDED_BATCHES };
    for (int k = 0; k < 2; ++k) {
        perma_config config;
        perma_config_init(&config);
        config.schedule.technique = techniques[k];
        config.schedule.batch_limit = LIMIT;
        config.queue_capacity = 16;
        perma_runtime *rt;
        perma_error error;
        ck_assert_msg(perma_create(&config, &rt, &error) == PERMA_OK, "%s", error.message);
        uint32_t counts[2] = { 0, 0 };
        uint64_t sums[1] = { 0 };
        perma_proc id = tree_add(rt, 1, counts, sums);
        struct tree_node root = { 0, DEPTH, 1, 0 };
        ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
        ck_assert_perma_ok(rt, perma_run(rt));
        ck_assert_uint_eq(counts[0], 1u << DEPTH);
        perma_procedure_stats ps;
        ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
        peaks[k] = ps.peak_queue_items;
        perma_destroy(rt);
    }
    ck_assert_uint_ge(peaks[0], 1u << DEPTH);            /* the widest level */
    ck_assert_uint_le(peaks[1], 1 + DEPTH * LIMIT + 2 * LIMIT); /* a stack of batches */
}
END_TEST

int main(void)
{
    Suite *s = suite_create("overflow");
    TCase *tc = tcase_create("overflow");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, tiny_queue_regrows_to_exact_result);
    tcase_add_test(tc, memory_cap_is_a_clear_error);
    tcase_add_test(tc, unbounded_recursion_hits_the_cap);
    tcase_add_test(tc, large_emit_maximum_fits_the_memory_cap);
    tcase_add_test(tc, kept_capacities_give_way_to_the_memory_limit);
    tcase_add_test(tc, bounded_batches_bound_memory);
    tcase_add_test(tc, declared_emits_do_not_cut_batches);
    tcase_add_test(tc, emits_beyond_the_reservation_overflow_and_arrive);
    tcase_add_test(tc, overflow_path_taken);
    tcase_add_test(tc, overflow_of_two_item_sizes_in_one_batch);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
