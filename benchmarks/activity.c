/* What perma-bench is doing, for the message it leaves when it is stopped.
 *
 * A test harness that times a benchmark out sends SIGTERM (meson test, then
 * SIGKILL half a second later); Ctrl-C sends SIGINT.  Either used to end
 * perma-bench with no word about where it was, so a benchmark that ran
 * past its timeout left only the rows it had finished (issue 23.6: a
 * build that took minutes on a loaded machine).  perma-bench now writes the
 * current activity, e.g.
 *   perma-bench pipeline: stopped by signal 15 after 181 s while building
 *   megakernel/shared+local256 (4096 producers, upstream first ...)
 * and exits with status 1.
 *
 * The signals are blocked in every thread and taken by one thread in
 * sigwait(), not by a handler: PoCL's LLVM installs its own SIGTERM, SIGINT
 * and SIGHUP handlers at the first compile (saving ours, with SA_RESETHAND),
 * so a second signal arriving while LLVM's handler was restoring ours -
 * `timeout` sends SIGTERM to the process and then to its group - found the
 * default action and ended perma-bench without a word (exit 143, 2 runs in
 * 16 with two SIGTERMs after a build).  A blocked signal never reaches any
 * handler, whoever installed it. */
#define _GNU_SOURCE /* pthread_setname_np */
#include "bench.h"

#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static char text[512] = "starting"; /* the activity; `text_lock` held */
static pthread_mutex_t text_lock = PTHREAD_MUTEX_INITIALIZER;
static char command[64] = "perma-bench";
static struct timespec started;

static void stop_signals(sigset_t *set)
{
    sigemptyset(set);
    sigaddset(set, SIGTERM);
    sigaddset(set, SIGINT);
    sigaddset(set, SIGHUP);
}

/* The thread that takes the stop signals: say where perma-bench was, end. */
static void *wait_for_stop(void *unused)
{
    (void)unused;
    pthread_setname_np(pthread_self(), "stop-signals"); /* tests tell it apart */
    sigset_t set;
    stop_signals(&set);
    int number = 0;
    while (sigwait(&set, &number) != 0)
        ;
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    pthread_mutex_lock(&text_lock);
    fprintf(stderr, "%s: stopped by signal %d after %ld s while %s\n", command, number,
            (long)(now.tv_sec - started.tv_sec), text);
    fflush(stderr);
    _exit(1);
}

void bench_activity_start(const char *benchmark)
{
    snprintf(command, sizeof command, "perma-bench %s", benchmark);
    clock_gettime(CLOCK_MONOTONIC, &started);
    /* Blocked here, before OpenCL and OpenMP start their threads, so every
     * thread inherits the mask and only wait_for_stop takes the signals. */
    sigset_t set, before;
    stop_signals(&set);
    pthread_sigmask(SIG_BLOCK, &set, &before);
    pthread_t waiter;
    if (pthread_create(&waiter, NULL, wait_for_stop, NULL) != 0) {
        pthread_sigmask(SIG_SETMASK, &before, NULL); /* no thread: the signals' defaults */
        return;
    }
    pthread_detach(waiter);
}

void bench_activity(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    pthread_mutex_lock(&text_lock);
    vsnprintf(text, sizeof text, fmt, ap);
    pthread_mutex_unlock(&text_lock);
    va_end(ap);
}
