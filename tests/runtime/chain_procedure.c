/* The chain workload shared by test_chain and the race checks. */
#include "chain_procedure.h"

#include <string.h>

#include "perma_test.h"

void chain_prepare(perma_runtime *rt, chain_run *run, unsigned producers)
{
    ck_assert(producers >= 1 && producers <= CHAIN_MAX_PRODUCERS);
    memset(run, 0, sizeof *run);
    run->producers = producers;
    ck_assert_perma_ok(rt, perma_add_source(rt, CHAIN_TYPES, "chain_types.cl"));
    /* All three functions live in one source that every procedure names:
     * it is compiled once. */
    perma_procedure produce = { .name = "produce", .item_type = "struct chain_item", .item_size = 8,
        .source = CHAIN_SOURCE, .source_file = "chain.cl", .function = "produce",
        .emits = { { "transform", CHAIN_FANOUT }, { "consume", 1 } } };
    perma_procedure transform = produce;
    transform.name = "transform";
    transform.function = "transform";
    transform.emits[0] = (perma_emit){ "consume", 1 };
    transform.emits[1] = (perma_emit){ NULL, 0 };
    perma_procedure consume = produce;
    consume.name = "consume";
    consume.function = "consume";
    memset(consume.emits, 0, sizeof consume.emits);
    ck_assert_perma_ok(rt, perma_register(rt, &consume, &run->consume));
    ck_assert_perma_ok(rt, perma_register(rt, &produce, &run->produce));
    ck_assert_perma_ok(rt, perma_register(rt, &transform, &run->transform));

    ck_assert_perma_ok(rt, perma_bind_host(rt, "seen_produce", "__global uint *", run->seen_produce,
                                           sizeof run->seen_produce, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "seen_transform", "__global uint *", run->seen_transform,
                                           sizeof run->seen_transform, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "seen_consume0", "__global uint *", run->seen_consume0,
                                           sizeof run->seen_consume0, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "seen_consume1", "__global uint *", run->seen_consume1,
                                           sizeof run->seen_consume1, PERMA_READ_WRITE));

    static struct { uint32_t id, tag; } seeds[CHAIN_MAX_PRODUCERS];
    for (unsigned i = 0; i < producers; ++i) {
        seeds[i].id = i;
        seeds[i].tag = 0;
    }
    ck_assert_perma_ok(rt, perma_seed(rt, run->produce, seeds, producers));
}

void chain_check(perma_runtime *rt, const chain_run *run)
{
    uint64_t transforms = 0;
    for (unsigned i = 0; i < CHAIN_MAX_PRODUCERS; ++i) {
        unsigned once = i < run->producers ? 1 : 0;
        ck_assert_msg(run->seen_produce[i] == once, "produce %u seen %u times", i, run->seen_produce[i]);
        ck_assert_msg(run->seen_consume0[i] == once, "consume(0,%u) seen %u times", i, run->seen_consume0[i]);
        for (unsigned j = 0; j < CHAIN_FANOUT; ++j) {
            unsigned id = i * CHAIN_FANOUT + j, want = once && j < i % 4 + 1 ? 1 : 0;
            ck_assert_msg(run->seen_transform[id] == want, "transform %u seen %u times", id,
                          run->seen_transform[id]);
            ck_assert_msg(run->seen_consume1[id] == want, "consume(1,%u) seen %u times", id,
                          run->seen_consume1[id]);
            transforms += want;
        }
    }
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, run->produce, &ps));
    ck_assert_uint_eq(ps.items, run->producers);
    ck_assert_uint_eq(ps.emitted[0], transforms);
    ck_assert_uint_eq(ps.emitted[1], run->producers);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, run->transform, &ps));
    ck_assert_uint_eq(ps.items, transforms);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, run->consume, &ps));
    ck_assert_uint_eq(ps.items, run->producers + transforms);
}
