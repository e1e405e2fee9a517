/*
 * Growing the queues on the device (runtime/src/state.c).  Between two
 * launches, with no batch running, the host checks that every queue's
 * reserved positions are published and its claimed ones released, gives
 * each queue its new capacity and offsets in fresh item and mark buffers,
 * writes the new control block (the queue's items from position 0: HEAD,
 * RELEASED 0, TAIL, PUBLISHED = count) and launches this kernel with one
 * record per queue saying where the items are now (perma_relayout_record).
 * One work-item per slot of the new layout moves an item, if the slot holds
 * one, and clears the slot's two completion marks, so no queued item
 * passes through the host.  The items keep their order, as a fresh upload
 * would lay them out; the items a launch left in the groups' overflow
 * areas (PERMA_OVERFLOW_*, the overflow data of the emit areas) follow them, segment by segment.
 */
__kernel void perma_relayout_kernel(PERMA_RELAYOUT_ARGS(PERMA_ARG_PARAM))
{
    uint j = get_global_id(0);
    if (j >= slots)
        return;
    /* The queue that slot j belongs to: the last record whose first slot
     * (new_seq / 2) is at most j. */
    uint lo = 0, hi = queues;
    while (hi - lo > 1u) {
        uint mid = lo + (hi - lo) / 2u;
        if (map[mid].new_seq / 2u <= j)
            lo = mid;
        else
            hi = mid;
    }
    __global const perma_relayout_record *q = map + lo;
    uint i = j - q->new_seq / 2u;
    /* Not done for any position (perma_queue_clear_mark). */
    new_seq[q->new_seq + i] = i;
    new_seq[q->new_seq + q->new_cap + i] = i;
    __global const uint *src = 0;
    if (i < q->count) {
        src = old_data + q->old_data + ((q->head + i) & (q->old_cap - 1u)) * q->words;
    } else if (i - q->count < q->overflow) {
        uint k = i - q->count;
        __global const uint *segment = segments + q->overflow_first;
        for (uint s = 0; s < q->overflow_segments && !src; ++s, segment += PERMA_RELAYOUT_SEGMENT_WORDS) {
            if (k < segment[1])
                src = emit_areas + segment[0] + k * q->words;
            k -= segment[1];
        }
    }
    if (!src)
        return;
    __global uint *dst = new_data + q->new_data + i * q->words;
    for (uint w = 0; w < q->words; ++w)
        dst[w] = src[w];
}
