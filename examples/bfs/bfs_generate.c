/* A deterministic preferential-attachment (Barabasi-Albert) graph. */
#include "bfs.h"

/* splitmix64: small, fast, and the same sequence on every platform. */
static uint64_t next_random(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

bfs_status bfs_generate(uint32_t vertices, uint32_t degree, uint64_t seed, bfs_edges *out,
                        char *message, size_t size)
{
    *out = (bfs_edges){ 0 };
    if (vertices < 2 || vertices > BFS_MAX_VERTICES || degree < 1 || degree >= vertices) {
        snprintf(message, size, "bfs_generate: need 2 <= vertices <= %u and 1 <= degree < vertices "
                 "(got %u vertices, degree %u)", BFS_MAX_VERTICES, vertices, degree);
        return BFS_ERR_USAGE;
    }
    uint64_t state = seed;
    /* Start from a path over the first degree+1 vertices.  Every edge's two
     * endpoints are in out->pairs, so a uniform pick among all endpoints is a
     * pick in proportion to degree. */
    for (uint32_t v = 1; v <= degree; ++v)
        if (bfs_edges_add(out, v - 1, v) != 0)
            goto no_memory;
    for (uint32_t v = degree + 1; v < vertices; ++v) {
        size_t endpoints = 2 * out->count;
        for (uint32_t k = 0; k < degree; ++k) {
            size_t pick = (size_t)(next_random(&state) % endpoints);
            if (bfs_edges_add(out, v, out->pairs[pick / 2][pick % 2]) != 0)
                goto no_memory;
        }
    }
    return BFS_OK;
no_memory:
    snprintf(message, size, "bfs_generate: out of memory after %zu edges", out->count);
    bfs_edges_free(out);
    return BFS_ERR_RUNTIME;
}
