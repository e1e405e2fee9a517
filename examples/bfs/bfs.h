/*
 * Breadth-first levels on perma: shared types and the functions of the
 * example's small library (used by the program and its tests).
 *
 * Every function that can fail returns a bfs_status and writes a message
 * naming the file and line, option or step into a caller's buffer.
 */
#ifndef BFS_H
#define BFS_H

#include <perma.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "example_session.h"

/* Exit codes of the program follow the README: 0 ok, 1 runtime or file
 * failure (as reyes-render does for a bad model file), 2 bad usage. */
typedef enum bfs_status {
    BFS_OK = 0,
    BFS_ERR_RUNTIME = 1,
    BFS_ERR_USAGE = 2
} bfs_status;

#define BFS_UNREACHED UINT32_MAX
#define BFS_MAX_VERTICES 100000000u

/* A list of edges (u, v); `vertices` is one more than the largest id. */
typedef struct bfs_edges {
    uint32_t (*pairs)[2];
    size_t count, capacity;
    uint32_t vertices;
} bfs_edges;

/* Read "u v" lines; blank lines and '#' comments (whole or trailing) are
 * skipped.  A malformed line fails with "FILE:LINE: ..." in the message. */
bfs_status bfs_read_edges(const char *path, bfs_edges *out, char *message, size_t size);
/* Append one edge, growing the list; -1 when out of memory. */
int bfs_edges_add(bfs_edges *e, uint32_t u, uint32_t v);
void bfs_edges_free(bfs_edges *e);

/* A deterministic power-law graph: Barabasi-Albert preferential attachment,
 * each new vertex linking to `degree` earlier ones chosen in proportion to
 * their degree, driven by a splitmix64 generator seeded with `seed`. */
bfs_status bfs_generate(uint32_t vertices, uint32_t degree, uint64_t seed, bfs_edges *out,
                        char *message, size_t size);

/* Compressed sparse rows: the neighbours of v are
 * targets[offsets[v] .. offsets[v+1]-1]. */
typedef struct bfs_graph {
    uint32_t vertices;
    uint32_t arcs;
    uint32_t *offsets;  /* vertices + 1 */
    uint32_t *targets;  /* arcs (at least one element, so it can be bound) */
} bfs_graph;

/* Build CSR; undirected adds each edge in both directions. */
bfs_status bfs_build_csr(const bfs_edges *e, int undirected, bfs_graph *out,
                         char *message, size_t size);
void bfs_graph_free(bfs_graph *g);

/* Sequential BFS into levels[vertices] (BFS_UNREACHED if not reached);
 * returns 0, or -1 when out of memory. */
int bfs_sequential(const bfs_graph *g, uint32_t source, uint32_t *levels);

/* The perma program (bfs_perma.c) over one graph: each run writes the
 * levels from `source` into `levels` (the caller's, one per vertex).  The
 * build sets `visit`. */
typedef struct bfs_run {
    const bfs_graph *graph;
    uint32_t source;
    uint32_t *levels;
    perma_proc visit;
} bfs_run;

extern const example_program bfs_program;

/* Levels with a fresh session (build included); BFS_ERR_USAGE if the
 * source is not a vertex. */
bfs_status bfs_perma(const bfs_graph *g, const example_run_options *options, uint32_t source,
                     uint32_t *levels, char *message, size_t size);

/* Device source: item types and the visit and expand procedures. */
const char *bfs_device_types(void);
const char *bfs_device_procedures(void);
/* Edges one visit or expand item relaxes itself; longer lists are halved. */
#define BFS_CHUNK 16

/* --compare: time the sequential BFS and every technique/strategy. */
bfs_status bfs_compare(const bfs_graph *g, uint32_t source, unsigned work_groups, unsigned repeats,
                       FILE *out, char *message, size_t size);

#endif
