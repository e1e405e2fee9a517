/*
 * dice: evaluate a sub-patch on a grid x grid vertex lattice, shade each
 * vertex, count the (grid-1)^2 quads that are visible as micropolygons and
 * hand the lattice to rasterize as one item (struct reyes_grid,
 * reyes_grid.cl).  The item's REYES_ITEM_THREADS work-items share the
 * vertices (vertex v is work-item v % threads's in pass v / threads) in
 * __local scratch laid out as the rasterize item.  Vertices are evaluated
 * on the base patch at global (u,v), so a vertex shared by two sub-patches
 * is bit-identical wherever it is computed.  The evaluation and shading
 * are in reyes_surface.cl.
 *
 * Each pass ends with a barrier although the work-items share nothing
 * within it: PoCL runs the work-items of a group in a loop per stretch
 * between barriers, and a stretch without inner loops or calls (one
 * vertex per work-item) is one its vectoriser turns into SIMD code across
 * work-items.  The trip counts are the same in every work-item.
 */

/* The scratch of one dice item. */
struct reyes_dice_scratch {
    struct reyes_grid grid;
    struct reyes_grid strips;                 /* wedge crack fix */
    uint quads[REYES_ITEM_THREADS];           /* visible quads, per work-item */
    uint fillers[REYES_ITEM_THREADS];         /* visible wedge quads, per work-item */
    uchar degenerate[REYES_GRID_VERTICES];    /* 1: the first normal vanished (a pole) */
};

/* Wedge crack fix: the strips along the settled edges, from the grid's
 * boundary vertices to the points at the same parameters on the chord of
 * the edge's settled segment (reyes_flatness.cl).  The sides of an edge
 * reach the same chord, so together they close the crack.  Strip e is
 * vertex rows 2e (the grid's vertices along edge e, in the edge's order)
 * and 2e + 1 (their chord points); its quads are quad row 2e. */
void reyes_dice_strip_vertex(perma_ctx *ctx, const struct reyes_subpatch *sp, __local struct reyes_dice_scratch *s,
                             int v)
{
    __global const struct reyes_params *p = ctx->buf.params;
    int n = (int)p->grid, side = n - 1;
    int edge = v / n, step = v % n;
    uint level = (sp->edge_levels >> (8 * edge)) & 0xffu;
    if (level == REYES_EDGE_UNSETTLED)
        return;
    float3 base[16];
    reyes_load_patch(ctx->buf.patches, sp->patch, base);
    struct reyes_chord chord = reyes_edge_chord(base, sp, edge, level);
    int along_u;
    float fixed, a, b;
    reyes_edge_line(sp, edge, &along_u, &fixed, &a, &b);
    int gi = along_u ? step : (edge == REYES_EDGE_U1 ? side : 0);
    int gj = along_u ? (edge == REYES_EDGE_V1 ? side : 0) : step;
    float t = (float)step / (float)side;
    float at = a * (1.0f - t) + b * t; /* as reyes_grid_vertex */
    struct reyes_vertex on_chord;
    reyes_vertex_place(p, reyes_chord_at(&chord, at), &on_chord);
    on_chord.rgba = s->grid.rgba[gj * n + gi];
    reyes_grid_copy_vertex(&s->grid, gj * n + gi, &s->strips, 2 * edge * n + step);
    reyes_grid_store(p, &s->strips, (2 * edge + 1) * n + step, &on_chord);
}

/* Visible quads of lattice g, counted by the work-items in passes over
 * its slots and summed over them by a tree of barriers (a loop in thread
 * 0 alone is what PoCL mishandles); returns the total. */
uint reyes_dice_count(__global const struct reyes_params *p, __local const struct reyes_grid *g, int active,
                      __local uint *partial, int thread)
{
    const int threads = REYES_ITEM_THREADS;
    const int passes = (REYES_GRID_SLOTS + threads - 1) / threads;
    uint visible = 0;
    for (int pass = 0; pass < passes; ++pass) {
        int k = pass * threads + thread;
        visible += active && k < REYES_GRID_SLOTS && reyes_grid_visible(p, g, k);
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    partial[thread] = visible;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (int stride = REYES_ITEM_THREADS_POW2 / 2; stride > 0; stride /= 2) {
        if (thread < stride && thread + stride < threads)
            partial[thread] += partial[thread + stride];
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    return partial[0];
}

/* Hand a lattice to rasterize (thread 0 of a full render). */
void reyes_dice_emit(perma_ctx *ctx, __local const struct reyes_grid *g)
{
    struct reyes_grid item = *g;
    emit_rasterize(ctx, &item);
}

/* Cooperative: every work-item of the group calls it. */
void reyes_dice(perma_ctx *ctx, __local const struct reyes_subpatch *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    __global uint *counters = ctx->buf.counters;
    __local struct reyes_dice_scratch *s = (__local struct reyes_dice_scratch *)ctx->scratch;
    const int threads = REYES_ITEM_THREADS;
    const int thread = (int)ctx->thread;
    const int passes = (REYES_GRID_VERTICES + threads - 1) / threads;
    int n = (int)p->grid;
    int diced = ctx->active && p->stages != REYES_STAGES_SUBDIVIDE;
    int full = p->stages == REYES_STAGES_ALL;
    struct reyes_subpatch sp = *item;
    if (ctx->active && thread == 0) {
        atomic_inc(&counters[REYES_COUNT_GRIDS]);
        s->grid.columns = (uint)n;
        s->grid.rows = (uint)n;
        s->grid.quad_rows = (1u << (n - 1)) - 1u;
        s->grid.pad = 0u;
    }
    float3 base = reyes_unpack_rgb(ctx->buf.colors[sp.patch]);
    struct reyes_displacement d = { p, ctx->buf.displacement_map };
    if (p->displace_mode == REYES_DISPLACE_NONE) {
        for (int pass = 0; pass < passes; ++pass) {
            int v = pass * threads + thread;
            if (diced && v < n * n) {
                float3 cp[16];
                reyes_load_patch(ctx->buf.patches, sp.patch, cp);
                int degenerate;
                struct reyes_vertex vertex = reyes_plain_vertex(p, cp, &sp, base, v % n, v / n, full, &degenerate);
                reyes_grid_store(p, &s->grid, v, &vertex);
                s->degenerate[v] = (uchar)degenerate;
            }
            barrier(CLK_LOCAL_MEM_FENCE);
        }
        /* Poles: the normal slightly inside (rare; scalar). */
        for (int v = thread; full && diced && v < n * n; v += threads) {
            if (s->degenerate[v]) {
                float3 cp[16];
                reyes_load_patch(ctx->buf.patches, sp.patch, cp);
                s->grid.rgba[v] = reyes_grid_vertex_color(p, cp, &sp, base, v % n, v / n);
            }
        }
    } else {
        for (int v = thread; diced && v < n * n; v += threads) {
            float3 cp[16];
            reyes_load_patch(ctx->buf.patches, sp.patch, cp);
            struct reyes_vertex vertex = reyes_grid_vertex(&d, cp, &sp, base, v % n, v / n, full);
            reyes_grid_store(p, &s->grid, v, &vertex);
        }
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    uint quads = reyes_dice_count(p, &s->grid, diced, s->quads, thread);
    if (thread == 0 && quads > 0u) {
        atomic_add(&counters[REYES_COUNT_MICROPOLYGONS], quads);
        if (full)
            reyes_dice_emit(ctx, &s->grid);
    }
    if (p->wedges) {
        if (ctx->active && thread == 0) {
            s->strips.columns = (uint)n;
            s->strips.rows = 8u;
            uint rows = 0;
            for (int edge = 0; edge < 4; ++edge)
                if (((sp.edge_levels >> (8 * edge)) & 0xffu) != REYES_EDGE_UNSETTLED)
                    rows |= 1u << (2 * edge);
            s->strips.quad_rows = rows;
            s->strips.pad = 0u;
        }
        for (int v = thread; diced && v < 4 * n; v += threads)
            reyes_dice_strip_vertex(ctx, &sp, s, v);
        barrier(CLK_LOCAL_MEM_FENCE);
        uint strip_quads = reyes_dice_count(p, &s->strips, diced, s->fillers, thread);
        if (thread == 0 && strip_quads > 0u) {
            atomic_add(&counters[REYES_COUNT_FILLERS], 2u * strip_quads); /* two triangles each */
            if (full)
                reyes_dice_emit(ctx, &s->strips);
        }
        /* A uniform branch with barriers ends with one: without it PoCL
         * ran the stretch above in every work-item as if thread were 0. */
        barrier(CLK_LOCAL_MEM_FENCE);
    }
}
