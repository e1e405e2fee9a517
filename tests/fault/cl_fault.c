/* See cl_fault.h.  Each wrapper looks up the real function with
 * dlsym(RTLD_NEXT) and forwards to it unless this call is the armed one. */
#define _GNU_SOURCE
#define CL_TARGET_OPENCL_VERSION 120
#include "cl_fault.h"
#include "perma_abi.h"

#include <CL/cl.h>
#include <dlfcn.h>
#include <stddef.h>
#include <string.h>

static unsigned long calls, armed_at;
static const char *failed_call;

void cl_fault_arm(unsigned long n)
{
    calls = 0;
    armed_at = n;
    failed_call = NULL;
}

unsigned long cl_fault_calls(void) { return calls; }
const char *cl_fault_failed_call(void) { return failed_call; }

static cl_fault_transfers transfers;

void cl_fault_transfers_reset(void)
{
    memset(&transfers, 0, sizeof transfers);
}

cl_fault_transfers cl_fault_transfers_since_launch(void)
{
    return transfers;
}

static void count_transfer(unsigned long long *total, size_t bytes)
{
    if (!transfers.launches)
        return;
    *total += bytes;
    transfers.calls++;
    if (bytes > transfers.largest)
        transfers.largest = bytes;
}

/* Count the call; true if it must fail. */
static int fault_now(const char *name)
{
    ++calls;
    if (armed_at && calls == armed_at) {
        failed_call = name;
        return 1;
    }
    return 0;
}

#define REAL(name) ((__typeof__(&name))dlsym(RTLD_NEXT, #name))

/* Calls that return a status. */
#define WRAP_STATUS(name, params, args)                 \
    cl_int name params                                  \
    {                                                   \
        if (fault_now(#name))                           \
            return CL_OUT_OF_RESOURCES;                 \
        return REAL(name) args;                         \
    }

/* Calls that return an object and report through errcode_ret. */
#define WRAP_OBJECT(type, name, params, args)           \
    type name params                                    \
    {                                                   \
        if (fault_now(#name)) {                         \
            if (errcode_ret)                            \
                *errcode_ret = CL_OUT_OF_RESOURCES;     \
            return NULL;                                \
        }                                               \
        return REAL(name) args;                         \
    }

WRAP_STATUS(clGetPlatformIDs, (cl_uint n, cl_platform_id *p, cl_uint *count), (n, p, count))
WRAP_STATUS(clGetDeviceIDs, (cl_platform_id p, cl_device_type t, cl_uint n, cl_device_id *d, cl_uint *count),
            (p, t, n, d, count))
static struct {
    cl_uint units;
    cl_ulong local_bytes;
    size_t kernel_group_size;
    cl_ulong kernel_local_bytes;
} pretend;

void cl_fault_pretend_gpu(unsigned compute_units, unsigned long local_bytes, size_t kernel_group_size,
                          unsigned long kernel_local_bytes)
{
    pretend.units = compute_units;
    pretend.local_bytes = local_bytes;
    pretend.kernel_group_size = kernel_group_size;
    pretend.kernel_local_bytes = kernel_local_bytes;
}

/* The pretended answer to a query of `size` bytes, if there is one. */
static int pretended(const void *answer, size_t answer_size, size_t size, void *value, size_t *size_ret)
{
    if (value && size < answer_size)
        return 0;
    if (value)
        memcpy(value, answer, answer_size);
    if (size_ret)
        *size_ret = answer_size;
    return 1;
}

cl_int clGetDeviceInfo(cl_device_id d, cl_device_info i, size_t s, void *v, size_t *r)
{
    if (fault_now("clGetDeviceInfo"))
        return CL_OUT_OF_RESOURCES;
    cl_device_type gpu = CL_DEVICE_TYPE_GPU;
    if (pretend.units && ((i == CL_DEVICE_TYPE && pretended(&gpu, sizeof gpu, s, v, r)) ||
                          (i == CL_DEVICE_MAX_COMPUTE_UNITS && pretended(&pretend.units, sizeof pretend.units, s, v, r)) ||
                          (i == CL_DEVICE_LOCAL_MEM_SIZE &&
                           pretended(&pretend.local_bytes, sizeof pretend.local_bytes, s, v, r))))
        return CL_SUCCESS;
    return REAL(clGetDeviceInfo)(d, i, s, v, r);
}

cl_int clGetKernelWorkGroupInfo(cl_kernel k, cl_device_id d, cl_kernel_work_group_info i, size_t s, void *v,
                                size_t *r)
{
    if (fault_now("clGetKernelWorkGroupInfo"))
        return CL_OUT_OF_RESOURCES;
    if (pretend.units && ((i == CL_KERNEL_WORK_GROUP_SIZE &&
                           pretended(&pretend.kernel_group_size, sizeof pretend.kernel_group_size, s, v, r)) ||
                          (i == CL_KERNEL_LOCAL_MEM_SIZE && pretend.kernel_local_bytes &&
                           pretended(&pretend.kernel_local_bytes, sizeof pretend.kernel_local_bytes, s, v, r))))
        return CL_SUCCESS;
    return REAL(clGetKernelWorkGroupInfo)(k, d, i, s, v, r);
}
WRAP_OBJECT(cl_context, clCreateContext,
            (const cl_context_properties *p, cl_uint n, const cl_device_id *d,
             void (CL_CALLBACK *f)(const char *, const void *, size_t, void *), void *u, cl_int *errcode_ret),
            (p, n, d, f, u, errcode_ret))
WRAP_OBJECT(cl_command_queue, clCreateCommandQueue,
            (cl_context c, cl_device_id d, cl_command_queue_properties p, cl_int *errcode_ret),
            (c, d, p, errcode_ret))
WRAP_OBJECT(cl_program, clCreateProgramWithSource,
            (cl_context c, cl_uint n, const char **s, const size_t *l, cl_int *errcode_ret), (c, n, s, l, errcode_ret))
WRAP_STATUS(clBuildProgram,
            (cl_program p, cl_uint n, const cl_device_id *d, const char *o,
             void (CL_CALLBACK *f)(cl_program, void *), void *u),
            (p, n, d, o, f, u))
WRAP_OBJECT(cl_kernel, clCreateKernel, (cl_program p, const char *name, cl_int *errcode_ret), (p, name, errcode_ret))
WRAP_STATUS(clSetKernelArg, (cl_kernel k, cl_uint i, size_t s, const void *v), (k, i, s, v))
WRAP_OBJECT(cl_mem, clCreateBuffer, (cl_context c, cl_mem_flags f, size_t s, void *h, cl_int *errcode_ret),
            (c, f, s, h, errcode_ret))
/* Calls that return a status and are counted first. */
#define WRAP_COUNTED(name, count, params, args)         \
    cl_int name params                                  \
    {                                                   \
        if (fault_now(#name))                           \
            return CL_OUT_OF_RESOURCES;                 \
        count;                                          \
        return REAL(name) args;                         \
    }

WRAP_COUNTED(clEnqueueWriteBuffer, count_transfer(&transfers.written, s),
             (cl_command_queue q, cl_mem m, cl_bool b, size_t o, size_t s, const void *p, cl_uint n,
              const cl_event *w, cl_event *e),
             (q, m, b, o, s, p, n, w, e))
static unsigned stalls_to_report, stalls_reported;

void cl_fault_report_stall(unsigned n)
{
    stalls_to_report = n;
    stalls_reported = 0;
}

unsigned cl_fault_stalls_reported(void) { return stalls_reported; }

/* A finished launch's header, read whole: report a stall instead. */
static void maybe_report_stall(cl_bool blocking, size_t offset, size_t bytes, void *host)
{
    perma_ctl_header *h = host;
    if (!stalls_to_report || !blocking || offset != 0 || bytes != sizeof *h || h->status != PERMA_KSTATUS_DONE ||
        h->outstanding != 0)
        return;
    h->status = PERMA_KSTATUS_NEEDS_ROOM;
    h->detail_proc = PERMA_DETAIL_NONE;
    h->detail_edge = 0;
    stalls_to_report--;
    stalls_reported++;
}

cl_int clEnqueueReadBuffer(cl_command_queue q, cl_mem m, cl_bool b, size_t o, size_t s, void *p, cl_uint n,
                           const cl_event *w, cl_event *e)
{
    if (fault_now("clEnqueueReadBuffer"))
        return CL_OUT_OF_RESOURCES;
    count_transfer(&transfers.read, s);
    cl_int err = REAL(clEnqueueReadBuffer)(q, m, b, o, s, p, n, w, e);
    if (err == CL_SUCCESS)
        maybe_report_stall(b, o, s, p);
    return err;
}
WRAP_STATUS(clEnqueueFillBuffer,
            (cl_command_queue q, cl_mem m, const void *pat, size_t ps, size_t o, size_t s, cl_uint n,
             const cl_event *w, cl_event *e),
            (q, m, pat, ps, o, s, n, w, e))
WRAP_COUNTED(clEnqueueNDRangeKernel, transfers.launches++,
             (cl_command_queue q, cl_kernel k, cl_uint dim, const size_t *off, const size_t *g, const size_t *l,
              cl_uint n, const cl_event *w, cl_event *e),
             (q, k, dim, off, g, l, n, w, e))
WRAP_STATUS(clGetEventInfo, (cl_event e, cl_event_info i, size_t s, void *v, size_t *r), (e, i, s, v, r))
WRAP_STATUS(clRetainMemObject, (cl_mem m), (m))
