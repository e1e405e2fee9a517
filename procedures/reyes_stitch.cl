/*
 * stitch: fill the crack along one edge of a diced sub-patch (the owner)
 * whose neighbours across the edge were diced finer (shorter, or with a
 * shading rate at more vertices), or belong to another base patch.  The owner's edge vertices C_0..C_{n-1} and the neighbours'
 * edge vertices F_0..F_m (piece after piece, in the owner's direction) are
 * both evaluated with reyes_grid_vertex, so each is bit-identical to the
 * vertex dice made for its grid.  A zipper triangulates the strip between
 * the two polylines: every triangle edge C_i C_{i+1} or F_j F_{j+1} is
 * exactly an edge of a grid triangle on the other side, so grids and
 * strips together form an edge-conforming mesh and the canonical edge
 * functions leave no sample uncovered between them.
 */

/* Segments of sub-patch sp's grid along edge `edge`: the edge's own with
 * a shading rate (reyes_edge_count), else the grid's. */
int reyes_edge_segments(__global const struct reyes_params *p, const struct reyes_subpatch *sp, uint edge)
{
    struct reyes_subpatch edge_sp = reyes_edge_subpatch(p, sp, (int)edge);
    int2 size = reyes_dice_size(p, edge_sp.dice_size);
    return edge == REYES_EDGE_V0 || edge == REYES_EDGE_V1 ? size.x - 1 : size.y - 1;
}

/* Shaded vertex k along edge `edge` of sub-patch sp's grid, evaluated as
 * dice does. */
struct reyes_vertex reyes_stitch_vertex(perma_ctx *ctx, const struct reyes_subpatch *sp, uint edge,
                                        int k)
{
    __global const struct reyes_params *p = ctx->buf.params;
    float3 cp[16];
    reyes_load_patch(ctx->buf.patches, sp->patch, cp);
    struct reyes_subpatch edge_sp = reyes_edge_subpatch(p, sp, (int)edge);
    int2 ij = reyes_edge_vertex(edge, k, reyes_dice_size(p, edge_sp.dice_size));
    struct reyes_displacement d = { p, ctx->buf.displacement_map };
    return reyes_grid_vertex(&d, cp, &edge_sp, ctx->buf.colors[sp->patch], ij.x, ij.y, 1);
}

/* Where the zipper is on the neighbours' polyline: vertex k of piece
 * `index` (of `last` segments), piece after piece in the owner's edge
 * order.  A piece's last vertex and the next piece's first are both
 * visited (the same point: a degenerate triangle between them). */
struct reyes_piece_cursor {
    uint index;
    int k, last;
};

/* The cursor's vertex and its position along the owner's edge (0..1). */
struct reyes_vertex reyes_piece_vertex(perma_ctx *ctx, uint first, struct reyes_piece_cursor *at, float *t)
{
    struct reyes_stitch_piece piece = ctx->buf.pieces[first + at->index];
    at->last = reyes_edge_segments(ctx->buf.params, &piece.sp, piece.edge);
    int own = piece.reversed ? at->last - at->k : at->k;
    *t = piece.t0 + (piece.t1 - piece.t0) * ((float)at->k / (float)at->last);
    return reyes_stitch_vertex(ctx, &piece.sp, piece.edge, own);
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
    reyes_sample_box(p, ctx->buf.samples, lo, hi, &q, &triangle, 1, base);
    return 1;
}

void reyes_stitch(perma_ctx *ctx, __local const struct reyes_stitch *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    struct reyes_stitch st = *item;
    int last = reyes_edge_segments(p, &st.owner, st.edge);
    /* The owner's vertices around the pieces' span [t_start, t_end]. */
    struct reyes_stitch_piece first_piece = ctx->buf.pieces[st.first];
    struct reyes_stitch_piece last_piece = ctx->buf.pieces[st.first + st.count - 1u];
    int i = (int)floor(first_piece.t0 * (float)last);
    int i_end = (int)ceil(last_piece.t1 * (float)last);
    struct reyes_piece_cursor at = { 0u, 0, 1 };
    float tf, tf_next;
    struct reyes_vertex c = reyes_stitch_vertex(ctx, &st.owner, st.edge, i);
    struct reyes_vertex f = reyes_piece_vertex(ctx, st.first, &at, &tf);
    uint fillers = 0, base = ctx->buf.colors[st.owner.patch];
    for (;;) {
        int f_done = at.index + 1u == st.count && at.k == at.last;
        if (i >= i_end && f_done)
            break;
        struct reyes_piece_cursor next = at;
        struct reyes_vertex f_next = f;
        tf_next = tf;
        if (!f_done) {
            if (next.k == next.last) {
                ++next.index;
                next.k = 0;
            } else {
                ++next.k;
            }
            f_next = reyes_piece_vertex(ctx, st.first, &next, &tf_next);
        }
        int advance_owner = f_done || (i < i_end && (float)(i + 1) / (float)last <= tf_next);
        if (advance_owner) {
            struct reyes_vertex c_next = reyes_stitch_vertex(ctx, &st.owner, st.edge, i + 1);
            fillers += (uint)reyes_fill_triangle(ctx, c, c_next, f, base);
            c = c_next;
            ++i;
        } else {
            fillers += (uint)reyes_fill_triangle(ctx, c, f, f_next, base);
            f = f_next;
            tf = tf_next;
            at = next;
        }
    }
    atomic_add(&ctx->buf.counters[REYES_COUNT_FILLERS], fillers);
}
