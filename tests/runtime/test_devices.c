/* Device lists and sub-devices: perma_device_list expands "P:D", "P:D/N",
 * "P:D/N.K" and "all" and refuses bad entries by name; a runtime per
 * equal sub-device runs, two of them at once from two threads, with exact
 * results; PERMA_DEVICE takes a list's first device. */
#include "perma_test.h"
#include "tree_procedure.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

/* Compute units of device 0:0 and whether it splits into equal parts. */
static cl_uint device_units(cl_uint *max_sub_devices)
{
    cl_platform_id platform;
    cl_device_id device;
    cl_uint units = 0;
    *max_sub_devices = 0;
    ck_assert_int_eq(clGetPlatformIDs(1, &platform, NULL), CL_SUCCESS);
    ck_assert_int_eq(clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 1, &device, NULL), CL_SUCCESS);
    clGetDeviceInfo(device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units, NULL);
    clGetDeviceInfo(device, CL_DEVICE_PARTITION_MAX_SUB_DEVICES, sizeof *max_sub_devices,
                    max_sub_devices, NULL);
    return units;
}

/* The summary of a runtime on half `part` of device 0:0 names the part and
 * the work-groups the runtime chose: at least one, at most the half's
 * compute units. */
static void expect_half_summary(perma_runtime *rt, int part)
{
    cl_uint most, units = device_units(&most);
    unsigned groups = 0;
    ck_assert_int_eq(perma_get_work_groups(rt, &groups, NULL), PERMA_OK);
    ck_assert_uint_ge(groups, 1);
    ck_assert_uint_le(groups, units / 2);
    char expected[64];
    snprintf(expected, sizeof expected, "(sub-device %d of 2): %u work-groups", part, groups);
    ck_assert_contains(perma_device_summary(rt), expected);
}

static void expect_label(const perma_device_ref *ref, const char *label)
{
    char text[64];
    ck_assert_int_eq(perma_device_ref_format(ref, text, sizeof text), (int)strlen(label));
    ck_assert_str_eq(text, label);
}

START_TEST(lists_expand_in_order)
{
    perma_device_ref refs[PERMA_MAX_DEVICES];
    unsigned count = 99;
    perma_error error;
    ck_assert_int_eq(perma_device_list("0:0", refs, PERMA_MAX_DEVICES, &count, &error), PERMA_OK);
    ck_assert_uint_eq(count, 1);
    expect_label(&refs[0], "0:0");
    ck_assert_uint_eq(refs[0].sub_devices, 0);

    ck_assert_int_eq(perma_device_list("all", refs, PERMA_MAX_DEVICES, &count, &error), PERMA_OK);
    ck_assert_uint_ge(count, 1);
    expect_label(&refs[0], "0:0");

    /* Platforms by name, in any case: PoCL's vendor is "The pocl project"
     * (platform 0 in this suite). */
    ck_assert_int_eq(perma_device_list("pocl", refs, PERMA_MAX_DEVICES, &count, &error), PERMA_OK);
    ck_assert_uint_eq(count, 1);
    expect_label(&refs[0], "0:0");
    ck_assert_int_eq(perma_device_list("Portable Computing:0", refs, PERMA_MAX_DEVICES, &count, &error),
                     PERMA_OK);
    expect_label(&refs[0], "0:0");
    ck_assert_int_eq(perma_device_list("POCL,0:0", refs, PERMA_MAX_DEVICES, &count, &error), PERMA_ERR_ARGUMENT);
    ck_assert_contains(error.message, "device 0:0 appears twice");

    cl_uint most;
    device_units(&most);
    if (most < 2) {
        printf("device 0:0 does not split into 2 equal sub-devices: the rest of device_lists skipped\n");
        return;
    }
    ck_assert_int_eq(perma_device_list("0:0/2", refs, PERMA_MAX_DEVICES, &count, &error), PERMA_OK);
    ck_assert_uint_eq(count, 2);
    expect_label(&refs[0], "0:0/2.0");
    expect_label(&refs[1], "0:0/2.1");
    ck_assert_int_eq(perma_device_list("pocl/2.1", refs, PERMA_MAX_DEVICES, &count, &error), PERMA_OK);
    ck_assert_uint_eq(count, 1);
    expect_label(&refs[0], "0:0/2.1");
    ck_assert_int_eq(perma_device_list("0:0/2.1,0:0/2.0,0:0", refs, PERMA_MAX_DEVICES, &count, &error),
                     PERMA_OK);
    ck_assert_uint_eq(count, 3);
    expect_label(&refs[0], "0:0/2.1");
    expect_label(&refs[1], "0:0/2.0");
    expect_label(&refs[2], "0:0");
    /* "/1" is the whole device. */
    ck_assert_int_eq(perma_device_list("0:0/1", refs, PERMA_MAX_DEVICES, &count, &error), PERMA_OK);
    ck_assert_uint_eq(count, 1);
    expect_label(&refs[0], "0:0");
    /* At most `max`. */
    ck_assert_int_eq(perma_device_list("0:0/2", refs, 1, &count, &error), PERMA_ERR_ARGUMENT);
    ck_assert_uint_eq(count, 0);
    ck_assert_contains(error.message, "more than 1 devices");
}
END_TEST

/* Each bad list fails with its status and a message naming the entry. */
START_TEST(bad_lists_name_the_entry)
{
    cl_uint most;
    cl_uint units = device_units(&most);
    char too_many[32];
    snprintf(too_many, sizeof too_many, "0:0/%u", (unsigned)(units > most ? units : most) + 1);
    const struct {
        const char *list;
        perma_status status;
        const char *message;
    } cases[] = {
        { "g/pu", PERMA_ERR_ARGUMENT, "entry 'g/pu' is not of the form platform:device" },
        { "pocl:", PERMA_ERR_ARGUMENT, "entry 'pocl:' is not of the form" },
        { "0:0,pocl:x", PERMA_ERR_ARGUMENT, "entry 'pocl:x' is not of the form" },
        { "gpu", PERMA_ERR_NO_DEVICE, "no OpenCL platform's name or vendor contains 'gpu'; the platforms are: 0 '" },
        { "0:0,", PERMA_ERR_ARGUMENT, "entry '' is not of the form" },
        { "0:0,0:x", PERMA_ERR_ARGUMENT, "entry '0:x' is not of the form" },
        { "0:0/2.2", PERMA_ERR_ARGUMENT, "entry '0:0/2.2' is not of the form" },
        { "0:0/0", PERMA_ERR_ARGUMENT, "entry '0:0/0'" },
        { "-1:0", PERMA_ERR_ARGUMENT, "entry '-1:0'" },
        { "0:0,0:0", PERMA_ERR_ARGUMENT, "device 0:0 appears twice" },
        { "9:9", PERMA_ERR_NO_DEVICE, "OpenCL platform 9 requested" },
        { "0:9", PERMA_ERR_NO_DEVICE, "OpenCL device 0:9 requested" },
        { too_many, PERMA_ERR_NO_DEVICE, "cannot split it into" },
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        perma_device_ref refs[4];
        unsigned count = 7;
        perma_error error;
        perma_status st = perma_device_list(cases[k].list, refs, 4, &count, &error);
        ck_assert_msg(st == cases[k].status, "'%s': %s (%s)", cases[k].list, perma_status_name(st),
                      error.message);
        ck_assert_uint_eq(count, 0);
        ck_assert_contains(error.message, cases[k].message);
        char quoted[64];
        snprintf(quoted, sizeof quoted, "device list '%s'", cases[k].list);
        ck_assert_contains(error.message, quoted);
    }
}
END_TEST

/* NULL or "" reads PERMA_DEVICE; perma_create takes its first device. */
START_TEST(environment_lists)
{
    perma_device_ref refs[4];
    unsigned count;
    perma_error error;
    unsetenv("PERMA_DEVICE");
    ck_assert_int_eq(perma_device_list(NULL, refs, 4, &count, &error), PERMA_OK);
    ck_assert_uint_eq(count, 1);
    expect_label(&refs[0], "0:0");

    cl_uint most;
    device_units(&most);
    if (most >= 2) {
        setenv("PERMA_DEVICE", "0:0/2.1,0:0/2.0", 1);
        ck_assert_int_eq(perma_device_list("", refs, 4, &count, &error), PERMA_OK);
        ck_assert_uint_eq(count, 2);
        expect_label(&refs[0], "0:0/2.1");
        perma_runtime *rt;
        ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_OK);
        expect_half_summary(rt, 1);
        perma_destroy(rt);
        setenv("PERMA_DEVICE", "pocl/2.1", 1); /* a platform by name, split */
        ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_OK);
        expect_half_summary(rt, 1);
        perma_destroy(rt);
    }
    setenv("PERMA_DEVICE", "all", 1);
    perma_runtime *rt;
    ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_OK);
    perma_destroy(rt);
    setenv("PERMA_DEVICE", "0:0,z/z", 1);
    ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_ERR_ARGUMENT);
    ck_assert_contains(error.message, "PERMA_DEVICE='0:0,z/z': entry 'z/z' is not of the form");
    unsetenv("PERMA_DEVICE");
}
END_TEST

/* Config fields out of range are refused by name. */
START_TEST(bad_sub_device_config)
{
    perma_config config;
    perma_config_init(&config);
    config.platform_index = 0;
    config.device_index = 0;
    config.sub_devices = 2;
    config.sub_device = 2;
    perma_runtime *rt;
    perma_error error;
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_ERR_ARGUMENT);
    ck_assert_contains(error.message, "sub-device 2 of 2 requested");
    ck_assert_ptr_null(rt);
    cl_uint most;
    cl_uint units = device_units(&most);
    config.sub_devices = (units > most ? units : most) + 1;
    config.sub_device = 0;
    ck_assert_int_eq(perma_create(&config, &rt, &error), PERMA_ERR_NO_DEVICE);
    ck_assert_contains(error.message, "OpenCL device 0:0 has");
}
END_TEST

/* A tree of depth 16 on one runtime: 2^16 leaves, checksum of their ids. */
typedef struct tree_job {
    perma_device_ref ref;
    uint32_t counts[2];
    uint64_t sums[1];
    perma_status status;
    char message[PERMA_MESSAGE_MAX];
    char summary[512];
    unsigned groups; /* the runtime's work-groups */
} tree_job;

static void *run_tree(void *arg)
{
    tree_job *job = arg;
    perma_config config;
    perma_config_init(&config);
    perma_config_set_device(&config, &job->ref);
    config.time_limit = 120;
    perma_runtime *rt = NULL;
    perma_error error;
    job->status = perma_create(&config, &rt, &error);
    if (job->status != PERMA_OK) {
        snprintf(job->message, sizeof job->message, "%s", error.message);
        return NULL;
    }
    snprintf(job->summary, sizeof job->summary, "%s", perma_device_summary(rt));
    perma_get_work_groups(rt, &job->groups, NULL);
    perma_procedure tree = {
        .name = "tree", .item_type = "struct tree_node", .item_size = sizeof(struct tree_node),
        .threads_per_item = 1, .source = TREE_SOURCE, .source_file = "tree_split.cl",
        .function = "tree_split", .emits = { { "tree", 2 } },
    };
    perma_proc id;
    struct tree_node root = { 0, 16, 1, 0 };
    perma_status st = perma_add_source(rt, TREE_TYPES, "tree_types.cl");
    if (st == PERMA_OK)
        st = perma_register(rt, &tree, &id);
    if (st == PERMA_OK)
        st = perma_bind_host(rt, "counts", "__global uint *", job->counts, sizeof job->counts,
                             PERMA_READ_WRITE);
    if (st == PERMA_OK)
        st = perma_bind_host(rt, "sums", "__global ulong *", job->sums, sizeof job->sums,
                             PERMA_READ_WRITE);
    if (st == PERMA_OK)
        st = perma_seed(rt, id, &root, 1);
    if (st == PERMA_OK)
        st = perma_run(rt);
    job->status = st;
    snprintf(job->message, sizeof job->message, "%s", perma_errmsg(rt));
    perma_destroy(rt);
    return NULL;
}

/* Two runtimes on the two halves of device 0:0, running at once. */
START_TEST(sub_devices_run_concurrently)
{
    cl_uint most;
    device_units(&most);
    if (most < 2) {
        printf("device 0:0 does not split into 2 equal sub-devices: skipped\n");
        return;
    }
    perma_device_ref refs[2];
    unsigned count;
    perma_error error;
    ck_assert_int_eq(perma_device_list("0:0/2", refs, 2, &count, &error), PERMA_OK);
    tree_job jobs[2];
    pthread_t threads[2];
    for (int k = 0; k < 2; ++k) {
        memset(&jobs[k], 0, sizeof jobs[k]);
        jobs[k].ref = refs[k];
        ck_assert_int_eq(pthread_create(&threads[k], NULL, run_tree, &jobs[k]), 0);
    }
    for (int k = 0; k < 2; ++k)
        pthread_join(threads[k], NULL);
    const uint64_t first = 1u << 16, last = (1u << 17) - 1;
    const cl_uint units = device_units(&most);
    for (int k = 0; k < 2; ++k) {
        ck_assert_msg(jobs[k].status == PERMA_OK, "%s: %s", perma_status_name(jobs[k].status),
                      jobs[k].message);
        ck_assert_uint_ge(jobs[k].groups, 1);
        ck_assert_uint_le(jobs[k].groups, units / 2);
        char part[64];
        snprintf(part, sizeof part, "(sub-device %d of 2): %u work-groups", k, jobs[k].groups);
        ck_assert_contains(jobs[k].summary, part);
        ck_assert_uint_eq(jobs[k].counts[0], 1u << 16);
        ck_assert_uint_eq(jobs[k].counts[1], (1u << 16) - 1);
        ck_assert_uint_eq(jobs[k].sums[0], (first + last) * (last - first + 1) / 2);
    }
}
END_TEST

int main(void)
{
    Suite *suite = suite_create("devices");
    TCase *tc = tcase_create("devices");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, lists_expand_in_order);
    tcase_add_test(tc, bad_lists_name_the_entry);
    tcase_add_test(tc, environment_lists);
    tcase_add_test(tc, bad_sub_device_config);
    tcase_add_test(tc, sub_devices_run_concurrently);
    suite_add_tcase(suite, tc);
    return test_run_suite(suite) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
