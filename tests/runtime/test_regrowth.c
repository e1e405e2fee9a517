/* A regrowth moves no queue bytes through the host: the queues grow on the
 * device (runtime/src/state.c, kernels/perma_relayout.cl).  The shim of
 * tests/fault/cl_fault.c counts the bytes every clEnqueueReadBuffer and
 * clEnqueueWriteBuffer moves once the run has launched its first kernel:
 * control blocks, statistics, relayout records and the user buffers copied
 * back, never a queue's items.  The items carry a payload every procedure
 * call checks, so an item moved to a wrong slot would be counted too. */
#include "perma_test.h"
#include "cl_fault.h"

#include <stdlib.h>
#include <string.h>

enum { DEPTH = 13, PAYLOAD = 13 };

/* 64 bytes: big enough that a queue round trip would dwarf the control
 * traffic. */
struct fat_node {
    uint32_t depth, target, id;
    uint32_t payload[PAYLOAD];
};

#define FAT_TYPES "struct fat_node { uint depth; uint target; uint id; uint payload[13]; };\n"

#define FAT_SOURCE                                                                   \
    "void fat_split(perma_ctx *ctx, __local const struct fat_node *node)\n"         \
    "{\n"                                                                            \
    "    uint wrong = 0;\n"                                                          \
    "    for (uint k = 0; k < 13u; ++k)\n"                                           \
    "        wrong |= node->payload[k] != node->id * 31u + k;\n"                     \
    "    if (wrong)\n"                                                               \
    "        atomic_inc(&ctx->buf.counts[1]);\n"                                     \
    "    if (node->depth == node->target) {\n"                                       \
    "        atomic_inc(&ctx->buf.counts[0]);\n"                                     \
    "        return;\n"                                                              \
    "    }\n"                                                                        \
    "    for (uint c = 0; c < 2u; ++c) {\n"                                          \
    "        struct fat_node child;\n"                                               \
    "        child.depth = node->depth + 1u;\n"                                      \
    "        child.target = node->target;\n"                                         \
    "        child.id = node->id * 2u + c;\n"                                        \
    "        for (uint k = 0; k < 13u; ++k)\n"                                       \
    "            child.payload[k] = child.id * 31u + k;\n"                           \
    "        emit_fat(ctx, &child);\n"                                               \
    "    }\n"                                                                        \
    "}\n"

static size_t max_size(size_t a, size_t b)
{
    return a > b ? a : b;
}

/* A runtime of the variant under test with the fat procedure, its
 * queues starting at `capacity`, counting into counts[2] (leaves, wrong
 * payloads), built, with a root that splits down to `depth` seeded.
 * Without work-first stacks: the tree must go through the queues to grow
 * them. */
static perma_runtime *fat_runtime(size_t capacity, uint32_t depth, uint32_t *counts, perma_proc *id)
{
    perma_config config;
    perma_config_init(&config);
    config.queue_capacity = capacity;
    config.time_limit = 120;
    perma_runtime *rt = test_runtime_queues_config(&config);
    ck_assert_perma_ok(rt, perma_add_source(rt, FAT_TYPES, "fat_types.cl"));
    perma_procedure fat = { .name = "fat", .item_type = "struct fat_node", .item_size = sizeof(struct fat_node),
                            .source = FAT_SOURCE, .function = "fat_split", .emits = { { "fat", 2 } } };
    ck_assert_perma_ok(rt, perma_register(rt, &fat, id));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "counts", "__global uint *", counts, 2 * sizeof *counts,
                                           PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_build(rt));
    struct fat_node root = { 0, depth, 1, { 0 } };
    for (unsigned k = 0; k < PAYLOAD; ++k)
        root.payload[k] = root.id * 31u + k;
    ck_assert_perma_ok(rt, perma_seed(rt, *id, &root, 1));
    return rt;
}

START_TEST(regrowth_moves_no_queue_bytes_through_the_host)
{
    uint32_t counts[2] = { 0, 0 };
    perma_proc id;
    perma_runtime *rt = fat_runtime(8 /* the run must grow its queues many times */, DEPTH, counts, &id);

    cl_fault_transfers_reset();
    ck_assert_perma_ok(rt, perma_run(rt));
    cl_fault_transfers moved = cl_fault_transfers_since_launch();

    ck_assert_uint_eq(counts[0], 1u << DEPTH);
    ck_assert_msg(counts[1] == 0, "%u items arrived with a wrong payload", counts[1]);
    perma_stats st;
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
    ck_assert_uint_ge(st.regrowths, 2);

    /* The largest thing the host may read or write after the first launch:
     * a control block (one queue per group at most), the statistics, the
     * relayout records or the user buffer. */
    size_t queues = st.work_groups, groups = st.work_groups;
    size_t control = 4 * (16 + 16 * queues + 2 * groups); /* header, 16-word queue records, group records */
    size_t statistics = 4 * groups * (3 + 8);
    size_t relayout = 48 * queues; /* no item overflowed: the records alone */
    size_t largest = max_size(max_size(control, statistics), max_size(relayout, sizeof counts));
    /* The queues the run ended with: a round trip of them would be this
     * many bytes each way, far more than any control traffic. */
    size_t queue_bytes = ps.queue_capacity * sizeof(struct fat_node);
    ck_assert_uint_gt(queue_bytes, 16 * largest);
    ck_assert_msg(moved.largest <= largest,
                  "a read or write of %llu bytes after the first launch (at most %zu expected; the queues hold "
                  "%zu bytes)", moved.largest, largest, queue_bytes);
    /* Per kernel launch at most a control block read, a queue record and a
     * header written and read, the statistics and the relayout records. */
    unsigned long long budget = (unsigned long long)moved.launches * (2 * control + statistics + relayout + 64) +
                                sizeof counts;
    ck_assert_msg(moved.read + moved.written <= budget,
                  "%llu bytes read and %llu written in %lu calls over %lu launches (budget %llu)", moved.read,
                  moved.written, moved.calls, moved.launches, budget);
    perma_destroy(rt);
}
END_TEST

/* Regression: a group stops the launch for room against the groups it
 * sees running, and a group it did not see (not started yet, or adopting
 * the set of one that left) may still run batches before it sees the stop,
 * up to the last item.  The host then found nothing waiting for room and
 * failed the run ("the kernel reported no room, but no queued item emits
 * anything", about one stress run in 150 under donation).  The shim makes
 * the finished launch report that stall, deterministically: the run is
 * done, with the exact count, and nothing grows. */
START_TEST(a_stall_reported_after_the_last_item_ends_the_run)
{
    enum { SMALL_DEPTH = 4 };
    uint32_t counts[2] = { 0, 0 };
    perma_proc id;
    perma_runtime *rt = fat_runtime(64 /* room for the whole tree: one launch */, SMALL_DEPTH, counts, &id);

    cl_fault_report_stall(1);
    perma_status run = perma_run(rt);
    unsigned reported = cl_fault_stalls_reported();
    cl_fault_report_stall(0);
    ck_assert_msg(run == PERMA_OK, "%s", perma_errmsg(rt));
    /* Only the megakernel reads a launch's header alone (the host-driven
     * steps read the whole control block and never see such a stall). */
    const char *technique = getenv("PERMA_TEST_TECHNIQUE");
    ck_assert_uint_eq(reported, !technique || !*technique ? 1u : 0u);
    ck_assert_uint_eq(counts[0], 1u << SMALL_DEPTH);
    ck_assert_msg(counts[1] == 0, "%u items arrived with a wrong payload", counts[1]);
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_eq(st.regrowths, 0);
    perma_destroy(rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("regrowth");
    TCase *tc = tcase_create("regrowth");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, regrowth_moves_no_queue_bytes_through_the_host);
    tcase_add_test(tc, a_stall_reported_after_the_last_item_ends_the_run);
    suite_add_tcase(s, tc);
    return test_run_suite(s) == 0 ? 0 : 1;
}
