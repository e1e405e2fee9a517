/* Quicksort, one range of the key array per item (perma-bench plain,
 * benchmarks/plain_sort.c).  The host defines SORT_CUTOFF in front of this
 * source: a range of at most SORT_CUTOFF keys is sorted inside its item,
 * a longer one is partitioned and its two sides emitted.  The keys are the
 * bound buffer `sort_keys`; nothing is counted (the host compares the
 * sorted array with the sequential one). */

void sort(perma_ctx *ctx, __local const struct sort_range *r)
{
    __global uint *keys = ctx->buf.sort_keys;
    if (r->hi - r->lo <= SORT_CUTOFF) {
        sort_range_sequential(keys, r->lo, r->hi);
        return;
    }
    uint p = sort_partition(keys, r->lo, r->hi);
    struct sort_range left = { r->lo, p }, right = { p, r->hi };
    emit_sort(ctx, &left);
    emit_sort(ctx, &right);
}
