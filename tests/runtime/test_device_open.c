/* Opening the device (device.c, device_list.c, platform_missing.c): a device the
 * environment names that does not exist, no OpenCL platform at all, a
 * driver that does not load; each named with what to do. */
#include "perma_test.h"

#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

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

PERMA_TEST_MAIN("device_open", missing_device_from_environment, no_platform_names_the_package, driver_that_does_not_load_is_named)
