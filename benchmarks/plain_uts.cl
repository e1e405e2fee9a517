/* UTS trees, one node per item (perma-bench plain, benchmarks/plain_uts.c).
 * The host defines the tree in front of this source: UTS_GEOMETRIC with
 * UTS_MAX_DEPTH and UTS_P64, or UTS_B0, UTS_M and UTS_Q64 (binomial). */

/* The one place this workload adds to its results: the node count and the
 * sum of the node hashes, two reductions (perma_declare_reduction).  With
 * --count atomic, the way README.md did it before reductions: a global
 * atomic per result, all work-groups on one word. */
void uts_count(perma_ctx *ctx, ulong hash)
{
#ifndef PLAIN_COUNT_ATOMIC
    reduce_uts_nodes(ctx, 1);
    reduce_uts_hash_sum(ctx, hash);
#else
    atom_inc(&ctx->buf.uts_nodes[0]);
    atom_add(&ctx->buf.uts_hash_sum[0], hash);
#endif
}

#ifdef UTS_GEOMETRIC
void uts_geometric(perma_ctx *ctx, __local const struct uts_node *node)
{
    uts_count(ctx, node->hash);
    uint k = uts_geometric_children(node->hash, node->depth, UTS_MAX_DEPTH, UTS_P64);
    for (uint i = 0; i < k; ++i) {
        struct uts_node child = uts_child(node->hash, node->depth, i);
        emit_uts_geometric(ctx, &child);
    }
}

#else
/* The binomial root has UTS_B0 children, every other node UTS_M or none:
 * the root gets a procedure of its own so that only it declares UTS_B0
 * emits (docs/writing-procedures.md, section 6). */
void uts_binomial(perma_ctx *ctx, __local const struct uts_node *node)
{
    uts_count(ctx, node->hash);
    uint k = uts_binomial_children(node->hash, UTS_M, UTS_Q64);
    for (uint i = 0; i < k; ++i) {
        struct uts_node child = uts_child(node->hash, node->depth, i);
        emit_uts_binomial(ctx, &child);
    }
}

void uts_binomial_root(perma_ctx *ctx, __local const struct uts_node *root)
{
    uts_count(ctx, root->hash);
    for (uint i = 0; i < UTS_B0; ++i) {
        struct uts_node child = uts_child(root->hash, root->depth, i);
        emit_uts_binomial(ctx, &child);
    }
}
#endif
