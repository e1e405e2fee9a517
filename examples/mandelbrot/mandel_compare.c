/*
 * --compare: time the sequential C versions and the perma version under
 * every technique and strategy on the same image, best of `repeats` runs
 * each after one untimed warm-up run (the program build and PoCL's
 * compile at the first launch are excluded), and check
 * that every perma image equals the sequential one.
 */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mandel.h"

/* Schedule labels (perma_schedule_parse). */
static const char *const variants[] = {
    "megakernel/shared",
    "megakernel/stealing",
    "megakernel/donation",
    "megakernel/stealing-donation",
    "kernel-per-procedure",
    "bounded-batches",
};

/* The run options of variant `index`; MANDEL_ERR_RUNTIME with the parser's
 * message for a bad label. */
static mandel_status variant_options(size_t index, unsigned work_groups, mandel_run_options *out,
                                     char *message, size_t size)
{
    perma_schedule schedule;
    perma_error error;
    if (perma_schedule_parse(variants[index], &schedule, &error) != PERMA_OK) {
        snprintf(message, size, "mandelbrot: --compare: %s", error.message);
        return MANDEL_ERR_RUNTIME;
    }
    out->schedule = schedule;
    out->work_groups = work_groups;
    return MANDEL_OK;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double best_sequential(const mandel_params *p, uint32_t *counts, unsigned repeats, int brute)
{
    double best = 1e30;
    for (unsigned r = 0; r < repeats; ++r) {
        double start = now();
        if (brute)
            mandel_brute_force(p, counts);
        else if (mandel_sequential(p, counts) != 0)
            return -1;
        double t = now() - start;
        best = t < best ? t : best;
    }
    return best;
}

/* Build once, run `repeats` times; *seconds is the best run. */
static mandel_status time_variant(const mandel_params *p, const mandel_run_options *v,
                                  uint32_t *counts, unsigned repeats, double *build,
                                  double *seconds, char *message, size_t size)
{
    double start = now();
    mandel_session *s;
    mandel_status st = mandel_session_create(p, v, counts, &s, message, size);
    if (st != MANDEL_OK)
        return st;
    *build = now() - start;
    /* PoCL compiles the kernel at its first launch: warm up untimed. */
    st = mandel_session_run(s, message, size);
    *seconds = 1e30;
    for (unsigned r = 0; r < repeats && st == MANDEL_OK; ++r) {
        start = now();
        st = mandel_session_run(s, message, size);
        double t = now() - start;
        *seconds = t < *seconds ? t : *seconds;
    }
    mandel_session_destroy(s);
    return st;
}

mandel_status mandel_compare(const mandel_params *p, unsigned work_groups, unsigned repeats,
                             FILE *out, char *message, size_t size)
{
    size_t pixels = (size_t)p->width * p->height;
    uint32_t *expected = malloc(pixels * sizeof *expected);
    uint32_t *counts = malloc(pixels * sizeof *counts);
    if (!expected || !counts) {
        free(expected);
        free(counts);
        snprintf(message, size, "mandelbrot: --compare: out of memory for %zu pixels", pixels);
        return MANDEL_ERR_RUNTIME;
    }
    fprintf(out, "%ux%u pixels, max_iter %u, min_size %u; best of %u runs after a warm-up; build excluded\n",
            p->width, p->height, p->max_iter, p->min_size, repeats);
    double brute = best_sequential(p, counts, repeats, 1);
    double sequential = best_sequential(p, expected, repeats, 0);
    if (sequential < 0) {
        free(expected);
        free(counts);
        snprintf(message, size, "mandelbrot: --compare: out of memory in the sequential version");
        return MANDEL_ERR_RUNTIME;
    }
    fprintf(out, "%-36s %10s %12s %10s %s\n", "version", "seconds", "/sequential", "build s", "image");
    fprintf(out, "%-36s %10.4f %12.2f %10s %s\n", "sequential C, Mariani-Silver", sequential, 1.0, "-", "reference");
    fprintf(out, "%-36s %10.4f %12.2f %10s %s\n", "sequential C, brute force", brute, brute / sequential, "-",
            memcmp(counts, expected, pixels * sizeof *counts) == 0 ? "identical" : "DIFFERS");
    mandel_status st = MANDEL_OK;
    for (size_t i = 0; i < sizeof variants / sizeof variants[0] && st == MANDEL_OK; ++i) {
        mandel_run_options v;
        st = variant_options(i, work_groups, &v, message, size);
        if (st != MANDEL_OK)
            break;
        double build, seconds;
        st = time_variant(p, &v, counts, repeats, &build, &seconds, message, size);
        if (st != MANDEL_OK)
            break;
        char name[64];
        if (v.schedule.technique == PERMA_TECHNIQUE_MEGAKERNEL)
            snprintf(name, sizeof name, "perma %s / %s", perma_technique_name(v.schedule.technique),
                     perma_strategy_name(v.schedule.strategy));
        else
            snprintf(name, sizeof name, "perma %s", perma_technique_name(v.schedule.technique));
        fprintf(out, "%-36s %10.4f %12.2f %10.2f %s\n", name, seconds, seconds / sequential, build,
                memcmp(counts, expected, pixels * sizeof *counts) == 0 ? "identical" : "DIFFERS");
        fflush(out);
    }
    free(expected);
    free(counts);
    return st;
}
