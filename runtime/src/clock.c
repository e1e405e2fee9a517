/* The host clock every deadline and trace timestamp uses. */
#include "clock.h"

#include <time.h>

double perma_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* CPU seconds the process has used, all threads: what a build cost in
 * work, whatever the machine's load. */
double perma_cpu_now(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
        return perma_now(); /* no CPU clock: wall time, which is never less */
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* The watchdog's limit in seconds: config.time_limit, 0 meaning 600. */
double perma_time_limit(const perma_config *config)
{
    return config->time_limit > 0 ? config->time_limit : 600.0;
}

/* Seconds without a completed item before the watchdog stops a run:
 * config.stall_limit, 0 meaning 20. */
double perma_stall_limit(const perma_config *config)
{
    return config->stall_limit > 0 ? config->stall_limit : 20.0;
}
