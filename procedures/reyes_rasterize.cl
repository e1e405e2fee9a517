/*
 * rasterize: one diced grid (or a sub-patch's wedge strips) per item,
 * struct reyes_grid of reyes_grid.cl, sampled cooperatively by the item's
 * REYES_ITEM_THREADS work-items: in each pass every work-item takes one
 * quad (two triangles).  Every sample in the quad's pixel box is tested
 * against both triangles; a covered sample stores (depth, color) with a
 * 64-bit atomic min, so the nearest surface wins whatever order work-items
 * and work-groups write in, and equal depths break ties by color.  Edges
 * are inclusive: a sample on an edge shared by two triangles may be
 * written twice, which the min makes harmless, and none is lost.
 *
 * A sharp quad whose pixel box is at most 2 x 2 pixels (nearly all of
 * them with the default bound and grid) takes the fast path: per sample
 * index s, every work-item computes the values its quad writes at sample
 * s of the four pixels of that box (straight-line code PoCL turns into
 * SIMD code across the work-items), then, after a barrier, merges them
 * into the sample buffer.  The barriers only split the work-items' loops
 * that PoCL builds; the trip counts are the same in every work-item.
 * Larger quads and blurred ones take the general loops afterwards.  Every
 * path tests the same samples of a quad with the same arithmetic.
 */

/* Which triangles of a sharp quad cover sample s of the (up to) four
 * pixels of its box (x0, y0, x1, y1): bit k for triangle 0 and bit 4 + k
 * for triangle 1 at pixel (x0 + k % 2, y0 + k / 2), none for a pixel
 * outside the box.  The coverage test alone: the values of the few
 * covered samples are computed afterwards. */
REYES_INLINE uint reyes_quad_coverage(const struct reyes_triangle t[2], int x0, int y0, int x1, int y1, uint s,
                                      uint columns, uint rows)
{
    uint covered = 0;
    for (int k = 0; k < 4; ++k) {
        int px = x0 + (k & 1), py = y0 + (k >> 1);
        float x, y;
        reyes_sample_xy((uint)px, (uint)py, s, columns, rows, &x, &y);
        uint in_box = px <= x1 && py <= y1;
        covered |= (in_box && reyes_triangle_covers(x, y, &t[0])) << k;
        covered |= (in_box && reyes_triangle_covers(x, y, &t[1])) << (4 + k);
    }
    return covered;
}

/* Write sample s of the pixels that reyes_quad_coverage found covered. */
void reyes_quad_write(__global const struct reyes_params *p, __global ulong *samples, const struct reyes_quad *q,
                      const struct reyes_triangle t[2], int x0, int y0, uint covered, uint s, uint columns,
                      uint rows)
{
    uint tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0;
    uint tile_width = (uint)p->tile_x1 - tile_x, spp = p->spp;
    for (int k = 0; k < 4; ++k) {
        if (!((covered >> k) & 0x11u))
            continue;
        uint px = (uint)(x0 + (k & 1)), py = (uint)(y0 + (k >> 1));
        float x, y;
        reyes_sample_xy(px, py, s, columns, rows, &x, &y);
        ulong first = (covered >> k) & 1u ? reyes_triangle_sample(x, y, q, &t[0]) : REYES_EMPTY_SAMPLE;
        ulong second = (covered >> (4 + k)) & 1u ? reyes_triangle_sample(x, y, q, &t[1]) : REYES_EMPTY_SAMPLE;
        reyes_sample_merge(samples, ((py - tile_y) * tile_width + (px - tile_x)) * spp + s, min(first, second));
    }
}

/* Blurred items: each visible quad with the configured algorithm. */
void reyes_rasterize_blurred_grid(perma_ctx *ctx, __local const struct reyes_grid *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    for (int k = (int)ctx->thread; ctx->active && k < REYES_GRID_SLOTS; k += REYES_ITEM_THREADS) {
        if (!reyes_grid_visible(p, item, k))
            continue;
        struct reyes_moving_quad m = reyes_grid_moving(p, item, k);
        reyes_rasterize_blurred(p, ctx->buf.blur_tuples, ctx->buf.samples, &m, 2);
    }
}

/* Cooperative: every work-item of the group calls it. */
void reyes_rasterize(perma_ctx *ctx, __local const struct reyes_grid *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    if (p->blur) {
        reyes_rasterize_blurred_grid(ctx, item);
        return;
    }
    __global ulong *samples = ctx->buf.samples;
    const int threads = REYES_ITEM_THREADS;
    const int passes = (REYES_GRID_SLOTS + threads - 1) / threads;
    const uint spp = p->spp, columns = reyes_sample_columns(spp), rows = (spp + columns - 1u) / columns;
    for (int pass = 0; pass < passes; ++pass) {
        int k = pass * threads + (int)ctx->thread;
        int exists = ctx->active && k < REYES_GRID_SLOTS && reyes_grid_has_quad(item, k);
        struct reyes_quad q = reyes_grid_quad_at(item, exists ? k : 0, exists ? (int)item->columns : 0);
        int live = exists && reyes_sharp_visible(p, &q);
        float2 lo, hi;
        reyes_quad_box(&q, &lo, &hi);
        int4 r = (int4)(0, 0, -1, -1);
        live = live && reyes_tile_pixels(p, lo, hi, &r);
        int fast = live && r.z - r.x < 2 && r.w - r.y < 2;
        const struct reyes_triangle t[2] = { reyes_triangle_setup(&q, 0, 1, 2), reyes_triangle_setup(&q, 0, 2, 3) };
        int x0 = r.x, y0 = r.y, x1 = fast ? r.z : -1, y1 = r.w;
        for (uint s = 0; s < spp; ++s) {
            barrier(CLK_LOCAL_MEM_FENCE);
            uint covered = reyes_quad_coverage(t, x0, y0, x1, y1, s, columns, rows);
            barrier(CLK_LOCAL_MEM_FENCE);
            if (covered)
                reyes_quad_write(p, samples, &q, t, x0, y0, covered, s, columns, rows);
        }
        if (live && !fast)
            reyes_sample_box(p, samples, lo, hi, &q, t, 2);
        barrier(CLK_LOCAL_MEM_FENCE);
    }
}
