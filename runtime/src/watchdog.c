/* Waiting for a kernel under the watchdog.  Two limits stop a run:
 *   - the time limit (config.time_limit): the run's deadline;
 *   - the stall limit (config.stall_limit): no item completed anywhere for
 *     that long, read from the groups' batch counts on the watch page
 *     (kernels/perma_abi.h) where the host can see them while the kernel
 *     runs (rt->watch_visible).
 * Either raises the abort flag every group polls and keeps the reason for
 * the error; a kernel that has not stopped GRACE_SECONDS later (a
 * procedure that never returns) is given up (rt->hung).
 *
 * The wait sleeps on a condition variable that the completion callbacks
 * of events signal, so a short launch (a host-driven step) is not held up
 * by a polling interval.  It wakes at least every CHECK_SECONDS (sooner at
 * first, for an implementation that never calls back) to ask
 * clGetEventInfo and to look at the clock and the watch page.  The
 * variable is the process's, not a runtime's: a callback may come after
 * its runtime is gone.  Meanwhile a helper thread blocks in
 * clWaitForEvents, which Intel's CPU runtime needs to run a launch's
 * groups at the same time (lend_thread). */
#include "internal.h"

#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Seconds a kernel gets to notice the abort flag before we give up on it. */
#define GRACE_SECONDS 10.0
/* Most seconds between looks at the event, the clock and the watch page. */
#define CHECK_SECONDS 0.05

/* Why the last launch the watchdog stopped was stopped. */
struct perma_watchdog {
    bool stalled;            /* no item completed for the stall limit */
    char in_flight[512];     /* "procedure 'a' (1 work-group), ..." */
};

static pthread_once_t callbacks_once = PTHREAD_ONCE_INIT;
static pthread_mutex_t callbacks_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t callbacks_changed;
static unsigned long callbacks_seen; /* completion callbacks so far, all runtimes */

static void init_callbacks(void)
{
    pthread_condattr_t attr;
    pthread_condattr_init(&attr);
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC); /* perma_now's clock */
    pthread_cond_init(&callbacks_changed, &attr);
    pthread_condattr_destroy(&attr);
}

perma_status perma_watchdog_open(perma_runtime *rt)
{
    pthread_once(&callbacks_once, init_callbacks);
    rt->watchdog = calloc(1, sizeof *rt->watchdog);
    if (!rt->watchdog)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the watchdog");
    return PERMA_OK;
}

void perma_watchdog_close(perma_runtime *rt)
{
    free(rt->watchdog);
    rt->watchdog = NULL;
}

static void CL_CALLBACK on_complete(cl_event event, cl_int status, void *data)
{
    (void)event;
    (void)status;
    (void)data;
    pthread_mutex_lock(&callbacks_lock);
    callbacks_seen++;
    pthread_cond_broadcast(&callbacks_changed);
    pthread_mutex_unlock(&callbacks_lock);
}

static unsigned long callbacks_now(void)
{
    pthread_mutex_lock(&callbacks_lock);
    unsigned long seen = callbacks_seen;
    pthread_mutex_unlock(&callbacks_lock);
    return seen;
}

/* Sleep until a completion callback after the `seen`-th one, or until
 * perma_now() reaches `until`. */
static void wait_for_callback(unsigned long seen, double until)
{
    struct timespec ts = { (time_t)until, (long)((until - (double)(time_t)until) * 1e9) };
    pthread_mutex_lock(&callbacks_lock);
    while (callbacks_seen == seen)
        if (pthread_cond_timedwait(&callbacks_changed, &callbacks_lock, &ts) == ETIMEDOUT)
            break;
    pthread_mutex_unlock(&callbacks_lock);
}

/* The procedures with items in flight, from the watch page. */
static void describe_in_flight(perma_runtime *rt, char *out, size_t size)
{
    unsigned running[PERMA_MAX_PROCEDURES];
    perma_state_watch(rt, running, rt->proc_count);
    size_t used = 0;
    out[0] = '\0';
    for (unsigned q = 0; q < rt->proc_count && used < size; ++q)
        if (running[q])
            used += (size_t)snprintf(out + used, size - used, "%sprocedure '%s' (%u work-group%s)", used ? ", " : "",
                                     rt->procs[q].name, running[q], running[q] == 1 ? "" : "s");
}

/* What the error message says about a stall. */
static int stall_sentence(const perma_watchdog *w, double limit, char *out, size_t size)
{
    if (w->in_flight[0])
        return snprintf(out, size, "no item completed for %g s (config.stall_limit): %s had items in flight "
                                   "(a procedure that never returns?)", limit, w->in_flight);
    return snprintf(out, size, "no item completed for %g s (config.stall_limit), and no procedure had an item in "
                               "flight", limit);
}

perma_status perma_watchdog_stop_error(perma_runtime *rt)
{
    const perma_watchdog *w = rt->watchdog;
    if (w && w->stalled) {
        char stall[768];
        stall_sentence(w, perma_stall_limit(rt), stall, sizeof stall);
        return perma_set_error(rt, PERMA_ERR_TIMEOUT, "%s; the run was stopped", stall);
    }
    return perma_set_error(rt, PERMA_ERR_TIMEOUT, "the run passed its time limit of %g s (config.time_limit) and "
                           "was stopped", perma_time_limit(rt));
}

/* The kernel did not stop after being told to. */
static perma_status give_up(perma_runtime *rt)
{
    const perma_watchdog *w = rt->watchdog;
    char reason[768];
    if (w->stalled)
        stall_sentence(w, perma_stall_limit(rt), reason, sizeof reason);
    else
        snprintf(reason, sizeof reason, "the run passed its time limit of %g s (config.time_limit)",
                 perma_time_limit(rt));
    rt->hung = true;
    return perma_set_error(rt, PERMA_ERR_TIMEOUT,
                           "%s, and the kernel did not stop within %g s after being told to; this runtime can no "
                           "longer be used, and the kernel keeps a compute unit busy until the process exits",
                           reason, GRACE_SECONDS);
}

/* Wait for the command of `done`; past the deadline or the stall limit
 * raise the abort flag, and give up after the grace period. */
static perma_status watch(perma_runtime *rt, cl_event done, double deadline)
{
    perma_watchdog *w = rt->watchdog;
    w->stalled = false;
    clSetEventCallback(done, CL_COMPLETE, on_complete, NULL); /* without it the wait polls */
    unsigned running[PERMA_MAX_PROCEDURES];
    double stall_limit = perma_stall_limit(rt), now = perma_now(), pause = 50e-6;
    double progress_at = now, aborted_at = 0.0;
    uint64_t batches = perma_state_watch(rt, running, rt->proc_count);
    /* The stall limit applies once the host has seen the kernel write its
     * records: a device that does not share the page (or copies it) never
     * shows progress, and must not be taken for a stuck one. */
    bool page_seen = false;
    for (;;) {
        /* A callback after this count means the state below may be stale:
         * the wait then returns at once. */
        unsigned long seen = callbacks_now();
        cl_int state = CL_QUEUED;
        PERMA_CL_CHECK(rt, "clGetEventInfo", clGetEventInfo(done, CL_EVENT_COMMAND_EXECUTION_STATUS,
                                                            sizeof state, &state, NULL));
        if (state < 0)
            return perma_set_error(rt, PERMA_ERR_OPENCL, "a kernel failed on the device: %s (%d)",
                                   perma_cl_error_name(state), (int)state);
        if (state == CL_COMPLETE)
            return PERMA_OK;
        now = perma_now();
        uint64_t finished = perma_state_watch(rt, running, rt->proc_count);
        if (finished != batches) {
            batches = finished;
            progress_at = now;
        }
        for (unsigned q = 0; q < rt->proc_count && !page_seen; ++q)
            page_seen = running[q] != 0;
        page_seen = page_seen || finished != 0;
        if (aborted_at == 0.0 && rt->watch_visible && page_seen && now - progress_at > stall_limit) {
            w->stalled = true;
            describe_in_flight(rt, w->in_flight, sizeof w->in_flight);
            perma_state_raise_abort(rt);
            aborted_at = now;
        }
        if (aborted_at == 0.0 && now > deadline) {
            perma_state_raise_abort(rt);
            aborted_at = now;
        }
        if (aborted_at != 0.0 && now > aborted_at + GRACE_SECONDS)
            return give_up(rt);
        wait_for_callback(seen, now + pause);
        if (pause < CHECK_SECONDS)
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

perma_status perma_watch_event(perma_runtime *rt, cl_event done, double deadline)
{
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
    return st;
}

perma_status perma_launch_watched(perma_runtime *rt, cl_kernel kernel, size_t global, size_t local, double deadline)
{
    cl_event done = NULL;
    PERMA_CL_CHECK(rt, "clEnqueueNDRangeKernel (megakernel)",
                   clEnqueueNDRangeKernel(rt->queue, kernel, 1, NULL, &global, &local, 0, NULL, &done));
    clFlush(rt->queue);
    perma_status st = perma_watch_event(rt, done, deadline);
    if (!rt->hung)
        clReleaseEvent(done);
    return st;
}
