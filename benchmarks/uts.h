/* UTS-style unbalanced trees (after Olivier et al., "UTS: An Unbalanced
 * Tree Search Benchmark", 2006), with our own integer hash instead of SHA-1.
 *
 * A node is {hash, depth}.  Its child count comes from its hash, and child i
 * gets a hash derived from (parent, i) in `rounds` rounds, so the whole tree
 * follows from the root hash.  The functions are written once in UTS_SHARED_CODE and
 * compiled both as C (below) and as OpenCL C (its text is the device source),
 * with 32-bit unsigned integer operations only, so host and device build the
 * identical tree.
 *
 *   geometric: a node above max_depth has k children with probability
 *              (1-p) p^k, capped at UTS_GEO_CAP, p = b / (1 + b), so the
 *              expected branching factor is about b (UTS "T1"-like).
 *   binomial:  the root has b0 children; every other node has m children
 *              with probability q, else none; q*m just below 1 keeps the
 *              tree finite but deep and very unbalanced (UTS "T3"-like).
 *
 * `rounds` sets the work per child: the number of hash rounds that derive a
 * child's hash (UTS spends one SHA-1 evaluation there). */
#ifndef UTS_H
#define UTS_H

#include <stdint.h>

#define UTS_GEO_CAP 32u
/* Children hashed side by side (uts_child_hashes). */
#define UTS_LANES 8u

#define UTS_SHARED_CODE(FN)                                                            \
    FN uint uts_mix(uint x)                                                            \
    {                                                                                  \
        x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;  \
        return x;                                                                      \
    }                                                                                  \
    /* The hashes of children base .. base + UTS_LANES - 1: independent      \
     * chains side by side in a fixed-length loop, which the compilers turn  \
     * into SIMD lanes (one child at a time is a latency-bound chain).  Every \
     * count (sequential C, OpenMP, perma) hashes children this way. */      \
    FN void uts_child_hashes(uint parent, uint base, uint rounds, uint out[UTS_LANES]) \
    {                                                                                  \
        for (uint j = 0; j < UTS_LANES; ++j)                                           \
            out[j] = parent ^ ((base + j) * 0x9e3779b9u + 0x632be5abu);                \
        for (uint r = 0; r < rounds; ++r)                                              \
            for (uint j = 0; j < UTS_LANES; ++j)                                       \
                out[j] = uts_mix(out[j] + r);                                          \
    }                                                                                  \
    /* p16 = p * 65536: each further child has probability p. */                     \
    FN uint uts_geometric_children(uint hash, uint depth, uint max_depth, uint p16)    \
    {                                                                                  \
        if (depth >= max_depth)                                                        \
            return 0u;                                                                 \
        uint k = 0u, h = hash;                                                         \
        while (k < UTS_GEO_CAP_VALUE) {                                                \
            h = uts_mix(h ^ 0x5bd1e995u);                                              \
            if ((h >> 16) >= p16)                                                      \
                break;                                                                 \
            ++k;                                                                       \
        }                                                                              \
        return k;                                                                      \
    }                                                                                  \
    /* q32 = q * 2^32. */                                                            \
    FN uint uts_binomial_children(uint hash, uint depth, uint b0, uint m, uint q32)    \
    {                                                                                  \
        if (depth == 0u)                                                               \
            return b0;                                                                 \
        return uts_mix(hash ^ 0x27d4eb2fu) < q32 ? m : 0u;                             \
    }

typedef uint32_t uint;
#define UTS_GEO_CAP_VALUE UTS_GEO_CAP
UTS_SHARED_CODE(static inline)

/* The OpenCL C text of the same functions (UTS_GEO_CAP_VALUE is defined in
 * the device source before it). */
#define UTS_STRINGIFY_(...) #__VA_ARGS__
#define UTS_STRINGIFY(...) UTS_STRINGIFY_(__VA_ARGS__)
#define UTS_DEVICE_CODE UTS_STRINGIFY(UTS_SHARED_CODE())

typedef enum uts_shape { UTS_GEOMETRIC, UTS_BINOMIAL } uts_shape;

typedef struct uts_tree {
    uts_shape shape;
    uint root_hash;
    uint rounds;
    /* geometric */
    uint max_depth, p16;
    /* binomial */
    uint b0, m, q32;
} uts_tree;

typedef struct uts_node {
    uint hash, depth;
} uts_node;

/* Host only: the first k children of parent (depth parent.depth + 1),
 * hashed UTS_LANES at a time and written one after another to out[0 .. k-1]
 * (the device source and OpenMP's tasks hash theirs themselves). */
static inline void uts_child_nodes(uts_node parent, uint k, uint rounds, uts_node *out)
{
    for (uint base = 0; base < k; base += UTS_LANES) {
        uint hashes[UTS_LANES];
        uts_child_hashes(parent.hash, base, rounds, hashes);
        for (uint j = 0; j < UTS_LANES && base + j < k; ++j)
            out[base + j] = (uts_node){ hashes[j], parent.depth + 1 };
    }
}

typedef struct uts_result {
    uint64_t nodes;
    uint64_t hash_sum; /* sum of all node hashes: checks the shape, not only the size */
    uint max_depth;
} uts_result;

static inline uint uts_children(const uts_tree *t, uts_node n)
{
    return t->shape == UTS_GEOMETRIC ? uts_geometric_children(n.hash, n.depth, t->max_depth, t->p16)
                                     : uts_binomial_children(n.hash, n.depth, t->b0, t->m, t->q32);
}

/* Sequential depth-first count with an explicit stack; 0 on success, -1 if
 * out of memory. */
int uts_count_sequential(const uts_tree *tree, uts_result *out);
/* The same with OpenMP tasks on `threads` threads; spawn_depth: nodes at a
 * depth below it spawn one task per child, deeper nodes recurse inline
 * (UINT32_MAX: a task per node). */
void uts_count_openmp(const uts_tree *tree, unsigned threads, uint spawn_depth, uts_result *out);

#endif
