/* Compressed sparse rows from an edge list. */
#include <stdlib.h>
#include <string.h>

#include "bfs.h"

bfs_status bfs_build_csr(const bfs_edges *e, int undirected, bfs_graph *out,
                         char *message, size_t size)
{
    *out = (bfs_graph){ 0 };
    size_t arcs = e->count * (undirected ? 2 : 1);
    if (arcs >= UINT32_MAX) {
        snprintf(message, size, "perma-bfs: %zu arcs do not fit 32-bit CSR offsets", arcs);
        return BFS_ERR_RUNTIME;
    }
    out->vertices = e->vertices;
    out->arcs = (uint32_t)arcs;
    out->offsets = calloc((size_t)e->vertices + 1, sizeof *out->offsets);
    out->targets = malloc((arcs ? arcs : 1) * sizeof *out->targets);
    if (!out->offsets || !out->targets) {
        bfs_graph_free(out);
        snprintf(message, size, "perma-bfs: out of memory for a graph of %zu arcs", arcs);
        return BFS_ERR_RUNTIME;
    }
    /* Count out-degrees into offsets[v+1], prefix-sum, then place. */
    for (size_t i = 0; i < e->count; ++i) {
        out->offsets[e->pairs[i][0] + 1]++;
        if (undirected)
            out->offsets[e->pairs[i][1] + 1]++;
    }
    for (uint32_t v = 0; v < e->vertices; ++v)
        out->offsets[v + 1] += out->offsets[v];
    uint32_t *next = malloc(((size_t)e->vertices + 1) * sizeof *next);
    if (!next) {
        bfs_graph_free(out);
        snprintf(message, size, "perma-bfs: out of memory for a graph of %u vertices", e->vertices);
        return BFS_ERR_RUNTIME;
    }
    memcpy(next, out->offsets, ((size_t)e->vertices + 1) * sizeof *next);
    for (size_t i = 0; i < e->count; ++i) {
        uint32_t u = e->pairs[i][0], v = e->pairs[i][1];
        out->targets[next[u]++] = v;
        if (undirected)
            out->targets[next[v]++] = u;
    }
    free(next);
    return BFS_OK;
}

void bfs_graph_free(bfs_graph *g)
{
    free(g->offsets);
    free(g->targets);
    *g = (bfs_graph){ 0 };
}
