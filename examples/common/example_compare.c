/* The examples' --compare harness (example_compare.h). */
#include "example_compare.h"

#include <string.h>
#include <time.h>

double example_compare_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

double example_compare_best(unsigned repeats, int (*run)(void *data), void *data)
{
    double best = 1e30;
    for (unsigned r = 0; r <= repeats; ++r) {
        double start = example_compare_now();
        if (run(data) != 0)
            return -1.0;
        double t = example_compare_now() - start;
        if (r > 0 && t < best)
            best = t;
    }
    return best;
}

void example_compare_header(const example_compare *ex, FILE *out)
{
    fprintf(out, "%-36s %10s %12s %10s", "version", "seconds", "/sequential", "build s");
    if (ex->items_column)
        fprintf(out, " %10s", "items");
    fprintf(out, " %s\n", ex->check_heading);
}

void example_compare_row(const example_compare *ex, FILE *out, const char *version, double seconds,
                         double sequential, double build, unsigned long long items, const char *check)
{
    fprintf(out, "%-36s %10.4f %12.2f ", version, seconds, seconds / sequential);
    if (build < 0)
        fprintf(out, "%10s", "-");
    else
        fprintf(out, "%10.2f", build);
    if (ex->items_column)
        fprintf(out, " %10llu", items);
    fprintf(out, " %s\n", check);
    fflush(out);
}

/* "perma megakernel / shared", "perma kernel-per-procedure". */
static void version_name(const perma_schedule *s, char *name, size_t size)
{
    if (s->technique == PERMA_TECHNIQUE_MEGAKERNEL)
        snprintf(name, size, "perma %s / %s", perma_technique_name(s->technique), perma_strategy_name(s->strategy));
    else
        snprintf(name, size, "perma %s", perma_technique_name(s->technique));
}

/* Build once (timed as *build), warm up, then the best of `repeats` runs;
 * *items: what the last run executed. */
static int time_schedule(const example_compare *ex, const perma_schedule *schedule, unsigned work_groups,
                         unsigned repeats, double *build, double *seconds, unsigned long long *items,
                         char *message, size_t size)
{
    double start = example_compare_now();
    example_run_options options = { *schedule, work_groups };
    example_session *session;
    int st = example_session_create(ex->program, ex->program_data, &options, &session, message, size);
    if (st != 0)
        return st;
    *build = example_compare_now() - start;
    *seconds = 1e30;
    for (unsigned r = 0; r <= repeats && st == 0; ++r) {
        start = example_compare_now();
        st = example_session_run(session, message, size);
        double t = example_compare_now() - start;
        if (r > 0 && t < *seconds)
            *seconds = t;
    }
    perma_stats stats;
    *items = perma_get_stats(example_session_runtime(session), &stats) == PERMA_OK ? stats.items : 0;
    example_session_destroy(session);
    return st;
}

int example_compare_schedules(const example_compare *ex, unsigned work_groups, unsigned repeats,
                              double sequential, FILE *out, char *message, size_t size)
{
    /* Every technique and strategy, the stealing ones with their default victim. */
    perma_schedule schedule;
    for (unsigned i = 0; perma_schedule_all(PERMA_SCHEDULES_DEFAULT_VICTIM, i, &schedule) == PERMA_OK; ++i) {
        double build, seconds;
        unsigned long long items;
        int st = time_schedule(ex, &schedule, work_groups, repeats, &build, &seconds, &items, message, size);
        if (st != 0)
            return st;
        char name[64];
        version_name(&schedule, name, sizeof name);
        example_compare_row(ex, out, name, seconds, sequential, build, items, ex->check(ex->data));
    }
    return 0;
}
