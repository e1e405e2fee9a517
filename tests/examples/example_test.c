#include "example_test.h"

#include <stdlib.h>

void example_test_variant(perma_technique *technique, perma_strategy *strategy)
{
    const char *v;
    *technique = PERMA_TECHNIQUE_MEGAKERNEL;
    *strategy = PERMA_STRATEGY_SHARED;
    if ((v = getenv("PERMA_TEST_TECHNIQUE")) && *v)
        ck_assert_msg(perma_technique_parse(v, technique) == PERMA_OK, "bad PERMA_TEST_TECHNIQUE %s", v);
    if ((v = getenv("PERMA_TEST_STRATEGY")) && *v)
        ck_assert_msg(perma_strategy_parse(v, strategy) == PERMA_OK, "bad PERMA_TEST_STRATEGY %s", v);
}

int example_test_run(Suite *suite)
{
    SRunner *runner = srunner_create(suite);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed;
}
