/* split_v: halve a sub-patch's v interval (see reyes_split_u.cl). */
void reyes_split_v(perma_ctx *ctx, __local const struct reyes_subpatch *item)
{
    struct reyes_subpatch low = *item, high = *item;
    float mid = 0.5f * (item->v0 + item->v1);
    low.v1 = mid;
    high.v0 = mid;
    low.depth = high.depth = item->depth + 1u;
    if (ctx->buf.params->polyline) {
        reyes_polyline_mark(&low, REYES_EDGE_V1, 0xffu);
        reyes_polyline_mark(&high, REYES_EDGE_V0, 0xffu);
    }
    atomic_inc(&ctx->buf.counters[REYES_COUNT_SPLITS]);
    emit_bound(ctx, &low);
    emit_bound(ctx, &high);
}
