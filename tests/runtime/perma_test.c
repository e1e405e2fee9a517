#include "perma_test.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* PERMA_TEST_TECHNIQUE, PERMA_TEST_STRATEGY, PERMA_TEST_VICTIM,
 * PERMA_TEST_LOCAL_QUEUE and PERMA_TEST_WORK_FIRST select the variant every test runs under (meson
 * registers each test once per variant). */
char *test_read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    ck_assert_msg(f != NULL, "cannot open %s", path);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = calloc(1, (size_t)size + 1);
    ck_assert_ptr_nonnull(text);
    ck_assert_uint_eq(fread(text, 1, (size_t)size, f), (size_t)size);
    fclose(f);
    return text;
}

unsigned test_occurrences(const char *text, const char *needle)
{
    unsigned n = 0;
    for (const char *p = text; (p = strstr(p, needle)) != NULL; p += strlen(needle))
        ++n;
    return n;
}

void test_parse_schedule(const char *label, perma_schedule *schedule)
{
    perma_error error;
    ck_assert_msg(perma_schedule_parse(label, schedule, &error) == PERMA_OK, "%s", error.message);
}

void test_apply_variant(perma_config *config)
{
    const char *v;
    if ((v = getenv("PERMA_TEST_TECHNIQUE")) && *v)
        ck_assert_msg(perma_technique_parse(v, &config->schedule.technique) == PERMA_OK,
                      "bad PERMA_TEST_TECHNIQUE %s", v);
    if ((v = getenv("PERMA_TEST_STRATEGY")) && *v)
        ck_assert_msg(perma_strategy_parse(v, &config->schedule.strategy) == PERMA_OK, "bad PERMA_TEST_STRATEGY %s", v);
    if ((v = getenv("PERMA_TEST_VICTIM")) && *v)
        ck_assert_msg(perma_victim_parse(v, &config->schedule.victim) == PERMA_OK, "bad PERMA_TEST_VICTIM %s", v);
    if ((v = getenv("PERMA_TEST_LOCAL_QUEUE")) && *v)
        config->schedule.local_queue_items = (unsigned)strtoul(v, NULL, 10);
    if ((v = getenv("PERMA_TEST_WORK_FIRST")) && *v) { /* 0: off (every item through the queues) */
        unsigned items = (unsigned)strtoul(v, NULL, 10);
        config->schedule.work_first_items = items ? items : PERMA_WORK_FIRST_OFF;
    }
    if ((v = getenv("PERMA_TEST_BATCH_LIMIT")) && *v)
        config->schedule.batch_limit = (unsigned)strtoul(v, NULL, 10);
}

/* A runtime of `requested` under the test's variant; with `queues_only`,
 * work-first off whatever the variant says. */
static perma_runtime *create_under_variant(const perma_config *requested, bool queues_only)
{
    perma_config config = *requested;
    test_apply_variant(&config);
    if (queues_only)
        config.schedule.work_first_items = PERMA_WORK_FIRST_OFF;
    perma_runtime *rt = NULL;
    perma_error error;
    perma_status st = perma_create(&config, &rt, &error);
    ck_assert_msg(st == PERMA_OK, "perma_create: %s: %s", perma_status_name(st), error.message);
    return rt;
}

/* The tests' usual configuration: a group size, a group count and a
 * queue capacity, and a time limit that turns a hang into a failure. */
static perma_config small_config(unsigned group_size, unsigned work_groups, size_t queue_capacity)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = group_size;
    config.work_groups = work_groups;
    config.queue_capacity = queue_capacity;
    config.time_limit = 120;
    return config;
}

perma_runtime *test_runtime_config(const perma_config *requested)
{
    return create_under_variant(requested, false);
}

perma_runtime *test_runtime_queues_config(const perma_config *requested)
{
    return create_under_variant(requested, true);
}

perma_runtime *test_runtime_queues(unsigned group_size, unsigned work_groups, size_t queue_capacity)
{
    perma_config config = small_config(group_size, work_groups, queue_capacity);
    return create_under_variant(&config, true);
}

perma_runtime *test_runtime(unsigned group_size, unsigned work_groups, size_t queue_capacity)
{
    perma_config config = small_config(group_size, work_groups, queue_capacity);
    return create_under_variant(&config, false);
}

double perma_test_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int test_run_suite(Suite *suite)
{
    SRunner *runner = srunner_create(suite);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed;
}

int test_main(const char *name, const TTest *const *tests, size_t count)
{
    Suite *suite = suite_create(name);
    TCase *tc = tcase_create(name);
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    for (size_t t = 0; t < count; ++t)
        tcase_add_test(tc, tests[t]);
    suite_add_tcase(suite, tc);
    return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}

perma_procedure test_noop_procedure(void)
{
    static const char *source = "void noop(perma_ctx *ctx, __local const uint *x) { (void)ctx; (void)x; }\n";
    perma_procedure p = { .name = "noop", .item_type = "uint", .item_size = 4, .threads_per_item = 1,
                          .source = source, .function = "noop" };
    return p;
}
