/* The work of one item of each `perma-bench plain` workload, written once
 * in the common subset of C and OpenCL C: the sequential C and OpenMP
 * baselines include this header (built at -O3), and the build embeds it as
 * the device source of the perma procedures (plain_*.cl), so every count
 * does the identical arithmetic on the identical items.
 *
 * Only correctly rounded double operations (+ - * /) and no contraction into
 * fma, so the adaptive Simpson tree is the same on the host and the device. */
#ifndef PLAIN_WORK_H
#define PLAIN_WORK_H

#ifdef __OPENCL_VERSION__
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL FP_CONTRACT OFF
#define PLAIN_FN
#define PLAIN_GLOBAL __global
#define PLAIN_CONSTANT __constant
#else
#include <math.h>
#include <stdint.h>
typedef uint32_t uint;
typedef uint64_t ulong;
#define PLAIN_FN static inline
#define PLAIN_GLOBAL
#define PLAIN_CONSTANT
#endif

/* ---- UTS trees: a node per item, a splitmix64 hash per child ---- */

#define UTS_MAX_CHILDREN 32u   /* geometric: most children of one node */

struct uts_node {
    ulong hash;
    uint depth;
    uint pad;
};

/* splitmix64's output function on state x + golden ratio. */
PLAIN_FN ulong splitmix64(ulong x)
{
    x += 0x9e3779b97f4a7c15UL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9UL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebUL;
    return x ^ (x >> 31);
}

/* Child i of a node with hash `parent`: the (i+1)-th number of the
 * splitmix64 stream seeded with it. */
PLAIN_FN struct uts_node uts_child(ulong parent, uint depth, uint i)
{
    struct uts_node child = { splitmix64(parent + (ulong)i * 0x9e3779b97f4a7c15UL), depth + 1u, 0u };
    return child;
}

/* Geometric tree: below max_depth a node has k children with probability
 * (1 - p) p^k (at most UTS_MAX_CHILDREN), p = p64 / 2^64. */
PLAIN_FN uint uts_geometric_children(ulong hash, uint depth, uint max_depth, ulong p64)
{
    if (depth >= max_depth)
        return 0u;
    uint k = 0u;
    ulong h = hash;
    while (k < UTS_MAX_CHILDREN) {
        h = splitmix64(h ^ 0x5bd1e9955bd1e995UL);
        if (h >= p64)
            break;
        ++k;
    }
    return k;
}

/* Binomial tree (not the root): m children with probability q = q64 / 2^64,
 * else none. */
PLAIN_FN uint uts_binomial_children(ulong hash, uint m, ulong q64)
{
    return splitmix64(hash ^ 0x27d4eb2f165667c5UL) < q64 ? m : 0u;
}

/* ---- adaptive Simpson integration: an interval per item ---- */

struct simpson_interval {
    double a, b;          /* the interval */
    double fa, fm, fb;    /* f at a, (a + b) / 2, b */
    double whole;         /* Simpson's rule over [a, b] */
    double eps;           /* the error allowed on it */
    uint depth;
    uint pad;
};

/* The integrand on [0, 1]: a chirp of 100,000 smooth bumps (w (1 - w))^2,
 * w the fractional part of 100000 x^2, ever narrower towards 1, over a
 * cubic, plus a narrow peak at 0.3.  The interval tree is deep where the
 * bumps are narrow and at the peak, shallow elsewhere.  floor is exact, and
 * w (1 - w) is written so that no cancellation makes f noisy near x = 0 (a
 * noisy f never meets the tolerance and splits down to the depth limit). */
PLAIN_FN double simpson_f(double x)
{
    double t = 100000.0 * x * x;
    double w = t - floor(t);
    double bump = w * (1.0 - w), p = x - 0.3;
    return bump * bump + x * x * (1.0 - x) + 1e-4 / (p * p + 1e-6);
}

PLAIN_FN double simpson_rule(double a, double b, double fa, double fm, double fb)
{
    return (b - a) / 6.0 * (fa + 4.0 * fm + fb);
}

PLAIN_FN struct simpson_interval simpson_root(double a, double b, double eps)
{
    double m = 0.5 * (a + b);
    struct simpson_interval root = { a, b, simpson_f(a), simpson_f(m), simpson_f(b), 0.0, eps, 0u, 0u };
    root.whole = simpson_rule(a, b, root.fa, root.fm, root.fb);
    return root;
}

/* One step of adaptive Simpson on interval s: 1 and the accepted area in
 * *area when its two halves agree with it to 15 eps (or at max_depth), else
 * 0 and the two halves in halves[0], halves[1] with eps / 2 each.  Two
 * evaluations of f. */
PLAIN_FN int simpson_step(double a, double b, double fa, double fm, double fb, double whole, double eps,
                          uint depth, uint max_depth, double *area, struct simpson_interval *halves)
{
    double m = 0.5 * (a + b);
    double flm = simpson_f(0.5 * (a + m)), frm = simpson_f(0.5 * (m + b));
    double left = simpson_rule(a, m, fa, flm, fm), right = simpson_rule(m, b, fm, frm, fb);
    double delta = left + right - whole;
    if (depth >= max_depth || (delta <= 15.0 * eps && -delta <= 15.0 * eps)) {
        *area = left + right + delta / 15.0;
        return 1;
    }
    struct simpson_interval l = { a, m, fa, flm, fm, left, 0.5 * eps, depth + 1u, 0u };
    struct simpson_interval r = { m, b, fm, frm, fb, right, 0.5 * eps, depth + 1u, 0u };
    halves[0] = l;
    halves[1] = r;
    return 0;
}

/* ---- N-Queens: a partial board per item ---- */

#define QUEENS_MAX_N 16u

/* Queens on the first `row` rows: occupied columns and the two diagonals
 * as seen from the next row, as bit sets. */
struct queens_board {
    uint row, columns, left, right;
};

PLAIN_FN uint queens_free(uint n, uint columns, uint left, uint right)
{
    return ~(columns | left | right) & ((1u << n) - 1u);
}

/* The board after a queen at column bit `bit` on the next row. */
PLAIN_FN struct queens_board queens_place(uint n, uint row, uint columns, uint left, uint right, uint bit)
{
    struct queens_board next = { row + 1u, columns | bit, ((left | bit) << 1) & ((1u << n) - 1u),
                                 (right | bit) >> 1 };
    return next;
}

/* Solutions that complete a board: backtracking on an explicit stack (no
 * recursion in OpenCL C). */
PLAIN_FN uint queens_solve(uint n, uint row, uint columns, uint left, uint right)
{
    if (row >= n)
        return 1u;
    uint c[QUEENS_MAX_N], l[QUEENS_MAX_N], r[QUEENS_MAX_N], f[QUEENS_MAX_N];
    uint solutions = 0u, d = 0u, last = n - row - 1u;
    c[0] = columns;
    l[0] = left;
    r[0] = right;
    f[0] = queens_free(n, columns, left, right);
    for (;;) {
        if (f[d] == 0u) {
            if (d == 0u)
                return solutions;
            --d;
            continue;
        }
        uint bit = f[d] & (0u - f[d]);
        f[d] ^= bit;
        if (d == last) {
            ++solutions;
            continue;
        }
        c[d + 1u] = c[d] | bit;
        l[d + 1u] = ((l[d] | bit) << 1) & ((1u << n) - 1u);
        r[d + 1u] = (r[d] | bit) >> 1;
        f[d + 1u] = queens_free(n, c[d + 1u], l[d + 1u], r[d + 1u]);
        ++d;
    }
}

/* ---- subset sum: a node of a branch-and-bound search per item ---- */

#define SUBSET_MAX_WEIGHTS 48u

/* Choosing the weights index.. (each taken or not) to reach `need`. */
struct subset_node {
    uint index, need;
};

/* Weight i of the instance: 1000 to 9999. */
PLAIN_FN uint subset_weight(uint i)
{
    return 1000u + (uint)(splitmix64((ulong)i * 0x9e3779b97f4a7c15UL) % 9000UL);
}

/* Whether node v has children (it is not a solution, weights are left,
 * and those left can still reach its need); suffix[i] is the sum of
 * weights i, i + 1, ... */
PLAIN_FN int subset_branches(uint n, PLAIN_CONSTANT const uint *suffix, uint index, uint need)
{
    return need != 0u && index < n && suffix[index] >= need;
}

/* ---- quicksort: a range of the key array per item ---- */

struct sort_range {
    uint lo, hi;   /* keys [lo, hi) */
};

/* Keys of the input array. */
PLAIN_FN uint sort_key(uint seed, uint i)
{
    return (uint)(splitmix64(((ulong)seed << 32) | i) >> 32);
}

PLAIN_FN uint sort_median3(uint x, uint y, uint z)
{
    return x < y ? (y < z ? y : x < z ? z : x) : (x < z ? x : y < z ? z : y);
}

/* Hoare partition of keys [lo, hi), hi - lo >= 3, around the median of the
 * first, middle and last key: returns p, lo < p < hi, with every key of
 * [lo, p) <= every key of [p, hi). */
PLAIN_FN uint sort_partition(PLAIN_GLOBAL uint *keys, uint lo, uint hi)
{
    uint pivot = sort_median3(keys[lo], keys[lo + (hi - lo) / 2u], keys[hi - 1u]);
    uint i = lo - 1u, j = hi;
    for (;;) {
        do
            ++i;
        while (keys[i] < pivot);
        do
            --j;
        while (keys[j] > pivot);
        if (i >= j)
            return j + 1u;
        uint t = keys[i];
        keys[i] = keys[j];
        keys[j] = t;
    }
}

PLAIN_FN void sort_insertion(PLAIN_GLOBAL uint *keys, uint lo, uint hi)
{
    for (uint i = lo + 1u; i < hi; ++i) {
        uint key = keys[i], j = i;
        while (j > lo && keys[j - 1u] > key) {
            keys[j] = keys[j - 1u];
            --j;
        }
        keys[j] = key;
    }
}

#define SORT_INSERTION_BELOW 16u
#define SORT_STACK 64u

/* Sort keys [lo, hi): quicksort with the same partition, the smaller side
 * first (so the stack holds at most log2(n) ranges), insertion sort below
 * SORT_INSERTION_BELOW keys. */
PLAIN_FN void sort_range_sequential(PLAIN_GLOBAL uint *keys, uint lo, uint hi)
{
    uint stack_lo[SORT_STACK], stack_hi[SORT_STACK], top = 0u;
    for (;;) {
        while (hi - lo >= SORT_INSERTION_BELOW) {
            uint p = sort_partition(keys, lo, hi);
            if (p - lo < hi - p) {
                stack_lo[top] = p;
                stack_hi[top++] = hi;
                hi = p;
            } else {
                stack_lo[top] = lo;
                stack_hi[top++] = p;
                lo = p;
            }
        }
        sort_insertion(keys, lo, hi);
        if (top == 0u)
            return;
        --top;
        lo = stack_lo[top];
        hi = stack_hi[top];
    }
}

#endif
