/* A chain of three procedures with fan-out and fan-in:
 *   produce --(1..4)--> transform --(1)--> consume
 *   produce --(1)-----------------------> consume
 * Every item must be processed exactly once: each procedure counts the ids
 * it sees and the host checks every count is exactly 1. */
#include "perma_test.h"

#include <stdlib.h>
#include <string.h>

enum { PRODUCERS = 2000, FANOUT = 4 };

static const char *chain_types =
    "struct chain_item { uint id; uint tag; };\n";

static const char *chain_source =
    "void produce(perma_ctx *ctx, __local const struct chain_item *it)\n"
    "{\n"
    "    atomic_inc(&ctx->buf.seen_produce[it->id]);\n"
    "    uint fan = it->id % 4u + 1u;\n"
    "    for (uint j = 0; j < fan; ++j) {\n"
    "        struct chain_item t = { it->id * 4u + j, 0 };\n"
    "        emit_transform(ctx, &t);\n"
    "    }\n"
    "    struct chain_item c = { it->id, 0 };\n"
    "    emit_consume(ctx, &c);\n"
    "}\n"
    "void transform(perma_ctx *ctx, __local const struct chain_item *it)\n"
    "{\n"
    "    atomic_inc(&ctx->buf.seen_transform[it->id]);\n"
    "    struct chain_item c = { it->id, 1 };\n"
    "    emit_consume(ctx, &c);\n"
    "}\n"
    "void consume(perma_ctx *ctx, __local const struct chain_item *it)\n"
    "{\n"
    "    if (it->tag == 0)\n"
    "        atomic_inc(&ctx->buf.seen_consume0[it->id]);\n"
    "    else\n"
    "        atomic_inc(&ctx->buf.seen_consume1[it->id]);\n"
    "}\n";

static const struct {
    unsigned work_groups;
    size_t capacity;
} configs[] = { { 0, 0 }, { 1, 0 }, { 2, 16 } };

START_TEST(chain_every_item_once)
{
    perma_runtime *rt = test_runtime(64, configs[_i].work_groups, configs[_i].capacity);
    ck_assert_perma_ok(rt, perma_add_source(rt, chain_types, "chain_types.cl"));
    /* All three functions live in one source that every procedure names:
     * it is compiled once. */
    perma_procedure produce = { .name = "produce", .item_type = "struct chain_item", .item_size = 8,
        .source = chain_source, .source_file = "chain.cl", .function = "produce",
        .emits = { { "transform", FANOUT }, { "consume", 1 } } };
    perma_procedure transform = produce;
    transform.name = "transform";
    transform.function = "transform";
    transform.emits[0] = (perma_emit){ "consume", 1 };
    transform.emits[1] = (perma_emit){ NULL, 0 };
    perma_procedure consume = produce;
    consume.name = "consume";
    consume.function = "consume";
    memset(consume.emits, 0, sizeof consume.emits);
    perma_proc p_id, t_id, c_id;
    ck_assert_perma_ok(rt, perma_register(rt, &consume, &c_id));
    ck_assert_perma_ok(rt, perma_register(rt, &produce, &p_id));
    ck_assert_perma_ok(rt, perma_register(rt, &transform, &t_id));

    static uint32_t seen_produce[PRODUCERS], seen_transform[PRODUCERS * FANOUT];
    static uint32_t seen_consume0[PRODUCERS], seen_consume1[PRODUCERS * FANOUT];
    memset(seen_produce, 0, sizeof seen_produce);
    memset(seen_transform, 0, sizeof seen_transform);
    memset(seen_consume0, 0, sizeof seen_consume0);
    memset(seen_consume1, 0, sizeof seen_consume1);
    ck_assert_perma_ok(rt, perma_bind_host(rt, "seen_produce", "__global uint *", seen_produce, sizeof seen_produce, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "seen_transform", "__global uint *", seen_transform, sizeof seen_transform, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "seen_consume0", "__global uint *", seen_consume0, sizeof seen_consume0, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "seen_consume1", "__global uint *", seen_consume1, sizeof seen_consume1, PERMA_READ_WRITE));

    struct { uint32_t id, tag; } seeds[PRODUCERS];
    for (unsigned i = 0; i < PRODUCERS; ++i) {
        seeds[i].id = i;
        seeds[i].tag = 0;
    }
    ck_assert_perma_ok(rt, perma_seed(rt, p_id, seeds, PRODUCERS));
    ck_assert_perma_ok(rt, perma_run(rt));

    uint64_t transforms = 0;
    for (unsigned i = 0; i < PRODUCERS; ++i) {
        ck_assert_msg(seen_produce[i] == 1, "produce %u seen %u times", i, seen_produce[i]);
        ck_assert_msg(seen_consume0[i] == 1, "consume(0,%u) seen %u times", i, seen_consume0[i]);
        for (unsigned j = 0; j < FANOUT; ++j) {
            unsigned id = i * FANOUT + j, want = j < i % 4 + 1 ? 1 : 0;
            ck_assert_msg(seen_transform[id] == want, "transform %u seen %u times", id, seen_transform[id]);
            ck_assert_msg(seen_consume1[id] == want, "consume(1,%u) seen %u times", id, seen_consume1[id]);
            transforms += want;
        }
    }
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, p_id, &ps));
    ck_assert_uint_eq(ps.items, PRODUCERS);
    ck_assert_uint_eq(ps.emitted[0], transforms);
    ck_assert_uint_eq(ps.emitted[1], PRODUCERS);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, t_id, &ps));
    ck_assert_uint_eq(ps.items, transforms);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, c_id, &ps));
    ck_assert_uint_eq(ps.items, PRODUCERS + transforms);
    perma_destroy(rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("chain");
    TCase *tc = tcase_create("chain");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_loop_test(tc, chain_every_item_once, 0, (int)(sizeof configs / sizeof configs[0]));
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
