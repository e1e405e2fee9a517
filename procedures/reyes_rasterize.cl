/*
 * rasterize: one micropolygon (two triangles) per item.  Every sample in
 * the quad's pixel box is tested against both triangles; a covered sample
 * stores (depth, color) with a 64-bit atomic min, so the nearest surface
 * wins whatever order work-groups write in, and equal depths break ties by
 * color.  Edges are inclusive: a sample on an edge shared by two triangles
 * may be written twice, which the min makes harmless, and none is lost.
 */

/* The item type (reyes_renderer.c): with per-vertex motion every quad
 * carries its vertices' motions. */
#ifdef REYES_VERTEX_MOTION
#define REYES_RASTER_ITEM struct reyes_moving_quad
#else
#define REYES_RASTER_ITEM struct reyes_quad
#endif

/* A blurred item: each vertex moves by its own motion, or by the
 * parameters' one motion when the items carry none. */
void reyes_rasterize_moving(perma_ctx *ctx, __local const REYES_RASTER_ITEM *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
#ifdef REYES_VERTEX_MOTION
    struct reyes_moving_quad m = *item;
#else
    struct reyes_quad q = *item;
    struct reyes_moving_quad m = reyes_moving_uniform(p, &q);
#endif
    reyes_rasterize_blurred(p, ctx->buf.blur_tuples, ctx->buf.samples, &m, 2);
}

void reyes_rasterize(perma_ctx *ctx, __local const REYES_RASTER_ITEM *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    __global ulong *samples = ctx->buf.samples;
    if (p->blur) {
        reyes_rasterize_moving(ctx, item);
        return;
    }
#ifdef REYES_VERTEX_MOTION
    struct reyes_quad q = item->quad;
#else
    struct reyes_quad q = *item;
#endif
    float min_x = fmin(fmin(q.x[0], q.x[1]), fmin(q.x[2], q.x[3]));
    float max_x = fmax(fmax(q.x[0], q.x[1]), fmax(q.x[2], q.x[3]));
    float min_y = fmin(fmin(q.y[0], q.y[1]), fmin(q.y[2], q.y[3]));
    float max_y = fmax(fmax(q.y[0], q.y[1]), fmax(q.y[2], q.y[3]));
    /* Clamp to the tile in float first: the box may lie far outside int
     * range.  Pixels are global; the sample buffer holds the tile's. */
    int x0 = (int)floor(clamp(min_x, p->tile_x0, p->tile_x1 - 1.0f));
    int x1 = (int)floor(clamp(max_x, p->tile_x0, p->tile_x1 - 1.0f));
    int y0 = (int)floor(clamp(min_y, p->tile_y0, p->tile_y1 - 1.0f));
    int y1 = (int)floor(clamp(max_y, p->tile_y0, p->tile_y1 - 1.0f));
    uint tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0;
    uint tile_width = (uint)p->tile_x1 - tile_x, spp = p->spp;
    uint columns = reyes_sample_columns(spp), rows = (spp + columns - 1u) / columns;
    struct reyes_triangle first = reyes_triangle_setup(&q, 0, 1, 2);
    struct reyes_triangle second = reyes_triangle_setup(&q, 0, 2, 3);
    for (int py = y0; py <= y1; ++py) {
        for (int px = x0; px <= x1; ++px) {
            for (uint s = 0; s < spp; ++s) {
                float2 pos = reyes_sample_position_on((uint)px, (uint)py, s, columns, rows);
                uint index = (((uint)py - tile_y) * tile_width + ((uint)px - tile_x)) * spp + s;
                reyes_sample_in_triangle(samples, index, pos, &q, &first);
                reyes_sample_in_triangle(samples, index, pos, &q, &second);
            }
        }
    }
}
