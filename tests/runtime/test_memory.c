/* Memory limits (runtime/src/memory.c): what does not fit is refused as out
 * of memory, naming what and how big, before the OpenCL driver sees it (PoCL
 * aborted, crashed or asserted instead).  Each test runs in its own process
 * (Check forks), so a limit set here ends with it. */
#include "perma_test.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#define MIB ((size_t)1 << 20)

static bool forked(void)
{
    const char *fork = getenv("CK_FORK");
    return !fork || strcmp(fork, "no") != 0;
}

/* The process's address space now (VmSize). */
static size_t mapped_bytes(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    ck_assert_ptr_nonnull(f);
    char line[256];
    size_t kib = 0;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "VmSize:", 7) == 0)
            kib = strtoull(line + 7, NULL, 10);
    fclose(f);
    ck_assert_uint_gt(kib, 0);
    return kib * 1024;
}

static void limit_address_space(size_t bytes)
{
    struct rlimit limit = { bytes, bytes };
    ck_assert_int_eq(setrlimit(RLIMIT_AS, &limit), 0);
}

/* A limit too small for the driver: refused before the first OpenCL call
 * (it was "no OpenCL platform found; install an OpenCL driver", or PoCL
 * aborting). */
START_TEST(driver_that_does_not_fit_is_refused)
{
    if (!forked())
        return; /* the limit would stay for the other tests */
    limit_address_space(mapped_bytes() + 200 * MIB);
    perma_runtime *rt = NULL;
    perma_error error;
    ck_assert_int_eq(perma_create(NULL, &rt, &error), PERMA_ERR_NO_MEMORY);
    ck_assert_ptr_null(rt);
    ck_assert_contains(error.message, "out of memory: the OpenCL driver, to start and run, needs about 456 MiB "
                                      "(PoCL), but the process's address-space limit (ulimit -v) of ");
    ck_assert_msg(strstr(error.message, "install") == NULL, "%s", error.message);
}
END_TEST

/* A buffer above the device's largest allocation: out of memory naming
 * the buffer and its size (it was clCreateBuffer's CL_INVALID_BUFFER_SIZE). */
START_TEST(buffer_above_the_device_limit)
{
    perma_runtime *rt = test_runtime(0, 0, 0);
    uint32_t word = 0;
    size_t huge = (size_t)1 << 50;
    ck_assert_int_eq(perma_bind_host(rt, "huge", "__global uint *", &word, huge, PERMA_READ), PERMA_ERR_NO_MEMORY);
    char expected[160];
    snprintf(expected, sizeof expected, "out of memory for buffer 'huge' (%zu bytes, %zu MiB): more than the "
             "device's largest buffer (CL_DEVICE_MAX_MEM_ALLOC_SIZE, ", huge, huge / MIB);
    ck_assert_contains(perma_errmsg(rt), expected);
    perma_destroy(rt);
}
END_TEST

/* On a CPU device a buffer is the process's memory: one that does not fit
 * the address-space limit, with room for the driver, is refused. */
START_TEST(buffer_above_the_process_limit)
{
    if (!forked())
        return;
    perma_runtime *rt = test_runtime(0, 0, 0);
    cl_device_type type = 0;
    clGetDeviceInfo(perma_cl_device(rt), CL_DEVICE_TYPE, sizeof type, &type, NULL);
    if (!(type & CL_DEVICE_TYPE_CPU)) {
        perma_destroy(rt);
        return; /* a GPU's buffers are its own memory */
    }
    limit_address_space(mapped_bytes() + 256 * MIB);
    ck_assert_perma_ok(rt, perma_check_memory(rt, 16 * MIB, "a small buffer"));
    ck_assert_int_eq(perma_check_memory(rt, 512 * MIB, "the test buffer"), PERMA_ERR_NO_MEMORY);
    ck_assert_contains(perma_errmsg(rt), "out of memory for the test buffer (536870912 bytes, 512 MiB): the "
                                         "process's address-space limit (ulimit -v) of ");
    ck_assert_contains(perma_errmsg(rt), "and the OpenCL driver needs about 32 MiB beside it");
    perma_destroy(rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("memory");
    TCase *tc = tcase_create("memory");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, driver_that_does_not_fit_is_refused);
    tcase_add_test(tc, buffer_above_the_device_limit);
    tcase_add_test(tc, buffer_above_the_process_limit);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
