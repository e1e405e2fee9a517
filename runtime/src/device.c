/* Choosing the OpenCL device and the number of persistent work-groups. */
#include "device.h"
#include "device_list.h"
#include "executor.h"
#include "internal.h"
#include "layout.h"

#include <hwloc.h>
#include <stdlib.h>
#include <string.h>

/* Parse PERMA_DEVICE: a device list (device_list.h) of which the runtime
 * takes the first device ("all": 0:0; "P:D/N": part 0; "NAME": device 0 of
 * the platform the name matches, resolved by the caller). */
static perma_status parse_device_env(perma_runtime *rt, const char *value, perma_device_entry *entry)
{
    perma_device_entry first;
    size_t bad_offset, bad_length;
    if (!perma_device_list_first(value, &first, &bad_offset, &bad_length)) {
        if (bad_length == strlen(value))
            return perma_set_error(rt, PERMA_ERR_ARGUMENT, "PERMA_DEVICE='%s' is not of the form %s",
                                   value, PERMA_DEVICE_FORMS);
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "PERMA_DEVICE='%s': entry '%.*s' is not of the "
                               "form %s", value, (int)bad_length, value + bad_offset, PERMA_DEVICE_FORMS);
    }
    if (first.all)
        first.platform = first.device = 0;
    *entry = first;
    return PERMA_OK;
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

void perma_residency_of(unsigned compute_units, size_t device_local, size_t kernel_local,
                        size_t kernel_group_size, unsigned group_size, perma_residency *out)
{
    unsigned per_unit = PERMA_MAX_GROUPS_PER_UNIT;
    char bound[96];
    snprintf(bound, sizeof bound, "at most %u per compute unit", per_unit);
    size_t by_size = group_size ? kernel_group_size / group_size : 0;
    if (by_size < per_unit) {
        per_unit = (unsigned)by_size;
        snprintf(bound, sizeof bound, "%zu work-items per compute unit (CL_KERNEL_WORK_GROUP_SIZE)",
                 kernel_group_size);
    }
    size_t by_local = kernel_local ? device_local / kernel_local : per_unit;
    if (by_local < per_unit) {
        per_unit = (unsigned)by_local;
        snprintf(bound, sizeof bound, "__local memory: %zu of %zu bytes each", kernel_local, device_local);
    }
    out->per_unit = per_unit;
    out->limit = compute_units * per_unit;
    snprintf(out->why, sizeof out->why, "%u compute units x %u, %s", compute_units, per_unit, bound);
}

/* The summary line (perma_device_summary) for the count and its reason. */
static void summarize(perma_runtime *rt)
{
    snprintf(rt->summary, sizeof rt->summary, "%s: %u work-groups (%s) of %u work-items", rt->caps.name,
             rt->work_groups, rt->work_groups_reason, rt->group_size);
}

static void set_work_groups(perma_runtime *rt, unsigned groups, const char *why)
{
    rt->work_groups = groups;
    size_t length = strlen(why); /* cut to the field */
    if (length >= sizeof rt->work_groups_reason)
        length = sizeof rt->work_groups_reason - 1;
    memcpy(rt->work_groups_reason, why, length);
    rt->work_groups_reason[length] = '\0';
    summarize(rt);
}

/* The count from perma_create on.  A CPU runs as many groups as it has
 * physical cores, or compute units if fewer (a group that cannot start
 * waits for one that ends).  Another device runs as many as it holds at
 * once, which depends on the kernel: until the program is built, the most
 * the device allows for any kernel (perma_work_groups_plan and
 * perma_work_groups_fit lower it), so that an array sized by
 * perma_get_work_groups holds every ctx->group. */
static void choose_work_groups(perma_runtime *rt)
{
    char why[PERMA_REASON_MAX + 32];
    unsigned units = rt->caps.compute_units ? rt->caps.compute_units : 1;
    unsigned groups = units;
    snprintf(why, sizeof why, "%u compute units", (unsigned)rt->caps.compute_units);
    if (rt->caps.is_cpu) {
        unsigned cores = physical_cores();
        if (cores && cores < groups) {
            groups = cores;
            snprintf(why, sizeof why, "%u physical cores (hwloc) of %u compute units", cores,
                     (unsigned)rt->caps.compute_units);
        }
    } else {
        perma_residency r;
        perma_residency_of(units, rt->caps.local_mem_size, 0, rt->caps.max_group_size, rt->group_size, &r);
        groups = r.limit ? r.limit : units;
        snprintf(why, sizeof why, "%s; until the program is built", r.why);
    }
    if (rt->config.work_groups) {
        groups = rt->config.work_groups;
        snprintf(why, sizeof why, rt->debug ? "PERMA_DEBUG" : "configured");
    }
    rt->work_groups_bound = groups;
    set_work_groups(rt, groups, why);
}

bool perma_work_groups_plan(perma_runtime *rt, size_t local_bytes)
{
    if (rt->caps.is_cpu || rt->config.work_groups)
        return false;
    unsigned units = rt->caps.compute_units ? rt->caps.compute_units : 1;
    perma_residency r;
    perma_residency_of(units, rt->caps.local_mem_size, local_bytes, rt->caps.max_group_size, rt->group_size, &r);
    unsigned groups = r.limit < rt->work_groups_bound ? r.limit : rt->work_groups_bound;
    if (!groups || groups == rt->work_groups)
        return false; /* none: perma_work_groups_fit says why */
    set_work_groups(rt, groups, r.why);
    return true;
}

/* CL_KERNEL_* of the built megakernel on the device. */
static perma_status kernel_info(perma_runtime *rt, cl_kernel_work_group_info what, const char *name, void *value,
                                size_t size)
{
    cl_int err = clGetKernelWorkGroupInfo(rt->build.kernel, rt->device, what, size, value, NULL);
    if (err != CL_SUCCESS)
        return perma_set_error(rt, PERMA_ERR_OPENCL, "clGetKernelWorkGroupInfo(%s) failed: %s (%d)", name,
                               perma_cl_error_name(err), (int)err);
    return PERMA_OK;
}

perma_status perma_work_groups_fit(perma_runtime *rt, bool *rebuild)
{
    *rebuild = false;
    rt->resident_groups = 0;
    size_t kernel_size = 0;
    cl_ulong kernel_local = 0;
    perma_status st = kernel_info(rt, CL_KERNEL_WORK_GROUP_SIZE, "CL_KERNEL_WORK_GROUP_SIZE", &kernel_size,
                                  sizeof kernel_size);
    if (st == PERMA_OK)
        st = kernel_info(rt, CL_KERNEL_LOCAL_MEM_SIZE, "CL_KERNEL_LOCAL_MEM_SIZE", &kernel_local,
                         sizeof kernel_local);
    if (st != PERMA_OK)
        return st;
    rt->kernel_local_bytes = (size_t)kernel_local;
    if (kernel_size < rt->group_size)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "the megakernel can run work-groups of at most %zu work-items on %s "
                               "(CL_KERNEL_WORK_GROUP_SIZE: its registers), fewer than the group_size %u: set "
                               "config.group_size to at most %zu", kernel_size, rt->caps.name, rt->group_size,
                               kernel_size);
    size_t limit = perma_local_memory(rt);
    if (kernel_local > limit)
        return perma_set_error(rt, PERMA_ERR_BUILD,
                               "the megakernel uses %zu bytes of __local memory per work-group, more than the %zu "
                               "bytes a group may use on %s (%s)", (size_t)kernel_local, limit, rt->caps.name,
                               limit < rt->caps.local_mem_size ? "config.local_memory_limit"
                                                               : "CL_DEVICE_LOCAL_MEM_SIZE");
    if (rt->caps.is_cpu)
        return PERMA_OK; /* a group that cannot start waits for one that ends */
    unsigned units = rt->caps.compute_units ? rt->caps.compute_units : 1;
    perma_residency r;
    perma_residency_of(units, rt->caps.local_mem_size, (size_t)kernel_local, kernel_size, rt->group_size, &r);
    rt->resident_groups = r.limit;
    if (!rt->config.work_groups && rt->work_groups == r.limit)
        set_work_groups(rt, r.limit, r.why); /* the kernel's own figures, as the layout's gave */
    if (rt->work_groups <= r.limit)
        return PERMA_OK;
    if (rt->config.work_groups && rt->executor->persistent)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "config.work_groups %u is more persistent work-groups than %s holds at once for "
                               "this program (%u: %s); groups that are not all running could wait for each other "
                               "forever: ask for at most %u, or 0 (the runtime's choice)",
                               rt->config.work_groups, rt->caps.name, r.limit, r.why, r.limit);
    if (rt->config.work_groups)
        return PERMA_OK; /* host-driven: groups do not wait for each other */
    set_work_groups(rt, r.limit, r.why);
    *rebuild = true;
    return PERMA_OK;
}

/* Which device: platform and device indexes (or a platform by name) and
 * the sub-device, from the config, else PERMA_DEVICE. */
typedef struct device_choice {
    int platform, device;
    char platform_name[sizeof ((perma_device_entry *)0)->name]; /* "": by index */
    unsigned parts, part;
} device_choice;

static perma_status resolve(perma_runtime *rt, device_choice *c)
{
    c->platform = rt->config.platform_index;
    c->device = rt->config.device_index;
    c->parts = rt->config.sub_devices;
    c->part = rt->config.sub_device;
    c->platform_name[0] = '\0';
    if (c->platform < 0 && rt->config.platform_name) {
        if (!perma_platform_name_valid(rt->config.platform_name, strlen(rt->config.platform_name)))
            return perma_set_error(rt, PERMA_ERR_ARGUMENT, "config.platform_name '%s' is not a platform name "
                                   "(letters, digits, spaces and \"()._-\", starting with a letter)",
                                   rt->config.platform_name);
        snprintf(c->platform_name, sizeof c->platform_name, "%s", rt->config.platform_name);
    } else if (c->platform < 0 || c->device < 0) {
        const char *env = rt->settings.device;
        perma_device_entry entry = { .part = -1 };
        if (*env) {
            perma_status st = parse_device_env(rt, env, &entry);
            if (st != PERMA_OK)
                return st;
        }
        if (c->platform < 0) {
            c->platform = entry.platform;
            memcpy(c->platform_name, entry.name, sizeof c->platform_name);
        }
        if (c->device < 0)
            c->device = entry.device;
        if (c->parts < 2) {
            c->parts = entry.parts;
            c->part = entry.part < 0 ? 0 : (unsigned)entry.part;
        }
    }
    rt->config.platform_name = NULL; /* the caller's string is not kept */
    if (c->device < 0)
        c->device = 0;
    return PERMA_OK;
}

/* rt->platform: by index or by name. */
static perma_status find_platform(perma_runtime *rt, device_choice *c)
{
    char message[PERMA_MESSAGE_MAX];
    cl_uint platform_count = 0;
    cl_int err = clGetPlatformIDs(0, NULL, &platform_count);
    if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || (err == CL_SUCCESS && platform_count == 0)) {
        perma_no_platform_message(message, sizeof message);
        return perma_set_error(rt, PERMA_ERR_NO_PLATFORM, "%s", message);
    }
    PERMA_CL_CHECK(rt, "clGetPlatformIDs", err);
    if (!c->platform_name[0] && (cl_uint)c->platform >= platform_count)
        return perma_set_error(rt, PERMA_ERR_NO_DEVICE,
                               "OpenCL platform %d requested (PERMA_DEVICE or config), but only %u "
                               "platform(s) exist", c->platform, (unsigned)platform_count);
    cl_platform_id *platforms = calloc(platform_count, sizeof *platforms);
    if (!platforms)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory listing platforms");
    err = clGetPlatformIDs(platform_count, platforms, NULL);
    char listing[PERMA_MESSAGE_MAX / 2];
    if (err == CL_SUCCESS && c->platform_name[0])
        c->platform = perma_platform_find(platforms, platform_count, c->platform_name, listing, sizeof listing);
    if (err == CL_SUCCESS && c->platform >= 0)
        rt->platform = platforms[c->platform];
    free(platforms);
    PERMA_CL_CHECK(rt, "clGetPlatformIDs", err);
    if (c->platform < 0)
        return perma_set_error(rt, PERMA_ERR_NO_DEVICE, "no OpenCL platform's name or vendor contains '%s' "
                               "(PERMA_DEVICE or config); the platforms are: %s", c->platform_name, listing);
    return PERMA_OK;
}

/* rt->device on rt->platform, or its part. */
static perma_status find_device(perma_runtime *rt, const device_choice *c)
{
    cl_uint device_count = 0;
    cl_int err = clGetDeviceIDs(rt->platform, CL_DEVICE_TYPE_ALL, 0, NULL, &device_count);
    if (err != CL_DEVICE_NOT_FOUND)
        PERMA_CL_CHECK(rt, "clGetDeviceIDs", err);
    if ((cl_uint)c->device >= device_count)
        return perma_set_error(rt, PERMA_ERR_NO_DEVICE,
                               "OpenCL device %d:%d requested (PERMA_DEVICE or config%s%s%s), but platform "
                               "%d has %u device(s)", c->platform, c->device,
                               c->platform_name[0] ? "; platform '" : "", c->platform_name,
                               c->platform_name[0] ? "'" : "", c->platform, (unsigned)device_count);
    cl_device_id *devices = calloc(device_count, sizeof *devices);
    if (!devices)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory listing devices");
    err = clGetDeviceIDs(rt->platform, CL_DEVICE_TYPE_ALL, device_count, devices, NULL);
    rt->device = devices[c->device];
    free(devices);
    PERMA_CL_CHECK(rt, "clGetDeviceIDs", err);
    if (c->parts >= 2)
        return perma_open_sub_device(rt, c->platform, c->device, c->parts, c->part);
    return PERMA_OK;
}

/* rt->caps: what the device is, and its implementation's quirks. */
static perma_status query(perma_runtime *rt, const device_choice *c)
{
    perma_device_caps *caps = &rt->caps;
    cl_device_type type = 0;
    cl_ulong local_mem = 0;
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_TYPE)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_TYPE, sizeof type, &type, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_MAX_COMPUTE_UNITS)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof caps->compute_units,
                                   &caps->compute_units, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_LOCAL_MEM_SIZE)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_LOCAL_MEM_SIZE, sizeof local_mem, &local_mem, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_MAX_MEM_ALLOC_SIZE)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof caps->max_alloc,
                                   &caps->max_alloc, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_MAX_WORK_GROUP_SIZE)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof caps->max_group_size,
                                   &caps->max_group_size, NULL));
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_NAME)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_NAME, sizeof caps->name - 1, caps->name, NULL));
    cl_bool unified = CL_FALSE; /* the watchdog sees the watch page during a kernel (watchdog.c) */
    PERMA_CL_CHECK(rt, "clGetDeviceInfo(CL_DEVICE_HOST_UNIFIED_MEMORY)",
                   clGetDeviceInfo(rt->device, CL_DEVICE_HOST_UNIFIED_MEMORY, sizeof unified, &unified, NULL));
    if (c->parts >= 2) {
        size_t used = strlen(caps->name);
        snprintf(caps->name + used, sizeof caps->name - used, " (sub-device %u of %u)", c->part, c->parts);
    }
    caps->is_cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
    caps->watch_visible = caps->is_cpu || unified;
    caps->local_mem_size = (size_t)local_mem;
    /* PoCL keeps the programs it compiles in a cache of its own (POCL_CACHE_DIR). */
    char platform[256] = "";
    clGetPlatformInfo(rt->platform, CL_PLATFORM_NAME, sizeof platform - 1, platform, NULL);
    caps->caches_programs = strstr(platform, "Portable Computing Language") != NULL;
    return PERMA_OK;
}

/* The context and the command queue. */
static perma_status create_context(perma_runtime *rt)
{
    cl_int err;
    rt->context = clCreateContext(NULL, 1, &rt->device, NULL, NULL, &err);
    PERMA_CL_CHECK(rt, "clCreateContext", err);
    rt->queue = clCreateCommandQueue(rt->context, rt->device, 0, &err);
    PERMA_CL_CHECK(rt, "clCreateCommandQueue", err);
    return PERMA_OK;
}

perma_status perma_device_open(perma_runtime *rt)
{
    device_choice choice;
    perma_status st = resolve(rt, &choice);
    if (st != PERMA_OK)
        return st;
    char message[PERMA_MESSAGE_MAX];
    if (!perma_memory_driver_fits(message, sizeof message, true))
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "%s", message);
    st = find_platform(rt, &choice);
    if (st == PERMA_OK)
        st = find_device(rt, &choice);
    if (st == PERMA_OK)
        st = query(rt, &choice);
    if (st != PERMA_OK)
        return st;
    if (rt->group_size > rt->caps.max_group_size)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "group_size %u exceeds the device's maximum work-group size %zu",
                               rt->group_size, rt->caps.max_group_size);
    st = create_context(rt);
    if (st == PERMA_OK)
        choose_work_groups(rt);
    return st;
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
