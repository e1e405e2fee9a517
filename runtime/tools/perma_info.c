/*
 * perma-info: the OpenCL platforms and devices perma can use, and for each
 * device the persistent work-group count the runtime would choose and why,
 * its local memory, atomics support, how it splits into equal sub-devices
 * and the driver (PoCL) version.
 *
 *   perma-info [--json] [--devices LIST]
 * LIST is a device list (perma_device_list: "0:0,1:0", "0:0/2", "all");
 * the default is every device.
 * Exit codes: 0 ok, 1 no OpenCL platform, a bad device list or an OpenCL
 * failure, 2 bad usage.
 */
#include <perma.h>

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct device_info {
    char label[64];  /* "P:D" or "P:D/N.K" */
    char platform[256], platform_version[256], name[256], version[256], driver[256];
    char summary[PERMA_MESSAGE_MAX];
    const char *type;
    cl_uint compute_units;
    cl_ulong local_mem, global_mem, max_alloc;
    size_t max_group;
    cl_uint max_sub_devices;  /* 0: no equal partitions */
    bool int32_atomics, int64_base, int64_extended;
    perma_status runtime_status;
} device_info;

static void text(cl_device_id d, cl_device_info what, char *out, size_t size)
{
    out[0] = '\0';
    clGetDeviceInfo(d, what, size - 1, out, NULL);
}

static bool has_extension(const char *extensions, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = extensions; (p = strstr(p, name)) != NULL; p += n)
        if ((p == extensions || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

/* Most equal sub-devices the device splits into; 0 if it does not. */
static cl_uint equal_partitions(cl_device_id device)
{
    cl_device_partition_property props[16];
    size_t size = 0;
    cl_uint most = 0;
    if (clGetDeviceInfo(device, CL_DEVICE_PARTITION_PROPERTIES, sizeof props, props, &size) != CL_SUCCESS)
        return 0;
    for (size_t i = 0; i < size / sizeof props[0]; ++i)
        if (props[i] == CL_DEVICE_PARTITION_EQUALLY
            && clGetDeviceInfo(device, CL_DEVICE_PARTITION_MAX_SUB_DEVICES, sizeof most, &most, NULL)
                   == CL_SUCCESS)
            return most;
    return 0;
}

/* The device the list names: a whole device, or (through a runtime on it)
 * the sub-device the runtime made. */
static void describe(const perma_device_ref *ref, device_info *info)
{
    memset(info, 0, sizeof *info);
    perma_device_ref_format(ref, info->label, sizeof info->label);
    cl_platform_id platforms[64];
    cl_device_id devices[64];
    cl_uint count = 0;
    clGetPlatformIDs(64, platforms, NULL);
    cl_platform_id platform = platforms[ref->platform_index];
    clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 64, devices, &count);
    cl_device_id device = devices[ref->device_index];

    /* What the runtime itself would choose on this device. */
    perma_config config;
    perma_config_init(&config);
    perma_config_set_device(&config, ref);
    perma_runtime *rt;
    perma_error error;
    info->runtime_status = perma_create(&config, &rt, &error);
    if (info->runtime_status == PERMA_OK) {
        snprintf(info->summary, sizeof info->summary, "%s", perma_device_summary(rt));
        device = perma_cl_device(rt);
    } else {
        snprintf(info->summary, sizeof info->summary, "%s", error.message);
    }

    clGetPlatformInfo(platform, CL_PLATFORM_NAME, sizeof info->platform - 1, info->platform, NULL);
    clGetPlatformInfo(platform, CL_PLATFORM_VERSION, sizeof info->platform_version - 1, info->platform_version, NULL);
    text(device, CL_DEVICE_NAME, info->name, sizeof info->name);
    text(device, CL_DEVICE_VERSION, info->version, sizeof info->version);
    text(device, CL_DRIVER_VERSION, info->driver, sizeof info->driver);
    cl_device_type type = 0;
    clGetDeviceInfo(device, CL_DEVICE_TYPE, sizeof type, &type, NULL);
    info->type = type & CL_DEVICE_TYPE_CPU ? "CPU" : type & CL_DEVICE_TYPE_GPU ? "GPU"
               : type & CL_DEVICE_TYPE_ACCELERATOR ? "accelerator" : "other";
    clGetDeviceInfo(device, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof info->compute_units, &info->compute_units, NULL);
    clGetDeviceInfo(device, CL_DEVICE_LOCAL_MEM_SIZE, sizeof info->local_mem, &info->local_mem, NULL);
    clGetDeviceInfo(device, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof info->global_mem, &info->global_mem, NULL);
    clGetDeviceInfo(device, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof info->max_alloc, &info->max_alloc, NULL);
    clGetDeviceInfo(device, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof info->max_group, &info->max_group, NULL);
    info->max_sub_devices = ref->sub_devices >= 2 ? 0 : equal_partitions(device);
    size_t size = 0;
    clGetDeviceInfo(device, CL_DEVICE_EXTENSIONS, 0, NULL, &size);
    char *extensions = calloc(1, size + 1);
    if (extensions) {
        clGetDeviceInfo(device, CL_DEVICE_EXTENSIONS, size, extensions, NULL);
        info->int32_atomics = has_extension(extensions, "cl_khr_global_int32_base_atomics") &&
                              has_extension(extensions, "cl_khr_local_int32_base_atomics");
        info->int64_base = has_extension(extensions, "cl_khr_int64_base_atomics");
        info->int64_extended = has_extension(extensions, "cl_khr_int64_extended_atomics");
        free(extensions);
    }
    if (info->runtime_status == PERMA_OK)
        perma_destroy(rt);
}

static void json_string(const char *s)
{
    putchar('"');
    for (; *s; ++s) {
        if (*s == '"' || *s == '\\')
            printf("\\%c", *s);
        else if ((unsigned char)*s < 0x20)
            printf("\\u%04x", *s);
        else
            putchar(*s);
    }
    putchar('"');
}

static void print_text(const device_info *i)
{
    printf("device %s  %s (%s)\n", i->label, i->name, i->type);
    printf("  platform        %s, %s\n", i->platform, i->platform_version);
    printf("  device version  %s, driver %s\n", i->version, i->driver);
    printf("  compute units   %u, max work-group size %zu\n", (unsigned)i->compute_units, i->max_group);
    printf("  memory          local %llu bytes, global %llu MiB, largest allocation %llu MiB\n",
           (unsigned long long)i->local_mem, (unsigned long long)(i->global_mem >> 20),
           (unsigned long long)(i->max_alloc >> 20));
    printf("  atomics         32-bit global+local: %s, 64-bit base: %s, 64-bit extended (atom_min): %s\n",
           i->int32_atomics ? "yes" : "no", i->int64_base ? "yes" : "no", i->int64_extended ? "yes" : "no");
    if (i->max_sub_devices >= 2)
        printf("  sub-devices     equal parts, 2..%u (PERMA_DEVICE=%s/2 lists 2 of them)\n",
               (unsigned)i->max_sub_devices, i->label);
    else
        printf("  sub-devices     %s\n", strchr(i->label, '/') ? "this is one" : "no equal partitions");
    printf("  perma would use %s\n", i->summary);
}

static void print_json(const device_info *i, const perma_device_ref *ref, bool first)
{
    printf("%s    {\"device\": \"%s\", \"platform_index\": %d, \"device_index\": %d, "
           "\"sub_devices\": %u, \"sub_device\": %u, \"max_sub_devices\": %u, \"name\": ",
           first ? "" : ",\n", i->label, ref->platform_index, ref->device_index, ref->sub_devices,
           ref->sub_device, (unsigned)i->max_sub_devices);
    json_string(i->name);
    printf(", \"type\": \"%s\", \"platform\": ", i->type);
    json_string(i->platform);
    printf(", \"platform_version\": ");
    json_string(i->platform_version);
    printf(", \"device_version\": ");
    json_string(i->version);
    printf(", \"driver_version\": ");
    json_string(i->driver);
    printf(", \"compute_units\": %u, \"max_work_group_size\": %zu, \"local_mem_bytes\": %llu, "
           "\"global_mem_bytes\": %llu, \"max_alloc_bytes\": %llu, \"int32_atomics\": %s, "
           "\"int64_base_atomics\": %s, \"int64_extended_atomics\": %s, \"runtime_ok\": %s, \"runtime\": ",
           (unsigned)i->compute_units, i->max_group, (unsigned long long)i->local_mem,
           (unsigned long long)i->global_mem, (unsigned long long)i->max_alloc, i->int32_atomics ? "true" : "false",
           i->int64_base ? "true" : "false", i->int64_extended ? "true" : "false",
           i->runtime_status == PERMA_OK ? "true" : "false");
    json_string(i->summary);
    printf("}");
}

int main(int argc, char **argv)
{
    bool json = false;
    const char *list = "all";
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if (strcmp(argv[i], "--devices") == 0 && i + 1 < argc) {
            list = argv[++i];
        } else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            printf("usage: perma-info [--json] [--devices LIST]\n"
                   "Lists the OpenCL devices perma can use and how it would use them.\n"
                   "LIST: comma-separated P:D (a device), P:D/N (it split into N equal\n"
                   "sub-devices), P:D/N.K (the K-th of them) or 'all' (the default).\n");
            return 0;
        } else if (strcmp(argv[i], "--version") == 0) {
            printf("perma-info %s\n", PERMA_VERSION_STRING);
            return 0;
        } else {
            fprintf(stderr, "perma-info: %s '%s' (try --help)\n",
                    strcmp(argv[i], "--devices") == 0 ? "missing the list after" : "unknown option", argv[i]);
            return 2;
        }
    }
    perma_device_ref refs[PERMA_MAX_DEVICES];
    unsigned count = 0;
    perma_error error;
    if (perma_device_list(list, refs, PERMA_MAX_DEVICES, &count, &error) != PERMA_OK) {
        fprintf(stderr, "perma-info: %s\n", error.message);
        return 1;
    }
    if (json)
        printf("{\"perma_version\": \"%s\", \"devices\": [\n", PERMA_VERSION_STRING);
    for (unsigned k = 0; k < count; ++k) {
        device_info info;
        describe(&refs[k], &info);
        if (json)
            print_json(&info, &refs[k], k == 0);
        else
            print_text(&info);
    }
    if (json)
        printf("\n]}\n");
    return 0;
}
