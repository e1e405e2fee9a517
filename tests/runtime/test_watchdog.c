/* The watchdog (watchdog.c): an endless run and a stuck procedure end
 * with a message under every technique, the process can still exit, and a
 * procedure that polls perma_stop_requested stops cleanly. */
#include "perma_test.h"

#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

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

PERMA_TEST_MAIN("watchdog", watchdog_stops_an_endless_run, stuck_procedure_megakernel, stuck_procedure_kernel_per_procedure, stuck_kernel_lets_the_process_exit, cooperative_stop_megakernel, cooperative_stop_kernel_per_procedure)
