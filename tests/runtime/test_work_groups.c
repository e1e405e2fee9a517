/* How many persistent work-groups the runtime runs (runtime/src/device.c):
 * the residency figure alone; on this CPU the count as before (any number
 * runs); and on a pretended GPU (the fault shim answers the device and
 * kernel queries, PoCL runs the work) a count that all fit at once, said
 * in the statistics, a request for more refused before it could hang, and
 * a kernel that holds fewer groups than the layout planned built again. */
#include "cl_fault.h"
#include "device.h"
#include "perma_test.h"
#include "tree_procedure.h"

#include <stdlib.h>
#include <string.h>

#define DEPTH 10u
#define KIB 1024ul

START_TEST(residency_by_local_memory_registers_and_cap)
{
    perma_residency r;
    /* A Reyes-like kernel: 40 KiB of a GPU's 48 KiB, one group per unit. */
    perma_residency_of(132, 48 * KIB, 40 * KIB, 1024, 64, &r);
    ck_assert_uint_eq(r.per_unit, 1);
    ck_assert_uint_eq(r.limit, 132);
    ck_assert_str_eq(r.why, "132 compute units x 1, __local memory: 40960 of 49152 bytes each");
    /* 5 KiB: 9 by local memory. */
    perma_residency_of(132, 48 * KIB, 5 * KIB, 1024, 64, &r);
    ck_assert_uint_eq(r.limit, 132 * 9);
    /* Registers for 512 work-items: 8 groups of 64. */
    perma_residency_of(132, 48 * KIB, 2 * KIB, 512, 64, &r);
    ck_assert_uint_eq(r.per_unit, 8);
    ck_assert_str_eq(r.why, "132 compute units x 8, 512 work-items per compute unit (CL_KERNEL_WORK_GROUP_SIZE)");
    /* Small groups of a small kernel: the cap. */
    perma_residency_of(2, 48 * KIB, 1 * KIB, 1024, 32, &r);
    ck_assert_uint_eq(r.per_unit, PERMA_MAX_GROUPS_PER_UNIT);
    ck_assert_str_eq(r.why, "2 compute units x 16, at most 16 per compute unit");
    /* Before the kernel is known: registers and the cap only. */
    perma_residency_of(4, 48 * KIB, 0, 256, 64, &r);
    ck_assert_uint_eq(r.limit, 16);
    /* Groups larger than the kernel allows, or more __local memory than
     * the device has: not one. */
    perma_residency_of(4, 48 * KIB, 1 * KIB, 32, 64, &r);
    ck_assert_uint_eq(r.limit, 0);
    perma_residency_of(4, 48 * KIB, 49 * KIB, 1024, 64, &r);
    ck_assert_uint_eq(r.limit, 0);
}
END_TEST

/* The tree of DEPTH on rt, its root seeded; the counts arrive in *t. */
typedef struct tree_run {
    uint32_t counts[2];
    uint64_t sums[1];
} tree_run;

static void seed_tree(perma_runtime *rt, tree_run *t)
{
    memset(t, 0, sizeof *t);
    perma_proc id = tree_add(rt, 1, t->counts, t->sums);
    struct tree_node root = { 0, DEPTH, 1, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
}

/* The tree run on rt: exact counts; its statistics. */
static perma_stats run_tree(perma_runtime *rt)
{
    tree_run t;
    seed_tree(rt, &t);
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(t.counts[0], 1u << DEPTH);
    ck_assert_uint_eq(t.counts[1], (1u << DEPTH) - 1);
    perma_stats st;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &st));
    return st;
}

static perma_runtime *runtime_for(const char *schedule, unsigned work_groups)
{
    perma_config config;
    perma_config_init(&config);
    config.work_groups = work_groups;
    config.time_limit = 120;
    test_parse_schedule(schedule, &config.schedule);
    perma_runtime *rt = NULL;
    perma_error error;
    perma_status st = perma_create(&config, &rt, &error);
    ck_assert_msg(st == PERMA_OK, "perma_create: %s", error.message);
    return rt;
}

/* On a CPU the count is chosen at perma_create as before, the build keeps
 * it, and the statistics say why, with no residency limit. */
START_TEST(cpu_count_as_before)
{
    perma_runtime *rt = runtime_for("megakernel/shared", 0);
    unsigned before = 0;
    ck_assert_perma_ok(rt, perma_get_work_groups(rt, &before, NULL));
    perma_stats st = run_tree(rt);
    ck_assert_uint_eq(st.work_groups, before);
    ck_assert_uint_eq(st.resident_groups, 0);
    ck_assert_msg(strstr(st.work_groups_reason, "compute units") || strstr(st.work_groups_reason, "physical cores"),
                  "reason: %s", st.work_groups_reason);
    size_t local = 0;
    ck_assert_perma_ok(rt, perma_get_local_memory(rt, &local));
    ck_assert_uint_gt(st.kernel_local_bytes, 0);
    ck_assert_uint_le(st.kernel_local_bytes, local);
    perma_destroy(rt);
    /* More groups than compute units run on a CPU (some start late). */
    rt = runtime_for("megakernel/donation", 5);
    st = run_tree(rt);
    ck_assert_uint_eq(st.work_groups, 5);
    ck_assert_str_eq(st.work_groups_reason, "configured");
    perma_destroy(rt);
}
END_TEST

/* A pretended GPU of 3 compute units, 48 KiB of __local memory and
 * registers for 128 work-items: 2 groups of 64 per unit, 6 in all, under
 * every persistent strategy and the host-driven techniques.  Before the
 * build the count is the most any kernel could have (16 per unit), which
 * the build only lowers.  (Without work-first, whose stacks take half the
 * __local memory: gpu_work_first_leaves_room_for_two_groups.) */
static const char *const gpu_schedules[] = {
    "megakernel/shared+wf0", "megakernel/stealing+wf0", "megakernel/donation+wf0",
    "megakernel/stealing-donation+wf0", "megakernel/shared+local64+wf0", "kernel-per-procedure",
    "bounded-batches/p=100",
};

START_TEST(gpu_runs_what_fits_at_once)
{
    cl_fault_pretend_gpu(3, 48 * KIB, 128, 0);
    perma_runtime *rt = runtime_for(gpu_schedules[_i], 0);
    unsigned before = 0;
    ck_assert_perma_ok(rt, perma_get_work_groups(rt, &before, NULL));
    ck_assert_uint_eq(before, 3 * PERMA_MAX_GROUPS_PER_UNIT);
    perma_stats st = run_tree(rt);
    ck_assert_uint_eq(st.work_groups, 6);
    ck_assert_uint_eq(st.resident_groups, 6);
    ck_assert_str_eq(st.work_groups_reason,
                     "3 compute units x 2, 128 work-items per compute unit (CL_KERNEL_WORK_GROUP_SIZE)");
    ck_assert_uint_le(st.kernel_local_bytes, 48 * KIB);
    ck_assert_contains(perma_device_summary(rt), "6 work-groups (3 compute units x 2");
    perma_destroy(rt);
    cl_fault_pretend_gpu(0, 0, 0, 0);
}
END_TEST

/* Work-first's stacks take at most a quarter of the __local memory a
 * group has left on a device that is not a CPU (and at most 32 items), so
 * its megakernel leaves room for two groups per unit, which the
 * registers' limit of this device allows. */
START_TEST(gpu_work_first_leaves_room_for_two_groups)
{
    cl_fault_pretend_gpu(3, 48 * KIB, 128, 0);
    perma_runtime *rt = runtime_for("megakernel/shared", 0);
    perma_stats st = run_tree(rt);
    ck_assert_uint_ge(st.stack_items, 8);
    ck_assert_uint_le(st.stack_items, 32);
    ck_assert_uint_eq(st.work_groups, 6);
    ck_assert_uint_le(st.kernel_local_bytes, 24 * KIB);
    ck_assert_str_eq(st.work_groups_reason,
                     "3 compute units x 2, 128 work-items per compute unit (CL_KERNEL_WORK_GROUP_SIZE)");
    perma_destroy(rt);
    cl_fault_pretend_gpu(0, 0, 0, 0);
}
END_TEST

/* More persistent groups than fit at once: refused with the figures,
 * before anything runs; as many as fit run.  The host-driven techniques'
 * groups do not wait for each other: any number runs. */
START_TEST(gpu_refuses_more_groups_than_fit)
{
    cl_fault_pretend_gpu(2, 48 * KIB, 64, 0);
    perma_runtime *rt = runtime_for("megakernel/donation", 3);
    tree_run t;
    seed_tree(rt, &t);
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "config.work_groups 3 is more persistent work-groups than");
    ck_assert_contains(perma_errmsg(rt), "holds at once for this program (2: 2 compute units x 1, 64 work-items per "
                                         "compute unit (CL_KERNEL_WORK_GROUP_SIZE)); groups that are not all running "
                                         "could wait for each other forever: ask for at most 2");
    ck_assert_uint_eq(t.counts[0], 0);
    perma_destroy(rt);
    rt = runtime_for("megakernel/donation", 2);
    ck_assert_uint_eq(run_tree(rt).work_groups, 2);
    perma_destroy(rt);
    rt = runtime_for("kernel-per-procedure", 3);
    perma_stats st = run_tree(rt);
    ck_assert_uint_eq(st.work_groups, 3);
    ck_assert_uint_eq(st.resident_groups, 2);
    perma_destroy(rt);
    cl_fault_pretend_gpu(0, 0, 0, 0);
}
END_TEST

/* The compiled kernel uses more __local memory than the layout's figure
 * (20 KiB of 48: 2 per unit where the layout planned 16): the runtime
 * lowers the count and builds again, and the run is right. */
START_TEST(gpu_builds_again_for_fewer_groups)
{
    cl_fault_pretend_gpu(3, 48 * KIB, 1024, 20 * KIB);
    perma_runtime *rt = runtime_for("megakernel/stealing+wf0", 0);
    perma_stats st = run_tree(rt);
    ck_assert_uint_eq(st.work_groups, 6);
    ck_assert_str_eq(st.work_groups_reason, "3 compute units x 2, __local memory: 20480 of 49152 bytes each");
    perma_destroy(rt);
    cl_fault_pretend_gpu(0, 0, 0, 0);
}
END_TEST

/* The program built for the count the layout planned is stored in the
 * program cache; with one queue set (and staging the count does not cut)
 * the build for the lower count is the same program, loaded from there. */
START_TEST(gpu_builds_again_from_the_cache)
{
    char dir[] = "/tmp/perma-work-groups-cache.XXXXXX";
    ck_assert_ptr_nonnull(mkdtemp(dir));
    setenv("PERMA_CACHE_DIR", dir, 1);
    setenv("PERMA_CACHE_MIN_SECONDS", "0", 1);
    cl_fault_pretend_gpu(3, 48 * KIB, 1024, 20 * KIB);
    perma_runtime *rt = runtime_for("megakernel/shared+wf0", 0);
    ck_assert_uint_eq(run_tree(rt).work_groups, 6);
    perma_build_info info;
    ck_assert_perma_ok(rt, perma_get_build_info(rt, &info));
    ck_assert_int_eq(info.origin, PERMA_PROGRAM_CACHED);
    perma_destroy(rt);
    cl_fault_pretend_gpu(0, 0, 0, 0);
    unsetenv("PERMA_CACHE_DIR");
    unsetenv("PERMA_CACHE_MIN_SECONDS");
    char command[128];
    snprintf(command, sizeof command, "rm -rf %s", dir);
    ck_assert_int_eq(system(command), 0);
}
END_TEST

/* A kernel whose registers do not allow one group, or that uses more
 * __local memory than a group may: refused, saying which figure. */
START_TEST(gpu_kernel_that_cannot_run)
{
    cl_fault_pretend_gpu(2, 48 * KIB, 32, 0);
    perma_runtime *rt = runtime_for("megakernel/shared", 0);
    tree_run t;
    seed_tree(rt, &t);
    ck_assert_int_eq(perma_build(rt), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "the megakernel can run work-groups of at most 32 work-items on");
    ck_assert_contains(perma_errmsg(rt), "fewer than the group_size 64: set config.group_size to at most 32");
    perma_destroy(rt);
    cl_fault_pretend_gpu(2, 48 * KIB, 1024, 50 * KIB);
    rt = runtime_for("megakernel/shared", 0);
    seed_tree(rt, &t);
    ck_assert_int_eq(perma_build(rt), PERMA_ERR_BUILD);
    ck_assert_contains(perma_errmsg(rt), "the megakernel uses 51200 bytes of __local memory per work-group, more "
                                         "than the 49152 bytes a group may use on");
    ck_assert_contains(perma_errmsg(rt), "(CL_DEVICE_LOCAL_MEM_SIZE)");
    perma_destroy(rt);
    cl_fault_pretend_gpu(0, 0, 0, 0);
}
END_TEST

int main(void)
{
    Suite *suite = suite_create("work_groups");
    TCase *tc = tcase_create("work_groups");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, residency_by_local_memory_registers_and_cap);
    tcase_add_test(tc, cpu_count_as_before);
    tcase_add_loop_test(tc, gpu_runs_what_fits_at_once, 0, (int)(sizeof gpu_schedules / sizeof *gpu_schedules));
    tcase_add_test(tc, gpu_work_first_leaves_room_for_two_groups);
    tcase_add_test(tc, gpu_refuses_more_groups_than_fit);
    tcase_add_test(tc, gpu_builds_again_for_fewer_groups);
    tcase_add_test(tc, gpu_builds_again_from_the_cache);
    tcase_add_test(tc, gpu_kernel_that_cannot_run);
    suite_add_tcase(suite, tc);
    return test_run_suite(suite) ? EXIT_FAILURE : EXIT_SUCCESS;
}
