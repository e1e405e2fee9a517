/* The perma program: register visit and expand, bind the CSR arrays and
 * levels, seed the source (run by example_session.h). */
#include "bfs.h"

typedef struct device_visit {
    uint32_t vertex, level;
} device_visit;

static perma_status register_procedures(perma_runtime *rt, bfs_run *run)
{
    const char *source = bfs_device_procedures();
    perma_procedure visit = {
        .name = "visit", .item_type = "struct bfs_visit", .item_size = sizeof(device_visit),
        .threads_per_item = 1, .source = source, .source_file = "bfs_procedures.cl",
        .function = "bfs_visit",
        .emits = { { "visit", BFS_CHUNK }, { "expand", 1 } },
        .priority = 1, /* visit and expand emit into each other: visits first */
        /* Through the queues, near breadth-first order: run depth first, a
         * vertex first reached along a long path is expanded again for
         * every shorter one (ten times the visits on a power-law graph). */
        .queue_only = 1,
    };
    perma_procedure expand = {
        .name = "expand", .item_type = "struct bfs_slice", .item_size = 16,
        .threads_per_item = 1, .source = source, .source_file = "bfs_procedures.cl",
        .function = "bfs_expand",
        .emits = { { "visit", BFS_CHUNK }, { "expand", 2 } },
    };
    perma_proc expand_id;
    perma_status st;
    if ((st = perma_add_source(rt, bfs_device_types(), "bfs_types.cl")) != PERMA_OK ||
        (st = perma_register(rt, &visit, &run->visit)) != PERMA_OK ||
        (st = perma_register(rt, &expand, &expand_id)) != PERMA_OK)
        return st;
    return PERMA_OK;
}

static perma_status build(perma_runtime *rt, void *data, const char **step)
{
    bfs_run *run = data;
    const bfs_graph *g = run->graph;
    size_t arcs = g->arcs ? g->arcs : 1;
    perma_status st = register_procedures(rt, run);
    if (st != PERMA_OK)
        return st;
    *step = "binding buffers";
    if ((st = perma_bind_host(rt, "offsets", "__global const uint *", g->offsets,
                              ((size_t)g->vertices + 1) * sizeof *g->offsets, PERMA_READ)) != PERMA_OK ||
        (st = perma_bind_host(rt, "targets", "__global const uint *", g->targets, arcs * sizeof *g->targets,
                              PERMA_READ)) != PERMA_OK ||
        (st = perma_bind_host(rt, "levels", "__global uint *", run->levels,
                              (size_t)g->vertices * sizeof *run->levels, PERMA_READ_WRITE)) != PERMA_OK)
        return st;
    return PERMA_OK;
}

/* Every vertex unreached but the source, which is the root item. */
static perma_status seed(perma_runtime *rt, void *data)
{
    bfs_run *run = data;
    for (uint32_t v = 0; v < run->graph->vertices; ++v)
        run->levels[v] = BFS_UNREACHED;
    run->levels[run->source] = 0;
    device_visit root = { run->source, 0 };
    return perma_seed(rt, run->visit, &root, 1);
}

const example_program bfs_program = { "perma-bfs", build, seed };

bfs_status bfs_perma(const bfs_graph *g, const example_run_options *options, uint32_t source,
                     uint32_t *levels, char *message, size_t size)
{
    if (source >= g->vertices) {
        snprintf(message, size, "perma-bfs: source vertex %u is not below the %u vertices", source, g->vertices);
        return BFS_ERR_USAGE;
    }
    bfs_run run = { g, source, levels, 0 };
    return example_session_once(&bfs_program, &run, options, NULL, 0, message, size) ? BFS_ERR_RUNTIME : BFS_OK;
}
