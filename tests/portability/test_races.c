/*
 * Small workloads for Oclgrind's data-race detector (suite 'oclgrind',
 * tests/portability/run_on.sh): the runtime's batch, queue, emit, local
 * queue, donation and host-step code and every Reyes procedure, each as
 * its own Check case (CK_RUN_CASE selects one), each checked for exact
 * results as well.  Oclgrind interprets the device code, about a thousand
 * times slower than PoCL, hence the small sizes.  Without Oclgrind they run
 * on any device in seconds.
 */
#include "perma_test.h"
#include "chain_procedure.h"
#include "tree_procedure.h"

#include <stdlib.h>
#include <string.h>

#ifdef RACES_WITH_REYES
#include "reyes_reference.h"
#include "reyes_test_util.h"
#endif

/* A runtime for one schedule label with a group count (0: default) and an
 * initial queue capacity (0: default). */
static perma_runtime *schedule_runtime(const char *label, unsigned work_groups, size_t capacity,
                                       unsigned group_size)
{
    perma_config config;
    perma_config_init(&config);
    test_parse_schedule(label, &config.schedule);
    config.work_groups = work_groups;
    config.queue_capacity = capacity;
    config.group_size = group_size;
    config.time_limit = 500;
    return test_runtime_config(&config);
}

/* A binary tree of `depth` levels: exact leaf, inner-node and id counts. */
static void run_tree(const char *label, unsigned work_groups, size_t capacity, unsigned threads_per_item,
                     unsigned depth)
{
    perma_runtime *rt = schedule_runtime(label, work_groups, capacity, 64);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, threads_per_item, counts, sums);
    struct tree_node root = { 0, depth, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    uint64_t first = (uint64_t)1 << depth, last = ((uint64_t)2 << depth) - 1;
    ck_assert_uint_eq(counts[0], first);
    ck_assert_uint_eq(counts[1], first - 1);
    ck_assert_uint_eq(sums[0], (first + last) * (last - first + 1) / 2);
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_eq(st.items, last);
    if (capacity)
        ck_assert_uint_gt(st.regrowths, 0);
    perma_destroy(rt);
}

static void run_chain(const char *label, unsigned work_groups, unsigned producers)
{
    perma_runtime *rt = schedule_runtime(label, work_groups, 0, 64);
    static chain_run run;
    chain_prepare(rt, &run, producers);
    ck_assert_perma_ok(rt, perma_run(rt));
    chain_check(rt, &run);
    perma_destroy(rt);
}

START_TEST(tree)
{
    run_tree("megakernel/shared", 1, 0, 1, 7);
}
END_TEST

START_TEST(tree_threads)
{
    run_tree("megakernel/shared", 1, 0, 4, 6);
}
END_TEST

START_TEST(chain)
{
    run_chain("megakernel/shared", 1, 40);
}
END_TEST

/* Two groups: Oclgrind runs them one after the other, but checks the
 * accesses of both (queue slots handed from one group to the other). */
START_TEST(chain_stealing)
{
    run_chain("megakernel/stealing", 2, 40);
}
END_TEST

START_TEST(chain_donation)
{
    run_chain("megakernel/donation", 2, 40);
}
END_TEST

/* Queues of 2 items: the launch stops for room and is relaunched. */
START_TEST(overflow)
{
    run_tree("megakernel/shared", 2, 2, 1, 6);
}
END_TEST

START_TEST(local_queue)
{
    run_tree("megakernel/stealing+local32", 2, 0, 1, 7);
}
END_TEST

START_TEST(kernel_per_procedure)
{
    run_chain("kernel-per-procedure", 0, 40);
}
END_TEST

START_TEST(bounded_batches)
{
    run_tree("bounded-batches/p=16", 0, 0, 1, 6);
}
END_TEST

/* Reductions (every kind of lane: a word, an order key, an exact double
 * sum) over a small tree on two groups, and emits beyond a batch's
 * reservation (the first items make none, later ones up to 8) into a
 * queue of 2: the overflow areas, their copy into the grown queue. */
#define REDUCE_SOURCE                                                              \
    "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n"                              \
    "void rsplit(perma_ctx *ctx, __local const uint *id)\n"                        \
    "{\n"                                                                          \
    "    reduce_count(ctx, 1u);\n"                                                 \
    "    reduce_lowest(ctx, -(int)*id);\n"                                         \
    "    reduce_total(ctx, (double)*id * 0.25);\n"                                 \
    "    uint children = *id < 32u ? 0u : *id < 512u ? (*id * 7u) % 9u : 0u;\n"    \
    "    for (uint i = 0; i < children; ++i) {\n"                                  \
    "        uint child = *id * 8u + i;\n"                                          \
    "        emit_rsplit(ctx, &child);\n"                                          \
    "    }\n"                                                                      \
    "}\n"
START_TEST(reductions_and_overflow)
{
    perma_runtime *rt = schedule_runtime("megakernel/stealing", 2, 2, 64);
    uint32_t count = 0;
    int32_t lowest = 0;
    double total = 0;
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "count", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &count));
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "lowest", PERMA_REDUCE_MIN, PERMA_TYPE_INT, &lowest));
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "total", PERMA_REDUCE_SUM, PERMA_TYPE_DOUBLE, &total));
    perma_procedure p = { .name = "rsplit", .item_type = "uint", .item_size = 4, .source = REDUCE_SOURCE,
                          .source_file = "rsplit.cl", .function = "rsplit", .emits = { { "rsplit", 8 } } };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    uint32_t seeds[64], expected = 0, stack[4096], top = 0, max_id = 0;
    double sum = 0;
    for (uint32_t i = 0; i < 64; ++i)
        seeds[i] = stack[top++] = i;
    while (top) {
        uint32_t x = stack[--top], children = x < 32 ? 0 : x < 512 ? (x * 7) % 9 : 0;
        expected++;
        sum += x * 0.25;
        max_id = x > max_id ? x : max_id;
        for (uint32_t i = 0; i < children; ++i)
            stack[top++] = x * 8 + i;
    }
    ck_assert_perma_ok(rt, perma_seed(rt, id, seeds, 64));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(count, expected);
    ck_assert_int_eq(lowest, -(int32_t)max_id);
    ck_assert(total == sum); /* quarters of integers: exact either way */
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_gt(st.regrowths, 0);
    perma_destroy(rt);
}
END_TEST

#ifdef RACES_WITH_REYES
/* A tiny render of the built-in scene that reaches every procedure: bound,
 * split_u, split_v, dice (cooperative, __local grid), rasterize and
 * stitch (crack stitching, two passes); grid 4 keeps the micropolygons
 * few.  Its counts equal the C reference's. */
START_TEST(reyes)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 24, 24);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 24;
    o.height = 24;
    o.grid = 4;
    o.bound_px = 2.0f;
    o.work_groups = 1;
    o.time_limit = 500;
    reyes_image image;
    reyes_stats stats;
    reyes_test_render_once(&scene, &camera, &o, &image, &stats);
    for (int p = 0; p < REYES_PROC_COUNT; ++p)
        ck_assert_msg(stats.procedures[p].items > 0, "procedure %s was not reached", stats.procedures[p].name);
    ck_assert_uint_gt(stats.samples_written, 0);
    reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
    reyes_image_free(&image);
    reyes_stats_free(&stats);
    reyes_scene_free(&scene);
}
END_TEST
#endif

static void add_case(Suite *s, const char *name, const TTest *test)
{
    TCase *tc = tcase_create(name);
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, test);
    suite_add_tcase(s, tc);
}

int main(void)
{
    Suite *s = suite_create("races");
    add_case(s, "tree", tree);
    add_case(s, "tree_threads", tree_threads);
    add_case(s, "chain", chain);
    add_case(s, "chain_stealing", chain_stealing);
    add_case(s, "chain_donation", chain_donation);
    add_case(s, "overflow", overflow);
    add_case(s, "local_queue", local_queue);
    add_case(s, "kernel_per_procedure", kernel_per_procedure);
    add_case(s, "bounded_batches", bounded_batches);
    add_case(s, "reductions_and_overflow", reductions_and_overflow);
#ifdef RACES_WITH_REYES
    add_case(s, "reyes", reyes);
#endif
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
