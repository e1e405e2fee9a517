/*
 * split_u: halve a sub-patch's u interval and send both halves back to
 * bound.  With the (patch, rectangle) representation a split is a few
 * float operations; bound recomputes the control points of each half.
 */
void reyes_split_u(perma_ctx *ctx, __local const struct reyes_subpatch *item)
{
    struct reyes_subpatch left = *item, right = *item;
    float mid = 0.5f * (item->u0 + item->u1);
    left.u1 = mid;
    right.u0 = mid;
    left.depth = right.depth = item->depth + 1u;
    if (ctx->buf.params->polyline) {
        /* The split line's edges start unsettled (reyes_polyline.cl). */
        reyes_polyline_mark(&left, REYES_EDGE_U1, 0xffu);
        reyes_polyline_mark(&right, REYES_EDGE_U0, 0xffu);
    }
    atomic_inc(&ctx->buf.counters[REYES_COUNT_SPLITS]);
    emit_bound(ctx, &left);
    emit_bound(ctx, &right);
}
