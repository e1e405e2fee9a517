/*
 * perma-queens: count the N-queens solutions and search-tree nodes with a
 * perma procedure, in one process or spread over MPI ranks that steal
 * subtrees from each other (docs/scale-out.md).
 *
 * The search tree: a node is a valid placement of queens on the first
 * `row` rows (the empty board is the root); its children add a queen on
 * the next row where no queen attacks it.  The leaves at row N are the
 * solutions.  The host cuts the tree at row `depth`: the nodes there are
 * the work units, whose subtrees perma counts, `chunk` units per run.
 */
#ifndef QUEENS_H
#define QUEENS_H

#include <stddef.h>
#include <stdint.h>

#include "perma.h"

#define QUEENS_MAX_N 16

/* A node: occupied columns and the two diagonal masks seen from the next
 * row, as bit sets of the n columns. */
typedef struct queens_node {
    uint32_t row, n, columns, left, right;
} queens_node;

typedef struct queens_counts {
    uint64_t solutions;
    uint64_t nodes;
} queens_counts;

/* Sequential count of the whole tree (root included). */
queens_counts queens_count_sequential(unsigned n);

/* The nodes at row `depth` in depth-first order into *units (allocated,
 * free it), their number into *count, and the nodes above that row (root
 * included) and the solutions among them (depth >= n) into *above. */
int queens_units(unsigned n, unsigned depth, queens_node **units, size_t *count, queens_counts *above);

/* A perma runtime with the counting procedure, on `device` (NULL: the
 * default device). */
typedef struct queens_counter queens_counter;

perma_status queens_counter_create(const perma_device_ref *device, queens_counter **out, perma_error *error);
void queens_counter_destroy(queens_counter *counter);
const char *queens_counter_device(const queens_counter *counter);
/* Count the subtrees of `count` units (added to *counts); the message of a
 * failure is perma_errmsg's, in *error. */
perma_status queens_counter_run(queens_counter *counter, const queens_node *units, size_t count,
                                queens_counts *counts, perma_error *error);

#endif
