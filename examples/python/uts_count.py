"""Count the nodes of an unbalanced tree (UTS-style, geometric) with perma.

usage: python3 uts_count.py [MAX_DEPTH]     (default 8; PERMA_DEVICE picks the device)

A node is (hash, depth); its child count and its children's hashes follow
from its hash, so the whole tree follows from the root's.  One procedure
visits a node, counts it per depth and emits its children; numpy counts the
same tree level by level to check.
"""
import sys

import numpy as np
import perma

P16, ROUNDS, ROOT = 52429, 16, 5  # each further child with probability 0.8; hash rounds per child

VISIT = """
uint mix(uint x)
{
    x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
    return x;
}

void visit(perma_ctx *ctx, __local const struct uts_node *n)
{
    atomic_inc(&ctx->buf.per_depth[n->depth]);
    if (n->depth >= MAX_DEPTH)
        return;
    uint k = 0u, h = n->hash;
    while (k < 32u && ((h = mix(h ^ 0x5bd1e995u)) >> 16) < P16)
        ++k;
    struct uts_node child = { 0u, n->depth + 1u };
    for (uint i = 0u; i < k; ++i) {
        child.hash = n->hash ^ (i * 0x9e3779b9u + 0x632be5abu);
        for (uint r = 0u; r < ROUNDS; ++r)
            child.hash = mix(child.hash + r);
        emit_visit(ctx, &child);
    }
}
"""


def mix(x):
    x = x ^ (x >> 16)
    x = x * np.uint32(0x7feb352d)
    x = x ^ (x >> 15)
    x = x * np.uint32(0x846ca68b)
    return x ^ (x >> 16)


def count_levels(max_depth):
    """Nodes per depth, one numpy array per level."""
    level, counts = np.array([ROOT], np.uint32), []
    for depth in range(max_depth + 1):
        counts.append(len(level))
        if depth == max_depth:
            break
        k, h, going = np.zeros(len(level), np.uint32), level.copy(), np.ones(len(level), bool)
        for _ in range(32):
            h = mix(h ^ np.uint32(0x5bd1e995))
            going &= (h >> 16) < P16
            k += going
        first = np.repeat(np.cumsum(k) - k, k)  # each child's index among its siblings: i
        index = (np.arange(len(first)) - first).astype(np.uint32)
        level = np.repeat(level, k) ^ (index * np.uint32(0x9e3779b9) + np.uint32(0x632be5ab))
        for r in range(ROUNDS):
            level = mix(level + np.uint32(r))
    return counts


def main():
    max_depth = int(sys.argv[1]) if len(sys.argv) > 1 else 8
    node = np.dtype([('hash', np.uint32), ('depth', np.uint32)])
    options = '-DMAX_DEPTH=%du -DP16=%du -DROUNDS=%du' % (max_depth, P16, ROUNDS)
    with perma.Runtime('megakernel/stealing', build_options=options) as rt:
        rt.add_type('uts_node', node)
        visit = rt.register('visit', VISIT, item=node, emits={'visit': 32})
        per_depth = np.zeros(max_depth + 1, np.uint32)
        rt.bind('per_depth', per_depth)
        rt.seed(visit, np.array([(ROOT, 0)], node))
        stats = rt.run()
        print('%d nodes in %.3f s on %s (%s/%s)' % (per_depth.sum(), stats['seconds'], rt.device_summary,
                                                    stats['technique'], stats['strategy']))
    print('nodes per depth:', ' '.join(str(n) for n in per_depth))
    expected = count_levels(max_depth)
    if list(per_depth) != expected:
        print('numpy counts differently:', ' '.join(str(n) for n in expected))
        return 1
    print('numpy counts the same')
    return 0


if __name__ == '__main__':
    sys.exit(main())
