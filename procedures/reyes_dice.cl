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
        float3 base = reyes_unpack_rgb(ctx->buf.colors[sp.patch]);
        struct reyes_displacement d = { p, ctx->buf.displacement_map };
        for (int v = (int)ctx->thread; v < n * n; v += threads)
            grid[v] = reyes_grid_vertex(&d, cp, &sp, base, v % n, v / n, full);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (!diced)
        return;

    const int corner_i[4] = {0, 1, 1, 0}, corner_j[4] = {0, 0, 1, 1};
    for (int q = (int)ctx->thread; q < side * side; q += threads) {
        int i = q % side, j = q / side;
        struct reyes_quad quad;
        int visible = 1;
        float2 lo = (float2)(INFINITY, INFINITY), hi = (float2)(-INFINITY, -INFINITY);
        for (int k = 0; k < 4; ++k) {
            struct reyes_vertex vtx = grid[(j + corner_j[k]) * n + i + corner_i[k]];
            visible &= vtx.clip.w > p->near_w;
            /* Blurred quads keep clip x, y (rasterize moves them per sample). */
            float2 s = p->blur ? vtx.clip.xy : reyes_to_screen(p, vtx.clip);
            quad.x[k] = s.x;
            quad.y[k] = s.y;
            quad.z[k] = vtx.clip.w;
            quad.rgba[k] = vtx.rgba;
            lo = fmin(lo, s);
            hi = fmax(hi, s);
        }
        /* Quads through the near plane or wholly off the tile (the image
         * without buckets) are dropped. */
        visible &= p->blur || (hi.x >= p->tile_x0 && hi.y >= p->tile_y0 && lo.x <= p->tile_x1
                               && lo.y <= p->tile_y1);
        if (visible) {
            atomic_inc(&counters[REYES_COUNT_MICROPOLYGONS]);
            if (full)
                emit_rasterize(ctx, &quad);
        }
    }
}
