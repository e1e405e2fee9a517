/* Clock, median and the timing loop of the C and OpenMP baselines. */
#include "bench.h"

#include <stdlib.h>
#include <time.h>
#include <unistd.h>

double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

double bench_cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double bench_median(double *values, unsigned count)
{
    if (count == 0)
        return 0.0;
    qsort(values, count, sizeof *values, compare_doubles);
    return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

double bench_summary(const bench_options *options, double *values, unsigned count)
{
    if (!options->best || count == 0)
        return bench_median(values, count);
    double best = values[0];
    for (unsigned i = 1; i < count; ++i)
        if (values[i] < best)
            best = values[i];
    return best;
}

double bench_time_baseline(const bench_options *options, void (*fn)(void *), void *arg)
{
    return bench_time_runs(options, NULL, fn, arg).seconds;
}

double bench_time_prepared(const bench_options *options, void (*prepare)(void *), void (*fn)(void *), void *arg)
{
    return bench_time_runs(options, prepare, fn, arg).seconds;
}

bench_timing bench_time_runs(const bench_options *options, void (*prepare)(void *), void (*fn)(void *), void *arg)
{
    enum { MAX_REPEAT = 1000 };
    static double times[MAX_REPEAT], cpu[MAX_REPEAT];
    unsigned n = options->repeat < MAX_REPEAT ? options->repeat : MAX_REPEAT;
    for (unsigned i = 0; i <= n; ++i) { /* run 0: warm-up (page faults, OpenMP thread pool, caches) */
        if (prepare)
            prepare(arg);
        double start = bench_now(), cpu_start = bench_cpu_now();
        fn(arg);
        if (i > 0) {
            times[i - 1] = bench_now() - start;
            cpu[i - 1] = bench_cpu_now() - cpu_start;
        }
    }
    bench_timing t = { bench_summary(options, times, n), bench_summary(options, cpu, n) };
    return t;
}

unsigned bench_threads(const bench_options *options)
{
    if (options->threads)
        return options->threads;
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    return cpus > 0 ? (unsigned)cpus : 1;
}
