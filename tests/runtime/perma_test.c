#include "perma_test.h"

#include <stdlib.h>

perma_runtime *test_runtime_config(const perma_config *config)
{
    perma_runtime *rt = NULL;
    perma_error error;
    perma_status st = perma_create(config, &rt, &error);
    ck_assert_msg(st == PERMA_OK, "perma_create: %s: %s", perma_status_name(st), error.message);
    return rt;
}

perma_runtime *test_runtime(unsigned group_size, unsigned work_groups, size_t queue_capacity)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = group_size;
    config.work_groups = work_groups;
    config.queue_capacity = queue_capacity;
    config.time_limit = 120;
    return test_runtime_config(&config);
}

int test_run_suite(Suite *suite)
{
    SRunner *runner = srunner_create(suite);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed;
}
