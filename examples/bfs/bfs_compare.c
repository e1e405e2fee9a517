/*
 * --compare: the sequential BFS and the perma version under every schedule
 * on the same graph, through the examples' harness
 * (examples/common/example_compare.h), every result checked against the
 * sequential levels.
 */
#include <stdlib.h>
#include <string.h>

#include "bfs.h"
#include "example_compare.h"

typedef struct compare_data {
    const bfs_graph *graph;
    uint32_t source;
    uint32_t *expected; /* the sequential levels */
    uint32_t *levels;   /* perma's */
} compare_data;

static int run_sequential(void *data)
{
    compare_data *d = data;
    return bfs_sequential(d->graph, d->source, d->expected);
}

static int create(void *data, const perma_schedule *schedule, unsigned work_groups, void **session,
                  char *message, size_t size)
{
    compare_data *d = data;
    bfs_run_options options = { *schedule, work_groups };
    return bfs_session_create(d->graph, &options, d->levels, (bfs_session **)session, message, size);
}

static int run(void *data, void *session, char *message, size_t size)
{
    compare_data *d = data;
    return bfs_session_run(session, d->source, message, size);
}

static perma_runtime *runtime(void *session)
{
    return bfs_session_runtime(session);
}

static void destroy(void *session)
{
    bfs_session_destroy(session);
}

static const char *check(void *data)
{
    compare_data *d = data;
    return memcmp(d->levels, d->expected, (size_t)d->graph->vertices * sizeof *d->levels) == 0 ? "identical"
                                                                                              : "DIFFER";
}

bfs_status bfs_compare(const bfs_graph *g, uint32_t source, unsigned work_groups, unsigned repeats,
                       FILE *out, char *message, size_t size)
{
    size_t bytes = (size_t)g->vertices * sizeof(uint32_t);
    compare_data d = { g, source, malloc(bytes), malloc(bytes) };
    example_compare ex = { &d, create, run, runtime, destroy, check, "levels", 1 };
    double sequential = d.expected && d.levels ? example_compare_best(repeats, run_sequential, &d) : -1;
    bfs_status st = BFS_OK;
    if (sequential < 0) {
        snprintf(message, size, "perma-bfs: --compare: out of memory for %u vertices", g->vertices);
        st = BFS_ERR_RUNTIME;
    } else {
        fprintf(out, "%u vertices, %u arcs, source %u; best of %u runs after a warm-up; build excluded\n",
                g->vertices, g->arcs, source, repeats);
        example_compare_header(&ex, out);
        example_compare_row(&ex, out, "sequential C (FIFO queue)", sequential, sequential, -1, g->vertices,
                            "reference");
        if (example_compare_schedules(&ex, work_groups, repeats, sequential, out, message, size) != 0)
            st = BFS_ERR_RUNTIME;
    }
    free(d.expected);
    free(d.levels);
    return st;
}
