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
    bfs_run run;        /* perma's levels */
    uint32_t *expected; /* the sequential levels */
} compare_data;

static int run_sequential(void *data)
{
    compare_data *d = data;
    return bfs_sequential(d->run.graph, d->run.source, d->expected);
}

static const char *check(void *data)
{
    compare_data *d = data;
    return memcmp(d->run.levels, d->expected, (size_t)d->run.graph->vertices * sizeof *d->expected) == 0
               ? "identical"
               : "DIFFER";
}

bfs_status bfs_compare(const bfs_graph *g, uint32_t source, unsigned work_groups, unsigned repeats,
                       FILE *out, char *message, size_t size)
{
    size_t bytes = (size_t)g->vertices * sizeof(uint32_t);
    compare_data d = { { g, source, malloc(bytes), 0 }, malloc(bytes) };
    example_compare ex = { &bfs_program, &d.run, check, &d, "levels", 1 };
    double sequential = d.expected && d.run.levels ? example_compare_best(repeats, run_sequential, &d) : -1;
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
    free(d.run.levels);
    return st;
}
