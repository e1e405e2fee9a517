/* The layout of a build (runtime/src/layout.c): the order procedures are
 * served in, and each procedure's batch and __local arena, checked against
 * the arithmetic the layout promises.  A runtime is created (the device's
 * limits are read) but no program is compiled. */
#include "perma_test.h"

#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "layout.h"

/* Groups of 8 work-items and 32 KiB of __local memory (OpenCL's minimum),
 * whatever the device has. */
static perma_runtime *small_runtime(void)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = 8;
    config.work_groups = 2;
    config.local_memory_limit = 32768;
    return test_runtime_config(&config);
}

/* Register p, by default a procedure of uint items whose function (of its
 * name, a to e) is in the default source. */
static void add(perma_runtime *rt, perma_procedure p)
{
    perma_proc id;
    if (!p.source)
        p.source = "void a(perma_ctx *c, __local const uint *x) { (void)c; (void)x; }\n"
                   "void b(perma_ctx *c, __local const uint *x) { (void)c; (void)x; }\n"
                   "void c(perma_ctx *c, __local const uint *x) { (void)c; (void)x; }\n"
                   "void d(perma_ctx *c, __local const uint *x) { (void)c; (void)x; }\n"
                   "void e(perma_ctx *c, __local const uint *x) { (void)c; (void)x; }\n";
    if (!p.function)
        p.function = p.name;
    if (!p.item_type) {
        p.item_type = "uint";
        p.item_size = 4;
    }
    if (!p.threads_per_item)
        p.threads_per_item = 1;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
}

/* Downstream first: priority, then depth from a root, then the later
 * registered.  a -> b -> c; d (priority 1) and e are roots of nothing. */
START_TEST(order_is_priority_then_depth_then_registration)
{
    perma_runtime *rt = small_runtime();
    add(rt, (perma_procedure){ .name = "a", .emits = { { "b", 1 } } });
    add(rt, (perma_procedure){ .name = "b", .emits = { { "c", 1 } } });
    add(rt, (perma_procedure){ .name = "c" });
    add(rt, (perma_procedure){ .name = "d", .priority = 1 });
    add(rt, (perma_procedure){ .name = "e" });
    ck_assert_perma_ok(rt, perma_build_layout(rt));
    const unsigned depths[] = { 0, 1, 2, 0, 0 }, order[] = { 3, 2, 1, 4, 0 };
    for (unsigned i = 0; i < 5; ++i) {
        ck_assert_uint_eq(rt->procs[i].depth, depths[i]);
        ck_assert_uint_eq(rt->build.order[i], order[i]);
    }
    ck_assert_int_eq(rt->procs[0].emit_target[0], 1);
    ck_assert_int_eq(rt->procs[1].emit_target[0], 2);
    perma_destroy(rt);
}
END_TEST

/* A cycle with no root starts at its first registered member (depth 0);
 * a procedure emitting into itself is no cycle of two. */
START_TEST(a_cycle_is_ordered_by_its_priorities)
{
    perma_runtime *rt = small_runtime();
    add(rt, (perma_procedure){ .name = "a", .emits = { { "b", 1 }, { "a", 1 } } });
    add(rt, (perma_procedure){ .name = "b", .emits = { { "a", 1 } }, .priority = 2 });
    ck_assert_perma_ok(rt, perma_build_layout(rt));
    ck_assert_uint_eq(rt->procs[0].depth, 0);
    ck_assert_uint_eq(rt->procs[1].depth, 1);
    ck_assert_uint_eq(rt->build.order[0], 1);
    ck_assert_uint_eq(rt->build.order[1], 0);
    perma_destroy(rt);
}
END_TEST

/* Group 8, 4 items per work-item by default: a simple procedure's batch
 * is 32 items, run by lanes of 4; a cooperative one of 4 threads per item
 * takes 2.  Offsets are words, each block rounded up to 16. */
START_TEST(arena_offsets_follow_the_batch)
{
    perma_runtime *rt = small_runtime();
    /* a: uint items emitting up to 2 uint2 into b each. */
    add(rt, (perma_procedure){ .name = "a", .emits = { { "b", 2 } } });
    /* b: uint2 items with 12 bytes of scratch each (rounded to 4 words). */
    add(rt, (perma_procedure){ .name = "b", .item_type = "uint2", .item_size = 8, .local_bytes_per_item = 12,
                               .source = "void b(perma_ctx *c, __local const uint2 *x) { (void)c; (void)x; }\n" });
    add(rt, (perma_procedure){ .name = "c", .threads_per_item = 4, .cooperative = 1 });
    ck_assert_perma_ok(rt, perma_build_layout(rt));
    const perma_proc_info *a = &rt->procs[0], *b = &rt->procs[1], *c = &rt->procs[2];

    ck_assert_uint_eq(a->max_batch, 32);
    ck_assert_uint_eq(a->items_off, 0);
    ck_assert_uint_eq(a->scratch_off, 32);     /* 32 items of 1 word */
    ck_assert_uint_eq(a->counters_off, 32);    /* no scratch */
    ck_assert_uint_eq(a->lane_counts_off, 64); /* 32 items x 1 edge */
    ck_assert_uint_eq(a->lane_items, 4);
    ck_assert_uint_eq(a->stage_off[0], 0);

    ck_assert_uint_eq(b->max_batch, 32);
    ck_assert_uint_eq(b->scratch_words, 4);
    ck_assert_uint_eq(b->scratch_off, 64);     /* 32 items of 2 words */
    ck_assert_uint_eq(b->counters_off, 192);   /* + 32 x 4 words of scratch */
    ck_assert_uint_eq(b->lane_counts_off, 192);

    ck_assert_uint_eq(c->max_batch, 2);        /* 8 work-items / 4 per item */
    ck_assert_uint_eq(c->scratch_off, 16);
    ck_assert_uint_eq(c->lane_items, 0);       /* cooperative: staged per item */

    /* The arena is the largest procedure's (b: 192 words; a: 64 + 8 lane
     * counters); the staging area a's: 8 lanes x 4 items x 2 emits x 2 words. */
    ck_assert_uint_eq(rt->build.arena_words, 192);
    ck_assert_uint_eq(rt->build.stage_words, 128);
    perma_destroy(rt);
}
END_TEST

/* 32 KiB less the kernel's own words (168 bytes for one procedure of one
 * edge) holds 31 items of 1 KiB, not the 32 a full batch would be. */
START_TEST(local_memory_cuts_the_batch)
{
    perma_runtime *rt = small_runtime();
    add(rt, (perma_procedure){ .name = "big", .item_type = "struct big", .item_size = 1024,
                               .source = "struct big { uint w[256]; };\n"
                                         "void big(perma_ctx *c, __local const struct big *x) { (void)c; (void)x; }\n" });
    ck_assert_perma_ok(rt, perma_build_layout(rt));
    ck_assert_uint_eq(rt->procs[0].max_batch_local, 31);
    ck_assert_uint_eq(rt->procs[0].max_batch, 31);
    ck_assert_uint_eq(rt->build.arena_words, 31 * 256);
    perma_destroy(rt);
}
END_TEST

START_TEST(an_item_larger_than_local_memory_is_refused)
{
    perma_runtime *rt = small_runtime();
    /* Within the limit perma_register checks, but with the item (16 words
     * as a batch block) the arena is all 32 KiB: none left for the
     * kernel's own 172 bytes. */
    add(rt, (perma_procedure){ .name = "e", .local_bytes_per_item = 32700 });
    ck_assert_int_eq(perma_build_layout(rt), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "procedure 'e' needs 32768 bytes of __local memory for one item (item, "
                                         "scratch and emit counters), more than the 32596 bytes available");
    perma_destroy(rt);
}
END_TEST

PERMA_TEST_MAIN("layout", order_is_priority_then_depth_then_registration, a_cycle_is_ordered_by_its_priorities,
                arena_offsets_follow_the_batch, local_memory_cuts_the_batch, an_item_larger_than_local_memory_is_refused)
