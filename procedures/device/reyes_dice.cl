/*
 * dice: evaluate a sub-patch on a grid x grid vertex lattice (with a
 * shading rate: the size bound chose for it, reyes_subpatch.dice_size),
 * shade each vertex and rasterize the lattice (struct reyes_grid,
 * reyes_grid.cl) where it lies, in __local scratch (reyes_rasterize.cl),
 * which counts the quads that are visible as micropolygons.  One work-item
 * dices one sub-patch, REYES_LANES consecutive vertices at a time in SIMD
 * lanes (OpenCL vector types); a batch holds as many sub-patches as the
 * group has work-items, so the runtime's cost per batch is shared by that
 * many grids.  Vertices are evaluated on the base patch
 * at global (u,v), so a vertex shared by two sub-patches is bit-identical
 * wherever it is computed.  The evaluation and shading are in
 * reyes_surface.cl.
 */

/* The scratch of one dice item. */
struct reyes_dice_scratch {
    struct reyes_grid grid;
    struct reyes_grid strips; /* wedge crack fix */
};

/* Wedge crack fix: the strips along the settled edges, from the grid's
 * boundary vertices to the points at the same parameters on the polyline
 * of the edge's settled segment (reyes_flatness.cl).  The sides of an
 * edge reach the same polyline, so together they close the crack.  Strip
 * e is vertex rows 2e (the grid's vertices along edge e, in the edge's
 * order) and 2e + 1 (their polyline points); its quads are quad row 2e.
 * This makes strip `edge`, settled at `level`: the polyline once, then
 * its points at the edge's n grid steps. */
void reyes_dice_strip(__global const struct reyes_params *p, const float3 base[16], const struct reyes_subpatch *sp,
                      __local struct reyes_dice_scratch *s, int edge, uint level)
{
    int n = (int)p->grid, side = n - 1;
    struct reyes_polyline polyline = reyes_edge_polyline(base, sp, edge, level, (uint)side);
    int along_u;
    float fixed, a, b;
    reyes_edge_line(sp, edge, &along_u, &fixed, &a, &b);
    for (int step = 0; step < n; ++step) {
        int gi = along_u ? step : (edge == REYES_EDGE_U1 ? side : 0);
        int gj = along_u ? (edge == REYES_EDGE_V1 ? side : 0) : step;
        struct reyes_vertex on_polyline;
        reyes_vertex_place(p, reyes_strip_point(&polyline, step), &on_polyline);
        on_polyline.rgba = s->grid.rgba[gj * n + gi];
        reyes_grid_copy_vertex(&s->grid, gj * n + gi, &s->strips, 2 * edge * n + step);
        reyes_grid_store(p, &s->strips, (2 * edge + 1) * n + step, &on_polyline);
    }
}

/* A row has at most this many blocks of REYES_LANES vertices (32
 * vertices, REYES_MAX_GRID). */
#define REYES_DICE_ROW_BLOCKS 2

/* The parameters u of vertices i0 .. i0 + REYES_LANES - 1 of a row n
 * vertices wide, at u0 .. u1 across the grid, and their Bernstein weights
 * (bu) and derivatives (du): the same for every row. */
REYES_INLINE reyes_lanes reyes_dice_column_weights(float u0, float u1, int i0, int n, reyes_lanes bu[4],
                                                   reyes_lanes du[4])
{
    const reyes_lane_mask lane = (reyes_lane_mask)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    reyes_lane_mask i = i0 + lane;
    float last = (float)(n - 1);
    reyes_lanes tu = reyes_convert_lanes(i) / last;
    /* mix(a, b, 1) == b exactly, so shared patch edges get equal u. */
    reyes_lanes u = u0 * (1.0f - tu) + u1 * tu;
    reyes_bernstein_lanes(u, bu);
    reyes_bernstein_deriv_lanes(u, du);
    return u;
}

/* Vertices i0 .. i0 + REYES_LANES - 1 of row j (at v) of an undisplaced
 * grid n vertices wide into g, at parameters u (and their weights bu, du:
 * reyes_dice_column_weights), from the row's curves (the same for the
 * whole row, so scalars), as reyes_dice_place_lanes: the same arithmetic
 * as reyes_row_point_lanes and reyes_row_normal_lanes, so the same bits.
 * The lanes past the row write into the next row (made after this one) or
 * the lattice's padding. */
REYES_INLINE reyes_lane_mask reyes_dice_lanes(__global const struct reyes_params *p,
                                              const struct reyes_row_curves_one *rc, reyes_lanes u,
                                              const reyes_lanes bu[4], const reyes_lanes du[4],
                                              const struct reyes_lighting *light, const struct reyes_subpatch *sp,
                                              float v, uint base, __local struct reyes_grid *g, int j, int i0, int n,
                                              int shade)
{
    reyes_lanes x[3], normal[3], tu[3], tv[3];
    for (int d = 0; d < 3; ++d) {
        x[d] = reyes_curve_at_one(bu, rc->q[d]);
        tu[d] = reyes_curve_at_one(du, rc->q[d]);
        tv[d] = reyes_curve_at_one(bu, rc->qv[d]);
    }
    reyes_cross_lanes(tu, tv, normal);
    reyes_lane_mask collapsed = p->sample_shading ? reyes_collapsed_lanes(tu, tv, normal) : (reyes_lane_mask)0;
    struct reyes_vertex_lanes out;
    reyes_lane_mask degenerate = reyes_dice_place_lanes(p, light, x, normal, collapsed, u, (reyes_lanes)v, sp, base,
                                                        shade, &out);
    int first = j * n + i0;
    reyes_vstore_lanes(out.x, 0, g->x + first);
    reyes_vstore_lanes(out.y, 0, g->y + first);
    reyes_vstore_lanes(out.z, 0, g->z + first);
#ifdef REYES_VERTEX_MOTION
    reyes_vstore_lanes(out.motion[0], 0, g->mx + first);
    reyes_vstore_lanes(out.motion[1], 0, g->my + first);
    reyes_vstore_lanes(out.motion[2], 0, g->mw + first);
#endif
    reyes_vstore_lanes(out.rgba, 0, g->rgba + first);
    return degenerate;
}

/* The visible quads among the REYES_LANES slots from `first` of lattice g, as
 * a count: vector loads of the corners (the lattice's padding covers the
 * last slots' reads) and the tests of reyes_sharp_visible lane by lane. */
REYES_INLINE uint reyes_dice_visible_lanes(__global const struct reyes_params *p, __local const struct reyes_grid *g,
                                           int first)
{
    const reyes_lane_mask lane = (reyes_lane_mask)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    int c = (int)g->columns;
    reyes_lane_mask k = first + lane;
    reyes_lane_mask row = reyes_lattice_row_lanes(k, c);
    reyes_lane_mask has = (row + 1 < (int)g->rows) & (k - row * c != c - 1)
                          & (convert_int16((reyes_lane_uint)g->quad_rows >> reyes_convert_lane_uint(row)) & 1) != 0;
    const int corner[4] = { 0, 1, c + 1, c };
    reyes_lanes lo_x = (reyes_lanes)INFINITY, lo_y = lo_x, hi_x = -lo_x, hi_y = -lo_x;
    reyes_lane_mask front = (reyes_lane_mask)(-1);
    for (int i = 0; i < 4; ++i) {
        reyes_lanes x = reyes_vload_lanes(0, g->x + first + corner[i]), y = reyes_vload_lanes(0, g->y + first + corner[i]);
        reyes_lanes z = reyes_vload_lanes(0, g->z + first + corner[i]);
        lo_x = fmin(lo_x, x);
        lo_y = fmin(lo_y, y);
        hi_x = fmax(hi_x, x);
        hi_y = fmax(hi_y, y);
        front &= z > p->near_w;
    }
    reyes_lane_mask visible = has & front & (hi_x >= p->tile_x0) & (hi_y >= p->tile_y0) & (lo_x <= p->tile_x1)
                              & (lo_y <= p->tile_y1);
    return (uint)reyes_sum16(visible & 1);
}

/* Visible quads of lattice g, REYES_LANES slots at a time. */
uint reyes_dice_count(__global const struct reyes_params *p, __local const struct reyes_grid *g)
{
    int slots = (int)(g->rows - 1u) * (int)g->columns;
    uint visible = 0;
    if (p->blur) {
        for (int k = 0; k < slots; ++k)
            visible += reyes_grid_visible(p, g, k);
    } else {
        for (int first = 0; first < slots; first += REYES_LANES)
            visible += reyes_dice_visible_lanes(p, g, first);
    }
    return visible;
}

/* The base colour dice shades a grid of columns x rows vertices with: its
 * patch's, or with show_grid_sizes a false colour by the micropolygons'
 * count, from blue (1) through green to red ((grid - 1) squared). */
uint reyes_dice_base_color(__global const struct reyes_params *p, uint patch_color, int columns, int rows)
{
    if (!p->show_grid_sizes)
        return patch_color;
    float most = (float)((p->grid - 1u) * (p->grid - 1u));
    float t = most > 1.0f ? ((float)((columns - 1) * (rows - 1)) - 1.0f) / (most - 1.0f) : 1.0f;
    float3 c = t < 0.5f ? mix((float3)(0.15f, 0.3f, 1.0f), (float3)(0.2f, 0.9f, 0.3f), 2.0f * t)
                        : mix((float3)(0.2f, 0.9f, 0.3f), (float3)(1.0f, 0.2f, 0.1f), 2.0f * t - 1.0f);
    return reyes_pack_rgba(c);
}

/* Re-dice the boundary of an undisplaced lattice along its edges with
 * fewer segments, REYES_LANES slots at a time: the row curves are made
 * per lane at each slot's v, so every vertex gets the bits of the
 * lattice row (or the stitch's reyes_grid_vertex) that puts a vertex at
 * the same (u,v). */
void reyes_dice_edges(perma_ctx *ctx, __local const struct reyes_subpatch *item, const struct reyes_hull *h,
                      const struct reyes_lighting *light, uint base, __local struct reyes_grid *g, int shade)
{
    __global const struct reyes_params *p = ctx->buf.params;
    struct reyes_subpatch sp = *item;
    int columns = (int)g->columns, rows = (int)g->rows;
    for (int edge = 0; edge < 4; ++edge) {
        int along_u = edge == REYES_EDGE_V0 || edge == REYES_EDGE_V1;
        int n = (along_u ? columns : rows) - 1, c = reyes_edge_count(&sp, edge);
        if (c >= n)
            continue;
        float fixed = edge == REYES_EDGE_V0 ? sp.v0 : edge == REYES_EDGE_V1 ? sp.v1
                      : edge == REYES_EDGE_U0 ? sp.u0 : sp.u1;
        float a = along_u ? sp.u0 : sp.v0, b = along_u ? sp.u1 : sp.v1;
        for (int i0 = 0; i0 <= n; i0 += REYES_LANES) {
            float along[REYES_LANES];
            for (int k = 0; k < REYES_LANES; ++k) {
                float t = (float)reyes_edge_step(min(i0 + k, n), c, n) / (float)c;
                along[k] = a * (1.0f - t) + b * t; /* as reyes_grid_uv_of */
            }
            reyes_lanes s = reyes_vload_lanes(0, along);
            struct reyes_row_curves_lanes rc;
            reyes_row_curves_lanes(h, along_u ? (reyes_lanes)fixed : s, &rc);
            struct reyes_vertex_lanes v;
            reyes_lane_mask degenerate = reyes_dice_vertex_lanes(p, &rc, light, along_u ? s : (reyes_lanes)fixed,
                                                                 along_u ? (reyes_lanes)fixed : s, &sp, base, shade,
                                                                 &v);
            struct reyes_subpatch edge_sp = reyes_edge_subpatch(p, &sp, edge);
            float3 cp[16];
            int fix = shade && !p->sample_shading && any(degenerate);
            if (fix)
                reyes_load_patch(ctx->buf.patches, sp.patch, cp);
            for (int k = 0; k < REYES_LANES && i0 + k <= n; ++k) {
                int slot = reyes_edge_slot(edge, i0 + k, columns, rows);
                g->x[slot] = ((float *)&v.x)[k];
                g->y[slot] = ((float *)&v.y)[k];
                g->z[slot] = ((float *)&v.z)[k];
                g->rgba[slot] = ((uint *)&v.rgba)[k];
#ifdef REYES_VERTEX_MOTION
                g->mx[slot] = ((float *)&v.motion[0])[k];
                g->my[slot] = ((float *)&v.motion[1])[k];
                g->mw[slot] = ((float *)&v.motion[2])[k];
#endif
                if (fix && ((int *)&degenerate)[k]) {
                    int2 ij = reyes_edge_vertex((uint)edge, reyes_edge_step(i0 + k, c, n),
                                                reyes_dice_size(p, edge_sp.dice_size));
                    g->rgba[slot] = reyes_grid_vertex_color(p, cp, &edge_sp, base, ij.x, ij.y);
                }
            }
        }
    }
}

/* The vertices of an undisplaced grid, row by row (the row's curves made
 * once) and REYES_LANES at a time, and the poles' colours. */
void reyes_dice_plain(perma_ctx *ctx, __local const struct reyes_subpatch *item, __local struct reyes_grid *g,
                      int shade)
{
    __global const struct reyes_params *p = ctx->buf.params;
    int n = (int)g->columns, rows = (int)g->rows;
    struct reyes_hull h;
    reyes_load_hull(ctx->buf.patches, item->patch, &h);
    struct reyes_lighting light = reyes_lighting_of(p);
    uint base = reyes_dice_base_color(p, ctx->buf.colors[item->patch], n, rows);
    struct reyes_subpatch item_sp = *item;
    reyes_grid_shading(p, g, &item_sp, base, REYES_SHADE_SURFACE);
    float u0 = item->u0, v0 = item->v0, u1 = item->u1, v1 = item->v1;
    reyes_lanes us[REYES_DICE_ROW_BLOCKS], bu[REYES_DICE_ROW_BLOCKS][4], du[REYES_DICE_ROW_BLOCKS][4];
    for (int b = 0; b * REYES_LANES < n; ++b)
        us[b] = reyes_dice_column_weights(u0, u1, b * REYES_LANES, n, bu[b], du[b]);
    float last = (float)(rows - 1);
    for (int j = 0; j < rows; ++j) {
        float tv = (float)j / last;
        float v = v0 * (1.0f - tv) + v1 * tv; /* as reyes_grid_uv_of */
        struct reyes_row_curves_one rc;
        reyes_row_curves_one(&h, v, &rc);
        for (int b = 0, i0 = 0; i0 < n; ++b, i0 += REYES_LANES) {
            reyes_lane_mask degenerate = reyes_dice_lanes(p, &rc, us[b], bu[b], du[b], &light, &item_sp, v, base, g,
                                                          j, i0, n, shade);
            if (shade && !p->sample_shading && reyes_any16(degenerate)) {
                struct reyes_subpatch sp = *item;
                float3 cp[16];
                reyes_load_patch(ctx->buf.patches, sp.patch, cp);
                for (int k = 0; k < REYES_LANES && i0 + k < n; ++k)
                    if (((int *)&degenerate)[k])
                        g->rgba[j * n + i0 + k] = reyes_grid_vertex_color(p, cp, &sp, base, i0 + k, j);
            }
        }
    }
    if (p->polyline)
        reyes_polyline_edges(p, &item_sp, &h, &light, base, g, shade);
    else if (p->shading_rate > 0.0f)
        reyes_dice_edges(ctx, item, &h, &light, base, g, shade);
}

/* The vertices of a displaced grid (scalar). */
void reyes_dice_displaced(perma_ctx *ctx, __local const struct reyes_subpatch *item,
                          __local struct reyes_dice_scratch *s, int shade)
{
    __global const struct reyes_params *p = ctx->buf.params;
    struct reyes_displacement d = { p, ctx->buf.displacement_map };
    int n = (int)s->grid.columns, rows = (int)s->grid.rows;
    struct reyes_subpatch sp = *item;
    float3 cp[16];
    reyes_load_patch(ctx->buf.patches, sp.patch, cp);
    uint base = reyes_dice_base_color(p, ctx->buf.colors[sp.patch], n, rows);
    reyes_grid_shading(p, &s->grid, &sp, base, REYES_SHADE_NORMALS);
    for (int v = 0; v < n * rows; ++v) {
        struct reyes_vertex vertex = reyes_grid_vertex(&d, cp, &sp, base, v % n, v / n, shade);
        reyes_grid_store(p, &s->grid, v, &vertex);
    }
    /* Edges with fewer segments, as reyes_dice_edges. */
    for (int edge = 0; edge < 4 && p->shading_rate > 0.0f; ++edge) {
        int along = (edge == REYES_EDGE_V0 || edge == REYES_EDGE_V1 ? n : rows) - 1, c = reyes_edge_count(&sp, edge);
        struct reyes_subpatch edge_sp = reyes_edge_subpatch(p, &sp, edge);
        int2 size = reyes_dice_size(p, edge_sp.dice_size);
        for (int i = 0; i <= along && c < along; ++i) {
            int2 ij = reyes_edge_vertex((uint)edge, reyes_edge_step(i, c, along), size);
            struct reyes_vertex vertex = reyes_grid_vertex(&d, cp, &edge_sp, base, ij.x, ij.y, shade);
            reyes_grid_store(p, &s->grid, reyes_edge_slot(edge, i, n, rows), &vertex);
        }
    }
}

void reyes_dice(perma_ctx *ctx, __local const struct reyes_subpatch *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    __global uint *counters = ctx->buf.counters;
    __local struct reyes_dice_scratch *s = (__local struct reyes_dice_scratch *)ctx->scratch;
    int n = (int)p->grid;
    int full = p->stages == REYES_STAGES_ALL;
    atomic_inc(&counters[REYES_COUNT_GRIDS]);
    if (p->stages == REYES_STAGES_SUBDIVIDE)
        return;
    struct reyes_raster_target target = { p, ctx->buf.samples, counters, ctx->buf.blur_tuples, ctx->buf.patches };
    if (p->occlusion_cull) {
        struct reyes_subpatch sp = *item;
        if (reyes_grid_occluded(p, ctx->buf.patches, ctx->buf.samples, &sp)) {
            atomic_inc(&counters[REYES_COUNT_OCCLUDED]);
            /* Its fillers close its neighbours' cracks and may reach
             * past its hull. */
            if (p->polyline && (sp.edge_levels & REYES_POLYLINE_HAS_FILLERS)) {
                int2 size = reyes_dice_size(p, sp.dice_size);
                uint base = reyes_dice_base_color(p, ctx->buf.colors[sp.patch], size.x, size.y);
                reyes_polyline_fillers(&target, &sp, ctx->buf.patches, base, &s->strips, 1, 0);
            }
            return;
        }
    }
    int2 size = reyes_dice_size(p, item->dice_size); /* n x n without a shading rate */
    s->grid.columns = (uint)size.x;
    s->grid.rows = (uint)size.y;
    s->grid.quad_rows = (1u << (size.y - 1)) - 1u;
    s->grid.counted = full ? 1u : 0u;
    if (p->displace_mode == REYES_DISPLACE_NONE)
        reyes_dice_plain(ctx, item, &s->grid, full);
    else
        reyes_dice_displaced(ctx, item, s, full);
    if (p->polyline && (item->edge_levels & REYES_POLYLINE_HAS_FILLERS)) {
        struct reyes_subpatch sp = *item;
        reyes_polyline_fillers(&target, &sp, ctx->buf.patches, s->grid.base, &s->strips, full, 1);
    }
    if (full) {
        /* Rasterized where it lies, in __local scratch (no 4 KB item
         * through a queue); reyes_rasterize counts the visible quads: it
         * tests each one anyway (reyes_quad_setup_lanes), so the grid is
         * not tested twice. */
        reyes_rasterize(&target, &s->grid);
    } else {
        uint quads = reyes_dice_count(p, &s->grid);
        if (quads > 0u)
            atomic_add(&counters[REYES_COUNT_MICROPOLYGONS], quads);
    }
    if (!p->wedges)
        return;
    s->strips.columns = (uint)n;
    s->strips.rows = 8u;
    s->strips.counted = 0u; /* fillers, counted here */
    struct reyes_subpatch strip_sp = *item;
    reyes_grid_shading(p, &s->strips, &strip_sp, s->grid.base, REYES_SHADE_VERTICES);
    struct reyes_subpatch sp = *item;
    float3 base[16];
    reyes_load_patch(ctx->buf.patches, sp.patch, base);
    uint rows = 0;
    for (int edge = 0; edge < 4; ++edge) {
        uint level = (sp.edge_levels >> (8 * edge)) & 0xffu;
        if (level == REYES_EDGE_UNSETTLED)
            continue;
        reyes_dice_strip(p, base, &sp, s, edge, level);
        rows |= 1u << (2 * edge);
    }
    s->strips.quad_rows = rows;
    uint strip_quads = reyes_dice_count(p, &s->strips);
    if (strip_quads > 0u) {
        atomic_add(&counters[REYES_COUNT_FILLERS], 2u * strip_quads); /* two triangles each */
        if (full)
            reyes_rasterize(&target, &s->strips);
    }
}
