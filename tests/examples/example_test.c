#include "example_test.h"

#include <stdlib.h>
#include <string.h>

void example_test_variant(perma_schedule *schedule)
{
    const char *v;
    memset(schedule, 0, sizeof *schedule);
    if ((v = getenv("PERMA_TEST_TECHNIQUE")) && *v)
        ck_assert_msg(perma_technique_parse(v, &schedule->technique) == PERMA_OK, "bad PERMA_TEST_TECHNIQUE %s", v);
    if ((v = getenv("PERMA_TEST_STRATEGY")) && *v)
        ck_assert_msg(perma_strategy_parse(v, &schedule->strategy) == PERMA_OK, "bad PERMA_TEST_STRATEGY %s", v);
}

int example_test_run(Suite *suite)
{
    SRunner *runner = srunner_create(suite);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed;
}
