/* Choosing the OpenCL device and the number of persistent work-groups. */
#include "internal.h"

#include <ctype.h>
#include <hwloc.h>
#include <stdlib.h>
#include <string.h>

/* Which device PERMA_DEVICE (or the config) asks for: a platform by index
 * (platform >= 0) or by a substring of its name or vendor (name[0] != 0),
 * and a device index on it. */
typedef struct device_spec {
    int platform;
    char name[64];
    int device;
} device_spec;

/* Parse "P:D" (indices), "NAME" or "NAME:D" (NAME: letters, digits, spaces
 * and "()._-", not starting with a digit; D defaults to 0). */
static perma_status parse_device_spec(perma_runtime *rt, const char *value, device_spec *out)
{
    device_spec spec = { -1, "", 0 };
    const char *colon = strchr(value, ':');
    size_t head = colon ? (size_t)(colon - value) : strlen(value);
    char *end = NULL;
    if (head == 0 || head >= sizeof spec.name)
        goto bad;
    if (value[0] >= '0' && value[0] <= '9') {
        long p = strtol(value, &end, 10);
        if (end != value + head || !colon || p > 1000000)
            goto bad;
        spec.platform = (int)p;
    } else {
        for (size_t i = 0; i < head; ++i) {
            char c = value[i];
            if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                  strchr(" ()._-", c)))
                goto bad;
        }
        memcpy(spec.name, value, head);
        spec.name[head] = '\0';
    }
    if (colon) {
        const char *second = colon + 1;
        long d = strtol(second, &end, 10);
        if (end == second || *end != '\0' || d < 0 || d > 1000000 || *second == '-' || *second == '+')
            goto bad;
        spec.device = (int)d;
    }
    *out = spec;
    return PERMA_OK;
bad:
    return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                           "PERMA_DEVICE='%s' is not of the form platform:device (e.g. 0:0) or NAME[:device] "
                           "(a platform's name or vendor, e.g. intel or pocl:0)", value);
}

static bool contains_ignoring_case(const char *text, const char *part)
{
    size_t n = strlen(part);
    for (; *text; ++text) {
        size_t i = 0;
        while (i < n && tolower((unsigned char)text[i]) == tolower((unsigned char)part[i]))
            ++i;
        if (i == n)
            return true;
    }
    return false;
}

/* The first platform whose name or vendor contains `name`; PERMA_ERR_NO_DEVICE
 * listing the platforms if there is none. */
static perma_status find_platform(perma_runtime *rt, const cl_platform_id *platforms, cl_uint count,
                                  const char *name, int *index)
{
    char list[PERMA_MESSAGE_MAX / 2] = "";
    size_t used = 0;
    for (cl_uint p = 0; p < count; ++p) {
        char platform[128] = "", vendor[128] = "";
        clGetPlatformInfo(platforms[p], CL_PLATFORM_NAME, sizeof platform - 1, platform, NULL);
        clGetPlatformInfo(platforms[p], CL_PLATFORM_VENDOR, sizeof vendor - 1, vendor, NULL);
        if (contains_ignoring_case(platform, name) || contains_ignoring_case(vendor, name)) {
            *index = (int)p;
            return PERMA_OK;
        }
        int n = snprintf(list + used, sizeof list - used, "%s%u '%s' (%s)", p ? ", " : "", (unsigned)p,
                         platform, vendor);
        if (n > 0 && (size_t)n < sizeof list - used)
            used += (size_t)n;
    }
    return perma_set_error(rt, PERMA_ERR_NO_DEVICE,
                           "no OpenCL platform's name or vendor contains '%s' (PERMA_DEVICE or config); "
                           "the platforms are: %s", name, list);
}

/* Physical cores from hwloc; 0 if hwloc cannot tell. */
static unsigned physical_cores(void)
{
    hwloc_topology_t topology;
    if (hwloc_topology_init(&topology) != 0)
        return 0;
    int cores = 0;
    if (hwloc_topology_load(topology) == 0)
        cores = hwloc_get_nbobjs_by_type(topology, HWLOC_OBJ_CORE);
    hwloc_topology_destroy(topology);
    return cores > 0 ? (unsigned)cores : 0;
}

static void choose_work_groups(perma_runtime *rt, const char *device_name)
{
    char why[160];
    unsigned groups = rt->compute_units ? rt->compute_units : 1;
    snprintf(why, sizeof why, "%u compute units", (unsigned)rt->compute_units);
    if (rt->device_is_cpu) {
        unsigned cores = physical_cores();
        if (cores && cores < groups) {
            groups = cores;
            snprintf(why, sizeof why, "%u physical cores (hwloc) of %u compute units", cores,
                     (unsigned)rt->compute_units);
        }
    }
    if (rt->config.work_groups) {
        groups = rt->config.work_groups;
        snprintf(why, sizeof why, rt->debug ? "PERMA_DEBUG" : "configured");
    }
    rt->work_groups = groups;
    snprintf(rt->summary, sizeof rt->summary, "%s: %u work-groups (%s) of %u work-items",
             device_name, rt->work_groups, why, rt->group_size);
}

perma_status perma_device_open(perma_runtime *rt)
{
    device_spec spec = { rt->config.platform_index, "", rt->config.device_index };
    const char *env = getenv("PERMA_DEVICE");
    if (spec.platform < 0 && rt->config.platform_name) {
        if (!*rt->config.platform_name || strlen(rt->config.platform_name) >= sizeof spec.name)
            return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.platform_name '%s' is empty or too long",
                                   rt->config.platform_name);
        snprintf(spec.name, sizeof spec.name, "%s", rt->config.platform_name);
    } else if (env && *env && (spec.platform < 0 || spec.device < 0)) {
        device_spec asked = { -1, "", 0 };
        perma_status st = parse_device_spec(rt, env, &asked);
        if (st != PERMA_OK)
            return st;
        if (spec.platform < 0) {
            spec.platform = asked.platform;
            memcpy(spec.name, asked.name, sizeof spec.name);
        }
        if (spec.device < 0)
            spec.device = asked.device;
    }
    rt->config.platform_name = NULL; /* the caller's string is not kept */
    if (spec.platform < 0 && !spec.name[0])
        spec.platform = 0;
    if (spec.device < 0)
        spec.device = 0;

    cl_uint platform_count = 0;
    cl_int err = clGetPlatformIDs(0, NULL, &platform_count);
    if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || (err == CL_SUCCESS && platform_count == 0))
        return perma_set_error(rt, PERMA_ERR_NO_PLATFORM,
                               "no OpenCL platform found; install an OpenCL driver, e.g. "
                               "'apt-get install pocl-opencl-icd'");
    PERMA_CL_CHECK(rt, "clGetPlatformIDs", err);
    if (!spec.name[0] && (cl_uint)spec.platform >= platform_count)
        return perma_set_error(rt, PERMA_ERR_NO_DEVICE,
                               "OpenCL platform %d requested (PERMA_DEVICE or config), but only %u "
                               "platform(s) exist", spec.platform, (unsigned)platform_count);
    cl_platform_id *platforms = calloc(platform_count, sizeof *platforms);
    if (!platforms)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory listing platforms");
    err = clGetPlatformIDs(platform_count, platforms, NULL);
    perma_status found = err == CL_SUCCESS && spec.name[0]
                         ? find_platform(rt, platforms, platform_count, spec.name, &spec.platform) : PERMA_OK;
    if (err == CL_SUCCESS && found == PERMA_OK)
        rt->platform = platforms[spec.platform];
    free(platforms);
    PERMA_CL_CHECK(rt, "clGetPlatformIDs", err);
    if (found != PERMA_OK)
        return found;
    int platform_index = spec.platform, device_index = spec.device;

    cl_uint device_count = 0;
    err = clGetDeviceIDs(rt->platform, CL_DEVICE_TYPE_ALL, 0, NULL, &device_count);
    if (err != CL_DEVICE_NOT_FOUND)
        PERMA_CL_CHECK(rt, "clGetDeviceIDs", err);
    if ((cl_uint)device_index >= device_count)
        return perma_set_error(rt, PERMA_ERR_NO_DEVICE,
                               "OpenCL device %d:%d requested (PERMA_DEVICE or config%s%s%s), but platform "
                               "%d has %u device(s)", platform_index, device_index,
                               spec.name[0] ? "; platform '" : "", spec.name, spec.name[0] ? "'" : "",
                               platform_index, (unsigned)device_count);
    cl_device_id *devices = calloc(device_count, sizeof *devices);
    if (!devices)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory listing devices");
    err = clGetDeviceIDs(rt->platform, CL_DEVICE_TYPE_ALL, device_count, devices, NULL);
    rt->device = devices[device_index];
    free(devices);
    PERMA_CL_CHECK(rt, "clGetDeviceIDs", err);

    cl_device_type type = 0;
    cl_ulong local_mem = 0;
    size_t max_group = 0;
    char name[256] = "";
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_TYPE)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_TYPE, sizeof type, &type, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_MAX_COMPUTE_UNITS)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof rt->compute_units,
                                   &rt->compute_units, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_LOCAL_MEM_SIZE)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_LOCAL_MEM_SIZE, sizeof local_mem, &local_mem, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_MAX_MEM_ALLOC_SIZE)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof rt->max_alloc,
                                   &rt->max_alloc, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_MAX_WORK_GROUP_SIZE)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof max_group, &max_group, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_NAME)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_NAME, sizeof name - 1, name, NULL));
    rt->device_is_cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
    rt->local_mem_size = (size_t)local_mem;
    if (rt->group_size > max_group)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "group_size %u exceeds the device's maximum work-group size %zu",
                               rt->group_size, max_group);

    rt->context = clCreateContext(NULL, 1, &rt->device, NULL, NULL, &err);
    PERMA_CL_CHECK(rt, "clCreateContext", err);
    rt->queue = clCreateCommandQueue(rt->context, rt->device, 0, &err);
    PERMA_CL_CHECK(rt, "clCreateCommandQueue", err);
    choose_work_groups(rt, name);
    return PERMA_OK;
}

void perma_device_close(perma_runtime *rt)
{
    if (rt->queue)
        clReleaseCommandQueue(rt->queue);
    if (rt->context)
        clReleaseContext(rt->context);
    rt->queue = NULL;
    rt->context = NULL;
}

const char *perma_device_summary(const perma_runtime *rt)
{
    return rt ? rt->summary : "";
}
