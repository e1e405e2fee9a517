/* Cooperative procedures: called by every work-item of the group, they may
 * share per-item scratch in __local memory across a barrier. */
#include "perma_test.h"

#include <stdlib.h>

static const char *coop_source =
    "struct quad { uint v[4]; };\n"
    "void sum_squares(perma_ctx *ctx, __local const struct quad *q)\n"
    "{\n"
    "    __local uint *partial = (__local uint *)ctx->scratch;\n"
    "    if (ctx->active)\n"
    "        partial[ctx->thread] = q->v[ctx->thread] * q->v[ctx->thread];\n"
    "    barrier(CLK_LOCAL_MEM_FENCE);\n"
    "    if (ctx->active && ctx->thread == 0) {\n"
    "        uint s = partial[0] + partial[1] + partial[2] + partial[3];\n"
    "        atomic_add(&ctx->buf.result[0], s);\n"
    "        atomic_inc(&ctx->buf.result[1]);\n"
    "    }\n"
    "}\n";

START_TEST(cooperative_scratch_and_barrier)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = { .name = "sum_squares", .item_type = "struct quad", .item_size = 16,
                          .threads_per_item = 4, .local_bytes_per_item = 16, .source = coop_source,
                          .source_file = "coop.cl", .function = "sum_squares", .cooperative = 1 };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    uint32_t result[2] = { 0, 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "result", "__global uint *", result, sizeof result, PERMA_READ_WRITE));
    enum { N = 1001 };
    uint32_t (*items)[4] = calloc(N, sizeof *items);
    uint32_t expected = 0;
    for (unsigned i = 0; i < N; ++i)
        for (unsigned t = 0; t < 4; ++t) {
            items[i][t] = (i * 7 + t * 3) % 50;
            expected += items[i][t] * items[i][t];
        }
    ck_assert_perma_ok(rt, perma_seed(rt, id, items, N));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(result[1], N);
    ck_assert_uint_eq(result[0], expected);
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, id, &ps));
    ck_assert_uint_eq(ps.items, N);
    ck_assert_uint_ge(ps.batches, (N + 15) / 16); /* 64 work-items / 4 threads */
    free(items);
    perma_destroy(rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("cooperative");
    TCase *tc = tcase_create("cooperative");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, cooperative_scratch_and_barrier);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
