/*
 * --compare: time the sequential BFS and the perma version under every
 * technique and strategy on the same graph, best of `repeats` runs each
 * after one untimed warm-up run (the program build and PoCL's compile at
 * the first launch are excluded), and check every result against the
 * sequential levels.
 */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bfs.h"

/* Schedule labels (perma_schedule_parse). */
static const char *const variants[] = {
    "megakernel/shared",
    "megakernel/stealing",
    "megakernel/donation",
    "megakernel/stealing-donation",
    "kernel-per-procedure",
    "bounded-batches",
};

/* The run options of variant `index`; BFS_ERR_RUNTIME with the parser's
 * message for a bad label. */
static bfs_status variant_options(size_t index, unsigned work_groups, bfs_run_options *out,
                                  char *message, size_t size)
{
    perma_schedule schedule;
    perma_error error;
    if (perma_schedule_parse(variants[index], &schedule, &error) != PERMA_OK) {
        snprintf(message, size, "bfs: --compare: %s", error.message);
        return BFS_ERR_RUNTIME;
    }
    out->schedule = schedule;
    out->work_groups = work_groups;
    return BFS_OK;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static bfs_status time_variant(const bfs_graph *g, const bfs_run_options *v, uint32_t source,
                               uint32_t *levels, unsigned repeats, double *build, double *seconds,
                               uint64_t *items, char *message, size_t size)
{
    double start = now();
    bfs_session *s;
    bfs_status st = bfs_session_create(g, v, levels, &s, message, size);
    if (st != BFS_OK)
        return st;
    *build = now() - start;
    st = bfs_session_run(s, source, message, size); /* warm-up */
    *seconds = 1e30;
    for (unsigned r = 0; r < repeats && st == BFS_OK; ++r) {
        start = now();
        st = bfs_session_run(s, source, message, size);
        double t = now() - start;
        *seconds = t < *seconds ? t : *seconds;
    }
    perma_stats stats;
    *items = perma_get_stats(bfs_session_runtime(s), &stats) == PERMA_OK ? stats.items : 0;
    bfs_session_destroy(s);
    return st;
}

bfs_status bfs_compare(const bfs_graph *g, uint32_t source, unsigned work_groups, unsigned repeats,
                       FILE *out, char *message, size_t size)
{
    size_t bytes = (size_t)g->vertices * sizeof(uint32_t);
    uint32_t *expected = malloc(bytes), *levels = malloc(bytes);
    bfs_status st = BFS_OK;
    double sequential = 1e30;
    for (unsigned r = 0; expected && levels && r < repeats + 1 && st == BFS_OK; ++r) {
        double start = now();
        if (bfs_sequential(g, source, expected) != 0)
            st = BFS_ERR_RUNTIME;
        double t = now() - start;
        sequential = r > 0 && t < sequential ? t : sequential;
    }
    if (!expected || !levels || st != BFS_OK) {
        free(expected);
        free(levels);
        snprintf(message, size, "bfs: --compare: out of memory for %u vertices", g->vertices);
        return BFS_ERR_RUNTIME;
    }
    fprintf(out, "%u vertices, %u arcs, source %u; best of %u runs after a warm-up; build excluded\n",
            g->vertices, g->arcs, source, repeats);
    fprintf(out, "%-36s %10s %12s %10s %10s %s\n", "version", "seconds", "/sequential", "build s",
            "items", "levels");
    fprintf(out, "%-36s %10.4f %12.2f %10s %10u %s\n", "sequential C (FIFO queue)", sequential, 1.0, "-",
            g->vertices, "reference");
    for (size_t i = 0; i < sizeof variants / sizeof variants[0] && st == BFS_OK; ++i) {
        bfs_run_options v;
        st = variant_options(i, work_groups, &v, message, size);
        if (st != BFS_OK)
            break;
        double build, seconds;
        uint64_t items;
        st = time_variant(g, &v, source, levels, repeats, &build, &seconds, &items, message, size);
        if (st != BFS_OK)
            break;
        char name[64];
        if (v.schedule.technique == PERMA_TECHNIQUE_MEGAKERNEL)
            snprintf(name, sizeof name, "perma %s / %s", perma_technique_name(v.schedule.technique),
                     perma_strategy_name(v.schedule.strategy));
        else
            snprintf(name, sizeof name, "perma %s", perma_technique_name(v.schedule.technique));
        fprintf(out, "%-36s %10.4f %12.2f %10.2f %10llu %s\n", name, seconds, seconds / sequential, build,
                (unsigned long long)items, memcmp(levels, expected, bytes) == 0 ? "identical" : "DIFFER");
        fflush(out);
    }
    free(expected);
    free(levels);
    return st;
}
