/* The configuration perma_create takes (runtime.c): bad values named by
 * field, PERMA_STOP_GRACE's, and PERMA_DEBUG's one work-group. */
#include "perma_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

START_TEST(bad_config_values)
{
    perma_config config;
    perma_config_init(&config);
    config.time_limit = -1;
    perma_runtime *rt;
    perma_error error;
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_ERR_ARGUMENT);
    ck_assert_contains(error.message, "config.time_limit -1");
    perma_config_init(&config);
    config.stall_limit = -2;
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_ERR_ARGUMENT);
    ck_assert_contains(error.message, "config.stall_limit -2 is not a number of seconds");
    perma_config_init(&config);
    config.group_size = 100000;
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_ERR_ARGUMENT);
    ck_assert_contains(error.message, "config.group_size 100000");
}
END_TEST

/* PERMA_STOP_GRACE: seconds in 0.1..3600; anything else fails
 * perma_create naming the variable and its value (test_watchdog runs a
 * stuck kernel under a value and checks the message quotes it). */
START_TEST(bad_stop_grace)
{
    const char *const bad[] = { "x", "0", "-1", "0.05", "3601", "5s", "nan", "inf" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        setenv("PERMA_STOP_GRACE", bad[i], 1);
        perma_config config;
        perma_config_init(&config);
        perma_runtime *rt = NULL;
        perma_error error;
        ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_ERR_ARGUMENT);
        ck_assert_ptr_null(rt);
        char expected[128];
        snprintf(expected, sizeof expected, "PERMA_STOP_GRACE '%s' is not a number of seconds in 0.1..3600", bad[i]);
        ck_assert_contains(error.message, expected);
    }
    setenv("PERMA_STOP_GRACE", "", 1); /* empty: the default, as unset */
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_destroy(rt);
    unsetenv("PERMA_STOP_GRACE");
}
END_TEST

/* PERMA_DEBUG=1: one work-group and PERMA_DEBUG defined for procedures. */
START_TEST(debug_mode)
{
    setenv("PERMA_DEBUG", "1", 1);
    perma_runtime *rt = test_runtime(64, 0, 0);
    unsetenv("PERMA_DEBUG");
    perma_procedure p = {
        .name = "mark", .item_type = "uint", .item_size = 4, .function = "mark",
        .source = "void mark(perma_ctx *ctx, __local const uint *x)\n"
                  "{\n"
                  "#ifdef PERMA_DEBUG\n"
                  "    atomic_add(&ctx->buf.out[0], *x);\n"
                  "#endif\n"
                  "}\n",
    };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    uint32_t out[1] = { 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "out", "__global uint *", out, sizeof out, PERMA_READ_WRITE));
    uint32_t values[100];
    for (unsigned i = 0; i < 100; ++i)
        values[i] = i;
    ck_assert_perma_ok(rt, perma_seed(rt, id, values, 100));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(out[0], 4950);
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_uint_eq(st.work_groups, 1);
    ck_assert_contains(perma_device_summary(rt), "1 work-groups (PERMA_DEBUG)");
    perma_destroy(rt);
}
END_TEST

PERMA_TEST_MAIN("config", bad_config_values, bad_stop_grace, debug_mode)
