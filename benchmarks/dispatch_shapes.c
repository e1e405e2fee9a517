/* perma-dispatch-shapes: which shapes of a dispatch loop an OpenCL CPU
 * compiler vectorises across work-items (docs/writing-procedures.md,
 * "Code the compiler can vectorise").  Runs each kernel of
 * benchmarks/dispatch_shapes.cl over the same keys and prints the time per
 * item, best of --repeat runs, and whether its results equal the host's.
 *
 *     perma-dispatch-shapes [--quick] [--repeat N] [--groups N] [--platform I]
 *
 * Exit status 0 if every result was right, 1 if one was wrong or OpenCL
 * failed, 2 on bad usage. */
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "plain_work.h"
#include "dispatch_shapes_work.h"

extern const char plain_work_source[];
extern const char dispatch_shapes_work_source[];
extern const char dispatch_shapes_source[];

enum { GROUP = 64, BATCH = 256 };

struct shape {
    const char *kernel;
    const char *what;
    uint64_t (*reference)(uint64_t);
    int sums; /* also stores per-work-item sums after the items */
};

static const struct shape shapes[] = {
    { "strided", "work-item loop over a batch (perma's dispatch), inlined", shapes_item, 0 },
    { "strided_call", "work-item loop over a batch, procedure a call", shapes_item, 0 },
    { "rounds", "one item per work-item between barriers, inlined", shapes_item, 0 },
    { "rounds_call", "one item per work-item between barriers, a call", shapes_item, 0 },
    { "rounds_sum", "rounds + a scalar accumulator across barriers", shapes_item, 1 },
    { "rounds_lane", "rounds + an accumulator array, data-dependent index", shapes_item, 1 },
    { "strided_loop", "work-item loop, 0-7 hashes per item (a loop)", shapes_item_loop, 0 },
    { "rounds_loop", "rounds, 0-7 hashes per item (a loop)", shapes_item_loop, 0 },
    { "strided_double", "work-item loop, double with floor and a branch", shapes_item_double, 0 },
    { "rounds_double", "rounds, double with floor and a branch", shapes_item_double, 0 },
};

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int usage(const char *message)
{
    fprintf(stderr, "perma-dispatch-shapes: %s\nusage: perma-dispatch-shapes [--quick] [--repeat N] [--groups N] "
                    "[--platform I]\n", message);
    return 2;
}

/* A whole number in min..max from text (NULL: the option had no value). */
static int parse_number(const char *text, unsigned min, unsigned max, unsigned *out)
{
    char *end;
    if (!text || *text < '0' || *text > '9')
        return 0;
    unsigned long v = strtoul(text, &end, 10);
    if (*end || v < min || v > max)
        return 0;
    *out = (unsigned)v;
    return 1;
}

#define CHECK(call, what)                                                  \
    do {                                                                   \
        cl_int check_err_ = (call);                                        \
        if (check_err_ != CL_SUCCESS) {                                    \
            fprintf(stderr, "perma-dispatch-shapes: %s failed (%d)\n", what, check_err_); \
            return 1;                                                      \
        }                                                                  \
    } while (0)

int main(int argc, char **argv)
{
    unsigned repeat = 5, groups = 2, platform_index = 0, log2_items = 22;
    for (int i = 1; i < argc; ++i) {
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            printf("usage: perma-dispatch-shapes [--quick] [--repeat N] [--groups N] [--platform I]\n"
                   "Times one-item work in several dispatch shapes on an OpenCL device (docs/benchmarks.md,\n"
                   "Dispatch shapes and vectorisation); exit status 1 if a result was wrong.\n");
            return 0;
        } else if (!strcmp(argv[i], "--quick"))
            log2_items = 14;
        else if (!strcmp(argv[i], "--repeat") && parse_number(value, 1, 1000, &repeat))
            ++i;
        else if (!strcmp(argv[i], "--groups") && parse_number(value, 1, 64, &groups))
            ++i;
        else if (!strcmp(argv[i], "--platform") && parse_number(value, 0, 63, &platform_index))
            ++i;
        else
            return usage("bad option or value (--repeat 1..1000, --groups 1..64, --platform 0..63)");
    }
    const size_t n = (size_t)1 << log2_items;
    const cl_uint per = (cl_uint)(n / groups / BATCH * BATCH); /* items per group, whole batches */
    const size_t used = (size_t)per * groups, threads = (size_t)GROUP * groups;

    cl_platform_id platforms[64];
    cl_uint platform_count = 0;
    CHECK(clGetPlatformIDs(64, platforms, &platform_count), "clGetPlatformIDs");
    if (platform_index >= platform_count)
        return usage("--platform: no such OpenCL platform");
    cl_device_id device;
    CHECK(clGetDeviceIDs(platforms[platform_index], CL_DEVICE_TYPE_ALL, 1, &device, NULL), "clGetDeviceIDs");
    char name[256] = "";
    clGetDeviceInfo(device, CL_DEVICE_NAME, sizeof name, name, NULL);
    cl_int err;
    cl_context context = clCreateContext(NULL, 1, &device, NULL, NULL, &err);
    CHECK(err, "clCreateContext");
    cl_command_queue queue = clCreateCommandQueue(context, device, 0, &err);
    CHECK(err, "clCreateCommandQueue");
    const char *sources[] = { plain_work_source, dispatch_shapes_work_source, dispatch_shapes_source };
    cl_program program = clCreateProgramWithSource(context, 3, sources, NULL, &err);
    CHECK(err, "clCreateProgramWithSource");
    char options[128];
    snprintf(options, sizeof options, "-cl-std=CL1.2 -DSHAPES_GROUP=%uu -DSHAPES_BATCH=%uu", (unsigned)GROUP,
             (unsigned)BATCH);
    if (clBuildProgram(program, 1, &device, options, NULL, NULL) != CL_SUCCESS) {
        static char log[1 << 16];
        clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, sizeof log, log, NULL);
        fprintf(stderr, "perma-dispatch-shapes: benchmarks/dispatch_shapes.cl does not build:\n%s\n", log);
        return 1;
    }

    uint64_t *keys = malloc(n * sizeof *keys), *results = malloc((n + threads) * sizeof *results);
    if (!keys || !results)
        return usage("out of memory");
    for (size_t i = 0; i < n; ++i)
        keys[i] = splitmix64(i);
    cl_mem in = clCreateBuffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof *keys, keys, &err);
    CHECK(err, "clCreateBuffer");
    cl_mem out = clCreateBuffer(context, CL_MEM_READ_WRITE, (n + threads) * sizeof *results, NULL, &err);
    CHECK(err, "clCreateBuffer");

    printf("device %s, %u groups of %u, batches of %u, %zu items, best of %u\n", name, groups, (unsigned)GROUP,
           (unsigned)BATCH, used, repeat);
    printf("%-15s %9s %9s %6s  %s\n", "kernel", "ns/item", "vs first", "check", "shape");
    int wrong = 0;
    double first = 0;
    for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; ++s) {
        const struct shape *sh = &shapes[s];
        cl_kernel kernel = clCreateKernel(program, sh->kernel, &err);
        CHECK(err, "clCreateKernel");
        CHECK(clSetKernelArg(kernel, 0, sizeof in, &in), "clSetKernelArg");
        CHECK(clSetKernelArg(kernel, 1, sizeof out, &out), "clSetKernelArg");
        CHECK(clSetKernelArg(kernel, 2, sizeof per, &per), "clSetKernelArg");
        size_t local = GROUP;
        double best = 1e30;
        for (unsigned r = 0; r <= repeat; ++r) { /* run 0 warms up (PoCL compiles at the first enqueue) */
            double t0 = now();
            CHECK(clEnqueueNDRangeKernel(queue, kernel, 1, NULL, &threads, &local, 0, NULL, NULL), "enqueue");
            CHECK(clFinish(queue), "clFinish");
            double t = now() - t0;
            if (r && t < best)
                best = t;
        }
        CHECK(clEnqueueReadBuffer(queue, out, CL_TRUE, 0, (used + threads) * sizeof *results, results, 0, NULL, NULL),
              "clEnqueueReadBuffer");
        int ok = 1;
        uint64_t total = 0, sums = 0;
        for (size_t i = 0; i < used; ++i) {
            ok = ok && results[i] == sh->reference(keys[i]);
            total += results[i];
        }
        if (sh->sums) {
            for (size_t t = 0; t < threads; ++t)
                sums += results[used + t];
            ok = ok && sums == total;
        }
        wrong |= !ok;
        double ns = best * 1e9 / (double)used;
        if (s == 0)
            first = ns;
        printf("%-15s %9.2f %8.2fx %6s  %s\n", sh->kernel, ns, first / ns, ok ? "ok" : "WRONG", sh->what);
        clReleaseKernel(kernel);
    }
    clReleaseMemObject(in);
    clReleaseMemObject(out);
    clReleaseProgram(program);
    clReleaseCommandQueue(queue);
    clReleaseContext(context);
    free(keys);
    free(results);
    return wrong ? 1 : 0;
}
