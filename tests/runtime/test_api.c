/* The public API's promises that hold for every call: the message of
 * perma_errmsg, checked out pointers, the program's own OpenCL target
 * version, and the work-group count known before the first run. */

/* A program that targets another OpenCL version says so before including
 * perma.h (the project's build defines 120 for its own sources). */
#undef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 200
#include "perma_test.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *count_source =
    "void count(perma_ctx *ctx, __local const uint *x)\n"
    "{\n"
    "    atomic_add(&ctx->buf.per_group[min(ctx->group, ctx->buf.groups[0])], *x);\n"
    "}\n";

static perma_procedure count_procedure(void)
{
    perma_procedure p = { .name = "count", .item_type = "uint", .item_size = 4, .source = count_source,
                          .source_file = "count.cl", .function = "count" };
    return p;
}

START_TEST(opencl_target_version_is_the_programs)
{
    ck_assert_int_eq(CL_TARGET_OPENCL_VERSION, 200);
}
END_TEST

/* Make the last call fail, so that a call that succeeds must clear it. */
static void fail_once(perma_runtime *rt)
{
    perma_proc id;
    ck_assert_int_eq(perma_find(rt, "nope", &id), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "no procedure named 'nope'");
}

#define EXPECT_CLEARED(rt, call)                                                                    \
    do {                                                                                            \
        fail_once(rt);                                                                              \
        ck_assert_perma_ok(rt, call);                                                               \
        ck_assert_msg(perma_errmsg(rt)[0] == '\0', "%s left the message '%s'", #call, perma_errmsg(rt)); \
    } while (0)

START_TEST(errmsg_is_empty_after_every_successful_call)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = count_procedure();
    perma_proc id, found;
    uint32_t per_group[65] = { 0 }, groups[1] = { 64 }, items[3] = { 1, 2, 3 };
    EXPECT_CLEARED(rt, perma_add_source(rt, "/* nothing */", "empty.cl"));
    EXPECT_CLEARED(rt, perma_register(rt, &p, &id));
    EXPECT_CLEARED(rt, perma_find(rt, "count", &found));
    ck_assert_int_eq(found, id);
    EXPECT_CLEARED(rt, perma_bind_host(rt, "per_group", "__global uint *", per_group, sizeof per_group,
                                       PERMA_READ_WRITE));
    cl_int err;
    cl_mem groups_mem = clCreateBuffer(perma_cl_context(rt), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof groups,
                                       groups, &err);
    ck_assert_int_eq(err, CL_SUCCESS);
    EXPECT_CLEARED(rt, perma_bind_cl(rt, "groups", "__global const uint *", groups_mem));
    clReleaseMemObject(groups_mem);
    EXPECT_CLEARED(rt, perma_seed(rt, id, items, 3));
    EXPECT_CLEARED(rt, perma_seed(rt, id, items, 0));
    EXPECT_CLEARED(rt, perma_build(rt));
    EXPECT_CLEARED(rt, perma_build(rt)); /* already built */
    EXPECT_CLEARED(rt, perma_run(rt));
    uint32_t total = 0;
    for (unsigned g = 0; g < 65; ++g)
        total += per_group[g];
    ck_assert_uint_eq(total, 6);
    perma_stats stats;
    perma_procedure_stats ps;
    perma_group_stats gs;
    unsigned work_groups;
    EXPECT_CLEARED(rt, perma_get_stats(rt, &stats));
    EXPECT_CLEARED(rt, perma_get_procedure_stats(rt, id, &ps));
    EXPECT_CLEARED(rt, perma_get_group_stats(rt, 0, &gs));
    EXPECT_CLEARED(rt, perma_get_work_groups(rt, &work_groups, NULL));
    size_t local_bytes;
    EXPECT_CLEARED(rt, perma_get_local_memory(rt, &local_bytes));
    perma_destroy(rt);
}
END_TEST

START_TEST(out_pointers_are_checked)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    perma_procedure p = count_procedure();
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    ck_assert_int_eq(perma_find(rt, "count", NULL), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "perma_find('count'): out is NULL");
    ck_assert_int_eq(perma_get_work_groups(rt, NULL, NULL), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "perma_get_work_groups: both out pointers are NULL");
    ck_assert_int_eq(perma_get_local_memory(rt, NULL), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "perma_get_local_memory: bytes is NULL");
    perma_destroy(rt);
}
END_TEST

/* The __local memory a group may use, with config.local_memory_limit and
 * PERMA_LOCAL_MEMORY_LIMIT set or not (given as `limit`, `env`; NULL:
 * unset); PERMA_ERR_ARGUMENT and the message when perma_create refuses. */
static perma_status local_memory_with(size_t limit, const char *env, size_t *bytes, perma_error *error)
{
    if (env)
        setenv("PERMA_LOCAL_MEMORY_LIMIT", env, 1);
    else
        unsetenv("PERMA_LOCAL_MEMORY_LIMIT");
    perma_config config;
    perma_config_init(&config);
    config.local_memory_limit = limit;
    perma_runtime *rt;
    perma_status st = perma_create(&config, &rt, error);
    if (st == PERMA_OK) {
        ck_assert_perma_ok(rt, perma_get_local_memory(rt, bytes));
        cl_ulong device = 0;
        ck_assert_int_eq(clGetDeviceInfo(perma_cl_device(rt), CL_DEVICE_LOCAL_MEM_SIZE, sizeof device, &device, NULL),
                         CL_SUCCESS);
        ck_assert_uint_le(*bytes, device);
        perma_destroy(rt);
    }
    return st;
}

/* The device's size, unless config.local_memory_limit or (when that is 0)
 * PERMA_LOCAL_MEMORY_LIMIT caps it lower; a malformed variable fails
 * perma_create naming it.  (The suite also runs every runtime test under
 * the variable: it is put back afterwards.) */
START_TEST(local_memory_limit_from_config_and_environment)
{
    const char *saved = getenv("PERMA_LOCAL_MEMORY_LIMIT");
    char *restore = saved ? strdup(saved) : NULL;
    size_t device, bytes;
    perma_error error;
    ck_assert_int_eq(local_memory_with(0, NULL, &device, &error), PERMA_OK);
    ck_assert_uint_ge(device, 16 * 1024);
    ck_assert_int_eq(local_memory_with(0, "", &bytes, &error), PERMA_OK);
    ck_assert_uint_eq(bytes, device);
    ck_assert_int_eq(local_memory_with(10000, NULL, &bytes, &error), PERMA_OK);
    ck_assert_uint_eq(bytes, 10000);
    ck_assert_int_eq(local_memory_with(0, "12K", &bytes, &error), PERMA_OK);
    ck_assert_uint_eq(bytes, 12 * 1024);
    ck_assert_int_eq(local_memory_with(0, "12000", &bytes, &error), PERMA_OK);
    ck_assert_uint_eq(bytes, 12000);
    ck_assert_int_eq(local_memory_with(10000, "12K", &bytes, &error), PERMA_OK); /* the config wins */
    ck_assert_uint_eq(bytes, 10000);
    ck_assert_int_eq(local_memory_with(device + 4096, NULL, &bytes, &error), PERMA_OK); /* never above the device */
    ck_assert_uint_eq(bytes, device);
    ck_assert_int_eq(local_memory_with(0, "1024M", &bytes, &error), PERMA_OK);
    ck_assert_uint_eq(bytes, device);
    static const char *const bad[] = { "12Q", "-5", "0", "K", "1.5M", "99999999999999999999" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        ck_assert_int_eq(local_memory_with(0, bad[i], &bytes, &error), PERMA_ERR_ARGUMENT);
        char expected[128];
        snprintf(expected, sizeof expected, "PERMA_LOCAL_MEMORY_LIMIT '%s' is not a number of bytes", bad[i]);
        ck_assert_contains(error.message, expected);
    }
    if (restore)
        setenv("PERMA_LOCAL_MEMORY_LIMIT", restore, 1);
    else
        unsetenv("PERMA_LOCAL_MEMORY_LIMIT");
    free(restore);
}
END_TEST

/* Run `count` items of value 1 through `count`, which adds each to the
 * entry of its ctx->group in an array of work_groups entries plus one for
 * any group number out of range; the items that ran, those in *stray. */
static uint64_t run_ones(perma_runtime *rt, perma_proc id, size_t count, uint32_t *stray)
{
    unsigned work_groups;
    ck_assert_perma_ok(rt, perma_get_work_groups(rt, &work_groups, NULL));
    uint32_t *per_group = calloc(work_groups + 1, sizeof *per_group), groups[1] = { work_groups };
    uint32_t *ones = malloc(count * sizeof *ones);
    for (size_t i = 0; i < count; ++i)
        ones[i] = 1;
    ck_assert_perma_ok(rt, perma_bind_host(rt, "per_group", "__global uint *", per_group,
                                           (work_groups + 1) * sizeof *per_group, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "groups", "__global const uint *", groups, sizeof groups, PERMA_READ));
    ck_assert_perma_ok(rt, perma_seed(rt, id, ones, count));
    ck_assert_perma_ok(rt, perma_run(rt));
    uint64_t total = 0;
    for (unsigned g = 0; g <= work_groups; ++g)
        total += per_group[g];
    if (stray)
        *stray = per_group[work_groups];
    free(ones);
    free(per_group);
    return total;
}

/* An array with one entry per work-group, sized before the first run:
 * every item lands in an entry below work_groups, under every technique
 * (a host-driven step once ran a group per batch). */
START_TEST(work_groups_known_before_the_first_run)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = 32;
    config.time_limit = 120;
    perma_runtime *rt = test_runtime_config(&config);
    unsigned work_groups = 0, group_size = 0;
    ck_assert_perma_ok(rt, perma_get_work_groups(rt, &work_groups, &group_size));
    ck_assert_uint_ge(work_groups, 1);
    ck_assert_uint_eq(group_size, 32);
    perma_procedure p = count_procedure();
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    uint32_t stray = 0;
    ck_assert_uint_eq(run_ones(rt, id, 20000, &stray), 20000);
    ck_assert_msg(stray == 0, "%u items ran with ctx->group >= %u", stray, work_groups);
    perma_stats stats;
    ck_assert_perma_ok(rt, perma_get_stats(rt, &stats));
    /* A device that is not a CPU settles its count in the build, never
     * above the one known before (docs/gpu.md). */
    if (stats.resident_groups)
        ck_assert_uint_le(stats.work_groups, work_groups);
    else
        ck_assert_uint_eq(stats.work_groups, work_groups);
    ck_assert_uint_eq(stats.group_size, group_size);
    perma_destroy(rt);
}
END_TEST

/* The default cap on all queues' memory is half the device's largest
 * allocation, as perma.h says (a regrowth holds the old and the new queues
 * at once); a configured cap is used as given. */
START_TEST(default_queue_memory_limit_is_half_the_largest_allocation)
{
    perma_config config;
    perma_config_init(&config);
    config.time_limit = 120;
    for (int configured = 0; configured < 2; ++configured) {
        config.queue_memory_limit = configured ? 12345678 : 0;
        perma_runtime *rt = test_runtime_config(&config);
        cl_ulong max_alloc = 0;
        ck_assert_int_eq(clGetDeviceInfo(perma_cl_device(rt), CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof max_alloc,
                                         &max_alloc, NULL), CL_SUCCESS);
        perma_procedure p = count_procedure();
        perma_proc id;
        ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
        ck_assert_uint_eq(run_ones(rt, id, 10, NULL), 10);
        perma_stats stats;
        ck_assert_perma_ok(rt, perma_get_stats(rt, &stats));
        ck_assert_uint_eq(stats.queue_memory_limit, configured ? 12345678 : max_alloc / 2);
        perma_destroy(rt);
    }
}
END_TEST

/* Seeds whose queue could not fit are refused by perma_seed, which says
 * what they would need, rather than by the run. */
START_TEST(seeds_beyond_the_limits_are_refused_at_seed)
{
    perma_config config;
    perma_config_init(&config);
    config.queue_memory_limit = 1 << 20;
    config.time_limit = 120;
    perma_runtime *rt = test_runtime_config(&config);
    perma_procedure p = count_procedure();
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    enum { TOO_MANY = 200000 }; /* 2^18 slots of 12 bytes: 3 MiB */
    uint32_t *items = calloc(TOO_MANY, sizeof *items);
    ck_assert_int_eq(perma_seed(rt, id, items, TOO_MANY), PERMA_ERR_CAPACITY);
    ck_assert_contains(perma_errmsg(rt), "perma_seed('count'): 200000 items seeded would need");
    ck_assert_contains(perma_errmsg(rt), "more than the queue memory limit of 1048576 bytes");
    ck_assert_int_eq(perma_seed(rt, id, items, PERMA_MAX_QUEUED_ITEMS + 1), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "more than a queue holds (PERMA_MAX_QUEUED_ITEMS, 2^30)");
    /* The refused seeds were not queued; seeds that fit run. */
    ck_assert_uint_eq(run_ones(rt, id, 1000, NULL), 1000);
    free(items);
    perma_destroy(rt);
}
END_TEST

/* Calls made while another call holds the runtime: from a second thread
 * (started and joined inside the first run, from its progress callback,
 * so the two surely overlap) and from the callback itself. */
typedef struct overlapping_calls {
    perma_runtime *rt;
    perma_proc id;
    unsigned callbacks;
    perma_status status[3];
    char message[3][PERMA_MESSAGE_MAX];
} overlapping_calls;

static void note(overlapping_calls *c, int k, perma_status status)
{
    c->status[k] = status;
    snprintf(c->message[k], sizeof c->message[k], "%s", perma_errmsg(c->rt));
}

static void *second_thread(void *arg)
{
    overlapping_calls *c = arg;
    note(c, 0, perma_run(c->rt));
    uint32_t item = 100;
    note(c, 1, perma_seed(c->rt, c->id, &item, 1));
    return NULL;
}

static void during_the_run(void *user, const perma_progress *progress)
{
    overlapping_calls *c = user;
    (void)progress;
    if (c->callbacks++ > 0)
        return;
    pthread_t thread; /* no ck_assert here: this is the runtime's thread */
    if (pthread_create(&thread, NULL, second_thread, c) == 0)
        pthread_join(thread, NULL);
    perma_stats stats;
    note(c, 2, perma_get_stats(c->rt, &stats));
}

/* A runtime takes one call at a time: a second call while one runs fails
 * with PERMA_ERR_STATE naming both and changes nothing; the running call
 * ends exactly, its message untouched (it once returned PERMA_OK on both
 * threads and lost the results). */
START_TEST(a_second_call_while_one_runs_is_refused)
{
    uint32_t per_group[65] = { 0 }, groups[1] = { 64 }, items[3] = { 1, 2, 3 };
    overlapping_calls c = { 0 };
    perma_config config;
    perma_config_init(&config);
    config.group_size = 64;
    config.progress = during_the_run;
    config.progress_user = &c;
    c.rt = test_runtime_config(&config);
    perma_procedure p = count_procedure();
    ck_assert_perma_ok(c.rt, perma_register(c.rt, &p, &c.id));
    ck_assert_perma_ok(c.rt, perma_bind_host(c.rt, "per_group", "__global uint *", per_group, sizeof per_group,
                                             PERMA_READ_WRITE));
    ck_assert_perma_ok(c.rt, perma_bind_host(c.rt, "groups", "__global const uint *", groups, sizeof groups,
                                             PERMA_READ));
    ck_assert_perma_ok(c.rt, perma_seed(c.rt, c.id, items, 3));
    ck_assert_perma_ok(c.rt, perma_run(c.rt));
    ck_assert_str_eq(perma_errmsg(c.rt), "");
    ck_assert_uint_ge(c.callbacks, 1);
    const char *calls[3] = { "perma_run", "perma_seed", "perma_get_stats" };
    for (int k = 0; k < 3; ++k) {
        char expected[256];
        ck_assert_int_eq(c.status[k], PERMA_ERR_STATE);
        snprintf(expected, sizeof expected, "%s: perma_run is running on this runtime (in another thread, or this "
                 "call comes from inside it); a runtime takes one call at a time", calls[k]);
        ck_assert_contains(c.message[k], expected);
    }
    uint32_t total = 0;
    for (unsigned g = 0; g < 65; ++g)
        total += per_group[g];
    ck_assert_uint_eq(total, 6);
    /* The refused seed was not queued; the runtime takes calls again. */
    memset(per_group, 0, sizeof per_group);
    ck_assert_perma_ok(c.rt, perma_run(c.rt));
    for (unsigned g = 0; g < 65; ++g)
        ck_assert_uint_eq(per_group[g], 0);
    perma_stats stats;
    ck_assert_perma_ok(c.rt, perma_get_stats(c.rt, &stats));
    perma_destroy(c.rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("api");
    TCase *tc = tcase_create("api");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, opencl_target_version_is_the_programs);
    tcase_add_test(tc, errmsg_is_empty_after_every_successful_call);
    tcase_add_test(tc, out_pointers_are_checked);
    tcase_add_test(tc, local_memory_limit_from_config_and_environment);
    tcase_add_test(tc, work_groups_known_before_the_first_run);
    tcase_add_test(tc, default_queue_memory_limit_is_half_the_largest_allocation);
    tcase_add_test(tc, seeds_beyond_the_limits_are_refused_at_seed);
    tcase_add_test(tc, a_second_call_while_one_runs_is_refused);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
