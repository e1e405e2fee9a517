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
 * handler, whoever installed it (perma_cli_take_stop_signals). */
#include "bench.h"

#include <pthread.h>
#include <stdarg.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static char text[512] = "starting"; /* the activity; `text_lock` held */
static pthread_mutex_t text_lock = PTHREAD_MUTEX_INITIALIZER;
static char command[64] = "perma-bench";
static struct timespec started;

/* Say where perma-bench was, end. */
static void stopped(int number)
{
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
    /* Before OpenCL and OpenMP start their threads, so every thread
     * inherits the mask and only the stop-signals thread takes them. */
    perma_cli_take_stop_signals(stopped);
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
