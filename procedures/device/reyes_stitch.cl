/*
 * stitch: fill the crack along one edge of a diced sub-patch (the owner)
 * whose neighbours across the edge were diced finer (shorter, or with a
 * shading rate at more vertices), or belong to another base patch.  The owner's edge vertices C_0..C_{n-1} and the neighbours'
 * edge vertices F_0..F_m (piece after piece, in the owner's direction) are
 * both evaluated with reyes_grid_vertex's arithmetic (in lanes,
 * reyes_stitch_fill), so each is bit-identical to the vertex dice made
 * for its grid.  A zipper triangulates the strip between
 * the two polylines: every triangle edge C_i C_{i+1} or F_j F_{j+1} is
 * exactly an edge of a grid triangle on the other side, so grids and
 * strips together form an edge-conforming mesh and the canonical edge
 * functions leave no sample uncovered between them.
 */

/* One edge of a diced sub-patch, set up once for all its vertices: its
 * base patch's control points, the sub-patch with the edge's own grid
 * size (reyes_edge_subpatch), its segment count, and (for a neighbour's
 * piece) its place along the owner's edge.  The vertices are evaluated
 * REYES_LANES at a time into `window` (vertices k0 .. k0 + count - 1),
 * in the direction the zipper walks them. */
struct reyes_stitch_edge {
    float3 cp[16];
    struct reyes_subpatch sp;
    int2 size;
    uint edge, rgba;
    int last, reversed;
    float t0, t1;
    int k0, count;
    struct reyes_vertex window[REYES_LANES];
};

REYES_INLINE void reyes_stitch_edge_setup(perma_ctx *ctx, const struct reyes_subpatch *sp, uint edge,
                                          struct reyes_stitch_edge *e)
{
    __global const struct reyes_params *p = ctx->buf.params;
    reyes_load_patch(ctx->buf.patches, sp->patch, e->cp);
    e->sp = reyes_edge_subpatch(p, sp, (int)edge);
    e->size = reyes_dice_size(p, e->sp.dice_size);
    e->edge = edge;
    e->rgba = ctx->buf.colors[sp->patch];
    e->last = edge == REYES_EDGE_V0 || edge == REYES_EDGE_V1 ? e->size.x - 1 : e->size.y - 1;
    e->reversed = 0;
    e->t0 = 0.0f;
    e->t1 = 1.0f;
    e->k0 = e->count = 0;
}

/* Fill the window from vertex k0: each vertex is reyes_grid_vertex's, bit
 * for bit (undisplaced: the point, normal and clip position in lanes
 * with the arithmetic of reyes_patch_point_normal and reyes_clip_of, the
 * normal packed in lanes with sample shading, and shaded one by one as
 * there otherwise; displaced: reyes_grid_vertex itself). */
void reyes_stitch_fill(perma_ctx *ctx, struct reyes_stitch_edge *e, int k0)
{
    __global const struct reyes_params *p = ctx->buf.params;
    struct reyes_displacement d = { p, ctx->buf.displacement_map };
    e->k0 = k0;
    e->count = min(REYES_LANES, e->last - k0 + 1);
    float us[REYES_LANES], vs[REYES_LANES];
    for (int k = 0; k < REYES_LANES; ++k) {
        int2 ij = reyes_edge_vertex(e->edge, min(k0 + k, e->last), e->size);
        float2 uv = reyes_grid_uv(p, &e->sp, ij.x, ij.y);
        us[k] = uv.x;
        vs[k] = uv.y;
        if (p->displace_mode != REYES_DISPLACE_NONE && k < e->count)
            e->window[k] = reyes_grid_vertex(&d, e->cp, &e->sp, e->rgba, ij.x, ij.y, 1);
    }
    if (p->displace_mode != REYES_DISPLACE_NONE)
        return;
    struct reyes_hull h = reyes_hull_of(e->cp);
    struct reyes_row_curves_lanes rc;
    reyes_row_curves_lanes(&h, reyes_vload_lanes(0, vs), &rc);
    reyes_lanes x[3], n[3];
    reyes_lanes u = reyes_vload_lanes(0, us);
    reyes_row_point_lanes(&rc, u, x);
    reyes_lane_mask collapsed = reyes_row_normal_lanes(&rc, u, n);
    /* Placed as reyes_clip_of; with sample shading, a normal that is not
     * collapsed is reyes_lit_normal_from's and packed as reyes_shade does
     * (lane by lane). */
    __global const float *m = p->view_proj;
    reyes_lanes clip[4];
    for (int r = 0; r < 4; ++r)
        clip[r] = reyes_dot4_lanes(m[4 * r], m[4 * r + 1], m[4 * r + 2], m[4 * r + 3], x[0], x[1], x[2]);
    reyes_lane_uint packed = (reyes_lane_uint)0u;
    if (p->sample_shading)
        packed = reyes_pack_normal16(n[0], n[1], n[2]);
    for (int k = 0; k < e->count; ++k) {
        float3 xk = (float3)(((float *)&x[0])[k], ((float *)&x[1])[k], ((float *)&x[2])[k]);
        struct reyes_vertex out;
        out.clip = (float4)(((float *)&clip[0])[k], ((float *)&clip[1])[k], ((float *)&clip[2])[k],
                            ((float *)&clip[3])[k]);
#ifdef REYES_VERTEX_MOTION
        out.motion = reyes_motion_at(p, xk);
#endif
        out.rgba = ((uint *)&packed)[k];
        if (!p->sample_shading || ((int *)&collapsed)[k]) {
            float3 nk = (float3)(((float *)&n[0])[k], ((float *)&n[1])[k], ((float *)&n[2])[k]);
            out.rgba = reyes_shade(p, xk, reyes_vertex_normal_from(p, e->cp, us[k], vs[k], nk, ((int *)&collapsed)[k] != 0),
                                   e->rgba);
        }
        e->window[k] = out;
    }
}

/* Shaded vertex k along the edge, evaluated as dice does. */
REYES_INLINE struct reyes_vertex reyes_stitch_vertex(perma_ctx *ctx, struct reyes_stitch_edge *e, int k)
{
    if (k < e->k0 || k >= e->k0 + e->count)
        reyes_stitch_fill(ctx, e, e->reversed ? max(k - (REYES_LANES - 1), 0) : k);
    return e->window[k - e->k0];
}

/* Where the zipper is on the neighbours' polyline: vertex k of piece
 * `index`, piece after piece in the owner's edge order; the piece is set
 * up in slot index % 2 of the stitch's two (the zipper's vertex and the
 * next one are on the same piece or on consecutive ones).  A piece's last
 * vertex and the next piece's first are both visited (the same point: a
 * degenerate triangle between them). */
struct reyes_piece_cursor {
    uint index;
    int k;
};

/* Point the cursor at vertex 0 of piece `index`, set up in its slot. */
REYES_INLINE void reyes_piece_enter(perma_ctx *ctx, uint first, uint index, struct reyes_stitch_edge slots[2],
                                    struct reyes_piece_cursor *at)
{
    struct reyes_stitch_piece piece = ctx->buf.pieces[first + index];
    struct reyes_stitch_edge *e = &slots[index & 1u];
    reyes_stitch_edge_setup(ctx, &piece.sp, piece.edge, e);
    e->reversed = piece.reversed != 0u;
    e->t0 = piece.t0;
    e->t1 = piece.t1;
    at->index = index;
    at->k = 0;
}

/* The cursor's vertex and its position along the owner's edge (0..1). */
REYES_INLINE struct reyes_vertex reyes_piece_vertex(perma_ctx *ctx, struct reyes_stitch_edge slots[2],
                                                    struct reyes_piece_cursor at, float *t)
{
    struct reyes_stitch_edge *e = &slots[at.index & 1u];
    int last = e->last;
    int own = e->reversed ? last - at.k : at.k;
    *t = e->t0 + (e->t1 - e->t0) * ((float)at.k / (float)last);
    return reyes_stitch_vertex(ctx, e, own);
}

/* Step the cursor to the neighbours' next vertex. */
REYES_INLINE void reyes_piece_step(perma_ctx *ctx, uint first, struct reyes_stitch_edge slots[2],
                                   struct reyes_piece_cursor *at)
{
    if (at->k == slots[at->index & 1u].last)
        reyes_piece_enter(ctx, first, at->index + 1u, slots, at);
    else
        ++at->k;
}

/* Rasterize triangle (a, b, c) over its pixel box clipped to the tile,
 * with the same sample positions and atomic min as rasterize (with sample
 * shading lit with base colour `base`).  Returns 1 if it was in front of
 * the near plane. */
int reyes_fill_triangle(perma_ctx *ctx, struct reyes_vertex a, struct reyes_vertex b,
                        struct reyes_vertex c, uint base)
{
    __global const struct reyes_params *p = ctx->buf.params;
    if (a.clip.w <= p->near_w || b.clip.w <= p->near_w || c.clip.w <= p->near_w)
        return 0;
    struct reyes_vertex v[3] = {a, b, c};
    struct reyes_quad q;
    for (int k = 0; k < 3; ++k) {
        /* Blurred: clip x, y, w, moved per sample by rasterize's code. */
        float2 s = p->blur ? v[k].clip.xy : reyes_to_screen(p, v[k].clip);
        q.x[k] = s.x;
        q.y[k] = s.y;
        q.z[k] = v[k].clip.w;
        q.rgba[k] = v[k].rgba;
    }
    q.x[3] = q.x[0];
    q.y[3] = q.y[0];
    q.z[3] = q.z[0];
    q.rgba[3] = q.rgba[0];
    if (p->blur) {
        struct reyes_moving_quad moving = reyes_vertex_moving(p, &q, v, 3);
        reyes_rasterize_blurred(p, ctx->buf.blur_tuples, ctx->buf.samples, &moving, 1);
        return 1;
    }
    float2 lo = (float2)(fmin(fmin(q.x[0], q.x[1]), q.x[2]), fmin(fmin(q.y[0], q.y[1]), q.y[2]));
    float2 hi = (float2)(fmax(fmax(q.x[0], q.x[1]), q.x[2]), fmax(fmax(q.y[0], q.y[1]), q.y[2]));
    const struct reyes_triangle triangle = reyes_triangle_setup(&q, 0, 1, 2);
    /* No sample is inside a triangle without area (reyes_triangle_covers);
     * the zipper makes one wherever two pieces meet. */
    if (triangle.area == 0.0f)
        return 1;
    reyes_sample_box(p, ctx->buf.samples, lo, hi, &q, &triangle, 1, base);
    return 1;
}

void reyes_stitch(perma_ctx *ctx, __local const struct reyes_stitch *item)
{
    struct reyes_stitch st = *item;
    struct reyes_stitch_edge owner, slots[2];
    reyes_stitch_edge_setup(ctx, &st.owner, st.edge, &owner);
    int last = owner.last;
    /* The owner's vertices around the pieces' span [t_start, t_end]. */
    float first_t0 = ctx->buf.pieces[st.first].t0;
    float last_t1 = ctx->buf.pieces[st.first + st.count - 1u].t1;
    int i = (int)floor(first_t0 * (float)last);
    int i_end = (int)ceil(last_t1 * (float)last);
    /* at: the zipper's neighbour vertex f; next: the one after it, f_next
     * (evaluated once, whichever side advances meanwhile). */
    struct reyes_piece_cursor at, next;
    float tf, tf_next;
    struct reyes_vertex c = reyes_stitch_vertex(ctx, &owner, i);
    reyes_piece_enter(ctx, st.first, 0u, slots, &at);
    struct reyes_vertex f = reyes_piece_vertex(ctx, slots, at, &tf);
    struct reyes_vertex f_next = f;
    int f_done = st.count == 1u && at.k == slots[0].last;
    tf_next = tf;
    if (!f_done) {
        next = at;
        reyes_piece_step(ctx, st.first, slots, &next);
        f_next = reyes_piece_vertex(ctx, slots, next, &tf_next);
    }
    uint fillers = 0, base = owner.rgba;
    for (;;) {
        if (i >= i_end && f_done)
            break;
        int advance_owner = f_done || (i < i_end && (float)(i + 1) / (float)last <= tf_next);
        if (advance_owner) {
            struct reyes_vertex c_next = reyes_stitch_vertex(ctx, &owner, i + 1);
            fillers += (uint)reyes_fill_triangle(ctx, c, c_next, f, base);
            c = c_next;
            ++i;
            continue;
        }
        fillers += (uint)reyes_fill_triangle(ctx, c, f, f_next, base);
        f = f_next;
        tf = tf_next;
        at = next;
        f_done = at.index + 1u == st.count && at.k == slots[at.index & 1u].last;
        if (!f_done) {
            reyes_piece_step(ctx, st.first, slots, &next);
            f_next = reyes_piece_vertex(ctx, slots, next, &tf_next);
        }
    }
    atomic_add(&ctx->buf.counters[REYES_COUNT_FILLERS], fillers);
}
