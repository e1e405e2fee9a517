/* Helpers shared by the example tests. */
#ifndef EXAMPLE_TEST_H
#define EXAMPLE_TEST_H

#include <check.h>
#include <perma.h>

/* Seconds one test may take; PoCL's first compile of a program is slow. */
#define EXAMPLE_TEST_TIMEOUT 300

/* The schedule whose technique and strategy PERMA_TEST_TECHNIQUE and
 * PERMA_TEST_STRATEGY name (meson registers each test once per variant);
 * megakernel and shared when unset.  Fails the test on an unknown name. */
void example_test_variant(perma_schedule *schedule);

/* Run a suite; returns the number of failures. */
int example_test_run(Suite *suite);

#endif
