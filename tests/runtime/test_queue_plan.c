/*
 * The queue planner (runtime/src/queues.c) alone: capacities at the start
 * of a run, the shares of the seeds, growth after a stall or for what a
 * launch needs, and the refusals at the memory limit, from a queue layout
 * written here.  No runtime and no device.
 */
#include "perma_test.h"
#include "queues.h"

#include <stdlib.h>
#include <string.h>

/* Two procedures: "split" (8-byte items) emits up to 4 "leaf" items (16
 * bytes) per item; "leaf" emits nothing.  `sets` queue sets. */
static perma_queue_layout two_procs(unsigned sets, size_t memory_limit)
{
    perma_queue_layout l;
    memset(&l, 0, sizeof l);
    l.procs = 2;
    l.sets = sets;
    l.count = sets * 2;
    l.initial_capacity = PERMA_DEFAULT_QUEUE_CAPACITY;
    l.memory_limit = memory_limit;
    l.proc[0] = (perma_queue_proc){ .name = "split", .item_size = 8, .emit_count = 1, .emit_target = { 1 },
                                    .emit_max = { 4 } };
    l.proc[1] = (perma_queue_proc){ .name = "leaf", .item_size = 16 };
    return l;
}

START_TEST(count_and_bytes)
{
    perma_queue_layout l = two_procs(3, 1 << 30);
    size_t caps[6] = { 1, 2, 4, 8, 16, 32 };
    /* queues 0, 2, 4 hold split (8 + 8 bytes a slot), 1, 3, 5 leaf (16 + 8). */
    ck_assert_uint_eq(perma_queues_bytes(&l, caps), (1 + 4 + 16) * 16 + (2 + 8 + 32) * 24);
}
END_TEST

START_TEST(initial_capacities)
{
    perma_queue_layout l = two_procs(1, 1 << 30);
    size_t seeds[2] = { 3000, 0 }, caps[2];
    unsigned kept = 99;
    perma_error error;
    ck_assert_int_eq(perma_queues_initial(&l, seeds, NULL, caps, &kept, &error), PERMA_OK);
    ck_assert_uint_eq(caps[0], 4096); /* the seeds, rounded up to a power of two */
    ck_assert_uint_eq(caps[1], 1024); /* the default */
    ck_assert_uint_eq(kept, 0);
    /* One item of a producer must fit: 5000 emits need 8192 slots. */
    l.proc[0].emit_max[0] = 5000;
    ck_assert_int_eq(perma_queues_initial(&l, seeds, NULL, caps, &kept, &error), PERMA_OK);
    ck_assert_uint_eq(caps[1], 8192);
    /* With four sets each starts with its share of the seeds (750). */
    l = two_procs(4, 1 << 30);
    l.initial_capacity = 16;
    size_t caps4[8];
    ck_assert_int_eq(perma_queues_initial(&l, seeds, NULL, caps4, &kept, &error), PERMA_OK);
    ck_assert_uint_eq(caps4[0], 1024);
    ck_assert_uint_eq(caps4[6], 1024);
    ck_assert_uint_eq(caps4[7], 16);
}
END_TEST

START_TEST(learned_capacities)
{
    perma_queue_layout l = two_procs(1, 1 << 20);
    size_t seeds[2] = { 0, 0 }, caps[2], learned[2] = { 512, 8192 };
    unsigned kept;
    perma_error error;
    ck_assert_int_eq(perma_queues_initial(&l, seeds, learned, caps, &kept, &error), PERMA_OK);
    ck_assert_uint_eq(caps[0], 1024); /* learned less: not kept */
    ck_assert_uint_eq(caps[1], 8192);
    ck_assert_uint_eq(kept, 1);
    /* Not kept when all queues would then pass the memory limit. */
    l.memory_limit = 1024 * 16 + 8192 * 24 - 1;
    ck_assert_int_eq(perma_queues_initial(&l, seeds, learned, caps, &kept, &error), PERMA_OK);
    ck_assert_uint_eq(caps[1], 1024);
    ck_assert_uint_eq(kept, 0);
    /* The starting queues themselves past the limit. */
    l.memory_limit = 1000;
    ck_assert_int_eq(perma_queues_initial(&l, seeds, NULL, caps, &kept, &error), PERMA_ERR_CAPACITY);
    ck_assert_int_eq(error.status, PERMA_ERR_CAPACITY);
    ck_assert_str_eq(error.message,
                     "the initial queues need 40960 bytes, more than the queue memory limit of 1000 bytes");
}
END_TEST

START_TEST(seed_checks_and_shares)
{
    perma_queue_layout l = two_procs(4, 1 << 20);
    perma_error error;
    ck_assert_int_eq(perma_queues_check_seeds(&l, 1, 0, 1000, &error), PERMA_OK);
    ck_assert_int_eq(perma_queues_check_seeds(&l, 1, 10, PERMA_MAX_QUEUED_ITEMS, &error), PERMA_ERR_ARGUMENT);
    ck_assert_contains(error.message, "perma_seed('leaf'): 1073741824 more items would make 1073741834 queued");
    /* 40000 seeds over 4 sets: 10000 each, a queue of 16384 leaf items
     * (24 bytes a slot) per group, 1572864 bytes. */
    ck_assert_int_eq(perma_queues_check_seeds(&l, 1, 0, 40000, &error), PERMA_ERR_CAPACITY);
    ck_assert_str_eq(error.message,
                     "perma_seed('leaf'): 40000 items seeded would need a queue per group of 16384 items of 24 "
                     "bytes (with its completion marks), 1572864 bytes, more than the queue memory limit of "
                     "1048576 bytes (config.queue_memory_limit; 0: half the device's largest allocation)");
    /* 10 seeds over 4 sets: 3, 3, 3, 1 (queue qi is set qi / 2). */
    size_t seeds[2] = { 2, 10 }, first[8], count[8];
    perma_queues_seed_shares(&l, seeds, first, count);
    size_t expect_first[4] = { 0, 3, 6, 9 }, expect_count[4] = { 3, 3, 3, 1 };
    for (unsigned set = 0; set < 4; ++set) {
        ck_assert_uint_eq(first[set * 2 + 1], expect_first[set]);
        ck_assert_uint_eq(count[set * 2 + 1], expect_count[set]);
    }
    /* 2 seeds: one each for the first two sets, none for the last. */
    ck_assert_uint_eq(count[0], 1);
    ck_assert_uint_eq(first[2], 1);
    ck_assert_uint_eq(count[2], 1);
    ck_assert_uint_eq(count[4], 0);
    ck_assert_uint_eq(count[6], 0);
}
END_TEST

START_TEST(stall_grows_the_full_target)
{
    perma_queue_layout l = two_procs(2, 1 << 30);
    size_t current[4] = { 1024, 1024, 1024, 1024 }, caps[4], none[4] = { 0 };
    /* split waits in set 0; leaf's queue in set 1 has room for 2 < 4. */
    size_t queued[4] = { 10, 0, 0, 1022 };
    perma_error error;
    ck_assert_int_eq(perma_queues_grow_stalled(&l, current, queued, UINT32_MAX, none, caps, &error), PERMA_OK);
    ck_assert_uint_eq(caps[0], 1024);
    ck_assert_uint_eq(caps[1], 1024);
    ck_assert_uint_eq(caps[2], 1024);
    ck_assert_uint_eq(caps[3], 2048); /* a stolen batch emits into the thief's set */
    /* A starved queue: only it grows. */
    ck_assert_int_eq(perma_queues_grow_stalled(&l, current, queued, 2, none, caps, &error), PERMA_OK);
    ck_assert_uint_eq(caps[2], 2048);
    ck_assert_uint_eq(caps[3], 1024);
    /* Room everywhere as the host sees it: every target of waiting work grows. */
    size_t roomy[4] = { 10, 0, 0, 0 };
    ck_assert_int_eq(perma_queues_grow_stalled(&l, current, roomy, UINT32_MAX, none, caps, &error), PERMA_OK);
    ck_assert_uint_eq(caps[1], 2048);
    ck_assert_uint_eq(caps[3], 2048);
    ck_assert_uint_eq(caps[0], 1024);
}
END_TEST

START_TEST(stall_without_waiting_work)
{
    perma_queue_layout l = two_procs(1, 1 << 30);
    size_t current[2] = { 1024, 1024 }, caps[2], queued[2] = { 0, 5 }, overflow[2] = { 0, 0 };
    perma_error error;
    ck_assert_int_eq(perma_queues_grow_stalled(&l, current, queued, UINT32_MAX, overflow, caps, &error),
                     PERMA_ERR_DEVICE);
    ck_assert_str_eq(error.message, "the kernel reported no room, but no queued item emits anything");
    /* Items in an overflow area are what waits: nothing grows. */
    overflow[1] = 3;
    ck_assert_int_eq(perma_queues_grow_stalled(&l, current, queued, UINT32_MAX, overflow, caps, &error), PERMA_OK);
    ck_assert_uint_eq(caps[0], 1024);
    ck_assert_uint_eq(caps[1], 1024);
}
END_TEST

START_TEST(fit_what_is_needed)
{
    perma_queue_layout l = two_procs(1, 1 << 30);
    size_t current[2] = { 1024, 1024 }, caps[2], queued[2] = { 100, 1000 }, needed[2] = { 924, 3000 };
    perma_error error;
    ck_assert_int_eq(perma_queues_grow_to_fit(&l, current, queued, needed, caps, &error), PERMA_OK);
    ck_assert_uint_eq(caps[0], 1024); /* 924 free: enough */
    ck_assert_uint_eq(caps[1], 4096); /* 4096 - 1000 >= 3000 */
    /* More from there. */
    size_t more[2] = { 0, 4000 };
    ck_assert_int_eq(perma_queues_fit_more(&l, current, queued, more, caps, &error), PERMA_OK);
    ck_assert_uint_eq(caps[1], 8192);
    /* Past the memory limit: refused, naming the queue. */
    l.memory_limit = 100000;
    ck_assert_int_eq(perma_queues_grow_to_fit(&l, current, queued, needed, caps, &error), PERMA_ERR_CAPACITY);
    ck_assert_str_eq(error.message,
                     "queue 'leaf' is full (1024 items of 16 bytes) and cannot grow to 4096 items: all queues "
                     "would need 114688 bytes, more than the queue memory limit of 100000 bytes");
    /* Past 2^30 items. */
    l.memory_limit = (size_t)1 << 62;
    size_t huge[2] = { 0, PERMA_MAX_QUEUED_ITEMS };
    ck_assert_int_eq(perma_queues_grow_to_fit(&l, current, queued, huge, caps, &error), PERMA_ERR_CAPACITY);
    ck_assert_str_eq(error.message, "queue 'leaf' would need more than 2^30 items (PERMA_MAX_QUEUED_ITEMS)");
}
END_TEST

int main(void)
{
    Suite *suite = suite_create("queue_plan");
    TCase *tc = tcase_create("plan");
    tcase_add_test(tc, count_and_bytes);
    tcase_add_test(tc, initial_capacities);
    tcase_add_test(tc, learned_capacities);
    tcase_add_test(tc, seed_checks_and_shares);
    tcase_add_test(tc, stall_grows_the_full_target);
    tcase_add_test(tc, stall_without_waiting_work);
    tcase_add_test(tc, fit_what_is_needed);
    suite_add_tcase(suite, tc);
    return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}
