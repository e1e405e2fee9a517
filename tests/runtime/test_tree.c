/* A recursive split procedure building a binary tree of depth d: exact leaf
 * and inner-node counts and a checksum of leaf ids, for several depths,
 * group sizes, threads per item and work-group counts. */
#include "perma_test.h"
#include "tree_procedure.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

static const struct {
    unsigned group_size, threads_per_item, work_groups;
} configs[] = {
    { 64, 1, 0 }, { 32, 1, 2 }, { 64, 2, 1 }, { 128, 4, 2 }, { 16, 16, 2 },
    { 64, 1, 5 }, /* more groups than compute units: some start late */
};

/* Per-group counters add up, and with one root (seeded into group 0's queue
 * set) any other group that ran items must have stolen them, or group 0
 * must have donated, or (donation) a group took over the set of group 0
 * while it was not running, which counts as a steal. */
static void check_group_stats(perma_runtime *rt, const perma_stats *st)
{
    uint64_t items = 0, steals = 0, donations = 0, others = 0;
    for (unsigned g = 0; g < st->work_groups; ++g) {
        perma_group_stats gs;
        ck_assert_perma_ok(rt, perma_get_group_stats(rt, g, &gs));
        items += gs.items;
        steals += gs.steals;
        donations += gs.donations;
        if (g > 0)
            others += gs.items;
        if (g > 0 && gs.items > 0 && st->strategy == PERMA_STRATEGY_STEALING)
            ck_assert_msg(gs.steals > 0, "group %u ran %llu items without stealing", g,
                          (unsigned long long)gs.items);
    }
    ck_assert_uint_eq(items, st->items);
    ck_assert_uint_eq(steals, st->steals);
    ck_assert_uint_eq(donations, st->donations);
    if (others > 0 && st->strategy == PERMA_STRATEGY_DONATION)
        ck_assert_uint_gt(donations + steals, 0);
    if (st->strategy == PERMA_STRATEGY_SHARED || st->work_groups == 1)
        ck_assert_uint_eq(steals + donations, 0);
    perma_group_stats none;
    ck_assert_int_eq(perma_get_group_stats(rt, st->work_groups, &none), PERMA_ERR_ARGUMENT);
}

static uint64_t leaf_id_sum(unsigned d)
{
    uint64_t first = (uint64_t)1 << d, last = ((uint64_t)1 << (d + 1)) - 1;
    return (first + last) * (last - first + 1) / 2;
}

START_TEST(tree_counts_exact)
{
    unsigned gs = configs[_i].group_size, tpi = configs[_i].threads_per_item;
    perma_runtime *rt = test_runtime(gs, configs[_i].work_groups, 0);
    uint32_t counts[2];
    uint64_t sums[1];
    perma_proc id = tree_add(rt, tpi, counts, sums);

    const unsigned depths[] = { 0, 1, 5, 12 };
    for (size_t k = 0; k < sizeof depths / sizeof depths[0]; ++k) {
        unsigned d = depths[k];
        memset(counts, 0, sizeof counts);
        sums[0] = 0;
        struct tree_node root = { 0, d, 1, 0 };
        ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
        ck_assert_perma_ok(rt, perma_run(rt));
        ck_assert_uint_eq(counts[0], 1u << d);
        ck_assert_uint_eq(counts[1], (1u << d) - 1);
        ck_assert_uint_eq(sums[0], leaf_id_sum(d));

        perma_procedure_stats ps;
        ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
        ck_assert_uint_eq(ps.items, (2u << d) - 1);
        ck_assert_uint_eq(ps.emitted[0], (2u << d) - 2);
        ck_assert_uint_eq(ps.seeded, 1);
        /* One thread per item: four items per work-item (the default);
         * else one item per tpi work-items. */
        ck_assert_uint_eq(ps.batch_size, tpi == 1 ? 4 * gs : gs / tpi);
        /* Items run in batches, but for those work-first ran from a stack. */
        ck_assert_uint_le(ps.stacked_items, ps.items);
        ck_assert_uint_ge(ps.batches, (ps.items - ps.stacked_items + ps.batch_size - 1) / ps.batch_size);
        perma_stats st;
        ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
        ck_assert_uint_eq(st.items, (2u << d) - 1);
        ck_assert_uint_eq(st.group_size, gs);
        /* Every strategy takes the groups asked for, donation too: groups
         * that start late (or never while others run) cannot hold up the
         * ones that run (perma_try_adopt). */
        if (configs[_i].work_groups)
            ck_assert_uint_eq(st.work_groups, configs[_i].work_groups);
        /* Growing 1024-item queues to a level of 2^d nodes takes at most
         * d - 8 doublings per queue set: more means stalls were declared
         * while work was available (a false stall). */
        ck_assert_uint_le(st.regrowths, (d > 9 ? d - 9 : 0) + 2u * st.work_groups);
        check_group_stats(rt, &st);
    }
    perma_destroy(rt);
}
END_TEST

/* Many roots seeded at once, more than one batch and than the initial
 * queue capacity. */
START_TEST(tree_many_roots)
{
    perma_runtime *rt = test_runtime(64, 0, 256);
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_proc id = tree_add(rt, 1, counts, sums);
    enum { ROOTS = 1000, DEPTH = 6 };
    struct tree_node *roots = calloc(ROOTS, sizeof *roots);
    uint64_t expected = 0;
    for (unsigned i = 0; i < ROOTS; ++i) {
        roots[i] = (struct tree_node){ 0, DEPTH, i + 1, 0 };
        for (uint64_t leaf = 0; leaf < (1u << DEPTH); ++leaf)
            expected += ((uint64_t)(i + 1) << DEPTH) + leaf;
    }
    ck_assert_perma_ok(rt, perma_seed(rt, id, roots, ROOTS));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(counts[0], ROOTS << DEPTH);
    ck_assert_uint_eq(counts[1], ROOTS * ((1u << DEPTH) - 1));
    ck_assert_uint_eq(sums[0], expected);
    free(roots);
    perma_destroy(rt);
}
END_TEST

/* The donation threshold is the schedule's (/d=N).  One tree of depth 16,
 * its root seeded alone into group 0's queue set, grows that set far past
 * the default threshold (4 batches: 1024 items here); the other groups get
 * items only by donation, or by adopting the set of a group that is not
 * running.  Whether another group is there before group 0 is done is up to
 * the device's threads (a loaded CPU often runs a short launch on one
 * thread; Intel's CPU runtime never runs two groups of a launch at once),
 * so the tree runs until runs with another group there (witnesses) show
 * the difference, at most DONATION_RUNS times; without witnesses the runs
 * only check their counts and that nothing was donated above the
 * threshold. */
enum { DONATION_DEPTH = 16, DONATION_RUNS = 40, DONATION_WITNESSES = 3 };

typedef struct tree_runtime {
    perma_runtime *rt;
    perma_proc id;
    uint32_t counts[2];
    uint64_t sums[1];
} tree_runtime;

static void tree_runtime_open(tree_runtime *t, const char *label)
{
    perma_config config;
    perma_config_init(&config);
    config.time_limit = 120;
    test_parse_schedule(label, &config.schedule);
    t->rt = test_runtime_config(&config);
    t->id = tree_add(t->rt, 1, t->counts, t->sums);
}

/* One tree, checked; its donations.  *others: a group other than 0 ran a
 * batch or looked for one while the tree was not done. */
static uint64_t donation_run(tree_runtime *t, bool *others)
{
    memset(t->counts, 0, sizeof t->counts);
    struct tree_node root = { 0, DONATION_DEPTH, 1, 0 };
    ck_assert_perma_ok(t->rt, perma_seed(t->rt, t->id, &root, 1));
    ck_assert_perma_ok(t->rt, perma_run(t->rt));
    ck_assert_uint_eq(t->counts[0], 1u << DONATION_DEPTH);
    perma_stats st;
    ck_assert_perma_ok(t->rt, perma_get_stats(t->rt, &st));
    check_group_stats(t->rt, &st);
    *others = false;
    for (unsigned g = 1; g < st.work_groups; ++g) {
        perma_group_stats gs;
        ck_assert_perma_ok(t->rt, perma_get_group_stats(t->rt, g, &gs));
        *others = *others || gs.batches > 0 || gs.idle_polls > 0;
    }
    return st.donations;
}

START_TEST(donation_threshold_is_the_schedules)
{
    tree_runtime never, standard;
    /* Without work-first stacks, whose gifts to idle groups count as
     * donations whatever the threshold. */
    tree_runtime_open(&never, "megakernel/donation/d=1048576+wf0"); /* more than any queue holds */
    tree_runtime_open(&standard, "megakernel/donation+wf0");
    unsigned never_witnessed = 0, standard_witnessed = 0;
    uint64_t donations = 0;
    for (unsigned run = 0; run < DONATION_RUNS; ++run) {
        bool standard_done = donations > 0 || standard_witnessed >= DONATION_WITNESSES;
        if (never_witnessed >= DONATION_WITNESSES && standard_done)
            break;
        bool others;
        ck_assert_uint_eq(donation_run(&never, &others), 0);
        never_witnessed += others;
        if (!standard_done) {
            donations = donation_run(&standard, &others);
            standard_witnessed += others;
        }
    }
    /* The default threshold does donate where another group is there. */
    if (standard_witnessed >= DONATION_WITNESSES)
        ck_assert_msg(donations > 0, "no donation at the default threshold in %u runs with another group there",
                      standard_witnessed);
    perma_destroy(never.rt);
    perma_destroy(standard.rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("tree");
    TCase *tc = tcase_create("tree");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_loop_test(tc, tree_counts_exact, 0, (int)(sizeof configs / sizeof configs[0]));
    tcase_add_test(tc, tree_many_roots);
    /* The threshold once, under megakernel/donation: each threshold is a
     * build of its own. */
    const char *strategy = getenv("PERMA_TEST_STRATEGY");
    if (strategy && strcmp(strategy, "donation") == 0)
        tcase_add_test(tc, donation_threshold_is_the_schedules);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
