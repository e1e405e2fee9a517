/* Errors are values with messages that name what is wrong: bad descriptor
 * fields, compile errors with the user's file and line, unknown emit
 * targets, missing devices, emit limits, the watchdog. */
#include "perma_test.h"

#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char *noop_source = "void noop(perma_ctx *ctx, __local const uint *x) { (void)ctx; (void)x; }\n";

static perma_procedure noop_procedure(void)
{
    perma_procedure p = { .name = "noop", .item_type = "uint", .item_size = 4, .threads_per_item = 1,
                          .source = noop_source, .function = "noop" };
    return p;
}

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
    perma_procedure p = noop_procedure();
    p.name = "9lives";
    expect_rejected(rt, &p, "procedure name '9lives' is not a C identifier");
    p = noop_procedure();
    p.name = NULL;
    expect_rejected(rt, &p, "procedure name '(null)'");
    p = noop_procedure();
    p.item_size = 6;
    expect_rejected(rt, &p, "item_size 6 must be a multiple of 4");
    p.item_size = 0;
    expect_rejected(rt, &p, "item_size 0");
    p.item_size = PERMA_MAX_ITEM_SIZE + 4;
    char too_big[64];
    snprintf(too_big, sizeof too_big, "item_size %d", PERMA_MAX_ITEM_SIZE + 4);
    expect_rejected(rt, &p, too_big);
    p = noop_procedure();
    p.threads_per_item = 65;
    expect_rejected(rt, &p, "threads_per_item 65 exceeds the group size 64");
    p = noop_procedure();
    p.item_type = "";
    expect_rejected(rt, &p, "item_type is empty");
    p = noop_procedure();
    p.source = NULL;
    expect_rejected(rt, &p, "neither source nor source_file is set");
    p = noop_procedure();
    p.function = "do-it";
    expect_rejected(rt, &p, "function 'do-it' is not a C identifier");
    p = noop_procedure();
    p.emits[0] = (perma_emit){ "noop", 0 };
    expect_rejected(rt, &p, "emits[0].max_items 0 must be in 1..4096");
    p.emits[0] = (perma_emit){ "noop", 1 };
    p.emits[1] = (perma_emit){ "noop", 1 };
    expect_rejected(rt, &p, "emits lists target 'noop' twice");
    p = noop_procedure();
    p.source = NULL;
    p.source_file = "tests/data/does-not-exist.cl";
    perma_proc id;
    ck_assert_int_eq(perma_register(rt, &p, &id), PERMA_ERR_IO);
    ck_assert_contains(perma_errmsg(rt), "cannot open 'tests/data/does-not-exist.cl'");

    p = noop_procedure();
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

START_TEST(no_procedures_is_a_state_error)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_STATE);
    ck_assert_contains(perma_errmsg(rt), "no procedure is registered");
    perma_destroy(rt);
}
END_TEST

START_TEST(syntax_error_names_file_and_line)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = { .name = "broken", .item_type = "uint", .item_size = 4,
                          .source_file = "tests/data/bad_syntax.cl", .function = "broken" };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    ck_assert_int_eq(perma_build(rt), PERMA_ERR_BUILD);
    ck_assert_contains(perma_errmsg(rt), "tests/data/bad_syntax.cl:4:");
    ck_assert_contains(perma_errmsg(rt), "error");
    /* perma_run reports the same. */
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_BUILD);
    ck_assert_contains(perma_errmsg(rt), "tests/data/bad_syntax.cl:4:");
    perma_destroy(rt);
}
END_TEST

/* docs/writing-procedures.md's sum_squares with four threads per item but
 * not declared cooperative: its barrier would be reached by the work-items
 * with an item only (a wrong sum on PoCL, a hang on a GPU).  It does not
 * build; the message names the procedure, its file and line, and the fix. */
static const char *divergent_source =
    "struct quad { uint v[4]; };\n"
    "void sum_squares(perma_ctx *ctx, __local const struct quad *q)\n"
    "{\n"
    "    __local uint *partial = (__local uint *)ctx->scratch;\n"
    "    if (ctx->active)\n"
    "        partial[ctx->thread] = q->v[ctx->thread] * q->v[ctx->thread];\n"
    "    barrier(CLK_LOCAL_MEM_FENCE);\n"
    "    if (ctx->active && ctx->thread == 0)\n"
    "        atomic_add(&ctx->buf.result[0], partial[0] + partial[1] + partial[2] + partial[3]);\n"
    "}\n"
    "void plain(perma_ctx *ctx, __local const struct quad *q) { (void)ctx; (void)q; }\n";
static const char *work_group_barrier_source =
    "void wg_barrier(perma_ctx *ctx, __local const struct quad *q)\n"
    "{\n"
    "    (void)ctx; (void)q;\n"
    "    work_group_barrier(CLK_LOCAL_MEM_FENCE);\n"
    "}\n";

/* Build sum_squares (cooperative or not), and `second` (NULL: none) from
 * the same source, with work_group_barrier_source added when `second` is
 * wg_barrier; the status of the build. */
static perma_status build_sum_squares(perma_runtime *rt, int cooperative, const char *second, int second_cooperative)
{
    static char source[2048];
    snprintf(source, sizeof source, "%s%s", divergent_source,
             second && strcmp(second, "wg_barrier") == 0 ? work_group_barrier_source : "");
    perma_procedure p = { .name = "sum_squares", .item_type = "struct quad", .item_size = 16,
                          .threads_per_item = 4, .local_bytes_per_item = 16, .source = source,
                          .source_file = "coop.cl", .function = "sum_squares", .cooperative = cooperative };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    if (second) {
        p.name = p.function = second;
        p.cooperative = second_cooperative;
        ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    }
    static uint32_t result[1];
    ck_assert_perma_ok(rt, perma_bind_host(rt, "result", "__global uint *", result, sizeof result, PERMA_READ_WRITE));
    return perma_build(rt);
}

START_TEST(barrier_in_a_non_cooperative_procedure)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    ck_assert_int_eq(build_sum_squares(rt, 0, NULL, 0), PERMA_ERR_BUILD);
    ck_assert_contains(perma_errmsg(rt), "coop.cl:7:");
    ck_assert_contains(perma_errmsg(rt), "barrier() (or a work_group_*() function) in procedure 'sum_squares', "
                                         "which is not declared .cooperative");
    ck_assert_contains(perma_errmsg(rt), "set .cooperative = 1");
    perma_destroy(rt);

    /* work_group_barrier too, in a source two procedures share. */
    rt = test_runtime(64, 0, 0);
    ck_assert_int_eq(build_sum_squares(rt, 0, "wg_barrier", 0), PERMA_ERR_BUILD);
    ck_assert_contains(perma_errmsg(rt), "in the source of procedures 'sum_squares', 'wg_barrier', which are not "
                                         "declared .cooperative");
    perma_destroy(rt);

    /* A source that a cooperative procedure uses may call barriers, also
     * when a non-cooperative one shares it. */
    rt = test_runtime(64, 0, 0);
    ck_assert_perma_ok(rt, build_sum_squares(rt, 1, "plain", 0));
    perma_destroy(rt);
}
END_TEST

/* A procedure with two mistakes clang warns about by default. */
static const char *warning_source =
    "void careless(perma_ctx *ctx, __local const uint *x)\n"
    "{\n"
    "    uint v = *x;\n"
    "    if (v = 3u)\n"
    "        atomic_add(&ctx->buf.out[0], v);\n"
    "    *x + 1u;\n"
    "}\n";

static void collect_text(void *user, const char *text)
{
    char *log = user;
    strncat(log, text, 8191 - strlen(log));
}

/* Build `source` as procedure `name` with config.build_log collecting into
 * log[8192] (NULL: the default, stderr). */
static void build_with_log(const char *name, const char *source, char *log)
{
    perma_config config;
    perma_config_init(&config);
    config.time_limit = 60;
    if (log) {
        log[0] = '\0';
        config.build_log = collect_text;
        config.build_log_user = log;
    }
    perma_runtime *rt = test_runtime_config(&config);
    perma_procedure p = { .name = name, .item_type = "uint", .item_size = 4, .source = source,
                          .source_file = "careless.cl", .function = name };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    uint32_t out[1];
    ck_assert_perma_ok(rt, perma_bind_host(rt, "out", "__global uint *", out, sizeof out, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_build(rt));
    perma_destroy(rt);
}

/* The warnings of a build that succeeds are shown, at the user's file and
 * line: through config.build_log, or on stderr.  A clean program gives
 * none (the generated code has no warnings of its own). */
START_TEST(compiler_warnings_are_shown)
{
    char log[8192];
    build_with_log("careless", warning_source, log);
    ck_assert_contains(log, "perma: the program built with 2 compiler warnings:\n");
    ck_assert_contains(log, "careless.cl:4:");
    ck_assert_contains(log, ": warning: using the result of an assignment as a condition");
    ck_assert_contains(log, "careless.cl:6:");
    ck_assert_contains(log, ": warning: expression result unused");

    build_with_log("noop", noop_source, log);
    ck_assert_msg(log[0] == '\0', "a clean program gave: %s", log);

    /* PERMA_BUILD_LOG=1: the whole log of every build. */
    setenv("PERMA_BUILD_LOG", "1", 1);
    build_with_log("noop", noop_source, log);
    unsetenv("PERMA_BUILD_LOG");
    ck_assert_contains(log, "perma: build log:\n");

    /* The default: stderr. */
    char path[] = "/tmp/perma-stderr-XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    fflush(stderr);
    int saved = dup(2);
    dup2(fd, 2);
    build_with_log("careless", warning_source, NULL);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    char text[8192] = "";
    ssize_t got = pread(fd, text, sizeof text - 1, 0);
    close(fd);
    unlink(path);
    ck_assert_int_gt(got, 0);
    ck_assert_contains(text, "careless.cl:4:");
    ck_assert_contains(text, ": warning: using the result of an assignment as a condition");
}
END_TEST

START_TEST(item_size_mismatch_is_a_build_error)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = noop_procedure();
    p.item_type = "uint2";
    p.source = "void noop(perma_ctx *ctx, __local const uint2 *x) { (void)ctx; (void)x; }\n";
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    ck_assert_int_eq(perma_build(rt), PERMA_ERR_BUILD);
    /* Both sizes, the host's and the device's, in a sentence. */
    ck_assert_contains(perma_errmsg(rt), "procedure 'noop': item_size is 4 bytes, but sizeof(uint2) is 8 bytes "
                                         "on the device");
    perma_destroy(rt);
}
END_TEST

START_TEST(unknown_emit_target)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = noop_procedure();
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
    perma_procedure p = noop_procedure();
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

START_TEST(missing_device_from_environment)
{
    setenv("PERMA_DEVICE", "9:9", 1);
    perma_runtime *rt = (perma_runtime *)1;
    perma_error error;
    perma_status st = perma_create(NULL, &rt, &error);
    ck_assert_int_eq(st, PERMA_ERR_NO_DEVICE);
    ck_assert_int_eq(error.status, PERMA_ERR_NO_DEVICE);
    ck_assert_ptr_null(rt);
    ck_assert_contains(error.message, "OpenCL platform 9 requested");

    setenv("PERMA_DEVICE", "0:9", 1);
    ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_ERR_NO_DEVICE);
    ck_assert_contains(error.message, "OpenCL device 0:9 requested");

    const char *malformed[] = { "0", "0:", ":0", "0:x", "pocl:", "pocl:-1", "po/cl", "0:0:0" };
    for (size_t i = 0; i < sizeof malformed / sizeof malformed[0]; ++i) {
        setenv("PERMA_DEVICE", malformed[i], 1);
        ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_ERR_ARGUMENT);
        ck_assert_contains(error.message, "is not of the form platform:device");
        ck_assert_contains(error.message, malformed[i]);
    }

    /* A name matches a platform's name or vendor in any case, PoCL's
     * vendor being "The pocl project"; one that matches nothing lists the
     * platforms there are. */
    setenv("PERMA_DEVICE", "no-such-platform", 1);
    ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_ERR_NO_DEVICE);
    ck_assert_contains(error.message, "no OpenCL platform's name or vendor contains 'no-such-platform'");
    ck_assert_contains(error.message, "Portable Computing Language");
    setenv("PERMA_DEVICE", "POCL:9", 1);
    ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_ERR_NO_DEVICE);
    ck_assert_contains(error.message, "platform 'POCL'), but platform");
    const char *pocl[] = { "pocl", "PoCL:0", "Portable Computing" };
    for (size_t i = 0; i < sizeof pocl / sizeof pocl[0]; ++i) {
        setenv("PERMA_DEVICE", pocl[i], 1);
        ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_OK);
        char name[256] = "";
        cl_platform_id platform = NULL;
        clGetDeviceInfo(perma_cl_device(rt), CL_DEVICE_PLATFORM, sizeof platform, &platform, NULL);
        clGetPlatformInfo(platform, CL_PLATFORM_VENDOR, sizeof name - 1, name, NULL);
        ck_assert_contains(name, "pocl");
        perma_destroy(rt);
    }

    /* An explicit config field wins over the environment. */
    setenv("PERMA_DEVICE", "9:9", 1);
    perma_config config;
    perma_config_init(&config);
    config.platform_index = 0;
    config.device_index = 0;
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_OK);
    perma_destroy(rt);
    perma_config_init(&config);
    config.platform_name = "pocl";
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_OK);
    perma_destroy(rt);
    config.platform_name = "no-such-platform";
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_ERR_NO_DEVICE);
    ck_assert_contains(error.message, "'no-such-platform'");
    unsetenv("PERMA_DEVICE");
}
END_TEST

/* No OpenCL platform at all: the ICD loader is pointed at an empty vendor
 * directory.  Needs its own process (the loader reads it once). */
START_TEST(no_platform_names_the_package)
{
    const char *fork = getenv("CK_FORK");
    if (fork && strcmp(fork, "no") == 0)
        return; /* would poison the loader for the other tests */
    char empty[] = "/tmp/perma-no-vendors-XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(empty));
    setenv("OCL_ICD_VENDORS", empty, 1);
    perma_runtime *rt = NULL;
    perma_error error;
    ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_ERR_NO_PLATFORM);
    ck_assert_ptr_null(rt);
    ck_assert_contains(error.message, "no OpenCL platform found");
    ck_assert_contains(error.message, "apt-get install pocl-opencl-icd");
    rmdir(empty);
}
END_TEST

/* A registered driver that does not load is not "no driver installed":
 * the message says which is registered and that it did not load. */
START_TEST(driver_that_does_not_load_is_named)
{
    const char *fork = getenv("CK_FORK");
    if (fork && strcmp(fork, "no") == 0)
        return; /* would poison the loader for the other tests */
    char vendors[] = "/tmp/perma-broken-vendors-XXXXXX", icd[96];
    ck_assert_ptr_nonnull(mkdtemp(vendors));
    snprintf(icd, sizeof icd, "%s/broken.icd", vendors);
    FILE *f = fopen(icd, "w");
    ck_assert_ptr_nonnull(f);
    fputs("/nonexistent/libbroken-opencl.so\n", f);
    fclose(f);
    setenv("OCL_ICD_VENDORS", vendors, 1);
    perma_runtime *rt = NULL;
    perma_error error;
    ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_ERR_NO_PLATFORM);
    char expected[256];
    snprintf(expected, sizeof expected, "no OpenCL platform could be loaded, though 1 driver is registered in %s "
             "(broken.icd); OCL_ICD_DEBUG=7 shows why", vendors);
    ck_assert_str_eq(error.message, expected);
    remove(icd);
    rmdir(vendors);
}
END_TEST

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

static const char *limit_source =
    "void greedy(perma_ctx *ctx, __local const uint *x)\n"
    "{\n"
    "    uint v = *x;\n"
    "    if (v == 0u) { uint a = 1u; emit_sink(ctx, &a); emit_sink(ctx, &a); emit_sink(ctx, &a); }\n"
    "}\n"
    "void sink(perma_ctx *ctx, __local const uint *x) { (void)ctx; (void)x; }\n";

START_TEST(emitting_beyond_the_declared_maximum)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure greedy = { .name = "greedy", .item_type = "uint", .item_size = 4, .source = limit_source,
                               .source_file = "limit.cl", .function = "greedy", .emits = { { "sink", 2 } } };
    perma_procedure sink = greedy;
    sink.name = "sink";
    sink.function = "sink";
    memset(sink.emits, 0, sizeof sink.emits);
    perma_proc g, s;
    ck_assert_perma_ok(rt, perma_register(rt, &greedy, &g));
    ck_assert_perma_ok(rt, perma_register(rt, &sink, &s));
    uint32_t zero = 0;
    ck_assert_perma_ok(rt, perma_seed(rt, g, &zero, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_EMIT_LIMIT);
    ck_assert_contains(perma_errmsg(rt),
                       "procedure 'greedy' emitted more than its declared maximum of 2 item(s) into 'sink'");
    perma_destroy(rt);
}
END_TEST

/* Two procedures in one source: `rogue` calls the emit helper of a target
 * that only `a` declares. */
static const char *undeclared_source =
    "void proc_a(perma_ctx *ctx, __local const uint *x) { uint v = *x; if (v) emit_b(ctx, &v); }\n"
    "void proc_b(perma_ctx *ctx, __local const uint *x) { (void)ctx; (void)x; }\n"
    "void rogue(perma_ctx *ctx, __local const uint *x) { uint v = 0; emit_b(ctx, &v); (void)x; }\n";

START_TEST(emitting_into_an_undeclared_target)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure a = { .name = "a", .item_type = "uint", .item_size = 4, .source = undeclared_source,
                          .source_file = "undeclared.cl", .function = "proc_a", .emits = { { "b", 1 } } };
    perma_procedure b = a, rogue = a;
    b.name = "b";
    b.function = "proc_b";
    memset(b.emits, 0, sizeof b.emits);
    rogue.name = "rogue";
    rogue.function = "rogue";
    memset(rogue.emits, 0, sizeof rogue.emits);
    perma_proc ia, ib, ir;
    ck_assert_perma_ok(rt, perma_register(rt, &a, &ia));
    ck_assert_perma_ok(rt, perma_register(rt, &b, &ib));
    ck_assert_perma_ok(rt, perma_register(rt, &rogue, &ir));
    uint32_t one = 1;
    ck_assert_perma_ok(rt, perma_seed(rt, ia, &one, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_perma_ok(rt, perma_seed(rt, ir, &one, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_EMIT_LIMIT);
    ck_assert_contains(perma_errmsg(rt), "procedure 'rogue' emitted into 'b', which is not listed in its .emits");
    perma_destroy(rt);
}
END_TEST

START_TEST(watchdog_stops_an_endless_run)
{
    perma_config config;
    perma_config_init(&config);
    config.time_limit = 1.0;
    config.stall_limit = 0.5; /* items keep completing: the time limit stops it */
    perma_runtime *rt = test_runtime_config(&config);
    perma_procedure spin = {
        .name = "spin", .item_type = "uint", .item_size = 4,
        .source = "void spin(perma_ctx *ctx, __local const uint *x) { uint v = *x + 1u; emit_spin(ctx, &v); }\n",
        .function = "spin", .emits = { { "spin", 1 } },
    };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &spin, &id));
    uint32_t zero = 0;
    ck_assert_perma_ok(rt, perma_seed(rt, id, &zero, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_TIMEOUT);
    ck_assert_contains(perma_errmsg(rt), "the run passed its time limit of 1 s (config.time_limit) and was stopped");
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    ck_assert_double_lt(st.seconds, 15.0);
    /* The runtime is still usable. */
    ck_assert_perma_ok(rt, perma_seed(rt, id, &zero, 1));
    perma_destroy(rt);
}
END_TEST

/* The procedures of the stuck tests: `fine` items complete, item 0 emits
 * one `stuck` item, which loops until the host sets release[0] (never) or,
 * if `cooperative`, until the watchdog asks the run to stop. */
static void add_stuck_procedures(perma_runtime *rt, int cooperative, perma_proc *f, perma_proc *s, uint32_t release[1])
{
    perma_procedure fine = {
        .name = "fine", .item_type = "uint", .item_size = 4, .source_file = "stuck.cl", .function = "fine",
        .source = cooperative
                      ? "void fine(perma_ctx *ctx, __local const uint *x) { if (*x == 0u) { uint v = 1u; emit_stuck(ctx, &v); } }\n"
                        "void stuck(perma_ctx *ctx, __local const uint *x)\n"
                        "{\n"
                        "    while (atomic_add(&ctx->buf.release[0], 0u) == 0u && !perma_stop_requested(ctx))\n"
                        "        ;\n"
                        "    (void)x;\n"
                        "}\n"
                      : "void fine(perma_ctx *ctx, __local const uint *x) { if (*x == 0u) { uint v = 1u; emit_stuck(ctx, &v); } }\n"
                        "void stuck(perma_ctx *ctx, __local const uint *x)\n"
                        "{\n"
                        "    while (atomic_add(&ctx->buf.release[0], 0u) == 0u)\n"
                        "        ;\n"
                        "    (void)x;\n"
                        "}\n",
        .emits = { { "stuck", 1 } },
    };
    perma_procedure stuck = fine;
    stuck.name = stuck.function = "stuck";
    memset(stuck.emits, 0, sizeof stuck.emits);
    ck_assert_perma_ok(rt, perma_register(rt, &fine, f));
    ck_assert_perma_ok(rt, perma_register(rt, &stuck, s));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "release", "__global uint *", release, sizeof(uint32_t), PERMA_READ));
}

/* 99 items that complete and one that emits the stuck item. */
static void seed_stuck_run(perma_runtime *rt, perma_proc f)
{
    uint32_t values[100] = { 0 };
    for (unsigned i = 1; i < 100; ++i)
        values[i] = i;
    ck_assert_perma_ok(rt, perma_seed(rt, f, values, 100));
}

/* A procedure that never returns: nothing completes, so the watchdog stops
 * the run after config.stall_limit (1 s here) instead of the time limit
 * (600 s), names the procedure in flight, and gives up on the kernel after
 * the grace period.  The runtime is then unusable: every call that uses the
 * device says so.  The test's process (check forks one per test) then
 * exits normally: with the runtime's command queue held, Intel's runtime
 * made exit() wait for the stuck kernel forever. */
static void stuck_procedure(perma_technique technique)
{
    perma_config config;
    perma_config_init(&config);
    config.schedule.technique = technique;
    config.stall_limit = 1.0;
    perma_runtime *rt = test_runtime_config(&config);
    perma_proc f, s;
    uint32_t release[1] = { 0 };
    add_stuck_procedures(rt, 0, &f, &s, release);
    ck_assert_perma_ok(rt, perma_build(rt));
    seed_stuck_run(rt, f);
    double start = perma_test_now();
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_TIMEOUT);
    double seconds = perma_test_now() - start;
    ck_assert_contains(perma_errmsg(rt), "no item completed for 1 s (config.stall_limit): procedure 'stuck' "
                                         "(1 work-group) had items in flight (a procedure that never returns?)");
    ck_assert_contains(perma_errmsg(rt), "the kernel did not stop within 10 s after being told to; this runtime "
                                         "can no longer be used");
    ck_assert_msg(seconds < 25.0, "the stall took %.1f s to end the run", seconds);
    ck_assert_int_eq(perma_seed(rt, f, release, 1), PERMA_ERR_STATE);
    ck_assert_contains(perma_errmsg(rt), "perma_seed: a previous run's kernel did not stop");
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_STATE);
    ck_assert_contains(perma_errmsg(rt), "perma_run: a previous run's kernel did not stop");
    ck_assert_ptr_null(perma_cl_queue(rt)); /* released: see stuck_kernel_lets_the_process_exit */
    perma_destroy(rt); /* returns; the stuck kernel spins until the test process exits */
}

START_TEST(stuck_procedure_megakernel)
{
    stuck_procedure(PERMA_TECHNIQUE_MEGAKERNEL);
}
END_TEST

START_TEST(stuck_procedure_kernel_per_procedure)
{
    stuck_procedure(PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE);
}
END_TEST

/* Issue 23.7: after the watchdog gave up on a stuck kernel, the process
 * must still exit, promptly and with its status and its buffered output:
 * Intel's runtime used to wait in its exit handler for the runtime's
 * command queue, forever.  The stuck run happens in a child process (one
 * that has not set up OpenCL may fork), which reports when perma_destroy
 * returned and then returns from its work with exit(3). */
START_TEST(stuck_kernel_lets_the_process_exit)
{
    int report[2];
    ck_assert_int_eq(pipe(report), 0);
    pid_t child = fork();
    ck_assert_int_ge(child, 0);
    if (child == 0) {
        close(report[0]);
        perma_config config;
        perma_config_init(&config);
        config.stall_limit = 1.0;
        perma_runtime *rt = NULL;
        perma_proc f, s;
        uint32_t release[1] = { 0 };
        if (perma_create(&config, &rt, NULL) != PERMA_OK)
            _exit(90);
        add_stuck_procedures(rt, 0, &f, &s, release);
        seed_stuck_run(rt, f);
        if (perma_run(rt) != PERMA_ERR_TIMEOUT || !strstr(perma_errmsg(rt), "did not stop"))
            _exit(91);
        perma_destroy(rt);
        printf("buffered output of the child\n"); /* stdout is a pipe here: buffered until exit */
        char done = 'd';
        if (write(report[1], &done, 1) != 1)
            _exit(92);
        exit(3);
    }
    close(report[1]);
    char done = 0;
    ck_assert_int_eq(read(report[0], &done, 1), 1); /* the run takes the 1 s stall limit and the 10 s grace */
    close(report[0]);
    double start = perma_test_now();
    int status = 0;
    pid_t ended = 0;
    while ((ended = waitpid(child, &status, WNOHANG)) == 0 && perma_test_now() - start < 20.0) {
        const struct timespec pause = { 0, 20000000 };
        nanosleep(&pause, NULL);
    }
    if (ended == 0) {
        kill(child, SIGKILL);
        waitpid(child, &status, 0);
        ck_abort_msg("the process had not exited 20 s after perma_destroy of a runtime whose kernel never ended");
    }
    ck_assert_msg(WIFEXITED(status) && WEXITSTATUS(status) == 3, "the process ended with status %d", status);
    ck_assert_msg(perma_test_now() - start < 5.0, "exit took %.1f s", perma_test_now() - start);
}
END_TEST

/* A procedure whose loop polls perma_stop_requested ends when the
 * watchdog stops the run: the run fails with the stall error, the kernel
 * is not given up on, and the runtime runs the next work. */
static void cooperative_stop(perma_technique technique)
{
    perma_config config;
    perma_config_init(&config);
    config.schedule.technique = technique;
    config.stall_limit = 1.0;
    perma_runtime *rt = test_runtime_config(&config);
    perma_proc f, s;
    uint32_t release[1] = { 0 };
    add_stuck_procedures(rt, 1, &f, &s, release);
    seed_stuck_run(rt, f);
    double start = perma_test_now();
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_TIMEOUT);
    double seconds = perma_test_now() - start;
    ck_assert_contains(perma_errmsg(rt), "no item completed for 1 s (config.stall_limit): procedure 'stuck' "
                                         "(1 work-group) had items in flight");
    ck_assert_contains(perma_errmsg(rt), "; the run was stopped");
    ck_assert_msg(!strstr(perma_errmsg(rt), "did not stop"), "given up on: %s", perma_errmsg(rt));
    ck_assert_msg(seconds < 10.0, "the stall took %.1f s to end the run", seconds);
    /* Usable: 100 items of which none is 0, so nothing gets stuck. */
    uint32_t values[100];
    for (unsigned i = 0; i < 100; ++i)
        values[i] = i + 1;
    ck_assert_perma_ok(rt, perma_seed(rt, f, values, 100));
    ck_assert_perma_ok(rt, perma_run(rt));
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, f, &ps));
    ck_assert_uint_eq(ps.items, 100);
    perma_destroy(rt);
}

START_TEST(cooperative_stop_megakernel)
{
    cooperative_stop(PERMA_TECHNIQUE_MEGAKERNEL);
}
END_TEST

START_TEST(cooperative_stop_kernel_per_procedure)
{
    cooperative_stop(PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE);
}
END_TEST

/* A tree whose root has FANOUT children and whose other nodes have 2,
 * down to depth 4: 1 + FANOUT + 2 FANOUT + 4 FANOUT + 8 FANOUT nodes.
 * FANOUT comes from the build options (run_fanout). */
static const char *fanout_types = "struct fan { uint depth; uint pad; };\n";
static const char *fanout_source =
    "void node(perma_ctx *ctx, __local const struct fan *n)\n"
    "{\n"
    "    atomic_inc(&ctx->buf.nodes[0]);\n"
    "    struct fan child = { n->depth + 1u, 0u };\n"
    "    uint children = n->depth == 0u ? FANOUT : n->depth < 4u ? 2u : 0u;\n"
    "    for (uint i = 0; i < children; ++i)\n"
    "        emit_node(ctx, &child);\n"
    "}\n"
    "void root(perma_ctx *ctx, __local const struct fan *n) { node(ctx, n); }\n";

/* How a fan-out run is set up: the root's children (and what the
 * procedure that runs the root declares), items per work-item, and the
 * caps on queue memory and __local memory (0: the defaults). */
typedef struct fanout_case {
    const char *root_name; /* "node": one procedure for all; "root": a separate one */
    unsigned fanout;
    unsigned items_per_work_item;
    size_t queue_capacity;
    size_t queue_memory_limit;
    size_t local_memory_limit;
} fanout_case;

static perma_config fanout_config(const fanout_case *c, char *options, size_t size)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = 64;
    config.time_limit = 120;
    config.items_per_work_item = c->items_per_work_item;
    config.queue_capacity = c->queue_capacity;
    config.queue_memory_limit = c->queue_memory_limit;
    config.local_memory_limit = c->local_memory_limit;
    snprintf(options, size, "-DFANOUT=%uu", c->fanout);
    config.build_options = options;
    return config;
}

/* The __local memory a group of the fan-out runtime may use: the device's,
 * or a lower cap (PERMA_LOCAL_MEMORY_LIMIT, under which the suite also runs
 * this test). */
static size_t fanout_local_memory(void)
{
    fanout_case c = { "node", 2, 0, 0, 0, 0 };
    char options[64];
    perma_config config = fanout_config(&c, options, sizeof options);
    perma_runtime *rt = test_runtime_config(&config);
    size_t bytes = 0;
    ck_assert_perma_ok(rt, perma_get_local_memory(rt, &bytes));
    perma_destroy(rt);
    return bytes;
}

/* Run the fan-out tree of case `c`; the statistics of `node` and what
 * perma_print_stats printed. */
static void run_fanout(const fanout_case *c, perma_procedure_stats *node_stats, char **printed)
{
    char options[64];
    perma_config config = fanout_config(c, options, sizeof options);
    perma_runtime *rt = test_runtime_config(&config);
    bool separate = strcmp(c->root_name, "root") == 0;
    ck_assert_perma_ok(rt, perma_add_source(rt, fanout_types, "fan_types.cl"));
    perma_procedure node = { .name = "node", .item_type = "struct fan", .item_size = 8, .function = "node",
                             .source = fanout_source, .source_file = "fan.cl",
                             .emits = { { "node", separate ? 2 : c->fanout } } };
    perma_proc node_id, root_id;
    ck_assert_perma_ok(rt, perma_register(rt, &node, &node_id));
    root_id = node_id;
    if (separate) {
        perma_procedure root = node;
        root.name = root.function = "root";
        root.emits[0].max_items = c->fanout;
        ck_assert_perma_ok(rt, perma_register(rt, &root, &root_id));
    }
    uint32_t nodes[1] = { 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "nodes", "__global uint *", nodes, sizeof nodes, PERMA_READ_WRITE));
    struct { uint32_t depth, pad; } top = { 0, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, root_id, &top, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(nodes[0], 1 + 15 * c->fanout);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, node_id, node_stats));
    size_t size;
    FILE *out = open_memstream(printed, &size);
    perma_print_stats(rt, out);
    fclose(out);
    perma_destroy(rt);
}

/* `wide` items (8 bytes) each emit `emits` leaves of `leaf_size` bytes into
 * `leaf`, declaring `declared`; `count` of them seeded, a queue memory
 * limit (0: the default), one item per work-item per batch or the default
 * (0).  The statistics of `wide` and what perma_print_stats printed. */
#define WIDE_SOURCE                                                          \
    "struct wide { uint emits; uint pad; };\n"                               \
    "void wide(perma_ctx *ctx, __local const struct wide *w)\n"              \
    "{\n"                                                                    \
    "    struct leaf l = { 0 };\n"                                           \
    "    for (uint i = 0; i < w->emits; ++i)\n"                              \
    "        emit_leaf(ctx, &l);\n"                                          \
    "}\n"                                                                    \
    "void leaf(perma_ctx *ctx, __local const struct leaf *l) { atomic_inc(&ctx->buf.leaves[0]); }\n"
static void run_wide(unsigned declared, unsigned leaf_size, unsigned emits, unsigned count, size_t memory_limit,
                     unsigned items_per_work_item, perma_procedure_stats *wide_stats, char **printed)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = 64;
    config.time_limit = 120;
    config.queue_memory_limit = memory_limit;
    config.items_per_work_item = items_per_work_item;
    perma_runtime *rt = test_runtime_config(&config);
    char types[64];
    snprintf(types, sizeof types, "struct leaf { uint w[%u]; };\n", leaf_size / 4);
    ck_assert_perma_ok(rt, perma_add_source(rt, types, "leaf_types.cl"));
    perma_procedure w = { .name = "wide", .item_type = "struct wide", .item_size = 8, .function = "wide",
                          .source = WIDE_SOURCE, .source_file = "wide.cl", .emits = { { "leaf", declared } } };
    perma_procedure l = { .name = "leaf", .item_type = "struct leaf", .item_size = leaf_size, .function = "leaf",
                          .source = WIDE_SOURCE, .source_file = "wide.cl" };
    perma_proc wide_id, leaf_id;
    ck_assert_perma_ok(rt, perma_register(rt, &w, &wide_id));
    ck_assert_perma_ok(rt, perma_register(rt, &l, &leaf_id));
    uint32_t leaves[1] = { 0 };
    ck_assert_perma_ok(rt, perma_bind_host(rt, "leaves", "__global uint *", leaves, sizeof leaves, PERMA_READ_WRITE));
    struct { uint32_t emits, pad; } *seeds = calloc(count, sizeof *seeds);
    for (unsigned i = 0; i < count; ++i)
        seeds[i].emits = emits;
    ck_assert_perma_ok(rt, perma_seed(rt, wide_id, seeds, count));
    free(seeds);
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(leaves[0], count * emits);
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, wide_id, wide_stats));
    size_t size;
    FILE *out = open_memstream(printed, &size);
    perma_print_stats(rt, out);
    fclose(out);
    perma_destroy(rt);
}

/* A batch reserves room for the emits its items are expected to make (the
 * mean so far), not for the declared maximum, and stages them in global
 * memory: one procedure for root and nodes that declares the root's 1000
 * children for every node runs full batches, even under a small cap on
 * __local memory.  What still cuts batches is
 * said, naming the declaration: staging the declared maximum of a full
 * batch beyond what a group may stage (4096 emits of 64 bytes per item),
 * and expected emits that do not fit a queue the memory limit keeps small
 * (1000 real emits per item). */
START_TEST(cut_batches_are_explained)
{
    perma_procedure_stats ps;
    char *printed = NULL;
    /* 4 x 64 items of 8 bytes, each declaring 1000 emits (2 MB of staging
     * for a full batch, in global memory), under a cap of 128 KiB of
     * __local memory: full batches. */
    fanout_case by_memory = { "node", 1000, 0, 0, 0, 128 * 1024 };
    ck_assert_uint_ge(fanout_local_memory(), 16 * 1024);
    run_fanout(&by_memory, &ps, &printed);
    ck_assert_int_eq(ps.batch_cut, PERMA_BATCH_FULL);
    ck_assert_uint_eq(ps.batch_size, 4 * 64);
    ck_assert_uint_ge(ps.items, ps.batches * 16);
    ck_assert_msg(strstr(printed, "warning") == NULL, "unexpected warning: %s", printed);
    free(printed);

    printed = NULL;
    run_wide(4096, 64, 1, 1000, 0, 0, &ps, &printed);
    ck_assert_int_eq(ps.batch_cut, PERMA_BATCH_CUT_STAGING);
    ck_assert_int_eq(ps.batch_cut_emit, 0);
    ck_assert_uint_lt(ps.batch_size, 4 * 64);
    ck_assert_contains(printed, "warning: procedure 'wide' runs at most ");
    ck_assert_contains(printed, ".emits[0] (up to 4096 items of 64 bytes into 'leaf' per item) needs 262144 bytes "
                                "of staging per item");
    ck_assert_contains(printed, "a separate procedure");
    free(printed);

    /* The leaf queue may hold at most 16384 items of 8 bytes and two
     * completion marks beside the wide queue's 1024: full batches of 64
     * wide items would need room for 64000. */
    printed = NULL;
    run_wide(1000, 8, 1000, 512, (size_t)16384 * 16 + 1024 * 16, 1, &ps, &printed);
    ck_assert_int_eq(ps.batch_cut_emit, 0);
    ck_assert_int_eq(ps.batch_cut, PERMA_BATCH_CUT_ROOM);
    ck_assert_uint_eq(ps.batch_size, 64);
    ck_assert_uint_lt(ps.items, ps.batches * 32);
    ck_assert_contains(printed, "warning: procedure 'wide' ran batches of ");
    ck_assert_contains(printed, "instead of up to 64: a full batch reserves room for the emits it is expected to "
                                "make (1000.0 per item into 'leaf'");
    ck_assert_contains(printed, "config.queue_memory_limit");
    free(printed);

    /* The fix: only the root promises 1000 children; node's full batches of
     * 4 x 64 items stage 2 emits each (8 KiB). */
    fanout_case separate = { "root", 1000, 0, 0, 0, 0 };
    printed = NULL;
    run_fanout(&separate, &ps, &printed);
    ck_assert_int_eq(ps.batch_cut, PERMA_BATCH_FULL);
    ck_assert_int_eq(ps.batch_cut_emit, -1);
    ck_assert_uint_eq(ps.batch_size, 4 * 64);
    ck_assert_uint_ge(ps.items, ps.batches * 32);
    ck_assert_msg(strstr(printed, "warning") == NULL, "unexpected warning: %s", printed);
    free(printed);
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

int main(void)
{
    Suite *s = suite_create("errors");
    TCase *tc = tcase_create("errors");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, bad_registration_fields);
    tcase_add_test(tc, no_procedures_is_a_state_error);
    tcase_add_test(tc, syntax_error_names_file_and_line);
    tcase_add_test(tc, item_size_mismatch_is_a_build_error);
    tcase_add_test(tc, barrier_in_a_non_cooperative_procedure);
    tcase_add_test(tc, compiler_warnings_are_shown);
    tcase_add_test(tc, unknown_emit_target);
    tcase_add_test(tc, function_missing_from_its_source);
    tcase_add_test(tc, cycle_without_priority_order);
    tcase_add_test(tc, missing_device_from_environment);
    tcase_add_test(tc, no_platform_names_the_package);
    tcase_add_test(tc, driver_that_does_not_load_is_named);
    tcase_add_test(tc, bad_config_values);
    tcase_add_test(tc, emitting_beyond_the_declared_maximum);
    tcase_add_test(tc, emitting_into_an_undeclared_target);
    tcase_add_test(tc, watchdog_stops_an_endless_run);
    tcase_add_test(tc, stuck_procedure_megakernel);
    tcase_add_test(tc, stuck_procedure_kernel_per_procedure);
    tcase_add_test(tc, stuck_kernel_lets_the_process_exit);
    tcase_add_test(tc, cooperative_stop_megakernel);
    tcase_add_test(tc, cooperative_stop_kernel_per_procedure);
    tcase_add_test(tc, debug_mode);
    tcase_add_test(tc, cut_batches_are_explained);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
