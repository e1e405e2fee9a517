/* Work-first execution (perma_schedule.work_first_items, the megakernel's
 * default): a depth-first search needs queue memory that does not grow
 * with its tree, full stacks spill to the queues and lose nothing (also
 * when the queues must grow for them), an idle group gets a share of a
 * busy group's stacks (traced as a donation under donation), queue_only procedures stay off the stacks, and the
 * statistics say so. */
#include "perma_test.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A binary tree of heap ids (root 1) down to `target`: every node adds 1
 * to `nodes`, every leaf its id to `leaf_ids`. */
static const char *types = "struct node { uint depth; uint target; uint id; uint pad; };\n";
static const char *source = "void split(perma_ctx *ctx, __local const struct node *n)\n"
                            "{\n"
                            "    reduce_nodes(ctx, 1u);\n"
                            "    if (n->depth == n->target) {\n"
                            "        reduce_leaf_ids(ctx, (ulong)n->id);\n"
                            "        return;\n"
                            "    }\n"
                            "    struct node child = { n->depth + 1u, n->target, 2u * n->id, 0u };\n"
                            "    emit_split(ctx, &child);\n"
                            "    child.id += 1u;\n"
                            "    emit_split(ctx, &child);\n"
                            "}\n";

struct node {
    uint32_t depth, target, id, pad;
};

typedef struct tree {
    perma_runtime *rt;
    perma_proc split;
    uint64_t nodes, leaf_ids;
} tree;

/* A configuration of `label`'s schedule with `groups` work-groups of
 * `group_size` work-items (0: the defaults). */
static perma_config tree_config(const char *label, unsigned groups, unsigned group_size)
{
    perma_config config;
    perma_config_init(&config);
    test_parse_schedule(label, &config.schedule);
    config.work_groups = groups;
    config.group_size = group_size;
    config.time_limit = 120;
    return config;
}

/* A runtime of `config` with the tree registered. */
static void tree_open_config(tree *t, const perma_config *config)
{
    perma_error error;
    ck_assert_msg(perma_create(config, &t->rt, &error) == PERMA_OK, "%s", error.message);
    ck_assert_perma_ok(t->rt, perma_add_source(t->rt, types, "node.cl"));
    perma_procedure split = { .name = "split", .item_type = "struct node", .item_size = sizeof(struct node),
                              .source = source, .function = "split", .emits = { { "split", 2 } } };
    ck_assert_perma_ok(t->rt, perma_register(t->rt, &split, &t->split));
    ck_assert_perma_ok(t->rt, perma_declare_reduction(t->rt, "nodes", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &t->nodes));
    ck_assert_perma_ok(t->rt,
                       perma_declare_reduction(t->rt, "leaf_ids", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &t->leaf_ids));
}

static void tree_open(tree *t, const char *label, unsigned groups, unsigned group_size)
{
    perma_config config = tree_config(label, groups, group_size);
    tree_open_config(t, &config);
}

/* Run the tree of depth `depth` (from a fresh queue capacity) and check its
 * counts; the run's statistics in *stats. */
static void tree_run(tree *t, unsigned depth, perma_stats *stats)
{
    struct node root = { 0, depth, 1, 0 };
    ck_assert_perma_ok(t->rt, perma_forget_capacities(t->rt));
    ck_assert_perma_ok(t->rt, perma_seed(t->rt, t->split, &root, 1));
    ck_assert_perma_ok(t->rt, perma_run(t->rt));
    uint64_t first = 1ull << depth, last = (2ull << depth) - 1;
    ck_assert_uint_eq(t->nodes, (2ull << depth) - 1);
    ck_assert_uint_eq(t->leaf_ids, (first + last) * (last - first + 1) / 2);
    ck_assert_perma_ok(t->rt, perma_get_stats(t->rt, stats));
    ck_assert_uint_eq(stats->items, (2ull << depth) - 1);
}

/* The queues of a depth-first run hold the root and what the busy group
 * gives the idle one: their memory is the same for a tree of 2^15 nodes
 * and one of 2^23, where breadth first it grows with the widest level.  A
 * search takes two slots per level (an item stays in its slot until its
 * children are done), so the default stack holds these trees. */
START_TEST(depth_first_memory_does_not_grow_with_the_tree)
{
    tree t;
    tree_open(&t, "megakernel/shared", 2, 0);
    const unsigned depths[] = { 14, 18, 22 };
    size_t peak[3];
    for (unsigned k = 0; k < 3; ++k) {
        perma_stats st;
        tree_run(&t, depths[k], &st);
        peak[k] = st.peak_queue_bytes;
        ck_assert_uint_ge(st.stack_items, 2 * depths[k] + 2); /* the default stack holds the search */
        ck_assert_uint_eq(st.regrowths, 0);
        ck_assert_uint_le(st.stack_peak, st.stack_items);
        /* Every item but the root and those moved from the stacks to the
         * queues (the shares given to the idle group: how many depends on
         * how often it is idle, under load more) ran from a stack: none
         * went through a batch's staging. */
        ck_assert_uint_eq(st.stacked_items + st.stack_spills + 1, st.items);
        ck_assert_uint_gt(st.stacked_items, st.items / 2);
        ck_assert_uint_eq(peak[k], peak[0]);
    }
    perma_destroy(t.rt);

    /* Breadth first (+wf0), the queue grows to a tree level. */
    tree_open(&t, "megakernel/shared+wf0", 2, 0);
    perma_stats st;
    tree_run(&t, 18, &st);
    ck_assert_uint_eq(st.stack_items, 0);
    ck_assert_uint_eq(st.stacked_items, 0);
    ck_assert_uint_gt(st.peak_queue_bytes, 4 * peak[0]);
    ck_assert_uint_ge(st.peak_queue_bytes, (1u << 17) * sizeof(struct node));
    perma_destroy(t.rt);
}
END_TEST

/* Stacks of 8 items cannot hold a search 20 levels deep: the bottom half
 * of a full stack goes to the queue, and every item still runs once. */
START_TEST(full_stacks_spill_and_lose_nothing)
{
    tree t;
    tree_open(&t, "megakernel/shared+wf8", 2, 0);
    perma_stats st;
    tree_run(&t, 20, &st);
    ck_assert_uint_eq(st.stack_items, 8);
    ck_assert_uint_gt(st.stack_spills, 0);
    ck_assert_uint_le(st.stack_peak, 8);
    ck_assert_uint_gt(st.stacked_items, st.items / 2);
    perma_procedure_stats ps;
    ck_assert_perma_ok(t.rt, perma_get_procedure_stats(t.rt, t.split, &ps));
    ck_assert_uint_eq(ps.stacked_items, st.stacked_items);
    ck_assert_uint_eq(ps.emitted[0], st.items - 1);
    perma_destroy(t.rt);
}
END_TEST

/* One root, two groups: the group without work counts itself hungry and
 * the other gives it the bottom of its stacks (into the shared queue, its
 * own set, or under donation the hungry group's), so both run items. */
START_TEST(an_idle_group_gets_a_share_of_the_stacks)
{
    const char *const labels[] = { "megakernel/shared", "megakernel/stealing", "megakernel/donation" };
    tree t;
    tree_open(&t, labels[_i], 2, 0);
    perma_stats st;
    tree_run(&t, 21, &st);
    ck_assert_uint_gt(st.stack_spills, 0);
    for (unsigned g = 0; g < st.work_groups; ++g) {
        perma_group_stats gs;
        ck_assert_perma_ok(t.rt, perma_get_group_stats(t.rt, g, &gs));
        ck_assert_msg(gs.items > st.items / 20, "%s: group %u ran %llu of %llu items", labels[_i], g,
                      (unsigned long long)gs.items, (unsigned long long)st.items);
        ck_assert_uint_le(gs.stack_peak, st.stack_items);
    }
    perma_destroy(t.rt);
}
END_TEST

/* Under donation the idle group's share of the stacks goes into its own
 * queue set: a donation in the statistics and in the trace, where it is
 * an event of the stacks ("(stacks)", kind donate) with the items given. */
START_TEST(a_share_given_under_donation_is_a_traced_donation)
{
    char path[] = "/tmp/perma-wf-trace-XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    close(fd);
    perma_config config = tree_config("megakernel/donation", 2, 0);
    config.trace_path = path;
    tree t;
    tree_open_config(&t, &config);
    perma_stats st;
    tree_run(&t, 21, &st);
    uint64_t given = 0, donated = 0;
    for (unsigned g = 0; g < st.work_groups; ++g) {
        perma_group_stats gs;
        ck_assert_perma_ok(t.rt, perma_get_group_stats(t.rt, g, &gs));
        donated += gs.donated_items;
    }
    ck_assert_uint_gt(st.donations, 0);
    perma_destroy(t.rt);

    char *json = test_read_file(path);
    remove(path);
    ck_assert_uint_eq(test_occurrences(json, "\"cat\":\"donate\""), st.donations);
    ck_assert_uint_gt(test_occurrences(json, "{\"name\":\"(stacks)\",\"cat\":\"donate\""), 0);
    for (const char *p = json; (p = strstr(p, "\"cat\":\"donate\"")) != NULL; ++p)
        given += strtoull(strstr(p, "\"items\":") + 8, NULL, 10);
    ck_assert_uint_eq(given, donated);
    free(json);
}
END_TEST

/* Two procedures that emit into each other, stacks of 8 items and queues
 * of 8: a stuck stack's bottom half holds items of both, and one queue may
 * have room while the other has none.  The spill then moves nothing and
 * must not count as progress, or the groups never agree that only bigger
 * queues help and spin until the watchdog stops the run. */
static const char *mixed_source = "void left(perma_ctx *ctx, __local const struct node *n)\n"
                                  "{\n"
                                  "    reduce_nodes(ctx, 1u);\n"
                                  "    if (n->depth == n->target)\n"
                                  "        return;\n"
                                  "    struct node child = { n->depth + 1u, n->target, 2u * n->id, 0u };\n"
                                  "    emit_left(ctx, &child);\n"
                                  "    child.id += 1u;\n"
                                  "    emit_right(ctx, &child);\n"
                                  "}\n"
                                  "void right(perma_ctx *ctx, __local const struct node *n)\n"
                                  "{\n"
                                  "    reduce_nodes(ctx, 1u);\n"
                                  "    reduce_leaf_ids(ctx, (ulong)n->id);\n"
                                  "    if (n->depth == n->target)\n"
                                  "        return;\n"
                                  "    struct node child = { n->depth + 1u, n->target, 2u * n->id, 0u };\n"
                                  "    emit_right(ctx, &child);\n"
                                  "    child.id += 1u;\n"
                                  "    emit_left(ctx, &child);\n"
                                  "}\n";

/* The sum of the ids of the right items below (and including) an item. */
static uint64_t right_id_sum(uint64_t id, int is_right, unsigned depth, unsigned target)
{
    uint64_t sum = is_right ? id : 0;
    if (depth < target)
        sum += right_id_sum(2 * id, is_right, depth + 1, target) + right_id_sum(2 * id + 1, !is_right, depth + 1, target);
    return sum;
}

/* Run the left/right tree of `depth` under `config`, with .queue_only set
 * as given, check its counts against the host and return its statistics. */
static void mixed_tree_run(const perma_config *config, int left_queue_only, int right_queue_only, unsigned depth,
                           perma_stats *stats, perma_procedure_stats *right_stats)
{
    perma_error error;
    perma_runtime *rt;
    ck_assert_msg(perma_create(config, &rt, &error) == PERMA_OK, "%s", error.message);
    ck_assert_perma_ok(rt, perma_add_source(rt, types, "node.cl"));
    perma_proc left, right;
    perma_procedure l = { .name = "left", .item_type = "struct node", .item_size = sizeof(struct node),
                          .source = mixed_source, .source_file = "mixed.cl", .function = "left",
                          .emits = { { "left", 1 }, { "right", 1 } }, .priority = 1,
                          .queue_only = left_queue_only };
    perma_procedure r = { .name = "right", .item_type = "struct node", .item_size = sizeof(struct node),
                          .source = mixed_source, .source_file = "mixed.cl", .function = "right",
                          .emits = { { "right", 1 }, { "left", 1 } }, .queue_only = right_queue_only };
    ck_assert_perma_ok(rt, perma_register(rt, &l, &left));
    ck_assert_perma_ok(rt, perma_register(rt, &r, &right));
    uint64_t nodes = 0, right_ids = 0;
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "nodes", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &nodes));
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "leaf_ids", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &right_ids));
    struct node root = { 0, depth, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, left, &root, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(nodes, (2ull << depth) - 1);
    ck_assert_uint_eq(right_ids, right_id_sum(1, 0, 0, depth));
    ck_assert_perma_ok(rt, perma_get_stats(rt, stats));
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, right, right_stats));
    perma_destroy(rt);
}

START_TEST(spills_of_two_procedures_into_full_queues_grow_them)
{
    const unsigned groups[] = { 1, 2 };
    perma_config config;
    perma_config_init(&config);
    test_parse_schedule("megakernel/shared+wf8", &config.schedule);
    config.work_groups = groups[_i];
    config.group_size = 8;
    config.queue_capacity = 8;
    config.stall_limit = 10;
    config.time_limit = 60;
    perma_stats st;
    perma_procedure_stats right;
    mixed_tree_run(&config, 0, 0, 16, &st, &right);
    ck_assert_uint_gt(st.stack_spills, 0);
    ck_assert_uint_gt(st.regrowths, 0);
}
END_TEST

/* A queue_only procedure's items always go through the queues, and so do
 * those of a procedure that emits into it: no stacks at all here, and the
 * counts are still exact. */
START_TEST(queue_only_items_never_run_from_a_stack)
{
    perma_config config;
    perma_config_init(&config);
    config.work_groups = 2;
    config.time_limit = 60;
    const unsigned depth = 14;
    perma_stats st;
    perma_procedure_stats right;
    mixed_tree_run(&config, _i, !_i, depth, &st, &right);
    ck_assert_uint_eq(st.stack_items, 0);
    ck_assert_uint_eq(st.stacked_items, 0);
    ck_assert_uint_eq(right.stacked_items, 0);
    ck_assert_uint_eq(right.items, (1ull << depth) - 1);

    /* The same procedures without queue_only run almost all from stacks. */
    mixed_tree_run(&config, 0, 0, depth, &st, &right);
    ck_assert_uint_gt(st.stack_items, 0);
    ck_assert_uint_gt(st.stacked_items, st.items / 2);
}
END_TEST

/* The statistics text says what the stacks did. */
START_TEST(stats_name_the_stacks)
{
    tree t;
    tree_open(&t, "megakernel/shared+wf16", 1, 8);
    perma_stats st;
    tree_run(&t, 12, &st);
    char *text = NULL;
    size_t size = 0;
    FILE *out = open_memstream(&text, &size);
    ck_assert_ptr_nonnull(out);
    perma_print_stats(t.rt, out);
    fclose(out);
    ck_assert_contains(text, "work-first: stacks of 16 items;");
    ck_assert_contains(text, "moved from them to the queues");
    free(text);
    perma_destroy(t.rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("work_first");
    TCase *tc = tcase_create("work_first");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, depth_first_memory_does_not_grow_with_the_tree);
    tcase_add_test(tc, full_stacks_spill_and_lose_nothing);
    tcase_add_loop_test(tc, an_idle_group_gets_a_share_of_the_stacks, 0, 3);
    tcase_add_test(tc, a_share_given_under_donation_is_a_traced_donation);
    tcase_add_loop_test(tc, spills_of_two_procedures_into_full_queues_grow_them, 0, 2);
    tcase_add_loop_test(tc, queue_only_items_never_run_from_a_stack, 0, 2);
    tcase_add_test(tc, stats_name_the_stacks);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
