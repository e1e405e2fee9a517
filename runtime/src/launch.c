/* Launching the megakernel once, under the watchdog. */
#include "internal.h"

#include <time.h>

/* Seconds a kernel gets to notice the abort flag before we give up on it. */
#define ABORT_GRACE_SECONDS 10.0

static void sleep_seconds(double s)
{
    struct timespec ts = { (time_t)s, (long)((s - (double)(time_t)s) * 1e9) };
    nanosleep(&ts, NULL);
}

/* The control block, queue items, statistics, watchdog flag and trace
 * (arguments 0-4) and the user buffers from `first_user_arg` on. */
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
    cl_mem fixed[] = { rt->ctl_mem, rt->data_mem, rt->stats_mem, rt->abort_mem, rt->trace_mem };
    for (cl_uint i = 0; i < 5; ++i)
        PERMA_CL_CHECK(rt, "clSetKernelArg", clSetKernelArg(kernel, i, sizeof(cl_mem), &fixed[i]));
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
                                   "can no longer be used", rt->config.time_limit, ABORT_GRACE_SECONDS);
        }
        sleep_seconds(pause);
        if (pause < 2e-3)
            pause *= 2;
    }
}

perma_status perma_launch_megakernel(perma_runtime *rt, double deadline, uint32_t *kernel_status)
{
    cl_int err;
    __atomic_store_n(rt->abort_flag, 0u, __ATOMIC_SEQ_CST);
    perma_status st = perma_set_common_args(rt, rt->kernel, PERMA_MEGAKERNEL_USER_ARG);
    if (st != PERMA_OK)
        return st;
    size_t local = rt->group_size;
    size_t global = (size_t)rt->work_groups * local;
    cl_event done = NULL;
    err = clEnqueueNDRangeKernel(rt->queue, rt->kernel, 1, NULL, &global, &local, 0, NULL, &done);
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (megakernel)", err);
    clFlush(rt->queue);
    st = watch(rt, done, deadline);
    if (!rt->hung)
        clReleaseEvent(done);
    if (st != PERMA_OK)
        return st;
    uint32_t header[PERMA_CTL_HEADER_WORDS];
    PERMA_CL_CHECK(rt, "clEnqueueReadBuffer (control block)",
                   clEnqueueReadBuffer(rt->queue, rt->ctl_mem, CL_TRUE, 0, sizeof header, header, 0, NULL, NULL));
    kernel_status[0] = header[PERMA_CTL_STATUS];
    kernel_status[1] = header[PERMA_CTL_DETAIL_PROC];
    kernel_status[2] = header[PERMA_CTL_DETAIL_EDGE];
    kernel_status[3] = header[PERMA_CTL_OUTSTANDING];
    return PERMA_OK;
}
