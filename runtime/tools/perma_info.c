/*
 * perma-info: every OpenCL platform and device, whether perma (and the
 * Reyes renderer, which needs 64-bit atomics) can run on it and why not,
 * the persistent work-group count the runtime would choose and why, its
 * local memory per work-group, atomics support, double precision, the
 * preferred and native vector widths per type, how it splits into equal
 * sub-devices and the driver version: what a procedure author needs to know
 * (docs/writing-procedures.md).  --check builds and runs a small tree on each device
 * that can run perma.
 *
 *   perma-info [--json] [--devices LIST] [--check]
 * LIST is a device list (perma_device_list: "0:0,1:0", "intel", "0:0/2",
 * "all"); the default is every device, and then platforms without devices
 * are listed too.
 * Exit codes: 0 ok, 1 no OpenCL platform, a bad device list, an OpenCL
 * failure or a failed check, 2 bad usage.
 */
#include <perma.h>
#include <perma_cli.h>

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Work-items per group perma uses unless configured otherwise. */
#define DEFAULT_GROUP_SIZE 64

/* The scalar types whose vector widths a device reports, in the order of
 * the text and JSON output. */
#define VECTOR_TYPES 7
static const struct {
    const char *name;
    cl_device_info preferred, native;
} vector_types[VECTOR_TYPES] = {
    { "char", CL_DEVICE_PREFERRED_VECTOR_WIDTH_CHAR, CL_DEVICE_NATIVE_VECTOR_WIDTH_CHAR },
    { "short", CL_DEVICE_PREFERRED_VECTOR_WIDTH_SHORT, CL_DEVICE_NATIVE_VECTOR_WIDTH_SHORT },
    { "int", CL_DEVICE_PREFERRED_VECTOR_WIDTH_INT, CL_DEVICE_NATIVE_VECTOR_WIDTH_INT },
    { "long", CL_DEVICE_PREFERRED_VECTOR_WIDTH_LONG, CL_DEVICE_NATIVE_VECTOR_WIDTH_LONG },
    { "half", CL_DEVICE_PREFERRED_VECTOR_WIDTH_HALF, CL_DEVICE_NATIVE_VECTOR_WIDTH_HALF },
    { "float", CL_DEVICE_PREFERRED_VECTOR_WIDTH_FLOAT, CL_DEVICE_NATIVE_VECTOR_WIDTH_FLOAT },
    { "double", CL_DEVICE_PREFERRED_VECTOR_WIDTH_DOUBLE, CL_DEVICE_NATIVE_VECTOR_WIDTH_DOUBLE },
};

typedef struct device_info {
    char label[64];  /* "P:D" or "P:D/N.K" */
    char platform[256], platform_version[256], name[256], version[256], driver[256], c_version[256];
    char summary[PERMA_MESSAGE_MAX];
    char why_not[PERMA_MESSAGE_MAX];       /* empty: perma can run */
    char reyes_why_not[256];               /* empty: reyes-render can run */
    char check[PERMA_MESSAGE_MAX + 16];    /* --check: what happened */
    const char *type;
    cl_uint compute_units;
    cl_ulong local_mem, global_mem, max_alloc;
    bool local_mem_dedicated;  /* CL_LOCAL: dedicated; else carved out of global memory */
    size_t max_group;
    cl_uint max_sub_devices;  /* 0: no equal partitions */
    /* Per vector_types entry: CL_DEVICE_PREFERRED_ and _NATIVE_VECTOR_WIDTH_ (0: the type is
     * not supported, e.g. double without fp64). */
    cl_uint preferred_width[VECTOR_TYPES], native_width[VECTOR_TYPES];
    bool available, compiler, int32_atomics, int64_base, int64_extended, fp64, fp16, checked, check_ok;
    perma_status runtime_status;
} device_info;

/* Append a reason to a "; "-separated list. */
static void add_reason(char *list, size_t size, const char *reason)
{
    size_t used = strlen(list);
    snprintf(list + used, size - used, "%s%s", used ? "; " : "", reason);
}

/* The OpenCL C version a device compiles, as major * 10 + minor (0 if
 * unknown): "OpenCL C 1.2 ..." gives 12. */
static int c_version(const char *text)
{
    int major = 0, minor = 0;
    if (sscanf(text, "OpenCL C %d.%d", &major, &minor) != 2)
        return 0;
    return major * 10 + minor;
}

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
    cl_device_local_mem_type local_type = CL_LOCAL;
    clGetDeviceInfo(device, CL_DEVICE_LOCAL_MEM_TYPE, sizeof local_type, &local_type, NULL);
    info->local_mem_dedicated = local_type == CL_LOCAL;
    for (int t = 0; t < VECTOR_TYPES; ++t) {
        clGetDeviceInfo(device, vector_types[t].preferred, sizeof(cl_uint), &info->preferred_width[t], NULL);
        clGetDeviceInfo(device, vector_types[t].native, sizeof(cl_uint), &info->native_width[t], NULL);
    }
    /* Double precision: the extension (OpenCL 1.x) or a non-empty
     * CL_DEVICE_DOUBLE_FP_CONFIG (3.0 reports the feature that way). */
    cl_device_fp_config fp64_config = 0;
    clGetDeviceInfo(device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof fp64_config, &fp64_config, NULL);
    info->max_sub_devices = ref->sub_devices >= 2 ? 0 : equal_partitions(device);
    text(device, CL_DEVICE_OPENCL_C_VERSION, info->c_version, sizeof info->c_version);
    cl_bool flag = CL_FALSE;
    clGetDeviceInfo(device, CL_DEVICE_AVAILABLE, sizeof flag, &flag, NULL);
    info->available = flag == CL_TRUE;
    flag = CL_FALSE;
    clGetDeviceInfo(device, CL_DEVICE_COMPILER_AVAILABLE, sizeof flag, &flag, NULL);
    info->compiler = flag == CL_TRUE;
    size_t size = 0;
    clGetDeviceInfo(device, CL_DEVICE_EXTENSIONS, 0, NULL, &size);
    char *extensions = calloc(1, size + 1);
    if (extensions) {
        clGetDeviceInfo(device, CL_DEVICE_EXTENSIONS, size, extensions, NULL);
        info->int32_atomics = has_extension(extensions, "cl_khr_global_int32_base_atomics") &&
                              has_extension(extensions, "cl_khr_local_int32_base_atomics");
        info->int64_base = has_extension(extensions, "cl_khr_int64_base_atomics");
        info->int64_extended = has_extension(extensions, "cl_khr_int64_extended_atomics");
        info->fp64 = has_extension(extensions, "cl_khr_fp64") || fp64_config != 0;
        info->fp16 = has_extension(extensions, "cl_khr_fp16");
        free(extensions);
    }
    if (info->runtime_status == PERMA_OK)
        perma_destroy(rt);

    /* What perma needs: a device that compiles OpenCL C 1.2 (the generated
     * program is built with -cl-std=CL1.2), 32-bit global and local
     * atomics, groups of 64 work-items; the Reyes procedures also need
     * 64-bit atomics (atom_min of depth and color per sample). */
    char reason[320];
    if (!info->available)
        add_reason(info->why_not, sizeof info->why_not, "the device reports itself unavailable");
    if (!info->compiler)
        add_reason(info->why_not, sizeof info->why_not, "no OpenCL C compiler");
    if (c_version(info->c_version) < 12) {
        snprintf(reason, sizeof reason, "OpenCL C 1.2 needed, the device has '%s'", info->c_version);
        add_reason(info->why_not, sizeof info->why_not, reason);
    }
    if (!info->int32_atomics)
        add_reason(info->why_not, sizeof info->why_not,
                   "no 32-bit global and local atomics (cl_khr_global/local_int32_base_atomics)");
    if (info->max_group < DEFAULT_GROUP_SIZE) {
        snprintf(reason, sizeof reason, "work-groups of at most %zu work-items (set config.group_size)",
                 info->max_group);
        add_reason(info->why_not, sizeof info->why_not, reason);
    }
    if (info->runtime_status != PERMA_OK)
        add_reason(info->why_not, sizeof info->why_not, info->summary);
    if (info->why_not[0])
        snprintf(info->reyes_why_not, sizeof info->reyes_why_not, "perma cannot run");
    else if (!info->int64_base || !info->int64_extended)
        snprintf(info->reyes_why_not, sizeof info->reyes_why_not,
                 "no 64-bit atomics (cl_khr_int64_base_atomics and cl_khr_int64_extended_atomics)");
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* --check: a binary tree of depth CHECK_DEPTH built by one procedure. */
#define CHECK_DEPTH 12u
static const char *const check_source =
    "void split(perma_ctx *ctx, __local const uint *depth)\n"
    "{\n"
    "    if (*depth == 0) { reduce_leaves(ctx, 1u); return; }\n"
    "    uint child = *depth - 1u;\n"
    "    emit_split(ctx, &child);\n"
    "    emit_split(ctx, &child);\n"
    "}\n";

static void run_check(const perma_device_ref *ref, device_info *info)
{
    info->checked = true;
    perma_config config;
    perma_config_init(&config);
    perma_config_set_device(&config, ref);
    config.time_limit = 60;
    perma_runtime *rt;
    perma_error error;
    if (perma_create(&config, &rt, &error) != PERMA_OK) {
        snprintf(info->check, sizeof info->check, "failed: %s", error.message);
        return;
    }
    perma_procedure split = { .name = "split", .item_type = "uint", .item_size = 4, .source = check_source,
                              .function = "split", .emits = { { "split", 2 } } };
    perma_proc id;
    unsigned leaves = 0, root = CHECK_DEPTH;
    perma_stats stats;
    double start = now_seconds();
    perma_status st = perma_register(rt, &split, &id);
    if (st == PERMA_OK)
        st = perma_declare_reduction(rt, "leaves", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &leaves);
    if (st == PERMA_OK)
        st = perma_build(rt);
    double built = now_seconds();
    if (st == PERMA_OK)
        st = perma_seed(rt, id, &root, 1);
    if (st == PERMA_OK)
        st = perma_run(rt);
    if (st == PERMA_OK)
        st = perma_get_stats(rt, &stats);
    if (st != PERMA_OK) {
        snprintf(info->check, sizeof info->check, "failed: %s", perma_errmsg(rt));
    } else if (leaves != 1u << CHECK_DEPTH) {
        snprintf(info->check, sizeof info->check, "failed: %u leaves of a depth-%u tree, expected %u", leaves,
                 CHECK_DEPTH, 1u << CHECK_DEPTH);
    } else {
        info->check_ok = true;
        char stacks[96] = "; work-first off";
        if (stats.stack_items)
            snprintf(stacks, sizeof stacks, "; work-first stacks of %u items, %llu of the nodes ran from them",
                     stats.stack_items, (unsigned long long)stats.stacked_items);
        snprintf(info->check, sizeof info->check, "ok: %u leaves of a depth-%u tree in %.3f s (build %.2f s) on %u "
                 "work-groups (%s), %zu bytes of __local memory each%s", leaves, CHECK_DEPTH, stats.seconds,
                 built - start, stats.work_groups, stats.work_groups_reason, stats.kernel_local_bytes, stacks);
    }
    perma_destroy(rt);
}

/* With the default list, platforms that report no device (they are not in
 * the list) are named too (on stderr with --json). */
static void list_platforms_without_devices(int json)
{
    cl_platform_id platforms[64];
    cl_uint count = 0;
    if (clGetPlatformIDs(64, platforms, &count) != CL_SUCCESS)
        return;
    for (cl_uint p = 0; p < count && p < 64; ++p) {
        cl_uint devices = 0;
        cl_int err = clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 0, NULL, &devices);
        if (err == CL_SUCCESS && devices > 0)
            continue;
        char name[256] = "";
        clGetPlatformInfo(platforms[p], CL_PLATFORM_NAME, sizeof name - 1, name, NULL);
        fprintf(json ? stderr : stdout, "platform %u  %s: no devices (%s)\n", (unsigned)p, name,
                err == CL_SUCCESS || err == CL_DEVICE_NOT_FOUND ? "none reported" : "clGetDeviceIDs failed");
    }
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
    printf("  memory          local %llu bytes per work-group (%s), global %llu MiB, largest allocation %llu MiB\n",
           (unsigned long long)i->local_mem, i->local_mem_dedicated ? "dedicated" : "in global memory",
           (unsigned long long)(i->global_mem >> 20), (unsigned long long)(i->max_alloc >> 20));
    printf("  atomics         32-bit global+local: %s, 64-bit base (atom_add, atom_xchg): %s, "
           "64-bit extended (atom_min, atom_max): %s\n",
           i->int32_atomics ? "yes" : "no", i->int64_base ? "yes" : "no", i->int64_extended ? "yes" : "no");
    printf("  floating point  double (cl_khr_fp64): %s, half (cl_khr_fp16): %s\n", i->fp64 ? "yes" : "no",
           i->fp16 ? "yes" : "no");
    printf("  vector widths   preferred");
    for (int t = 0; t < VECTOR_TYPES; ++t)
        printf("%s %s %u", t ? "," : "", vector_types[t].name, (unsigned)i->preferred_width[t]);
    printf("\n                  native   ");
    for (int t = 0; t < VECTOR_TYPES; ++t)
        printf("%s %s %u", t ? "," : "", vector_types[t].name, (unsigned)i->native_width[t]);
    printf("\n");
    if (i->max_sub_devices >= 2)
        printf("  sub-devices     equal parts, 2..%u (PERMA_DEVICE=%s/2 lists 2 of them)\n",
               (unsigned)i->max_sub_devices, i->label);
    else
        printf("  sub-devices     %s\n", strchr(i->label, '/') ? "this is one" : "no equal partitions");
    if (i->why_not[0]) {
        printf("  perma           cannot run: %s\n", i->why_not);
    } else {
        printf("  perma           can run; would use %s\n", i->summary);
        printf("  reyes-render    %s%s\n", i->reyes_why_not[0] ? "cannot run: " : "can run",
               i->reyes_why_not);
    }
    if (i->checked)
        printf("  check           %s\n", i->check);
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
    printf(", \"opencl_c_version\": ");
    json_string(i->c_version);
    printf(", \"can_run\": %s, \"why_not\": ", i->why_not[0] ? "false" : "true");
    json_string(i->why_not);
    printf(", \"reyes_can_run\": %s, \"reyes_why_not\": ",
           i->why_not[0] || i->reyes_why_not[0] ? "false" : "true");
    json_string(i->reyes_why_not);
    if (i->checked) {
        printf(", \"check_ok\": %s, \"check\": ", i->check_ok ? "true" : "false");
        json_string(i->check);
    }
    printf(", \"compute_units\": %u, \"max_work_group_size\": %zu, \"local_mem_bytes\": %llu, "
           "\"global_mem_bytes\": %llu, \"max_alloc_bytes\": %llu, \"int32_atomics\": %s, "
           "\"int64_base_atomics\": %s, \"int64_extended_atomics\": %s, \"runtime_ok\": %s, \"runtime\": ",
           (unsigned)i->compute_units, i->max_group, (unsigned long long)i->local_mem,
           (unsigned long long)i->global_mem, (unsigned long long)i->max_alloc, i->int32_atomics ? "true" : "false",
           i->int64_base ? "true" : "false", i->int64_extended ? "true" : "false",
           i->runtime_status == PERMA_OK ? "true" : "false");
    json_string(i->summary);
    printf(", \"local_mem_dedicated\": %s, \"fp64\": %s, \"fp16\": %s",
           i->local_mem_dedicated ? "true" : "false", i->fp64 ? "true" : "false", i->fp16 ? "true" : "false");
    const char *kinds[2] = { "preferred_vector_width", "native_vector_width" };
    for (int k = 0; k < 2; ++k) {
        printf(", \"%s\": {", kinds[k]);
        for (int t = 0; t < VECTOR_TYPES; ++t)
            printf("%s\"%s\": %u", t ? ", " : "", vector_types[t].name,
                   (unsigned)(k ? i->native_width[t] : i->preferred_width[t]));
        printf("}");
    }
    printf("}");
}

int main(int argc, char **argv)
{
    int json = 0, check = 0;
    const char *list = "all";
    const perma_cli_option rows[] = {
        { PERMA_CLI_FLAG("json", &json, "print JSON (for scripts) instead of text") },
        { PERMA_CLI_TEXT("devices", "LIST", &list, "the devices of a device list (default all)") },
        { PERMA_CLI_FLAG("check", &check,
                         "also build and run a small tree on each device perma can run on (exit status 1 if one "
                         "fails)") },
    };
    const perma_cli_table table = { "options", rows, sizeof rows / sizeof rows[0] };
    const perma_cli cli = {
        .program = "perma-info",
        .synopsis = "[--json] [--devices LIST] [--check]",
        .about = "Lists every OpenCL platform and device, whether perma and reyes-render can run on\n"
                 "it (and why not), how perma would use it and what a procedure may use there:\n"
                 "local memory per work-group, 32- and 64-bit atomics, double and half precision,\n"
                 "preferred and native vector widths.\n"
                 "LIST: comma-separated P:D (a device), NAME[:D] (device D, default 0, of the\n"
                 "platform whose name or vendor contains NAME: intel, pocl), P:D/N (it split into\n"
                 "N equal sub-devices), P:D/N.K (the K-th of them) or 'all' (the default).",
        .tables = &table,
        .table_count = 1,
        .notes = "exit status: 0 ok, 1 no OpenCL platform, a bad device list, an OpenCL failure or a\n"
                 "failed check, 2 bad usage",
    };
    char message[PERMA_CLI_MESSAGE_MAX];
    perma_cli_status parsed = perma_cli_parse(&cli, argc, argv, message, sizeof message);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    perma_device_ref refs[PERMA_MAX_DEVICES];
    unsigned count = 0;
    perma_error error;
    if (perma_device_list(list, refs, PERMA_MAX_DEVICES, &count, &error) != PERMA_OK) {
        fprintf(stderr, "perma-info: %s\n", error.message);
        return 1;
    }
    if (strcmp(list, "all") == 0)
        list_platforms_without_devices(json);
    if (json)
        printf("{\"perma_version\": \"%s\", \"devices\": [\n", PERMA_VERSION_STRING);
    bool failed = false;
    for (unsigned k = 0; k < count; ++k) {
        device_info info;
        describe(&refs[k], &info);
        if (check && !info.why_not[0]) {
            run_check(&refs[k], &info);
            failed |= !info.check_ok;
        }
        if (json)
            print_json(&info, &refs[k], k == 0);
        else
            print_text(&info);
    }
    if (json)
        printf("\n]}\n");
    return failed ? 1 : 0;
}
