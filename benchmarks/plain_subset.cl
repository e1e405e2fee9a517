/* Subset sum, a branch-and-bound node per item (perma-bench plain,
 * benchmarks/plain_subset.c).  The host defines SUBSET_N, SUBSET_WEIGHTS
 * and SUBSET_SUFFIX (__constant arrays) in front of this source. */

void subset(perma_ctx *ctx, __local const struct subset_node *v)
{
    uint index = v->index, need = v->need;
#ifndef PLAIN_COUNT_ATOMIC
    reduce_subset_nodes(ctx, 1ul);
    if (need == 0u)
        reduce_subset_solutions(ctx, 1ul);
#else
    atom_inc(&ctx->buf.subset_nodes[0]);
    if (need == 0u)
        atom_inc(&ctx->buf.subset_solutions[0]);
#endif
    if (!subset_branches(SUBSET_N, SUBSET_SUFFIX, index, need))
        return;
    struct subset_node child = { index + 1u, need };
    emit_subset(ctx, &child);
    uint w = SUBSET_WEIGHTS[index];
    if (w <= need) {
        child.need = need - w;
        emit_subset(ctx, &child);
    }
}
