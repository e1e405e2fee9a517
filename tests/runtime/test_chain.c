/* A chain of three procedures with fan-out and fan-in
 * (chain_procedure.h): every item must be processed exactly once. */
#include "perma_test.h"
#include "chain_procedure.h"

#include <stdlib.h>

static const struct {
    unsigned work_groups;
    size_t capacity;
} configs[] = { { 0, 0 }, { 1, 0 }, { 2, 16 } };

START_TEST(chain_every_item_once)
{
    perma_runtime *rt = test_runtime(64, configs[_i].work_groups, configs[_i].capacity);
    static chain_run run;
    chain_prepare(rt, &run, CHAIN_MAX_PRODUCERS);
    ck_assert_perma_ok(rt, perma_run(rt));
    chain_check(rt, &run);
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
