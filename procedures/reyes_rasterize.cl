/*
 * rasterize: one diced grid (or a sub-patch's wedge strips) per item,
 * struct reyes_grid of reyes_grid.cl, its quads shared among the item's
 * REYES_ITEM_THREADS work-items (quad slot k is work-item k % threads's).
 * Every sample in a quad's pixel box is tested against both of its
 * triangles; a covered sample stores (depth, color) with a 64-bit atomic
 * min, so the nearest surface wins whatever order work-items and
 * work-groups write in, and equal depths break ties by color.  Edges are
 * inclusive: a sample on an edge shared by two triangles may be written
 * twice, which the min makes harmless, and none is lost.
 *
 * A sharp quad whose pixel box is at most 2 x 2 pixels (nearly all of
 * them with the default bound and grid) takes the fast path: four sample
 * indices of the four pixels at once, sixteen SIMD lanes (OpenCL vector
 * types, so the code is SIMD whatever the compiler does across
 * work-items), test the coverage of both triangles; the few covered
 * samples are then written one by one.  Larger quads and blurred ones
 * take the general loops.  Every path tests the same samples of a quad
 * with the same arithmetic.
 */

/* Lane l of the fast path: pixel (x0 + l / 4 % 2, y0 + l / 8) of the
 * footprint, sample s0 + l % 4. */
#define REYES_FOOTPRINT_DX ((int16)(0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 1, 1, 1, 1))
#define REYES_FOOTPRINT_DY ((int16)(0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1))
#define REYES_FOOTPRINT_DS ((uint16)(0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3))

REYES_INLINE uint16 reyes_hash_lanes(uint16 x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/* Edge function of a set-up edge at sixteen points, as reyes_edge_at. */
REYES_INLINE float16 reyes_edge_lanes(const struct reyes_edge_setup *e, float16 px, float16 py)
{
    float16 v = (e->hi_x - e->lo_x) * (py - e->lo_y) - (e->hi_y - e->lo_y) * (px - e->lo_x);
    return e->swap ? -v : v;
}

/* Lanes inside the triangle, as reyes_triangle_covers. */
REYES_INLINE int16 reyes_triangle_covers_lanes(const struct reyes_triangle *t, float16 x, float16 y)
{
    float area = t->area;
    float16 wa = reyes_edge_lanes(&t->edge[0], x, y), wb = reyes_edge_lanes(&t->edge[1], x, y);
    float16 wc = reyes_edge_lanes(&t->edge[2], x, y);
    int16 inside = area > 0.0f ? (wa >= 0.0f & wb >= 0.0f & wc >= 0.0f) : (wa <= 0.0f & wb <= 0.0f & wc <= 0.0f);
    return area != 0.0f ? inside : (int16)0;
}

/* Samples s0 .. s0 + 3 (those below spp) of the pixels of box (x0, y0,
 * x1, y1) of at most 2 x 2 pixels: coverage in sixteen lanes, then the
 * covered samples written one by one. */
void reyes_quad_footprint(__global const struct reyes_params *p, __global ulong *samples,
                          const struct reyes_quad *q, const struct reyes_triangle t[2], int4 r, uint s0,
                          uint columns, uint rows)
{
    uint spp = p->spp;
    int16 px = r.x + REYES_FOOTPRINT_DX, py = r.y + REYES_FOOTPRINT_DY;
    uint16 s = s0 + REYES_FOOTPRINT_DS;
    uint16 h = reyes_hash_lanes(as_uint16(px) * 0x9e3779b9u
                                ^ reyes_hash_lanes(as_uint16(py) * 0x85ebca6bu ^ reyes_hash_lanes(s)));
    float16 jx = convert_float16(h & 0xffffu) * (1.0f / 65536.0f);
    float16 jy = convert_float16(h >> 16) * (1.0f / 65536.0f);
    /* The lattice cell of each sample index (integer division per index,
     * not per lane). */
    float4 cell_x, cell_y;
    for (uint k = 0; k < 4u; ++k) {
        ((float *)&cell_x)[k] = (float)((s0 + k) % columns);
        ((float *)&cell_y)[k] = (float)((s0 + k) / columns);
    }
    float16 cx = (float16)(cell_x, cell_x, cell_x, cell_x), cy = (float16)(cell_y, cell_y, cell_y, cell_y);
    float16 x = convert_float16(px) + (cx + jx) / (float)columns;
    float16 y = convert_float16(py) + (cy + jy) / (float)rows;
    int16 valid = (s < spp) & (px <= r.z) & (py <= r.w);
    int16 first = reyes_triangle_covers_lanes(&t[0], x, y) & valid;
    int16 second = reyes_triangle_covers_lanes(&t[1], x, y) & valid;
    if (!any(first | second))
        return;
    uint tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0;
    uint tile_width = (uint)p->tile_x1 - tile_x;
    for (int l = 0; l < 16; ++l) {
        int a = ((int *)&first)[l], b = ((int *)&second)[l];
        if (!(a | b))
            continue;
        float sx = ((float *)&x)[l], sy = ((float *)&y)[l];
        ulong value = min(a ? reyes_triangle_sample(sx, sy, q, &t[0]) : REYES_EMPTY_SAMPLE,
                          b ? reyes_triangle_sample(sx, sy, q, &t[1]) : REYES_EMPTY_SAMPLE);
        uint pxl = (uint)((int *)&px)[l], pyl = (uint)((int *)&py)[l], sl = ((uint *)&s)[l];
        reyes_sample_merge(samples, ((pyl - tile_y) * tile_width + (pxl - tile_x)) * spp + sl, value);
    }
}

/* Blurred items: each visible quad with the configured algorithm. */
void reyes_rasterize_blurred_grid(perma_ctx *ctx, __local const struct reyes_grid *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    int slots = (int)(item->rows - 1u) * (int)item->columns;
    for (int k = (int)ctx->thread; k < slots; k += REYES_ITEM_THREADS) {
        if (!reyes_grid_visible(p, item, k))
            continue;
        struct reyes_moving_quad m = reyes_grid_moving(p, item, k);
        reyes_rasterize_blurred(p, ctx->buf.blur_tuples, ctx->buf.samples, &m, 2);
    }
}

/* Cooperative: every work-item of the group calls it (it has no
 * barrier; its threads_per_item is the group size). */
void reyes_rasterize(perma_ctx *ctx, __local const struct reyes_grid *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    if (!ctx->active)
        return;
    if (p->blur) {
        reyes_rasterize_blurred_grid(ctx, item);
        return;
    }
    __global ulong *samples = ctx->buf.samples;
    const uint spp = p->spp, columns = reyes_sample_columns(spp), rows = (spp + columns - 1u) / columns;
    int slots = (int)(item->rows - 1u) * (int)item->columns;
    for (int k = (int)ctx->thread; k < slots; k += REYES_ITEM_THREADS) {
        if (!reyes_grid_has_quad(item, k))
            continue;
        struct reyes_quad q = reyes_grid_quad(item, k);
        if (!reyes_sharp_visible(p, &q))
            continue;
        float2 lo, hi;
        reyes_quad_box(&q, &lo, &hi);
        int4 r;
        if (!reyes_tile_pixels(p, lo, hi, &r))
            continue;
        const struct reyes_triangle t[2] = { reyes_triangle_setup(&q, 0, 1, 2), reyes_triangle_setup(&q, 0, 2, 3) };
        if (r.z - r.x < 2 && r.w - r.y < 2) {
            for (uint s0 = 0; s0 < spp; s0 += 4u)
                reyes_quad_footprint(p, samples, &q, t, r, s0, columns, rows);
        } else {
            reyes_sample_box(p, samples, lo, hi, &q, t, 2);
        }
    }
}
