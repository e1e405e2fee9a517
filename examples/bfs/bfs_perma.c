/* The perma side: register visit and expand, bind the CSR arrays and levels. */
#include <stdlib.h>

#include "bfs.h"

struct bfs_session {
    perma_runtime *rt;
    perma_proc visit;
    uint32_t vertices;
    uint32_t *levels;
};

typedef struct device_visit {
    uint32_t vertex, level;
} device_visit;

static bfs_status fail(bfs_session *s, const char *step, char *message, size_t size)
{
    snprintf(message, size, "perma-bfs: %s: %s", step, perma_errmsg(s->rt));
    return BFS_ERR_RUNTIME;
}

static perma_status register_procedures(bfs_session *s)
{
    const char *source = bfs_device_procedures();
    perma_procedure visit = {
        .name = "visit", .item_type = "struct bfs_visit", .item_size = sizeof(device_visit),
        .threads_per_item = 1, .source = source, .source_file = "bfs_procedures.cl",
        .function = "bfs_visit",
        .emits = { { "visit", BFS_CHUNK }, { "expand", 1 } },
        .priority = 1, /* visit and expand emit into each other: visits first */
    };
    perma_procedure expand = {
        .name = "expand", .item_type = "struct bfs_slice", .item_size = 16,
        .threads_per_item = 1, .source = source, .source_file = "bfs_procedures.cl",
        .function = "bfs_expand",
        .emits = { { "visit", BFS_CHUNK }, { "expand", 2 } },
    };
    perma_proc expand_id;
    perma_status st;
    if ((st = perma_add_source(s->rt, bfs_device_types(), "bfs_types.cl")) != PERMA_OK ||
        (st = perma_register(s->rt, &visit, &s->visit)) != PERMA_OK ||
        (st = perma_register(s->rt, &expand, &expand_id)) != PERMA_OK)
        return st;
    return PERMA_OK;
}

bfs_status bfs_session_create(const bfs_graph *g, const bfs_run_options *options, uint32_t *levels,
                              bfs_session **out, char *message, size_t size)
{
    *out = NULL;
    bfs_session *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(message, size, "perma-bfs: out of memory for the session");
        return BFS_ERR_RUNTIME;
    }
    s->vertices = g->vertices;
    s->levels = levels;
    perma_config config;
    perma_config_init(&config);
    config.schedule = options->schedule;
    config.work_groups = options->work_groups;
    perma_error error;
    if (perma_create(&config, &s->rt, &error) != PERMA_OK) {
        snprintf(message, size, "perma-bfs: perma_create: %s", error.message);
        free(s);
        return BFS_ERR_RUNTIME;
    }
    bfs_status st = BFS_OK;
    size_t arcs = g->arcs ? g->arcs : 1;
    if (register_procedures(s) != PERMA_OK)
        st = fail(s, "registering procedures", message, size);
    else if (perma_bind_host(s->rt, "offsets", "__global const uint *", g->offsets,
                             ((size_t)g->vertices + 1) * sizeof *g->offsets, PERMA_READ) != PERMA_OK ||
             perma_bind_host(s->rt, "targets", "__global const uint *", g->targets,
                             arcs * sizeof *g->targets, PERMA_READ) != PERMA_OK ||
             perma_bind_host(s->rt, "levels", "__global uint *", levels,
                             (size_t)g->vertices * sizeof *levels, PERMA_READ_WRITE) != PERMA_OK)
        st = fail(s, "binding buffers", message, size);
    else if (perma_build(s->rt) != PERMA_OK)
        st = fail(s, "building the program", message, size);
    if (st != BFS_OK) {
        bfs_session_destroy(s);
        return st;
    }
    *out = s;
    return BFS_OK;
}

bfs_status bfs_session_run(bfs_session *s, uint32_t source, char *message, size_t size)
{
    if (source >= s->vertices) {
        snprintf(message, size, "perma-bfs: source vertex %u is not below the %u vertices", source, s->vertices);
        return BFS_ERR_USAGE;
    }
    for (uint32_t v = 0; v < s->vertices; ++v)
        s->levels[v] = BFS_UNREACHED;
    s->levels[source] = 0;
    device_visit root = { source, 0 };
    if (perma_seed(s->rt, s->visit, &root, 1) != PERMA_OK)
        return fail(s, "seeding", message, size);
    if (perma_run(s->rt) != PERMA_OK)
        return fail(s, "running", message, size);
    return BFS_OK;
}

perma_runtime *bfs_session_runtime(bfs_session *s)
{
    return s->rt;
}

void bfs_session_destroy(bfs_session *s)
{
    if (!s)
        return;
    perma_destroy(s->rt);
    free(s);
}

bfs_status bfs_perma(const bfs_graph *g, const bfs_run_options *options, uint32_t source,
                     uint32_t *levels, char *message, size_t size)
{
    bfs_session *s;
    bfs_status st = bfs_session_create(g, options, levels, &s, message, size);
    if (st != BFS_OK)
        return st;
    st = bfs_session_run(s, source, message, size);
    bfs_session_destroy(s);
    return st;
}
