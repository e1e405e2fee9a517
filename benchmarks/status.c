/* Which row perma-bench is measuring, on one line of stderr when stderr is
 * a terminal:
 *
 *     perma-bench: row 7, 12.3 s: geometric b=4 d=10: megakernel/stealing/random
 *
 * drawn when a row's measurement starts (bench_row_init), cut to the
 * terminal's width so that it never wraps, and cleared before the row is
 * printed, so the table on stdout stays as it was. */
#include "bench.h"

#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

static int shown;            /* a status line is on the terminal */
static unsigned rows_printed;
static double started;

static unsigned terminal_columns(void)
{
    struct winsize size;
    if (ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0)
        return size.ws_col;
    return 80;
}

void bench_status_show(const char *workload, const char *variant)
{
    if (!isatty(STDERR_FILENO))
        return;
    double now = bench_now();
    if (started == 0.0)
        started = now;
    char line[512];
    snprintf(line, sizeof line, "perma-bench: row %u, %.1f s: %s: %s", rows_printed + 1, now - started, workload,
             variant);
    unsigned columns = terminal_columns();
    if (strlen(line) >= columns)
        line[columns - 1] = '\0';
    fflush(stdout);
    fprintf(stderr, "\r%s\033[K", line);
    fflush(stderr);
    shown = 1;
}

void bench_status_row_printed(void)
{
    rows_printed++;
    if (!shown)
        return;
    fputs("\r\033[K", stderr);
    fflush(stderr);
    shown = 0;
}
