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

/* One edge of a diced sub-patch, set up once for all its vertices: its
 * base patch's control points, the sub-patch with the edge's own grid
 * size (reyes_edge_subpatch), and its segment count. */
struct reyes_stitch_edge {
    float3 cp[16];
    struct reyes_subpatch sp;
    int2 size;
    uint edge, rgba;
    int last;
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
}

/* Shaded vertex k along the edge, evaluated as dice does. */
REYES_INLINE struct reyes_vertex reyes_stitch_vertex(perma_ctx *ctx, const struct reyes_stitch_edge *e, int k)
{
    int2 ij = reyes_edge_vertex(e->edge, k, e->size);
    struct reyes_displacement d = { ctx->buf.params, ctx->buf.displacement_map };
    return reyes_grid_vertex(&d, e->cp, &e->sp, e->rgba, ij.x, ij.y, 1);
}

/* Where the zipper is on the neighbours' polyline: vertex k of piece
 * `index` (set up in `e`), piece after piece in the owner's edge order.
 * A piece's last vertex and the next piece's first are both visited (the
 * same point: a degenerate triangle between them). */
struct reyes_piece_cursor {
    uint index;
    int k;
    int reversed;
    float t0, t1;
    struct reyes_stitch_edge e;
};

/* Point the cursor at vertex 0 of piece `index`. */
REYES_INLINE void reyes_piece_enter(perma_ctx *ctx, uint first, uint index, struct reyes_piece_cursor *at)
{
    struct reyes_stitch_piece piece = ctx->buf.pieces[first + index];
    at->index = index;
    at->k = 0;
    at->reversed = piece.reversed != 0u;
    at->t0 = piece.t0;
    at->t1 = piece.t1;
    reyes_stitch_edge_setup(ctx, &piece.sp, piece.edge, &at->e);
}

/* The cursor's vertex and its position along the owner's edge (0..1). */
REYES_INLINE struct reyes_vertex reyes_piece_vertex(perma_ctx *ctx, const struct reyes_piece_cursor *at, float *t)
{
    int last = at->e.last;
    int own = at->reversed ? last - at->k : at->k;
    *t = at->t0 + (at->t1 - at->t0) * ((float)at->k / (float)last);
    return reyes_stitch_vertex(ctx, &at->e, own);
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
    struct reyes_stitch_edge owner;
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
    reyes_piece_enter(ctx, st.first, 0u, &at);
    struct reyes_vertex f = reyes_piece_vertex(ctx, &at, &tf);
    struct reyes_vertex f_next = f;
    int f_done = st.count == 1u && at.k == at.e.last;
    tf_next = tf;
    if (!f_done) {
        next = at;
        if (next.k == next.e.last)
            reyes_piece_enter(ctx, st.first, next.index + 1u, &next);
        else
            ++next.k;
        f_next = reyes_piece_vertex(ctx, &next, &tf_next);
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
        f_done = at.index + 1u == st.count && at.k == at.e.last;
        if (!f_done) {
            if (next.k == next.e.last)
                reyes_piece_enter(ctx, st.first, next.index + 1u, &next);
            else
                ++next.k;
            f_next = reyes_piece_vertex(ctx, &next, &tf_next);
        }
    }
    atomic_add(&ctx->buf.counters[REYES_COUNT_FILLERS], fillers);
}
