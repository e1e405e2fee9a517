/*
 * dice: evaluate a sub-patch on a grid x grid vertex lattice, shade each
 * vertex and emit the (grid-1)^2 quads as micropolygons.  The threads of an
 * item share the vertices, then the quads (v, q = thread, thread + threads,
 * ...), with one barrier between, through REYES_DICE_VERTEX_BYTES of
 * __local scratch per vertex.  Vertices are evaluated on the base patch at
 * global (u,v), so a vertex shared by two sub-patches is bit-identical
 * wherever it is computed.  The evaluation and shading are in
 * reyes_surface.cl.
 */

/* Hand a visible quad to rasterize: with per-vertex motion rasterize
 * takes the quad with its vertices' motions (blurred or not). */
void reyes_emit_raster(perma_ctx *ctx, const struct reyes_quad *quad, const struct reyes_moving_quad *moving,
                       const struct reyes_vertex corners[4])
{
#ifdef REYES_VERTEX_MOTION
    if (moving) {
        emit_rasterize(ctx, moving);
        return;
    }
    struct reyes_moving_quad item = reyes_vertex_moving(ctx->buf.params, quad, corners, 4);
    emit_rasterize(ctx, &item);
#else
    (void)moving;
    (void)corners;
    emit_rasterize(ctx, quad);
#endif
}

/* Send one quad (vertices around it) to rasterize if it is in front of
 * the near plane and on the tile; returns whether it was visible. */
int reyes_emit_quad(perma_ctx *ctx, const struct reyes_vertex corners[4], int full)
{
    __global const struct reyes_params *p = ctx->buf.params;
    struct reyes_quad quad;
    int visible = 1;
    float2 lo = (float2)(INFINITY, INFINITY), hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < 4; ++k) {
        visible &= corners[k].clip.w > p->near_w;
        /* Blurred quads keep clip x, y (rasterize moves them per sample). */
        float2 s = p->blur ? corners[k].clip.xy : reyes_to_screen(p, corners[k].clip);
        quad.x[k] = s.x;
        quad.y[k] = s.y;
        quad.z[k] = corners[k].clip.w;
        quad.rgba[k] = corners[k].rgba;
        lo = fmin(lo, s);
        hi = fmax(hi, s);
    }
    /* Quads through the near plane or wholly off the tile (the image
     * without buckets) are dropped; blurred ones when their box over the
     * shutter and lens misses it. */
    if (p->blur) {
        /* Each vertex moves by its own motion (one for all without a
         * rotation). */
        struct reyes_moving_quad moving = reyes_vertex_moving(p, &quad, corners, 4);
        visible = visible && reyes_blur_meets_tile(p, &moving);
        if (visible && full)
            reyes_emit_raster(ctx, &quad, &moving, corners);
        return visible;
    }
    visible &= hi.x >= p->tile_x0 && hi.y >= p->tile_y0 && lo.x <= p->tile_x1
               && lo.y <= p->tile_y1;
    if (visible && full)
        reyes_emit_raster(ctx, &quad, 0, corners);
    return visible;
}

/* Quad i of the wedge strip of `edge`, whose settled segment's chord is c. */
void reyes_emit_wedge(perma_ctx *ctx, const struct reyes_chord *c, const struct reyes_subpatch *sp,
                      __local const struct reyes_vertex *grid, int edge, int i, int full)
{
    __global const struct reyes_params *p = ctx->buf.params;
    int n = (int)p->grid, side = n - 1;
    float last = (float)side;
    int along_u;
    float fixed, a, b;
    reyes_edge_line(sp, edge, &along_u, &fixed, &a, &b);
    struct reyes_vertex corners[4];
    for (int k = 0; k < 2; ++k) {
        int step = i + k; /* along the edge */
        int gi = along_u ? step : (edge == REYES_EDGE_U1 ? side : 0);
        int gj = along_u ? (edge == REYES_EDGE_V1 ? side : 0) : step;
        float t = (float)step / last;
        float s = a * (1.0f - t) + b * t; /* as reyes_grid_vertex */
        struct reyes_vertex on_grid = grid[gj * n + gi], on_chord;
        reyes_vertex_place(p, reyes_chord_at(c, s), &on_chord);
        on_chord.rgba = on_grid.rgba;
        corners[k] = on_grid;
        corners[3 - k] = on_chord;
    }
    if (reyes_emit_quad(ctx, corners, full))
        atomic_add(&ctx->buf.counters[REYES_COUNT_FILLERS], 2u);
}


/* Wedge crack fix: for every settled edge, a strip of quads from the
 * grid's boundary vertices to the points at the same parameters on the
 * chord of the edge's settled segment (reyes_flatness.cl).  The sides of
 * an edge reach the same chord, so together they close the crack.  A
 * thread's quads run through the edges in order, so it makes each edge's
 * chord once. */
void reyes_dice_wedges(perma_ctx *ctx, const struct reyes_subpatch *sp,
                       __local const struct reyes_vertex *grid, int full)
{
    __global const struct reyes_params *p = ctx->buf.params;
    int side = (int)p->grid - 1;
    float3 base[16];
    reyes_load_patch(ctx->buf.patches, sp->patch, base);
    struct reyes_chord chord;
    int chord_edge = -1;
    for (int q = (int)ctx->thread; q < 4 * side; q += (int)p->dice_threads) {
        int edge = q / side, i = q % side;
        uint level = (sp->edge_levels >> (8 * edge)) & 0xffu;
        if (level != REYES_EDGE_UNSETTLED) {
            if (edge != chord_edge) {
                chord = reyes_edge_chord(base, sp, edge, level);
                chord_edge = edge;
            }
            reyes_emit_wedge(ctx, &chord, sp, grid, edge, i, full);
        }
    }
}

/* Cooperative: every work-item of the group calls it.  The item's threads
 * first evaluate and shade each grid vertex once into __local scratch, then,
 * after the barrier, assemble the quads from it. */
void reyes_dice(perma_ctx *ctx, __local const struct reyes_subpatch *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    __global uint *counters = ctx->buf.counters;
    __local struct reyes_vertex *grid = (__local struct reyes_vertex *)ctx->scratch;
    int n = (int)p->grid, side = n - 1;
    int threads = (int)p->dice_threads;
    int diced = ctx->active && p->stages != REYES_STAGES_SUBDIVIDE;
    int full = p->stages == REYES_STAGES_ALL;
    struct reyes_subpatch sp;
    if (ctx->active) {
        sp = *item;
        if (ctx->thread == 0)
            atomic_inc(&counters[REYES_COUNT_GRIDS]);
    }
    if (diced) {
        float3 cp[16];
        reyes_load_patch(ctx->buf.patches, sp.patch, cp);
        uint rgba = ctx->buf.colors[sp.patch];
        struct reyes_displacement d = { p, ctx->buf.displacement_map };
        for (int v = (int)ctx->thread; v < n * n; v += threads)
            grid[v] = reyes_grid_vertex(&d, cp, &sp, rgba, v % n, v / n, full);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (!diced)
        return;

    const int corner_i[4] = {0, 1, 1, 0}, corner_j[4] = {0, 0, 1, 1};
    for (int q = (int)ctx->thread; q < side * side; q += threads) {
        int i = q % side, j = q / side;
        struct reyes_vertex corners[4];
        for (int k = 0; k < 4; ++k)
            corners[k] = grid[(j + corner_j[k]) * n + i + corner_i[k]];
        if (reyes_emit_quad(ctx, corners, full))
            atomic_inc(&counters[REYES_COUNT_MICROPOLYGONS]);
    }
    if (p->wedges)
        reyes_dice_wedges(ctx, &sp, grid, full);
}
