/* Waiting for a kernel under the watchdog.  Two limits stop a run:
 *   - the time limit (config.time_limit): the run's deadline;
 *   - the stall limit (config.stall_limit): no item completed anywhere for
 *     that long, read from the groups' batch counts on the watch page
 *     (kernels/perma_abi.h) where the host can see them while the kernel
 *     runs (rt->caps.watch_visible).
 * Either raises the abort flag every group polls and keeps the reason for
 * the error; a kernel that has not stopped the grace period later
 * (PERMA_STOP_GRACE, 10 s by default: a procedure that never returns) is
 * given up (rt->hung).
 *
 * The wait sleeps on a condition variable that the completion callbacks
 * of events signal, so a short launch (a host-driven step) is not held up
 * by a polling interval.  It wakes at least every CHECK_SECONDS (sooner at
 * first, for an implementation that never calls back) to ask
 * clGetEventInfo and to look at the clock and the watch page.  The
 * variable is the process's, not a runtime's: a callback may come after
 * its runtime is gone.
 *
 * Meanwhile a waiter thread blocks in clWaitForEvents for the same event,
 * which Intel's CPU runtime needs to run a launch's groups at the same
 * time (see perma_waiter below).  It is one persistent thread per
 * runtime, started at the first watched launch and handed each launch's
 * event through a mutex and condition variable, not a thread created and
 * joined per launch: a host-driven run makes hundreds to thousands of
 * launches.  Between launches it is idle (perma_watch_event waits for it
 * to let go of the event, as a join did), so the next handoff never waits.
 * perma_watchdog_close stops and joins it; if a kernel never ended
 * (rt->hung) the waiter stays blocked in clWaitForEvents forever, so it is
 * detached instead, and its state lives in a heap block the thread and the
 * runtime share by reference count: the last to let go frees it, which
 * for a hung waiter is never (a deliberate leak, like the hung runtime's
 * OpenCL objects).  A process forked after a launch starts a waiter of
 * its own at its first watched launch. */
#include "clock.h"
#include "internal.h"
#include "progress.h"
#include "state.h"
#include "trace.h"
#include "watchdog.h"

#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* Most seconds between looks at the event, the clock and the watch page. */
#define CHECK_SECONDS 0.05

/* Intel's CPU runtime runs the groups of a launch on its own worker
 * threads plus any host thread blocked in a wait for it; with as many
 * workers as cores minus one, a host that polls (the watchdog) leaves a
 * core idle and a launch's second group does not start before its first
 * has left.  The waiter, blocked in clWaitForEvents, lends the runtime
 * that thread; other implementations just wake it at the end.  Shared by
 * the runtime and the thread; `lock` guards every field but `thread`
 * (written before the thread exists, read by the runtime only). */
typedef struct perma_waiter {
    pthread_mutex_t lock;
    pthread_cond_t changed;  /* an event handed over, one let go, or quit */
    cl_event handed;         /* retained for the waiter; NULL: none pending */
    bool busy;               /* the waiter has taken an event, not yet released it */
    bool quit;               /* the runtime is closing: exit when idle */
    unsigned refs;           /* 2 while the thread runs: it and the runtime */
    pthread_t thread;
} perma_waiter;

/* Why the last launch the watchdog stopped was stopped, and the waiter. */
struct perma_watchdog {
    bool stalled;            /* no item completed for the stall limit */
    char in_flight[512];     /* "procedure 'a' (1 work-group), ..." */
    perma_waiter *waiter;    /* NULL until the first watched launch starts it */
    pid_t waiter_pid;        /* the process that started it */
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

static void waiter_free(perma_waiter *wt)
{
    pthread_cond_destroy(&wt->changed);
    pthread_mutex_destroy(&wt->lock);
    free(wt);
}

/* Drop one reference (with wt->lock held, which this releases); the last
 * frees the block. */
static void waiter_unref_unlock(perma_waiter *wt)
{
    bool last = --wt->refs == 0;
    pthread_mutex_unlock(&wt->lock);
    if (last)
        waiter_free(wt);
}

/* The waiter thread: wait for each handed event, let go of it, repeat. */
static void *waiter_main(void *arg)
{
    perma_waiter *wt = arg;
    pthread_mutex_lock(&wt->lock);
    for (;;) {
        while (!wt->handed && !wt->quit)
            pthread_cond_wait(&wt->changed, &wt->lock);
        if (!wt->handed)
            break; /* quit, and nothing left to wait for */
        cl_event event = wt->handed;
        wt->handed = NULL;
        wt->busy = true;
        pthread_mutex_unlock(&wt->lock);
        /* For a kernel that never ends this never returns (rt->hung). */
        clWaitForEvents(1, &event);
        clReleaseEvent(event);
        pthread_mutex_lock(&wt->lock);
        wt->busy = false;
        pthread_cond_broadcast(&wt->changed);
    }
    waiter_unref_unlock(wt);
    return NULL;
}

/* The runtime's waiter, started if it is not yet; NULL if it cannot be
 * (the launch is then watched without one, which only costs Intel's
 * runtime its concurrency). */
static perma_waiter *waiter_get(perma_watchdog *w)
{
    pid_t pid = getpid();
    if (w->waiter && w->waiter_pid == pid)
        return w->waiter;
    /* A forked child has no copy of the thread: it would never take the
     * event.  Leave the parent's block alone (its lock may be held) and
     * start a waiter of the child's own. */
    w->waiter = NULL;
    perma_waiter *wt = calloc(1, sizeof *wt);
    if (!wt)
        return NULL;
    if (pthread_mutex_init(&wt->lock, NULL) != 0) {
        free(wt);
        return NULL;
    }
    if (pthread_cond_init(&wt->changed, NULL) != 0) {
        pthread_mutex_destroy(&wt->lock);
        free(wt);
        return NULL;
    }
    wt->refs = 2;
    /* A library's hidden thread takes none of the application's signals. */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    int created = pthread_create(&wt->thread, NULL, waiter_main, wt);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (created != 0) {
        waiter_free(wt);
        return NULL;
    }
    w->waiter = wt;
    w->waiter_pid = pid;
    return wt;
}

/* Hand `event` to the waiter; false if there is none to take it. */
static bool waiter_lend(perma_watchdog *w, cl_event event)
{
    perma_waiter *wt = waiter_get(w);
    if (!wt || clRetainEvent(event) != CL_SUCCESS)
        return false;
    pthread_mutex_lock(&wt->lock);
    bool idle = !wt->handed && !wt->busy; /* always, unless a launch hung */
    if (idle) {
        wt->handed = event;
        pthread_cond_broadcast(&wt->changed);
    }
    pthread_mutex_unlock(&wt->lock);
    if (!idle)
        clReleaseEvent(event);
    return idle;
}

/* Wait for the waiter to let go of the event it was lent (what joining
 * the per-launch thread did): its clWaitForEvents returns when the
 * launch has ended, which the caller has seen or caused. */
static void waiter_settle(perma_watchdog *w)
{
    perma_waiter *wt = w->waiter;
    pthread_mutex_lock(&wt->lock);
    while (wt->handed || wt->busy)
        pthread_cond_wait(&wt->changed, &wt->lock);
    pthread_mutex_unlock(&wt->lock);
}

void perma_watchdog_close(perma_runtime *rt)
{
    perma_watchdog *w = rt->watchdog;
    if (!w)
        return;
    perma_waiter *wt = w->waiter;
    if (wt && w->waiter_pid == getpid()) {
        pthread_t thread = wt->thread;
        pthread_mutex_lock(&wt->lock);
        wt->quit = true;
        pthread_cond_broadcast(&wt->changed);
        waiter_unref_unlock(wt); /* wt may be gone from here on */
        if (rt->hung)
            pthread_detach(thread); /* blocked on a kernel that never ends */
        else
            pthread_join(thread, NULL);
    }
    free(w);
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

/* The procedures with items in flight: running[q] groups run procedure q
 * (the watch page as perma_state_watch read it). */
static void describe_in_flight(const perma_runtime *rt, const unsigned *running, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (unsigned q = 0; q < rt->proc_count && used < size; ++q)
        if (running[q])
            used += (size_t)snprintf(out + used, size - used, "%sprocedure '%s' (%u work-group%s)", used ? ", " : "",
                                     rt->procs[q].name, running[q], running[q] == 1 ? "" : "s");
}

/* Why the watchdog stopped the last launch, as the opening of the error
 * message: the stall (with what was in flight) or the time limit.  True
 * for a stall. */
static bool stop_reason(const perma_runtime *rt, char *out, size_t size)
{
    const perma_watchdog *w = rt->watchdog;
    if (!w || !w->stalled) {
        snprintf(out, size, "the run passed its time limit of %g s (config.time_limit)", perma_time_limit(&rt->config));
        return false;
    }
    if (w->in_flight[0])
        snprintf(out, size, "no item completed for %g s (config.stall_limit): %s had items in flight "
                            "(a procedure that never returns?)", perma_stall_limit(&rt->config), w->in_flight);
    else
        snprintf(out, size, "no item completed for %g s (config.stall_limit), and no procedure had an item in "
                            "flight", perma_stall_limit(&rt->config));
    return true;
}

perma_status perma_watchdog_stop_error(perma_runtime *rt)
{
    char reason[768];
    bool stalled = stop_reason(rt, reason, sizeof reason);
    return perma_set_error(rt, PERMA_ERR_TIMEOUT, "%s%s", reason,
                           stalled ? "; the run was stopped" : " and was stopped");
}

/* The kernel did not stop after being told to.  Nothing stops it now:
 * OpenCL has no way to cancel a running kernel (neither PoCL nor Intel's
 * runtime offers one), and a procedure stuck in a loop of its own never
 * comes back to the scheduler, which polls the abort flag between
 * batches (procedures with long loops can poll it too:
 * perma_stop_requested).  The runtime's other OpenCL objects stay as they
 * are (the kernel still uses its buffers, and releasing them could
 * block), but the command queue is released: Intel's runtime waits at
 * process exit for every queue still held to finish, which this one never
 * would, so the process could not exit.  PoCL's and Intel's
 * clReleaseCommandQueue return at once here (measured), and the kernel
 * keeps its compute unit until the process exits. */
static perma_status give_up(perma_runtime *rt)
{
    char reason[768];
    stop_reason(rt, reason, sizeof reason);
    rt->hung = true;
    if (rt->queue)
        clReleaseCommandQueue(rt->queue);
    rt->queue = NULL;
    return perma_set_error(rt, PERMA_ERR_TIMEOUT,
                           "%s, and the kernel did not stop within %g s after being told to; this runtime can no "
                           "longer be used, and the kernel keeps a compute unit busy until the process exits",
                           reason, rt->settings.stop_grace);
}

/* Wait for the command of `done`; past the deadline or the stall limit
 * raise the abort flag, and give up after the grace period. */
static perma_status watch(perma_runtime *rt, cl_event done, double deadline)
{
    perma_watchdog *w = rt->watchdog;
    w->stalled = false;
    clSetEventCallback(done, CL_COMPLETE, on_complete, NULL); /* without it the wait polls */
    unsigned running[PERMA_MAX_PROCEDURES];
    double stall_limit = perma_stall_limit(&rt->config), now = perma_now(), pause = 50e-6;
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
        perma_progress_sample(rt, now);
        perma_trace_read_clock(rt, now);
        if (finished != batches) {
            batches = finished;
            progress_at = now;
        }
        for (unsigned q = 0; q < rt->proc_count && !page_seen; ++q)
            page_seen = running[q] != 0;
        page_seen = page_seen || finished != 0;
        if (aborted_at == 0.0 && rt->caps.watch_visible && page_seen && now - progress_at > stall_limit) {
            w->stalled = true;
            describe_in_flight(rt, running, w->in_flight, sizeof w->in_flight);
            perma_state_raise_abort(rt);
            aborted_at = now;
        }
        if (aborted_at == 0.0 && now > deadline) {
            perma_state_raise_abort(rt);
            aborted_at = now;
        }
        if (aborted_at != 0.0 && now > aborted_at + rt->settings.stop_grace)
            return give_up(rt);
        wait_for_callback(seen, now + pause);
        if (pause < (perma_trace_on_device(rt) ? PERMA_TRACE_SAMPLE_SECONDS : CHECK_SECONDS))
            pause *= 2;
    }
}

perma_status perma_watch_event(perma_runtime *rt, cl_event done, double deadline)
{
    perma_progress_kernel_started(rt);
    bool lent = waiter_lend(rt->watchdog, done);
    perma_status st = watch(rt, done, deadline);
    if (lent && !rt->hung)
        waiter_settle(rt->watchdog);
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
