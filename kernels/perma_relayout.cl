/*
 * Growing the queues on the device (runtime/src/state.c).  Between two
 * launches, with no batch running, the host gives each queue its new
 * capacity and offsets in fresh data and sequence buffers, writes the new
 * control block (the queue's items from position 0: HEAD 0, TAIL = count)
 * and launches this kernel with one record per queue saying where the
 * items are now (perma_relayout_record).  One work-item per slot of the new
 * layout moves an item or marks the slot free, so no queued item passes
 * through the host.  The items keep their order, as a fresh upload would
 * lay them out.  A queued item that was never published (its sequence word
 * is not pos + 1) fails the regrowth with PERMA_KSTATUS_UNPUBLISHED instead
 * of being copied as garbage.
 */
__kernel void perma_relayout_kernel(PERMA_RELAYOUT_ARGS(PERMA_ARG_PARAM))
{
    uint j = get_global_id(0);
    if (j >= slots)
        return;
    /* The queue that slot j belongs to: the last record with new_seq <= j
     * (the new layout puts the queues one after another). */
    uint lo = 0, hi = queues;
    while (hi - lo > 1u) {
        uint mid = lo + (hi - lo) / 2u;
        if (map[mid].new_seq <= j)
            lo = mid;
        else
            hi = mid;
    }
    __global const perma_relayout_record *q = map + lo;
    uint i = j - q->new_seq;
    if (i >= q->count) {
        new_seq[j] = i; /* free for the writer of position i */
        return;
    }
    uint pos = q->head + i;
    uint slot = pos & (q->old_cap - 1u);
    if (old_seq[q->old_seq + slot] != pos + 1u) {
        perma_fail(ctl, PERMA_KSTATUS_UNPUBLISHED, lo, pos);
        return;
    }
    __global const uint *src = old_data + q->old_data + slot * q->words;
    __global uint *dst = new_data + q->new_data + i * q->words;
    for (uint w = 0; w < q->words; ++w)
        dst[w] = src[w];
    new_seq[j] = i + 1u; /* published */
}
