/* Fault injection: every OpenCL call perma makes is made to fail in turn
 * (tests/fault/cl_fault.c).  Each failure must come back as a status whose
 * message names the failing call, never a crash or a hang; a runtime whose
 * run failed must run again correctly; and no memory is leaked (the
 * sanitize suite runs this test under AddressSanitizer). */
#include "perma_test.h"
#include "tree_procedure.h"
#include "cl_fault.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

enum { DEPTH = 9 };

typedef struct scenario {
    perma_technique technique;
    size_t capacity;        /* small: the run grows its queues */
} scenario;

static const scenario scenarios[] = {
    { PERMA_TECHNIQUE_MEGAKERNEL, 8 },
    { PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE, 8 },
};

typedef struct outcome {
    perma_status status;
    char message[PERMA_MESSAGE_MAX];
    bool failed_in_run;
    const char *failed_call; /* the call the shim failed, before any retry */
} outcome;

/* Create, register, bind, seed, run the tree; stop at the first failure.
 * On a failure inside perma_run, disarm and run again: it must succeed. */
static outcome run_tree(const scenario *sc)
{
    outcome out = { PERMA_OK, "", false, NULL };
    perma_config config;
    perma_config_init(&config);
    config.schedule.technique = sc->technique;
    config.queue_capacity = sc->capacity;
    config.time_limit = 60;
    perma_runtime *rt = NULL;
    perma_error error;
    out.status = perma_create(&config, &rt, &error);
    out.failed_call = cl_fault_failed_call();
    if (out.status != PERMA_OK) {
        snprintf(out.message, sizeof out.message, "%s", error.message);
        ck_assert_ptr_null(rt);
        return out;
    }
    uint32_t counts[2] = { 0, 0 };
    uint64_t sums[1] = { 0 };
    perma_procedure tree = { .name = "tree", .item_type = "struct tree_node", .item_size = sizeof(struct tree_node),
                             .source = TREE_SOURCE, .function = "tree_split", .emits = { { "tree", 2 } } };
    perma_proc id = 0;
    struct tree_node root = { 0, DEPTH, 1, 0 };
    if ((out.status = perma_add_source(rt, TREE_TYPES, "tree_types.cl")) == PERMA_OK &&
        (out.status = perma_register(rt, &tree, &id)) == PERMA_OK &&
        (out.status = perma_bind_host(rt, "counts", "__global uint *", counts, sizeof counts, PERMA_READ_WRITE)) == PERMA_OK &&
        (out.status = perma_bind_host(rt, "sums", "__global ulong *", sums, sizeof sums, PERMA_READ_WRITE)) == PERMA_OK &&
        (out.status = perma_seed(rt, id, &root, 1)) == PERMA_OK) {
        out.status = perma_run(rt);
        out.failed_in_run = out.status != PERMA_OK;
        if (out.status == PERMA_OK)
            ck_assert_uint_eq(counts[0], 1u << DEPTH);
    }
    snprintf(out.message, sizeof out.message, "%s", perma_errmsg(rt));
    out.failed_call = cl_fault_failed_call();
    if (out.failed_in_run) {
        cl_fault_arm(0);
        memset(counts, 0, sizeof counts);
        ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
        ck_assert_perma_ok(rt, perma_run(rt));
        ck_assert_uint_eq(counts[0], 1u << DEPTH);
        ck_assert_uint_eq(counts[1], (1u << DEPTH) - 1);
    }
    perma_destroy(rt);
    return out;
}

START_TEST(every_opencl_call_failing_is_reported)
{
    const scenario *sc = &scenarios[_i];
    cl_fault_arm(0);
    outcome clean = run_tree(sc);
    ck_assert_msg(clean.status == PERMA_OK, "clean run: %s", clean.message);
    unsigned long total = cl_fault_calls();
    ck_assert_uint_gt(total, 20);
    unsigned runs_recovered = 0, never_reached = 0;
    for (unsigned long k = 1; k <= total; ++k) {
        cl_fault_arm(k);
        outcome out = run_tree(sc);
        const char *call = out.failed_call;
        if (call == NULL) {
            /* The watchdog polls the kernel's event a timing-dependent number
             * of times, so a run may end before call k: it must succeed. */
            ck_assert_msg(out.status == PERMA_OK, "call %lu was not made, yet: %s", k, out.message);
            ++never_reached;
            continue;
        }
        ck_assert_msg(out.status != PERMA_OK, "%s (call %lu) failed but the run reported success", call, k);
        ck_assert_msg(strstr(out.message, call) != NULL, "%s (call %lu) failed; the message does not name it: %s",
                      call, k, out.message);
        runs_recovered += out.failed_in_run;
    }
    cl_fault_arm(0);
    ck_assert_uint_gt(runs_recovered, 5);
    ck_assert_uint_le(never_reached, total / 5);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("faults");
    TCase *tc = tcase_create("faults");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_loop_test(tc, every_opencl_call_failing_is_reported, 0, (int)(sizeof scenarios / sizeof scenarios[0]));
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
