/* Building the program (program.c, build_log.c, abi.c, barriers.c):
 * compile errors and warnings with the user's file and line, barriers in
 * procedures not declared cooperative, item sizes the device disagrees
 * with. */
#include "perma_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

    build_with_log("noop", test_noop_procedure().source, log);
    ck_assert_msg(log[0] == '\0', "a clean program gave: %s", log);

    /* PERMA_BUILD_LOG=1: the whole log of every build. */
    setenv("PERMA_BUILD_LOG", "1", 1);
    build_with_log("noop", test_noop_procedure().source, log);
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
    perma_procedure p = test_noop_procedure();
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

PERMA_TEST_MAIN("build_errors", syntax_error_names_file_and_line, barrier_in_a_non_cooperative_procedure, compiler_warnings_are_shown, item_size_mismatch_is_a_build_error)
