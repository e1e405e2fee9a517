/* Waiting for a launch under the watchdog: past the run's deadline the
 * host raises the abort flag every group polls, and gives up on a kernel
 * that does not stop. */
#include "internal.h"

#include <pthread.h>
#include <time.h>

/* Seconds a kernel gets to notice the abort flag before we give up on it. */
#define ABORT_GRACE_SECONDS 10.0

static void sleep_seconds(double s)
{
    struct timespec ts = { (time_t)s, (long)((s - (double)(time_t)s) * 1e9) };
    nanosleep(&ts, NULL);
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
            perma_state_raise_abort(rt);
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

/* Intel's CPU runtime runs the groups of a launch on its own worker
 * threads plus any host thread blocked in a wait for it; with as many
 * workers as cores minus one, a host that polls (the watchdog) leaves a
 * core idle and a launch's second group does not start before its first
 * has left.  A helper thread blocked in clWaitForEvents lends the runtime
 * that thread; other implementations just wake it at the end. */
static void *lend_thread(void *event)
{
    clWaitForEvents(1, (cl_event *)&event);
    clReleaseEvent((cl_event)event);
    return NULL;
}

perma_status perma_launch_watched(perma_runtime *rt, cl_kernel kernel, size_t global, size_t local, double deadline)
{
    cl_event done = NULL;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (megakernel)",
                   clEnqueueNDRangeKernel(rt->queue, kernel, 1, NULL, &global, &local, 0, NULL, &done));
    clFlush(rt->queue);
    pthread_t helper;
    bool lent = clRetainEvent(done) == CL_SUCCESS;
    if (lent && pthread_create(&helper, NULL, lend_thread, done) != 0) {
        clReleaseEvent(done);
        lent = false;
    }
    perma_status st = watch(rt, done, deadline);
    if (lent && !rt->hung)
        pthread_join(helper, NULL);
    else if (lent)
        pthread_detach(helper); /* waits for a kernel that may never end */
    if (!rt->hung)
        clReleaseEvent(done);
    return st;
}
