/* The plain workloads with OpenMP tasks (gcc's libgomp), as a CPU
 * programmer would write them: recursive tasks above a depth cutoff, the
 * subtrees below it inside one task counted in locals, each thread adding
 * its tasks' counts into its own cache line. */
#include "plain_baselines.h"

#include <omp.h>
#include <string.h>

enum { MAX_THREADS = 256 };

/* One cache line per thread (aligned: otherwise two threads' sums may
 * share a line, and every update bounces it between the cores). */
struct thread_sums {
    _Alignas(64) uint64_t a;
    uint64_t b;
};

static struct thread_sums sums[MAX_THREADS];

static unsigned clamp_threads(unsigned threads)
{
    memset(sums, 0, sizeof sums);
    return threads > MAX_THREADS ? MAX_THREADS : threads;
}

static struct thread_sums add_sums(unsigned threads)
{
    struct thread_sums total = { 0, 0 };
    for (unsigned t = 0; t < threads; ++t) {
        total.a += sums[t].a;
        total.b += sums[t].b;
    }
    return total;
}

/* ---- UTS ---- */

/* A subtree inside one task, counted in locals. */
static void uts_inline(const plain_uts_tree *t, struct uts_node n, plain_uts_result *r)
{
    r->nodes++;
    r->hash_sum += n.hash;
    uint k = plain_uts_children(t, &n);
    for (uint i = 0; i < k; ++i)
        uts_inline(t, uts_child(n.hash, n.depth, i), r);
}

static void uts_visit(const plain_uts_tree *t, struct uts_node n, uint spawn_depth)
{
    struct thread_sums *s = &sums[omp_get_thread_num()];
    if (n.depth >= spawn_depth) {
        plain_uts_result r = { 0, 0 };
        uts_inline(t, n, &r);
        s->a += r.nodes;
        s->b += r.hash_sum;
        return;
    }
    s->a++;
    s->b += n.hash;
    uint k = plain_uts_children(t, &n);
    for (uint i = 0; i < k; ++i) {
        struct uts_node child = uts_child(n.hash, n.depth, i);
#pragma omp task firstprivate(child)
        uts_visit(t, child, spawn_depth);
    }
}

void plain_uts_openmp(const plain_uts_tree *t, unsigned threads, uint spawn_depth, plain_uts_result *out)
{
    threads = clamp_threads(threads);
#pragma omp parallel num_threads(threads)
#pragma omp single
    uts_visit(t, (struct uts_node){ t->root_hash, 0u, 0u }, spawn_depth);
    struct thread_sums total = add_sums(threads);
    out->nodes = total.a;
    out->hash_sum = total.b;
}

/* ---- adaptive Simpson ---- */

static double simpson_task(const struct simpson_interval *s, uint max_depth, uint spawn_depth,
                           plain_simpson_result *r)
{
    if (s->depth >= spawn_depth)
        return plain_simpson_visit(s, max_depth, r);
    double area;
    struct simpson_interval halves[2];
    if (simpson_step(s->a, s->b, s->fa, s->fm, s->fb, s->whole, s->eps, s->depth, max_depth, &area, halves)) {
        union { double d; uint64_t u; } bits = { area };
        r->accepted++;
        r->area_bits += bits.u;
        return area;
    }
    plain_simpson_result left = { 0, 0, 0.0 }, right = { 0, 0, 0.0 };
    double left_area, right_area;
#pragma omp task shared(halves, left, left_area)
    left_area = simpson_task(&halves[0], max_depth, spawn_depth, &left);
#pragma omp task shared(halves, right, right_area)
    right_area = simpson_task(&halves[1], max_depth, spawn_depth, &right);
#pragma omp taskwait
    r->accepted += left.accepted + right.accepted;
    r->area_bits += left.area_bits + right.area_bits;
    return left_area + right_area;
}

void plain_simpson_openmp(const struct simpson_interval *root, uint max_depth, unsigned threads, uint spawn_depth,
                          plain_simpson_result *out)
{
    plain_simpson_result r = { 0, 0, 0.0 };
    threads = clamp_threads(threads);
#pragma omp parallel num_threads(threads)
#pragma omp single
    r.area = simpson_task(root, max_depth, spawn_depth, &r);
    *out = r;
}

/* ---- N-Queens ---- */

static void queens_task(uint n, struct queens_board b, uint spawn_depth)
{
    if (b.row >= spawn_depth) {
        sums[omp_get_thread_num()].a += queens_solve(n, b.row, b.columns, b.left, b.right);
        return;
    }
    uint free = queens_free(n, b.columns, b.left, b.right);
    while (free) {
        uint bit = free & (0u - free);
        free ^= bit;
        struct queens_board next = queens_place(n, b.row, b.columns, b.left, b.right, bit);
#pragma omp task firstprivate(next)
        queens_task(n, next, spawn_depth);
    }
}

uint64_t plain_queens_openmp(uint n, unsigned threads, uint spawn_depth)
{
    threads = clamp_threads(threads);
#pragma omp parallel num_threads(threads)
#pragma omp single
    queens_task(n, (struct queens_board){ 0u, 0u, 0u, 0u }, spawn_depth);
    return add_sums(threads).a;
}

/* ---- quicksort ---- */

static void sort_task(uint *keys, uint lo, uint hi, uint cutoff, uint depth, uint spawn_depth)
{
    if (hi - lo <= cutoff || depth >= spawn_depth) {
        sort_range_sequential(keys, lo, hi);
        return;
    }
    uint p = sort_partition(keys, lo, hi);
#pragma omp task
    sort_task(keys, lo, p, cutoff, depth + 1u, spawn_depth);
#pragma omp task
    sort_task(keys, p, hi, cutoff, depth + 1u, spawn_depth);
}

void plain_sort_openmp(uint *keys, uint n, uint cutoff, unsigned threads, uint spawn_depth)
{
    threads = clamp_threads(threads);
#pragma omp parallel num_threads(threads)
#pragma omp single
    sort_task(keys, 0u, n, cutoff, 0u, spawn_depth);
}

/* ---- subset sum ---- */

static void subset_inline(const plain_subset_instance *s, uint index, uint need, plain_subset_result *r)
{
    r->nodes++;
    r->solutions += need == 0u;
    if (!subset_branches(s->n, s->suffix, index, need))
        return;
    subset_inline(s, index + 1u, need, r);
    if (s->weights[index] <= need)
        subset_inline(s, index + 1u, need - s->weights[index], r);
}

static void subset_task(const plain_subset_instance *s, uint index, uint need, uint spawn_depth)
{
    struct thread_sums *t = &sums[omp_get_thread_num()];
    if (index >= spawn_depth) {
        plain_subset_result r = { 0, 0 };
        subset_inline(s, index, need, &r);
        t->a += r.nodes;
        t->b += r.solutions;
        return;
    }
    t->a++;
    t->b += need == 0u;
    if (!subset_branches(s->n, s->suffix, index, need))
        return;
#pragma omp task
    subset_task(s, index + 1u, need, spawn_depth);
    if (s->weights[index] <= need) {
#pragma omp task
        subset_task(s, index + 1u, need - s->weights[index], spawn_depth);
    }
}

void plain_subset_openmp(const plain_subset_instance *s, unsigned threads, uint spawn_depth, plain_subset_result *out)
{
    threads = clamp_threads(threads);
#pragma omp parallel num_threads(threads)
#pragma omp single
    subset_task(s, 0u, s->target, spawn_depth);
    struct thread_sums total = add_sums(threads);
    out->nodes = total.a;
    out->solutions = total.b;
}
