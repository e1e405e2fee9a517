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
    if (p->blur) {
        reyes_rasterize_moving(ctx, item);
        return;
    }
#ifdef REYES_VERTEX_MOTION
    struct reyes_quad q = item->quad;
#else
    struct reyes_quad q = *item;
#endif
    float2 lo = (float2)(fmin(fmin(q.x[0], q.x[1]), fmin(q.x[2], q.x[3])),
                         fmin(fmin(q.y[0], q.y[1]), fmin(q.y[2], q.y[3])));
    float2 hi = (float2)(fmax(fmax(q.x[0], q.x[1]), fmax(q.x[2], q.x[3])),
                         fmax(fmax(q.y[0], q.y[1]), fmax(q.y[2], q.y[3])));
    const struct reyes_triangle triangles[2] = { reyes_triangle_setup(&q, 0, 1, 2),
                                                 reyes_triangle_setup(&q, 0, 2, 3) };
    reyes_sample_box(p, ctx->buf.samples, lo, hi, &q, triangles, 2);
}
