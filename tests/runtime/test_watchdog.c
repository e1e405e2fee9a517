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
 * with `stop_condition`, until the watchdog asks the run to stop. */
#define STUCK_SOURCE(stop_condition)                                                                             \
    "void fine(perma_ctx *ctx, __local const uint *x) { if (*x == 0u) { uint v = 1u; emit_stuck(ctx, &v); } }\n" \
    "void stuck(perma_ctx *ctx, __local const uint *x)\n"                                                        \
    "{\n"                                                                                                        \
    "    while (atomic_add(&ctx->buf.release[0], 0u) == 0u" stop_condition ")\n"                                 \
    "        ;\n"                                                                                                \
    "    (void)x;\n"                                                                                             \
    "}\n"

/* The start of the watchdog's message when the stuck item holds the run. */
#define STUCK_STALL_MESSAGE \
    "no item completed for 1 s (config.stall_limit): procedure 'stuck' (1 work-group) had items in flight"

/* The configuration of the stuck runs: a stall limit of 1 s. */
static perma_config stuck_config(perma_technique technique)
{
    perma_config config;
    perma_config_init(&config);
    config.schedule.technique = technique;
    config.stall_limit = 1.0;
    return config;
}

/* A run that gets stuck: `release` is bound as ctx->buf.release and the
 * host never sets it; `fine` is the procedure seeded. */
typedef struct stuck_run {
    perma_proc fine;
    uint32_t release[1];
} stuck_run;

/* Register the stuck procedures on `rt` (polling perma_stop_requested if
 * `cooperative`), build, and seed 99 items that complete and one that
 * emits the stuck item.  Returns the first failure (message in
 * perma_errmsg(rt)); `run` must outlive the runs of `rt`. */
static perma_status set_up_stuck_run(perma_runtime *rt, bool cooperative, stuck_run *run)
{
    perma_procedure fine = {
        .name = "fine", .item_type = "uint", .item_size = 4, .source_file = "stuck.cl", .function = "fine",
        .source = cooperative ? STUCK_SOURCE(" && !perma_stop_requested(ctx)") : STUCK_SOURCE(""),
        .emits = { { "stuck", 1 } },
    };
    perma_procedure stuck = fine;
    stuck.name = stuck.function = "stuck";
    memset(stuck.emits, 0, sizeof stuck.emits);
    perma_proc stuck_id;
    run->release[0] = 0;
    uint32_t values[100] = { 0 };
    for (unsigned i = 1; i < 100; ++i)
        values[i] = i;
    perma_status st = perma_register(rt, &fine, &run->fine);
    if (st == PERMA_OK)
        st = perma_register(rt, &stuck, &stuck_id);
    if (st == PERMA_OK)
        st = perma_bind_host(rt, "release", "__global uint *", run->release, sizeof(uint32_t), PERMA_READ);
    if (st == PERMA_OK)
        st = perma_build(rt);
    if (st == PERMA_OK)
        st = perma_seed(rt, run->fine, values, 100);
    return st;
}

/* A runtime under `technique` whose run the stuck item held until the
 * watchdog stopped it: the run failed with the stall error, after
 * *seconds. */
static perma_runtime *stalled_runtime(perma_technique technique, bool cooperative, stuck_run *run, double *seconds)
{
    perma_config config = stuck_config(technique);
    perma_runtime *rt = test_runtime_config(&config);
    ck_assert_perma_ok(rt, set_up_stuck_run(rt, cooperative, run));
    double start = perma_test_now();
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_TIMEOUT);
    *seconds = perma_test_now() - start;
    ck_assert_contains(perma_errmsg(rt), STUCK_STALL_MESSAGE);
    return rt;
}

/* The grace period a stuck kernel gets here (PERMA_STOP_GRACE; 10 s by
 * default): it never stops, so a shorter one only ends the test sooner. */
#define STUCK_GRACE "2"

/* A procedure that never returns: nothing completes, so the watchdog stops
 * the run after config.stall_limit (1 s here) instead of the time limit
 * (600 s), names the procedure in flight, and gives up on the kernel after
 * the grace period (STUCK_GRACE s).  The runtime is then unusable: every call that uses the
 * device says so.  The test's process (check forks one per test) then
 * exits normally: with the runtime's command queue held, Intel's runtime
 * made exit() wait for the stuck kernel forever. */
static void stuck_procedure(perma_technique technique)
{
    stuck_run run;
    double seconds;
    setenv("PERMA_STOP_GRACE", STUCK_GRACE, 1); /* check runs each test in a process of its own */
    perma_runtime *rt = stalled_runtime(technique, false, &run, &seconds);
    ck_assert_contains(perma_errmsg(rt), STUCK_STALL_MESSAGE " (a procedure that never returns?)");
    ck_assert_contains(perma_errmsg(rt), "the kernel did not stop within " STUCK_GRACE " s after being told to; "
                                         "this runtime can no longer be used");
    ck_assert_msg(seconds >= 1.0 + atof(STUCK_GRACE), "the run was given up after %.1f s, before the stall "
                  "limit and the grace period had passed", seconds);
    ck_assert_msg(seconds < 15.0, "the stall took %.1f s to end the run", seconds);
    ck_assert_int_eq(perma_seed(rt, run.fine, run.release, 1), PERMA_ERR_STATE);
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

/* After the watchdog gave up on a stuck kernel, the process
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
        setenv("PERMA_STOP_GRACE", STUCK_GRACE, 1);
        perma_config config = stuck_config(PERMA_TECHNIQUE_MEGAKERNEL);
        perma_runtime *rt = NULL;
        stuck_run run;
        if (perma_create(&config, &rt, NULL) != PERMA_OK || set_up_stuck_run(rt, false, &run) != PERMA_OK)
            _exit(90);
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
    ck_assert_int_eq(read(report[0], &done, 1), 1); /* the run takes the 1 s stall limit and the grace */
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
    stuck_run run;
    double seconds;
    perma_runtime *rt = stalled_runtime(technique, true, &run, &seconds);
    ck_assert_contains(perma_errmsg(rt), "; the run was stopped");
    ck_assert_msg(!strstr(perma_errmsg(rt), "did not stop"), "given up on: %s", perma_errmsg(rt));
    ck_assert_msg(seconds < 10.0, "the stall took %.1f s to end the run", seconds);
    /* Usable: 100 items of which none is 0, so nothing gets stuck. */
    uint32_t values[100];
    for (unsigned i = 0; i < 100; ++i)
        values[i] = i + 1;
    ck_assert_perma_ok(rt, perma_seed(rt, run.fine, values, 100));
    ck_assert_perma_ok(rt, perma_run(rt));
    perma_procedure_stats ps;
    ck_assert_perma_ok(rt, perma_get_procedure_stats(rt, run.fine, &ps));
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
