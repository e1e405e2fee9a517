/* bfs: breadth-first levels of a graph with perma, or --compare. */
#include <stdlib.h>
#include <string.h>

#include "bfs_options.h"

static bfs_status load_graph(const bfs_options *o, bfs_graph *g, char *message, size_t size)
{
    bfs_edges edges;
    bfs_status st = o->edge_file ? bfs_read_edges(o->edge_file, &edges, message, size)
                                 : bfs_generate(o->generate, o->degree, o->seed, &edges, message, size);
    if (st != BFS_OK)
        return st;
    st = bfs_build_csr(&edges, !o->directed, g, message, size);
    bfs_edges_free(&edges);
    if (st == BFS_OK && o->source >= g->vertices) {
        snprintf(message, size, "--source %u: the graph has vertices 0..%u", o->source, g->vertices - 1);
        bfs_graph_free(g);
        return BFS_ERR_USAGE;
    }
    return st;
}

static void print_summary(const bfs_graph *g, uint32_t source, const uint32_t *levels)
{
    uint32_t deepest = 0, reached = 0;
    for (uint32_t v = 0; v < g->vertices; ++v)
        if (levels[v] != BFS_UNREACHED) {
            ++reached;
            deepest = levels[v] > deepest ? levels[v] : deepest;
        }
    printf("%u vertices, %u arcs; from vertex %u reached %u vertices in %u levels\n", g->vertices,
           g->arcs, source, reached, deepest + 1);
    uint32_t *per_level = calloc((size_t)deepest + 1, sizeof *per_level);
    if (!per_level)
        return;
    for (uint32_t v = 0; v < g->vertices; ++v)
        if (levels[v] != BFS_UNREACHED)
            per_level[levels[v]]++;
    for (uint32_t l = 0; l <= deepest && l < 32; ++l)
        printf("  level %2u: %u vertices\n", l, per_level[l]);
    free(per_level);
}

static bfs_status write_levels(const char *path, const bfs_graph *g, const uint32_t *levels,
                               char *message, size_t size)
{
    perma_output *out;
    perma_error error;
    if (perma_output_open(path, &out, &error) != PERMA_OK) {
        snprintf(message, size, "%s", error.message);
        return BFS_ERR_RUNTIME;
    }
    FILE *f = perma_output_stream(out);
    for (uint32_t v = 0; v < g->vertices; ++v)
        fprintf(f, "%u %lld\n", v, levels[v] == BFS_UNREACHED ? -1LL : (long long)levels[v]);
    if (perma_output_commit(out, &error) != PERMA_OK) {
        snprintf(message, size, "%s", error.message);
        return BFS_ERR_RUNTIME;
    }
    return BFS_OK;
}

static bfs_status traverse(const bfs_options *o, const bfs_graph *g, char *message, size_t size)
{
    uint32_t *levels = malloc(((size_t)g->vertices) * sizeof *levels);
    if (!levels) {
        snprintf(message, size, "perma-bfs: out of memory for %u levels", g->vertices);
        return BFS_ERR_RUNTIME;
    }
    bfs_run run = { g, o->source, levels, 0 };
    bfs_status st = example_session_once(&bfs_program, &run, &o->common.run, stdout, o->common.stats, message, size)
                        ? BFS_ERR_RUNTIME
                        : BFS_OK;
    if (st == BFS_OK)
        print_summary(g, o->source, levels);
    if (st == BFS_OK && o->output)
        st = write_levels(o->output, g, levels, message, size);
    free(levels);
    return st;
}

int main(int argc, char **argv)
{
    char message[PERMA_MESSAGE_MAX + 256] = "";
    bfs_options o;
    perma_cli_status parsed = bfs_parse_options(argc, argv, &o, message, sizeof message);
    if (parsed != PERMA_CLI_OK)
        return perma_cli_exit_status(parsed);
    bfs_graph g;
    bfs_status st = load_graph(&o, &g, message, sizeof message);
    if (st == BFS_OK) {
        if (o.common.compare)
            st = bfs_compare(&g, o.source, o.common.run.work_groups, o.common.repeats, stdout, message,
                             sizeof message);
        else
            st = traverse(&o, &g, message, sizeof message);
        bfs_graph_free(&g);
    }
    if (st == BFS_ERR_USAGE)
        perma_cli_print_error("perma-bfs", message);
    else if (st != BFS_OK)
        fprintf(stderr, "%s\n", message);
    return st;
}
