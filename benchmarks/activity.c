/* What perma-bench is doing, for the message it leaves when it is stopped.
 *
 * A test harness that times a benchmark out sends SIGTERM (meson test, then
 * SIGKILL half a second later); Ctrl-C sends SIGINT.  Either used to end
 * perma-bench with no word about where it was, so a benchmark that ran
 * past its timeout left only the rows it had finished (issue 23.6: a
 * build that took minutes on a loaded machine).  The handler writes the
 * current activity, e.g.
 *   perma-bench pipeline: stopped by signal 15 after 181 s while building
 *   megakernel/shared+local256 (4096 producers, upstream first ...)
 * and exits with status 1.  The text is formatted outside the handler into
 * one of two buffers and published by switching an index, so the handler
 * only reads a finished text and calls async-signal-safe functions. */
#include "bench.h"

#include <signal.h>
#include <stdarg.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static char texts[2][512];
static volatile sig_atomic_t current; /* the buffer the handler reads */
static char command[64] = "perma-bench";
static struct timespec started;

/* Append the decimal digits of `value` to out[*used..size). */
static void append_number(char *out, size_t *used, size_t size, unsigned long value)
{
    char digits[24];
    size_t n = 0;
    do {
        digits[n++] = (char)('0' + value % 10);
        value /= 10;
    } while (value && n < sizeof digits);
    while (n && *used + 1 < size)
        out[(*used)++] = digits[--n];
}

static void append_text(char *out, size_t *used, size_t size, const char *text)
{
    while (*text && *used + 1 < size)
        out[(*used)++] = *text++;
}

static void on_stop(int signal_number)
{
    char line[768];
    size_t used = 0;
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    append_text(line, &used, sizeof line, command);
    append_text(line, &used, sizeof line, ": stopped by signal ");
    append_number(line, &used, sizeof line, (unsigned long)signal_number);
    append_text(line, &used, sizeof line, " after ");
    append_number(line, &used, sizeof line, (unsigned long)(now.tv_sec - started.tv_sec));
    append_text(line, &used, sizeof line, " s while ");
    append_text(line, &used, sizeof line, texts[current]);
    append_text(line, &used, sizeof line, "\n");
    ssize_t ignored = write(STDERR_FILENO, line, used);
    (void)ignored;
    _exit(1);
}

void bench_activity_start(const char *benchmark)
{
    snprintf(command, sizeof command, "perma-bench %s", benchmark);
    snprintf(texts[current], sizeof texts[0], "starting");
    clock_gettime(CLOCK_MONOTONIC, &started);
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = on_stop;
    sigemptyset(&action.sa_mask);
    sigaction(SIGTERM, &action, NULL);
    sigaction(SIGINT, &action, NULL);
    sigaction(SIGHUP, &action, NULL);
}

void bench_activity(const char *fmt, ...)
{
    int next = !current;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(texts[next], sizeof texts[next], fmt, ap);
    va_end(ap);
    current = next;
}
