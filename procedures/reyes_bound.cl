/*
 * bound: one item per sub-patch.  Culls it against the view frustum,
 * optionally culls back faces, and sends it to dice when the screen bound
 * of its control hull is small enough, else to split_u or split_v.
 */

/* 1 when every hull point lies outside the same side plane of the tile's
 * sub-frustum, widened by `margin` (a fraction of the half-viewport).  For
 * the whole image (-1, 1, -1, 1) the planes are x = +-(1 + margin) w
 * exactly, as without buckets. */
int reyes_outside_frustum(__global const struct reyes_params *p, const float4 clip[16],
                          float margin)
{
    float left_ndc = p->ndc_left - margin, right_ndc = p->ndc_right + margin;
    float bottom_ndc = p->ndc_bottom - margin, top_ndc = p->ndc_top + margin;
    int left = 1, right = 1, bottom = 1, top = 1;
    for (int k = 0; k < 16; ++k) {
        float w = clip[k].w;
        left &= clip[k].x < w * left_ndc;
        right &= clip[k].x > w * right_ndc;
        bottom &= clip[k].y < w * bottom_ndc;
        top &= clip[k].y > w * top_ndc;
    }
    return left | right | bottom | top;
}

/* 1 when every cross product of a u-difference and a v-difference of the
 * projected hull has the same sign as a back face: the patch's screen-space
 * normal (a positive combination of those) then faces away everywhere. */
int reyes_backfacing(const float2 s[16])
{
    for (int a = 0; a < 12; ++a) {
        int r = a / 3, c = a % 3;
        float2 du = s[r * 4 + c + 1] - s[r * 4 + c];
        for (int b = 0; b < 12; ++b) {
            int cc = b / 3, rr = b % 3;
            float2 dv = s[(rr + 1) * 4 + cc] - s[rr * 4 + cc];
            /* Screen y points down, so a front face has du x dv < 0. */
            if (du.x * dv.y - du.y * dv.x <= 0.0f)
                return 0;
        }
    }
    return 1;
}

/* Longest screen-space polyline of the hull along u (rows) or v (columns). */
float reyes_hull_extent(const float2 s[16], int along_u)
{
    float longest = 0.0f;
    for (int line = 0; line < 4; ++line) {
        float length = 0.0f;
        for (int k = 0; k < 3; ++k) {
            int i0 = along_u ? line * 4 + k : k * 4 + line;
            int i1 = along_u ? i0 + 1 : i0 + 4;
            length += distance(s[i0], s[i1]);
        }
        longest = fmax(longest, length);
    }
    return longest;
}

/* Same in world space, for patches that cannot be projected. */
float reyes_world_extent(const float3 cp[16], int along_u)
{
    float longest = 0.0f;
    for (int line = 0; line < 4; ++line) {
        float length = 0.0f;
        for (int k = 0; k < 3; ++k) {
            int i0 = along_u ? line * 4 + k : k * 4 + line;
            int i1 = along_u ? i0 + 1 : i0 + 4;
            length += distance(cp[i0], cp[i1]);
        }
        longest = fmax(longest, length);
    }
    return longest;
}

/* First pass of crack stitching: append the sub-patch to dice and its
 * screen box to the leaves buffer (the count goes on past the capacity, so
 * the host can retry with a larger buffer). */
void reyes_record_leaf(perma_ctx *ctx, const struct reyes_subpatch *sp, float2 lo, float2 hi)
{
    __global const struct reyes_params *p = ctx->buf.params;
    uint index = atomic_inc(&ctx->buf.counters[REYES_COUNT_LEAVES]);
    if (index >= p->leaf_capacity)
        return;
    __global struct reyes_leaf *leaf = &ctx->buf.leaves[index];
    leaf->sp = *sp;
    leaf->lo_x = lo.x;
    leaf->lo_y = lo.y;
    leaf->hi_x = hi.x;
    leaf->hi_y = hi.y;
}

void reyes_bound(perma_ctx *ctx, __local const struct reyes_subpatch *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    __global uint *counters = ctx->buf.counters;
    struct reyes_subpatch sp = *item;
    float3 cp[16];
    float4 clip[16];
    reyes_subpatch_points(ctx->buf.patches, &sp, cp);

    int all_behind = 1, any_behind = 0;
    for (int k = 0; k < 16; ++k) {
        clip[k] = reyes_to_clip(p, cp[k]);
        int behind = clip[k].w <= p->near_w;
        all_behind &= behind;
        any_behind |= behind;
    }
    if (all_behind || reyes_outside_frustum(p, clip, p->cull_margin)) {
        atomic_inc(&counters[REYES_COUNT_CULLED]);
        return;
    }
    int forced = sp.depth >= p->max_depth;
    if (any_behind) {
        /* Never project through the near plane: split in world space. */
        if (forced) {
            atomic_inc(&counters[REYES_COUNT_CULLED]);
        } else if (reyes_world_extent(cp, 1) >= reyes_world_extent(cp, 0)) {
            emit_split_u(ctx, &sp);
        } else {
            emit_split_v(ctx, &sp);
        }
        return;
    }

    float2 s[16];
    float2 lo = (float2)(INFINITY, INFINITY), hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < 16; ++k) {
        s[k] = reyes_to_screen(p, clip[k]);
        lo = fmin(lo, s[k]);
        hi = fmax(hi, s[k]);
    }
    if (p->backface_cull && reyes_backfacing(s)) {
        atomic_inc(&counters[REYES_COUNT_CULLED]);
        return;
    }
    float2 size = hi - lo;
    if (forced || fmax(size.x, size.y) <= p->bound_px) {
        if (forced)
            atomic_inc(&counters[REYES_COUNT_FORCED_DICE]);
        if (p->record_leaves)
            reyes_record_leaf(ctx, &sp, lo, hi);
        else
            emit_dice(ctx, &sp);
    } else if (reyes_hull_extent(s, 1) >= reyes_hull_extent(s, 0)) {
        emit_split_u(ctx, &sp);
    } else {
        emit_split_v(ctx, &sp);
    }
}
