/*
 * bound: one item per sub-patch.  Culls it against the view frustum,
 * optionally culls back faces, and sends it to dice when the screen bound
 * of its control hull is small enough (or, with the tiered criterion of
 * reyes_flatness.cl, when it is flat enough), else to split_u or split_v.
 */

/* Length of the xyz part of row `row` of the view-projection matrix minus
 * `scale` times row 3: how fast the clip-space function x - scale * w (or
 * y - scale * w) can change per world unit. */
float reyes_plane_slope(__global const struct reyes_params *p, int row, float scale)
{
    __global const float *m = p->view_proj;
    float3 r = (float3)(m[row * 4], m[row * 4 + 1], m[row * 4 + 2]);
    float3 w = (float3)(m[12], m[13], m[14]);
    return length(r - scale * w);
}

/* Largest distance displacement moves a surface point (0: none). */
float reyes_displacement_radius(__global const struct reyes_params *p)
{
    return p->displace_mode == REYES_DISPLACE_NONE ? 0.0f : fabs(p->displace_amplitude);
}

/* 1 when every hull point lies outside the same side plane of the tile's
 * sub-frustum, widened by `margin` (a fraction of the half-viewport), even
 * if displaced by up to `radius` in any direction and, with a lens
 * (defocus not 0), moved by up to defocus[k] * (lens_x, lens_y) in clip x
 * and y.  For the whole image (-1, 1, -1, 1), no displacement and no lens
 * the planes are x = +-(1 + margin) w exactly, as without buckets. */
int reyes_outside_frustum(__global const struct reyes_params *p, const float4 *clip, int count,
                          float margin, float radius, const float *defocus)
{
    float left_ndc = p->ndc_left - margin, right_ndc = p->ndc_right + margin;
    float bottom_ndc = p->ndc_bottom - margin, top_ndc = p->ndc_top + margin;
    float left_pad = 0.0f, right_pad = 0.0f, bottom_pad = 0.0f, top_pad = 0.0f;
    if (radius > 0.0f) {
        left_pad = radius * reyes_plane_slope(p, 0, left_ndc);
        right_pad = radius * reyes_plane_slope(p, 0, right_ndc);
        bottom_pad = radius * reyes_plane_slope(p, 1, bottom_ndc);
        top_pad = radius * reyes_plane_slope(p, 1, top_ndc);
    }
    int left = 1, right = 1, bottom = 1, top = 1;
    for (int k = 0; k < count; ++k) {
        float w = clip[k].w;
        if (defocus) {
            float lens_x = defocus[k] * p->lens_x, lens_y = defocus[k] * p->lens_y;
            left &= clip[k].x - w * left_ndc + left_pad + lens_x < 0.0f;
            right &= clip[k].x - w * right_ndc - right_pad - lens_x > 0.0f;
            bottom &= clip[k].y - w * bottom_ndc + bottom_pad + lens_y < 0.0f;
            top &= clip[k].y - w * top_ndc - top_pad - lens_y > 0.0f;
        } else if (radius > 0.0f) {
            left &= clip[k].x - w * left_ndc + left_pad < 0.0f;
            right &= clip[k].x - w * right_ndc - right_pad > 0.0f;
            bottom &= clip[k].y - w * bottom_ndc + bottom_pad < 0.0f;
            top &= clip[k].y - w * top_ndc - top_pad > 0.0f;
        } else {
            left &= clip[k].x < w * left_ndc;
            right &= clip[k].x > w * right_ndc;
            bottom &= clip[k].y < w * bottom_ndc;
            top &= clip[k].y > w * top_ndc;
        }
    }
    return left | right | bottom | top;
}

/* The hull's screen box grown by what a displacement of up to `radius`
 * can add (conservative: |d(x/w)| <= radius (|r0| + |x/w| |r3|) / w for the
 * nearest w a displaced point can have); infinite if that w may reach
 * the near plane. */
void reyes_grow_box(__global const struct reyes_params *p, const float4 clip[16], float radius,
                    float2 *lo, float2 *hi)
{
    if (radius <= 0.0f)
        return;
    float4 terms = reyes_projection_terms(p, clip, 16);
    float nearest = terms.w - radius * terms.z;
    if (nearest <= p->near_w) {
        *lo = (float2)(-INFINITY, -INFINITY);
        *hi = (float2)(INFINITY, INFINITY);
        return;
    }
    float2 grow = radius * terms.xy / nearest;
    *lo -= grow;
    *hi += grow;
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

/* With wedges, the edge tier is whether each edge has settled on a flat
 * segment of its line (the same answer on both sides of the edge); an
 * unsettled edge asks for a split along it.  Sets sp->edge_levels. */
uint reyes_wedge_reason(__global const struct reyes_params *p, __global const float4 *patches,
                        struct reyes_subpatch *sp, struct reyes_tiers tiers, int *split_u)
{
    float3 base[16];
    reyes_load_patch(patches, sp->patch, base);
    uint levels = reyes_edge_levels(p, base, sp);
    sp->edge_levels = levels;
    int unsettled_u = ((levels >> (8 * REYES_EDGE_V0)) & 0xffu) == REYES_EDGE_UNSETTLED
                      || ((levels >> (8 * REYES_EDGE_V1)) & 0xffu) == REYES_EDGE_UNSETTLED;
    int unsettled_v = ((levels >> (8 * REYES_EDGE_U0)) & 0xffu) == REYES_EDGE_UNSETTLED
                      || ((levels >> (8 * REYES_EDGE_U1)) & 0xffu) == REYES_EDGE_UNSETTLED;
    if (unsettled_u || unsettled_v) {
        *split_u = unsettled_u && (!unsettled_v || tiers.along_u >= tiers.along_v);
        return REYES_COUNT_SPLIT_EDGE;
    }
    if (tiers.failed & REYES_TIER_INNER) {
        *split_u = tiers.along_u >= tiers.along_v;
        return REYES_COUNT_SPLIT_INNER;
    }
    return 0u;
}

/* With polylines, an unsettled edge of a sub-patch that would be diced is
 * a reason to split across it (reyes_polyline.cl): along u for V0 or V1,
 * along v for U0 or U1, the longer need first when both. */
uint reyes_polyline_reason(const struct reyes_subpatch *sp, float2 need, int *split_u)
{
    int unsettled_u = !reyes_polyline_settled(sp, REYES_EDGE_V0) || !reyes_polyline_settled(sp, REYES_EDGE_V1);
    int unsettled_v = !reyes_polyline_settled(sp, REYES_EDGE_U0) || !reyes_polyline_settled(sp, REYES_EDGE_U1);
    if (!unsettled_u && !unsettled_v)
        return 0u;
    *split_u = unsettled_u && (!unsettled_v || need.x >= need.y);
    return REYES_COUNT_SPLIT_EDGE;
}

/* Whether a projectable sub-patch is split, as the counter naming the
 * reason (0: dice it), and in which direction (*split_u).  A bound that
 * is too large splits along the longer hull; with a shading rate the
 * bound is `need` (reyes_rate_segments, which the caller keeps for
 * dice_size) instead of the box `size`: a grid that would need more than
 * grid vertices along u or v splits across its longer need.  A tier over
 * epsilon splits across the more curved direction. */
uint reyes_split_reason(__global const struct reyes_params *p, __global const float4 *patches,
                        struct reyes_subpatch *sp, const float3 cp[16], const float4 clip[16],
                        const float2 s[16], float2 size, float2 need, int *split_u)
{
    int too_big;
    if (p->shading_rate > 0.0f) {
        too_big = fmax(need.x, need.y) > (float)(p->grid - 1u);
        if (too_big)
            *split_u = need.x >= need.y;
    } else {
        too_big = fmax(size.x, size.y) > (p->subdivision == REYES_SUBDIVISION_TIERED ? p->flat_cap_px : p->bound_px);
        if (too_big)
            *split_u = reyes_hull_extent(s, 1) >= reyes_hull_extent(s, 0);
    }
    if (p->subdivision != REYES_SUBDIVISION_TIERED)
        return too_big ? REYES_COUNT_SPLIT_BOUND : 0u;
    if (too_big)
        return REYES_COUNT_SPLIT_BOUND;
    struct reyes_tiers tiers = reyes_flatness(p, cp, clip);
    if (p->wedges)
        return reyes_wedge_reason(p, patches, sp, tiers, split_u);
    if (tiers.failed == 0)
        return 0u;
    *split_u = tiers.along_u >= tiers.along_v;
    return (tiers.failed & REYES_TIER_EDGE) ? REYES_COUNT_SPLIT_EDGE : REYES_COUNT_SPLIT_INNER;
}

/* First pass of crack stitching: append the sub-patch to dice, its
 * screen box and its hull's nearest clip w to the leaves buffer (the count
 * goes on past the capacity, so the host can retry with a larger buffer). */
void reyes_record_leaf(perma_ctx *ctx, const struct reyes_subpatch *sp, float2 lo, float2 hi, float near_w)
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
    leaf->near_w = near_w;
}

/* How far the lens can move a point at clip depth w, in units of
 * (lens_x, lens_y): |w / focus - 1| (the thin lens' offset), plus what a
 * displacement of up to `radius` can add to it by changing w (w_pad). */
float reyes_defocus_factor(__global const struct reyes_params *p, float w, float w_pad)
{
    return (fabs(w - p->focus) + w_pad) / p->focus;
}

/* The hull's 16 points at t = 0 (swept[0..15]) and t = 1 (swept[16..31],
 * each control point moved by its own motion).  The motion is an affine
 * map of the position (a rotation and a translation), so the patch at
 * time t is the patch of the control points moved to t, and those lie
 * on the segments between the 32 points: the hull over the shutter lies
 * in their hull. */
void reyes_sweep_hull(__global const struct reyes_params *p, const float3 cp[16], const float4 clip[16],
                      float4 swept[32])
{
    for (int k = 0; k < 16; ++k) {
        swept[k] = clip[k];
        swept[16 + k] = clip[k] + reyes_motion_at(p, cp[k]);
    }
}

/* Blurred: culled only if all 32 swept points are behind the eye or
 * outside one plane.  A lens moves a point by (w / focus - 1) L (lens_x,
 * lens_y), L in the unit disk; the plane test is linear in the point and
 * |w / focus - 1| convex in w, so growing each swept point by its own
 * largest offset bounds the whole hull over the shutter and the lens. */
int reyes_blur_culled(__global const struct reyes_params *p, const float3 cp[16], const float4 clip[16],
                      float radius)
{
    float4 swept[32];
    reyes_sweep_hull(p, cp, clip, swept);
    __global const float *m = p->view_proj;
    float w_pad = radius * length((float3)(m[12], m[13], m[14]));
    int behind = 1;
    for (int k = 0; k < 32; ++k)
        behind &= swept[k].w + w_pad <= p->near_w;
    if (behind)
        return 1;
    if (p->lens_x == 0.0f && p->lens_y == 0.0f)
        return reyes_outside_frustum(p, swept, 32, p->cull_margin, radius, 0);
    float defocus[32];
    for (int k = 0; k < 32; ++k)
        defocus[k] = reyes_defocus_factor(p, swept[k].w, w_pad);
    return reyes_outside_frustum(p, swept, 32, p->cull_margin, radius, defocus);
}

/* Screen box of a blurred leaf for the buckets' selection: every swept
 * point (reyes_sweep_hull) moved by up to its lens offset and a
 * displacement of up to `radius` (x by radius |r0|, y by radius |r1|, w
 * by w_pad = radius |r3|, which also grows the lens offset).  The
 * blurred surface lies in the convex hull of those boxes; x / w over a
 * box with w > 0 is extreme at its corners.  Infinite if a corner may
 * reach the near plane. */
void reyes_blur_leaf_box(__global const struct reyes_params *p, const float3 cp[16], const float4 clip[16],
                         float radius, float2 *lo, float2 *hi)
{
    __global const float *m = p->view_proj;
    float pad_x = radius * length((float3)(m[0], m[1], m[2]));
    float pad_y = radius * length((float3)(m[4], m[5], m[6]));
    float w_pad = radius * length((float3)(m[12], m[13], m[14]));
    float4 swept[32];
    reyes_sweep_hull(p, cp, clip, swept);
    *lo = (float2)(INFINITY, INFINITY);
    *hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < 32; ++k) {
        float defocus = reyes_defocus_factor(p, swept[k].w, w_pad);
        float2 grow = (float2)(pad_x + defocus * p->lens_x, pad_y + defocus * p->lens_y);
        if (swept[k].w - w_pad <= p->near_w) {
            *lo = (float2)(-INFINITY, -INFINITY);
            *hi = (float2)(INFINITY, INFINITY);
            return;
        }
        for (int c = 0; c < 4; ++c) {
            float2 xy = swept[k].xy + ((c & 1) ? grow : -grow);
            float w = swept[k].w + ((c & 2) ? w_pad : -w_pad);
            float2 s = reyes_to_screen(p, (float4)(xy, 0.0f, w));
            *lo = fmin(*lo, s);
            *hi = fmax(*hi, s);
        }
    }
}

/* Whether the projected hull s[16] may cover one of the image's sample
 * positions (reyes_sample.cl): 0 only when none lies in its octagon
 * (reyes_hull_octagon, reyes_occlusion.cl), so a surface inside the hull
 * covers no sample and dicing it cannot change the image.  Sub-pixel
 * patches (a killeroo seen small) often fall between the samples.
 * Boxes over more than REYES_SAMPLE_BOX_PIXELS pixels are not searched
 * (1). */
int reyes_hull_has_sample(__global const struct reyes_params *p, const float2 s[16], float2 lo, float2 hi)
{
    struct reyes_octagon o = reyes_hull_octagon(s, lo, hi);
    if (!(o.hi.x >= 0.0f && o.hi.y >= 0.0f && o.lo.x < p->width && o.lo.y < p->height))
        return 1; /* off the image or NaN: the frustum test's business */
    float2 first = fmax(floor(o.lo), (float2)(0.0f, 0.0f));
    float2 last = fmin(floor(o.hi), (float2)(p->width - 1.0f, p->height - 1.0f));
    if ((last.x - first.x + 1.0f) * (last.y - first.y + 1.0f) > (float)REYES_SAMPLE_BOX_PIXELS)
        return 1;
    uint columns = reyes_sample_columns(p->spp), rows = (p->spp + columns - 1u) / columns;
    for (uint py = (uint)first.y; py <= (uint)last.y; ++py)
        for (uint px = (uint)first.x; px <= (uint)last.x; ++px)
            for (uint k = 0; k < p->spp; ++k)
                if (reyes_octagon_contains(&o, reyes_sample_position_on(px, py, k, columns, rows)))
                    return 1;
    return 0;
}

void reyes_bound(perma_ctx *ctx, __local const struct reyes_subpatch *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    __global uint *counters = ctx->buf.counters;
    struct reyes_subpatch sp = *item;
    float3 cp[16];
    float4 clip[16];
    /* A whole base patch at a shading rate: its own control points (fixed
     * grids keep the C reference's restricted ones, bit for bit). */
    if (p->shading_rate > 0.0f && sp.u0 == 0.0f && sp.v0 == 0.0f && sp.u1 == 1.0f && sp.v1 == 1.0f)
        reyes_load_patch(ctx->buf.patches, sp.patch, cp);
    else
        reyes_subpatch_points(ctx->buf.patches, &sp, cp);

    float radius = reyes_displacement_radius(p);
    __global const float *m = p->view_proj;
    float w_pad = radius * length((float3)(m[12], m[13], m[14]));
    int all_behind = 1, any_behind = 0;
    for (int k = 0; k < 16; ++k) {
        clip[k] = reyes_to_clip(p, cp[k]);
        int behind = clip[k].w <= p->near_w;
        all_behind &= radius > 0.0f ? clip[k].w + w_pad <= p->near_w : behind;
        any_behind |= behind;
    }
    int culled = all_behind || reyes_outside_frustum(p, clip, 16, p->cull_margin, radius, 0);
    if (p->blur)
        culled = reyes_blur_culled(p, cp, clip, radius);
    if (culled) {
        atomic_inc(&counters[REYES_COUNT_CULLED]);
        return;
    }
    int forced = sp.depth >= p->max_depth;
    if (p->polyline)
        reyes_polyline_test_edges(p, ctx->buf.patches, &sp, forced);
    if (any_behind) {
        /* Never project through the near plane: split in world space. */
        if (forced) {
            atomic_inc(&counters[REYES_COUNT_CULLED]);
            return;
        }
        atomic_inc(&counters[REYES_COUNT_SPLIT_NEAR]);
        if (reyes_world_extent(cp, 1) >= reyes_world_extent(cp, 0))
            emit_split_u(ctx, &sp);
        else
            emit_split_v(ctx, &sp);
        return;
    }

    float2 s[16];
    float2 lo = (float2)(INFINITY, INFINITY), hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < 16; ++k) {
        s[k] = reyes_to_screen(p, clip[k]);
        lo = fmin(lo, s[k]);
        hi = fmax(hi, s[k]);
    }
    /* Displaced surfaces may face anywhere: no back-face culling. */
    if (p->backface_cull && radius == 0.0f && reyes_backfacing(s)) {
        atomic_inc(&counters[REYES_COUNT_CULLED]);
        return;
    }
    int split_u;
    if (!p->polyline)
        sp.edge_levels = 0xffffffffu;
    float2 need = p->shading_rate > 0.0f ? reyes_rate_segments(p, cp, clip, s) : (float2)(0.0f, 0.0f);
    uint reason = reyes_split_reason(p, ctx->buf.patches, &sp, cp, clip, s, hi - lo, need, &split_u);
    if (p->polyline && reason == 0u && !forced)
        reason = reyes_polyline_reason(&sp, need, &split_u);
    if (forced || reason == 0u) {
        int polyline_fillers = 0;
        if (forced)
            atomic_inc(&counters[REYES_COUNT_FORCED_DICE]);
        if (p->polyline) {
            /* The lattice takes the most of its rows and columns and of
             * its edges' polylines (reyes_polyline.cl). */
            uint2 sides = convert_uint2(fmin(need, (float)(p->grid - 1u)));
            uint counts[4];
            polyline_fillers = reyes_polyline_prepare_dice(ctx->buf.patches, &sp, counts);
            sides.x = max(sides.x, max(counts[REYES_EDGE_V0], counts[REYES_EDGE_V1]));
            sides.y = max(sides.y, max(counts[REYES_EDGE_U0], counts[REYES_EDGE_U1]));
            sp.dice_size = (sp.dice_size & 0xffff0000u) | (sides.x + 1u) | ((sides.y + 1u) << 8);
        } else if (p->shading_rate > 0.0f) {
            /* The lattice takes the most of its rows and columns and of
             * its edges (reyes_rate.cl); an edge with fewer keeps its own. */
            uint edges = reyes_rate_edges(p, ctx->buf.patches, &sp);
            uint2 sides = convert_uint2(fmin(need, (float)(p->grid - 1u)));
            sides.x = max(sides.x, max(edges & 0xffu, (edges >> (8 * REYES_EDGE_V1)) & 0xffu));
            sides.y = max(sides.y, max((edges >> (8 * REYES_EDGE_U0)) & 0xffu, (edges >> (8 * REYES_EDGE_U1)) & 0xffu));
            sp.dice_size = (sides.x + 1u) | ((sides.y + 1u) << 8);
            sp.edge_levels = edges;
        }
        /* With a shading rate, a grid that covers no sample is not diced
         * (the image is the same; fixed grids keep the reference's counts).
         * A stitched leaf is still recorded, flagged, so the stitch plan
         * is the same. */
        int sampleless = p->shading_rate > 0.0f && !p->blur && radius == 0.0f && !reyes_hull_has_sample(p, s, lo, hi);
        /* A polyline grid's T-junction fillers may reach past its hull:
         * kept. */
        if (polyline_fillers)
            sampleless = 0;
        if (sampleless && !p->polyline)
            sp.dice_size |= REYES_DICE_NO_SAMPLE;
        if (p->record_leaves) {
            if (p->blur)
                reyes_blur_leaf_box(p, cp, clip, radius, &lo, &hi);
            else
                reyes_grow_box(p, clip, radius, &lo, &hi);
            float near_w = INFINITY;
            for (int k = 0; k < 16; ++k)
                near_w = fmin(near_w, clip[k].w);
            reyes_record_leaf(ctx, &sp, lo, hi, near_w);
        } else if (sampleless)
            atomic_inc(&counters[REYES_COUNT_CULLED]);
        else
            emit_dice(ctx, &sp);
        return;
    }
    atomic_inc(&counters[reason]);
    if (split_u)
        emit_split_u(ctx, &sp);
    else
        emit_split_v(ctx, &sp);
}
