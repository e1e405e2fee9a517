/* What perma_register refuses (procedure.c) and what the layout of a
 * build refuses (layout.c): bad descriptor fields, no procedure, unknown
 * emit targets and functions, emit cycles without a priority order. */
#include "perma_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Register `p` and expect PERMA_ERR_ARGUMENT with `needle` in the message. */
static void expect_rejected(perma_runtime *rt, const perma_procedure *p, const char *needle)
{
    perma_proc id = -1;
    perma_status st = perma_register(rt, p, &id);
    ck_assert_msg(st == PERMA_ERR_ARGUMENT, "expected PERMA_ERR_ARGUMENT for '%s', got %s", needle,
                  perma_status_name(st));
    ck_assert_contains(perma_errmsg(rt), needle);
}

START_TEST(bad_registration_fields)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = test_noop_procedure();
    p.name = "9lives";
    expect_rejected(rt, &p, "procedure name '9lives' is not a C identifier");
    p = test_noop_procedure();
    p.name = NULL;
    expect_rejected(rt, &p, "procedure name '(null)'");
    p = test_noop_procedure();
    p.item_size = 6;
    expect_rejected(rt, &p, "item_size 6 must be a multiple of 4");
    p.item_size = 0;
    expect_rejected(rt, &p, "item_size 0");
    p.item_size = PERMA_MAX_ITEM_SIZE + 4;
    char too_big[64];
    snprintf(too_big, sizeof too_big, "item_size %d", PERMA_MAX_ITEM_SIZE + 4);
    expect_rejected(rt, &p, too_big);
    p = test_noop_procedure();
    p.threads_per_item = 65;
    expect_rejected(rt, &p, "threads_per_item 65 exceeds the group size 64");
    p = test_noop_procedure();
    p.item_type = "";
    expect_rejected(rt, &p, "item_type is empty");
    p = test_noop_procedure();
    p.source = NULL;
    expect_rejected(rt, &p, "neither source nor source_file is set");
    p = test_noop_procedure();
    p.function = "do-it";
    expect_rejected(rt, &p, "function 'do-it' is not a C identifier");
    p = test_noop_procedure();
    p.emits[0] = (perma_emit){ "noop", 0 };
    expect_rejected(rt, &p, "emits[0].max_items 0 must be in 1..4096");
    p.emits[0] = (perma_emit){ "noop", 1 };
    p.emits[1] = (perma_emit){ "noop", 1 };
    expect_rejected(rt, &p, "emits lists target 'noop' twice");
    p = test_noop_procedure();
    p.source = NULL;
    p.source_file = "tests/data/does-not-exist.cl";
    perma_proc id;
    ck_assert_int_eq(perma_register(rt, &p, &id), PERMA_ERR_IO);
    ck_assert_contains(perma_errmsg(rt), "cannot open 'tests/data/does-not-exist.cl'");

    p = test_noop_procedure();
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    expect_rejected(rt, &p, "procedure 'noop' is already registered");
    ck_assert_int_eq(perma_register(rt, NULL, &id), PERMA_ERR_ARGUMENT);
    ck_assert_int_eq(perma_find(rt, "nope", &id), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "no procedure named 'nope'");
    ck_assert_int_eq(perma_seed(rt, 7, &id, 1), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "7 is not a registered procedure");
    ck_assert_int_eq(perma_seed(rt, 0, NULL, 1), PERMA_ERR_ARGUMENT);
    uint32_t buf[4];
    ck_assert_int_eq(perma_bind_host(rt, "out", "float", buf, sizeof buf, PERMA_WRITE), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "type 'float' is not an OpenCL C pointer type");
    ck_assert_int_eq(perma_bind_host(rt, "out", "__global uint *", buf, sizeof buf, 8), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "flags 8");
    perma_destroy(rt);
}
END_TEST

/* Names the generated program cannot take are refused where they are
 * given, saying why (a buffer named 'kernel' once failed the build in
 * perma-generated.cl, a function named perma_megakernel in the
 * scheduler's source). */
START_TEST(reserved_names_are_refused_at_registration)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = test_noop_procedure();
    p.name = "kernel";
    expect_rejected(rt, &p, "procedure name 'kernel' is an OpenCL C keyword; choose another name");
    p.name = "uint4";
    expect_rejected(rt, &p, "procedure name 'uint4' is an OpenCL C type");
    p.name = "perma_queue";
    expect_rejected(rt, &p, "procedure name 'perma_queue' is reserved for perma's own names (perma_ and PERMA_)");
    p = test_noop_procedure();
    p.function = "perma_megakernel";
    expect_rejected(rt, &p, "procedure 'noop': function name 'perma_megakernel' is reserved for perma's own names "
                            "(perma_ and PERMA_); rename the function");
    p.function = "__noop";
    expect_rejected(rt, &p, "function name '__noop' is reserved for the compiler");
    p.function = "global";
    expect_rejected(rt, &p, "function name 'global' is an OpenCL C keyword");
    uint32_t buf[4];
    const char *const buffers[][2] = { { "kernel", "an OpenCL C keyword" }, { "int", "an OpenCL C keyword" },
                                       { "global", "an OpenCL C keyword" }, { "float2", "an OpenCL C type" },
                                       { "size_t", "an OpenCL C type" }, { "PERMA_WORDS", "reserved for perma's" } };
    for (size_t k = 0; k < sizeof buffers / sizeof buffers[0]; ++k) {
        char expected[160];
        snprintf(expected, sizeof expected, "buffer name '%s' is %s", buffers[k][0], buffers[k][1]);
        ck_assert_int_eq(perma_bind_host(rt, buffers[k][0], "__global uint *", buf, sizeof buf, PERMA_WRITE),
                         PERMA_ERR_ARGUMENT);
        ck_assert_contains(perma_errmsg(rt), expected);
    }
    ck_assert_int_eq(perma_declare_reduction(rt, "double", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, NULL),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "perma_declare_reduction: name 'double' is an OpenCL C keyword");
    /* Names that only look alike are fine, and nothing refused was kept. */
    p = test_noop_procedure();
    p.name = "kernels";
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "integer", "__global uint *", buf, sizeof buf, PERMA_WRITE));
    perma_proc found;
    ck_assert_int_eq(perma_find(rt, "kernel", &found), PERMA_ERR_ARGUMENT);
    ck_assert_perma_ok(rt, perma_build(rt));
    perma_destroy(rt);
}
END_TEST

START_TEST(no_procedures_is_a_state_error)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_STATE);
    ck_assert_contains(perma_errmsg(rt), "no procedure is registered");
    perma_destroy(rt);
}
END_TEST

START_TEST(unknown_emit_target)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = test_noop_procedure();
    p.emits[0] = (perma_emit){ "nowhere", 1 };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    ck_assert_int_eq(perma_build(rt), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "procedure 'noop' emits into 'nowhere', which is not a registered procedure");
    perma_destroy(rt);
}
END_TEST

START_TEST(function_missing_from_its_source)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = test_noop_procedure();
    p.function = "noop_typo";
    p.source_file = "noop.cl";
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    ck_assert_int_eq(perma_build(rt), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt),
                       "procedure 'noop': function 'noop_typo' is not defined in 'noop.cl' or a shared source");
    perma_destroy(rt);
}
END_TEST

/* Procedures that emit into each other need priorities that order them;
 * a procedure emitting into itself does not. */
START_TEST(cycle_without_priority_order)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    const char *source = "void ping(perma_ctx *c, __local const uint *x) { uint v = *x; if (v) { --v; emit_pong(c, &v); } }\n"
                         "void pong(perma_ctx *c, __local const uint *x) { uint v = *x; if (v) { --v; emit_ping(c, &v); } }\n";
    perma_procedure ping = { .name = "ping", .item_type = "uint", .item_size = 4, .source = source,
                             .source_file = "pingpong.cl", .function = "ping", .emits = { { "pong", 1 } } };
    perma_procedure pong = ping;
    pong.name = "pong";
    pong.function = "pong";
    pong.emits[0] = (perma_emit){ "ping", 1 };
    perma_proc a, b;
    ck_assert_perma_ok(rt, perma_register(rt, &ping, &a));
    ck_assert_perma_ok(rt, perma_register(rt, &pong, &b));
    ck_assert_int_eq(perma_build(rt), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "procedures 'ping', 'pong' emit into each other in a cycle and all have priority 0");
    perma_destroy(rt);

    /* With an order, the same pair runs: 10 hops back and forth. */
    rt = test_runtime(64, 0, 0);
    pong.priority = 1;
    ck_assert_perma_ok(rt, perma_register(rt, &ping, &a));
    ck_assert_perma_ok(rt, perma_register(rt, &pong, &b));
    uint32_t ten = 10;
    ck_assert_perma_ok(rt, perma_seed(rt, a, &ten, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, a, &ps));
    ck_assert_uint_eq(ps.items, 6); /* 10, 8, 6, 4, 2, 0 */
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, b, &ps));
    ck_assert_uint_eq(ps.items, 5); /* 9, 7, 5, 3, 1 */
    perma_destroy(rt);
}
END_TEST

PERMA_TEST_MAIN("registration", bad_registration_fields, reserved_names_are_refused_at_registration, no_procedures_is_a_state_error, unknown_emit_target, function_missing_from_its_source, cycle_without_priority_order)
