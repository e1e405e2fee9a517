/* Binding a kernel's common arguments, and waiting for a launch under the
 * watchdog. */
#include "internal.h"

#include <time.h>

/* Seconds a kernel gets to notice the abort flag before we give up on it. */
#define ABORT_GRACE_SECONDS 10.0

static void sleep_seconds(double s)
{
    struct timespec ts = { (time_t)s, (long)((s - (double)(time_t)s) * 1e9) };
    nanosleep(&ts, NULL);
}

/* The arguments PERMA_COMMON_ARGS lists (control block, queues,
 * statistics, watchdog flag, trace) and the user buffers from
 * `first_user_arg` on. */
perma_status perma_set_common_args(perma_runtime *rt, cl_kernel kernel, cl_uint first_user_arg)
{
    if (!rt->abort_mem) {
        cl_int err;
        rt->abort_mem = clCreateBuffer(rt->context, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, 4096,
                                       rt->abort_flag, &err);
        PERMA_CL_CHECK(rt, "clCreateBuffer (watchdog flag)", err);
    }
    perma_status st = perma_trace_prepare(rt);
    if (st != PERMA_OK)
        return st;
    cl_mem common[PERMA_MEGAKERNEL_USER_ARGS];
    common[PERMA_ARG_CTL] = rt->ctl_mem;
    common[PERMA_ARG_QUEUE_DATA] = rt->data_mem;
    common[PERMA_ARG_QUEUE_SEQ] = rt->seq_mem;
    common[PERMA_ARG_GROUP_STATS] = rt->stats_mem;
    common[PERMA_ARG_ABORT_FLAG] = rt->abort_mem;
    common[PERMA_ARG_TRACE] = rt->trace_mem;
    for (cl_uint i = 0; i < PERMA_MEGAKERNEL_USER_ARGS; ++i)
        PERMA_CL_CHECK(rt, "clSetKernelArg", clSetKernelArg(kernel, i, sizeof(cl_mem), &common[i]));
    for (unsigned b = 0; b < rt->buffer_count; ++b) {
        if (!rt->buffers[b].mem)
            return perma_set_error(rt, PERMA_ERR_STATE, "buffer '%s' has no memory bound", rt->buffers[b].name);
        cl_int err = clSetKernelArg(kernel, first_user_arg + b, sizeof(cl_mem), &rt->buffers[b].mem);
        if (err != CL_SUCCESS)
            return perma_set_error(rt, PERMA_ERR_OPENCL, "clSetKernelArg (buffer '%s') failed: %s (%d)",
                                   rt->buffers[b].name, perma_cl_error_name(err), (int)err);
    }
    return PERMA_OK;
}

/* Wait for the launch; past the deadline raise the abort flag, which every
 * group polls.  Returns PERMA_ERR_TIMEOUT only if the kernel ignores it. */
static perma_status watch(perma_runtime *rt, cl_event done, double deadline)
{
    double pause = 50e-6, aborted_at = 0.0;
    for (;;) {
        cl_int state = CL_QUEUED;
        PERMA_CL_CHECK(rt, "clGetEventInfo", clGetEventInfo(done, CL_EVENT_COMMAND_EXECUTION_STATUS,
                                                            sizeof state, &state, NULL));
        if (state < 0)
            return perma_set_error(rt, PERMA_ERR_OPENCL, "the megakernel failed on the device: %s (%d)",
                                   perma_cl_error_name(state), (int)state);
        if (state == CL_COMPLETE)
            return PERMA_OK;
        double now = perma_now();
        if (aborted_at == 0.0 && now > deadline) {
            __atomic_store_n(rt->abort_flag, 1u, __ATOMIC_SEQ_CST);
            aborted_at = now;
        }
        if (aborted_at != 0.0 && now > aborted_at + ABORT_GRACE_SECONDS) {
            rt->hung = true;
            return perma_set_error(rt, PERMA_ERR_TIMEOUT,
                                   "the run passed its time limit of %g s and the kernel did not stop within "
                                   "%g s after being told to (a procedure that never returns?); this runtime "
                                   "can no longer be used", perma_time_limit(rt), ABORT_GRACE_SECONDS);
        }
        sleep_seconds(pause);
        if (pause < 2e-3)
            pause *= 2;
    }
}

perma_status perma_launch_watched(perma_runtime *rt, cl_kernel kernel, size_t global, size_t local, double deadline)
{
    cl_event done = NULL;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (megakernel)",
                   clEnqueueNDRangeKernel(rt->queue, kernel, 1, NULL, &global, &local, 0, NULL, &done));
    clFlush(rt->queue);
    perma_status st = watch(rt, done, deadline);
    if (!rt->hung)
        clReleaseEvent(done);
    return st;
}
