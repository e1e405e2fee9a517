/* The sequential C and OpenMP-task versions of the `perma-bench plain`
 * workloads (plain_sequential.c, plain_openmp.c, built at -O3), doing per
 * node, interval, board or range the work of plain_work.h that the perma
 * procedures do per item. */
#ifndef PLAIN_BASELINES_H
#define PLAIN_BASELINES_H

#include "plain_work.h"

#include <stdint.h>

/* ---- UTS trees ---- */

typedef struct plain_uts_tree {
    int binomial;          /* 0: geometric */
    ulong root_hash;
    uint max_depth;        /* geometric */
    ulong p64;
    uint b0, m;            /* binomial: root's children, others' m or none */
    ulong q64;
} plain_uts_tree;

typedef struct plain_uts_result {
    uint64_t nodes, hash_sum;
} plain_uts_result;

static inline uint plain_uts_children(const plain_uts_tree *t, const struct uts_node *n)
{
    if (!t->binomial)
        return uts_geometric_children(n->hash, n->depth, t->max_depth, t->p64);
    return n->depth == 0u ? t->b0 : uts_binomial_children(n->hash, t->m, t->q64);
}

/* Depth first with an explicit stack; -1 if out of memory. */
int plain_uts_sequential(const plain_uts_tree *t, plain_uts_result *out);
/* Nodes above depth spawn_depth spawn a task per child, deeper ones
 * recurse inline (UINT32_MAX: a task per node). */
void plain_uts_openmp(const plain_uts_tree *t, unsigned threads, uint spawn_depth, plain_uts_result *out);

/* ---- adaptive Simpson ---- */

typedef struct plain_simpson_result {
    uint64_t accepted;     /* intervals accepted */
    uint64_t area_bits;    /* sum of the bit patterns of their areas */
    double area;           /* sum of their areas: the integral */
} plain_simpson_result;

/* The textbook recursion: the area of an interval is its accepted area or
 * the sum of its halves' (the integer checks add up in any order). */
static inline double plain_simpson_visit(const struct simpson_interval *s, uint max_depth, plain_simpson_result *r)
{
    double area;
    struct simpson_interval halves[2];
    if (simpson_step(s->a, s->b, s->fa, s->fm, s->fb, s->whole, s->eps, s->depth, max_depth, &area, halves)) {
        union { double d; uint64_t u; } bits = { area };
        r->accepted++;
        r->area_bits += bits.u;
        return area;
    }
    double left = plain_simpson_visit(&halves[0], max_depth, r);
    return left + plain_simpson_visit(&halves[1], max_depth, r);
}

void plain_simpson_sequential(const struct simpson_interval *root, uint max_depth, plain_simpson_result *out);
/* Intervals above depth spawn_depth are split into two tasks whose sums
 * are added after a taskwait, deeper ones recurse inline: the sum is added
 * in the same order as sequentially, so it is bit-identical to it. */
void plain_simpson_openmp(const struct simpson_interval *root, uint max_depth, unsigned threads, uint spawn_depth,
                          plain_simpson_result *out);

/* ---- N-Queens ---- */

/* All solutions of the n x n board. */
uint64_t plain_queens_sequential(uint n);
/* Boards with fewer than spawn_depth queens spawn a task per child, the
 * others are solved inside their task. */
uint64_t plain_queens_openmp(uint n, unsigned threads, uint spawn_depth);

/* ---- subset sum ---- */

typedef struct plain_subset_instance {
    uint n;                                 /* weights */
    uint weights[SUBSET_MAX_WEIGHTS];
    uint suffix[SUBSET_MAX_WEIGHTS + 1u];   /* suffix[i]: weights i, i + 1, ... */
    uint target;                            /* half their sum */
} plain_subset_instance;

typedef struct plain_subset_result {
    uint64_t nodes, solutions;
} plain_subset_result;

/* The instance of n weights (subset_weight). */
void plain_subset_instance_init(plain_subset_instance *s, uint n);
/* The textbook recursion over the whole search tree. */
void plain_subset_sequential(const plain_subset_instance *s, plain_subset_result *out);
/* Nodes above depth spawn_depth spawn a task per child, deeper ones
 * recurse inside their task. */
void plain_subset_openmp(const plain_subset_instance *s, unsigned threads, uint spawn_depth, plain_subset_result *out);

/* ---- quicksort ---- */

void plain_sort_sequential(uint *keys, uint n);
/* Ranges longer than cutoff keys are partitioned; above depth spawn_depth
 * their sides become two tasks, deeper ones are sorted inside the task
 * (UINT32_MAX: a task per range longer than cutoff). */
void plain_sort_openmp(uint *keys, uint n, uint cutoff, unsigned threads, uint spawn_depth);

#endif
