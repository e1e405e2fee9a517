/* Helpers shared by the runtime's Check tests. */
#ifndef PERMA_TEST_H
#define PERMA_TEST_H

#include <check.h>

#include "perma.h"

/* Seconds a test may take; PoCL's first compile of a program is slow. */
#define PERMA_TEST_TIMEOUT 300

/* A runtime on the default device with the given group size (0 = default),
 * work-group count (0 = automatic) and queue capacity (0 = default). */
perma_runtime *test_runtime(unsigned group_size, unsigned work_groups, size_t queue_capacity);
/* The same with every item through the queues, whatever the variant
 * (work-first stacks off): for the tests of queue growth and overflow,
 * which a depth-first run would not make grow. */
perma_runtime *test_runtime_queues(unsigned group_size, unsigned work_groups, size_t queue_capacity);
perma_runtime *test_runtime_queues_config(const perma_config *config);
/* The whole of file `path` as a string (free it); fails the test if unreadable. */
char *test_read_file(const char *path);
/* How many times `needle` occurs in `text`, not overlapping. */
unsigned test_occurrences(const char *text, const char *needle);
/* Parse schedule `label` into *schedule, failing the test with the
 * parser's message when it is not one. */
void test_parse_schedule(const char *label, perma_schedule *schedule);
/* Set the schedule of the variant the test runs under (PERMA_TEST_*), as
 * test_runtime_config does. */
void test_apply_variant(perma_config *config);
perma_runtime *test_runtime_config(const perma_config *config);

/* Fail the test with the runtime's message unless `status` is PERMA_OK. */
#define ck_assert_perma_ok(rt, status)                                                       \
    do {                                                                                     \
        perma_status perma_st_ = (status);                                                   \
        ck_assert_msg(perma_st_ == PERMA_OK, "%s: %s", perma_status_name(perma_st_),         \
                      perma_errmsg(rt));                                                     \
    } while (0)

/* Assert that `haystack` contains `needle`. */
#define ck_assert_contains(haystack, needle)                                                 \
    ck_assert_msg(strstr((haystack), (needle)) != NULL, "expected '%.1000s' in: %.2000s",    \
                  (needle), (haystack)) /* bounded: Check refuses longer messages */

/* A monotonic clock in seconds. */
double perma_test_now(void);

/* Run a suite; returns the number of failures. */
int test_run_suite(Suite *suite);

/* Run `tests` (names given to START_TEST) as suite `name`, one case with
 * PERMA_TEST_TIMEOUT: EXIT_SUCCESS when all pass, else EXIT_FAILURE. */
int test_main(const char *name, const TTest *const *tests, size_t count);

/* A test program's main: PERMA_TEST_MAIN("trace", test_a, test_b, ...). */
#define PERMA_TEST_MAIN(name, ...)                                                           \
    int main(void)                                                                           \
    {                                                                                        \
        const TTest *const tests_[] = { __VA_ARGS__ };                                       \
        return test_main(name, tests_, sizeof tests_ / sizeof *tests_);                      \
    }

/* A procedure `noop` over uint items that does nothing (its source
 * inline): the smallest valid descriptor, for tests to spoil one field. */
perma_procedure test_noop_procedure(void);

#endif
