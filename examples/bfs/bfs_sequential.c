/* The sequential reference: a FIFO breadth-first search. */
#include <stdlib.h>

#include "bfs.h"

int bfs_sequential(const bfs_graph *g, uint32_t source, uint32_t *levels)
{
    uint32_t *queue = malloc(((size_t)g->vertices + 1) * sizeof *queue);
    if (!queue)
        return -1;
    for (uint32_t v = 0; v < g->vertices; ++v)
        levels[v] = BFS_UNREACHED;
    size_t head = 0, tail = 0;
    levels[source] = 0;
    queue[tail++] = source;
    while (head < tail) {
        uint32_t u = queue[head++];
        for (uint32_t a = g->offsets[u]; a < g->offsets[u + 1]; ++a) {
            uint32_t w = g->targets[a];
            if (levels[w] == BFS_UNREACHED) {
                levels[w] = levels[u] + 1;
                queue[tail++] = w;
            }
        }
    }
    free(queue);
    return 0;
}
