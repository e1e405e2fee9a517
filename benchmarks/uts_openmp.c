/* UTS count with OpenMP tasks (gcc's libgomp): what a CPU programmer would
 * write instead of perma.  Each thread counts into its own cache line. */
#include "uts.h"

#include <omp.h>
#include <string.h>

enum { MAX_THREADS = 256 };

struct thread_count {
    uint64_t nodes, hash_sum;
    uint max_depth;
    char pad[64 - 2 * sizeof(uint64_t) - sizeof(uint)];
};

static struct thread_count counts[MAX_THREADS];

static void visit(const uts_tree *tree, uts_node n, uint spawn_depth)
{
    struct thread_count *c = &counts[omp_get_thread_num()];
    c->nodes++;
    c->hash_sum += n.hash;
    if (n.depth > c->max_depth)
        c->max_depth = n.depth;
    uint k = uts_children(tree, n);
    for (uint base = 0; base < k; base += UTS_LANES) {
        uint hashes[UTS_LANES];
        uts_child_hashes(n.hash, base, tree->rounds, hashes);
        for (uint j = 0; j < UTS_LANES && base + j < k; ++j) {
            uts_node child = { hashes[j], n.depth + 1 };
            if (n.depth < spawn_depth) {
#pragma omp task firstprivate(child)
                visit(tree, child, spawn_depth);
            } else {
                visit(tree, child, spawn_depth);
            }
        }
    }
}

void uts_count_openmp(const uts_tree *tree, unsigned threads, uint spawn_depth, uts_result *out)
{
    if (threads > MAX_THREADS)
        threads = MAX_THREADS;
    memset(counts, 0, sizeof counts);
#pragma omp parallel num_threads(threads)
#pragma omp single
    visit(tree, (uts_node){ tree->root_hash, 0 }, spawn_depth);

    uts_result r = { 0, 0, 0 };
    for (unsigned t = 0; t < threads; ++t) {
        r.nodes += counts[t].nodes;
        r.hash_sum += counts[t].hash_sum;
        if (counts[t].max_depth > r.max_depth)
            r.max_depth = counts[t].max_depth;
    }
    *out = r;
}
