/*
 * rasterize: one micropolygon (two triangles) per item.  Every sample in
 * the quad's pixel box is tested against both triangles; a covered sample
 * stores (depth, color) with a 64-bit atomic min, so the nearest surface
 * wins whatever order work-groups write in, and equal depths break ties by
 * color.  Edges are inclusive: a sample on an edge shared by two triangles
 * may be written twice, which the min makes harmless, and none is lost.
 */

/* Integer hash (lowbias32), for deterministic jitter. */
uint reyes_hash(uint x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/* Jittered sample position inside pixel (px, py): stratified on a
 * columns x rows lattice with a hashed offset in each cell. */
float2 reyes_sample_position(uint px, uint py, uint s, uint spp)
{
    uint columns = (uint)ceil(sqrt((float)spp));
    uint rows = (spp + columns - 1u) / columns;
    uint h = reyes_hash(px * 0x9e3779b9u ^ reyes_hash(py * 0x85ebca6bu ^ reyes_hash(s)));
    float jx = (float)(h & 0xffffu) * (1.0f / 65536.0f);
    float jy = (float)(h >> 16) * (1.0f / 65536.0f);
    return (float2)((float)px + ((float)(s % columns) + jx) / (float)columns,
                    (float)py + ((float)(s / columns) + jy) / (float)rows);
}

/* Edge function of the directed edge a->b at p, computed with the two end
 * points in a fixed order so that edge(a,b,p) == -edge(b,a,p) exactly: a
 * sample on an edge shared by two triangles is inside at least one. */
float reyes_edge(float2 a, float2 b, float2 p)
{
    int swap = a.x > b.x || (a.x == b.x && a.y > b.y);
    float2 lo = swap ? b : a, hi = swap ? a : b;
    float e = (hi.x - lo.x) * (p.y - lo.y) - (hi.y - lo.y) * (p.x - lo.x);
    return swap ? -e : e;
}

/* Write the sample if p is inside triangle (a,b,c) of the quad. */
void reyes_sample_triangle(__global ulong *samples, uint index, float2 p,
                           const struct reyes_quad *q, int a, int b, int c)
{
    float2 pa = (float2)(q->x[a], q->y[a]);
    float2 pb = (float2)(q->x[b], q->y[b]);
    float2 pc = (float2)(q->x[c], q->y[c]);
    float area = reyes_edge(pa, pb, pc);
    if (area == 0.0f)
        return;
    float wa = reyes_edge(pb, pc, p), wb = reyes_edge(pc, pa, p), wc = reyes_edge(pa, pb, p);
    int inside = area > 0.0f ? (wa >= 0.0f && wb >= 0.0f && wc >= 0.0f)
                             : (wa <= 0.0f && wb <= 0.0f && wc <= 0.0f);
    if (!inside)
        return;
    float inv_area = 1.0f / area;
    float ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
    float depth = fmax(ba * q->z[a] + bb * q->z[b] + bc * q->z[c], 0.0f);
    float3 color = ba * reyes_unpack_rgb(q->rgba[a]) + bb * reyes_unpack_rgb(q->rgba[b])
                   + bc * reyes_unpack_rgb(q->rgba[c]);
    /* depth >= 0, so its bit pattern orders like the float. */
    ulong packed = ((ulong)as_uint(depth) << 32) | (ulong)reyes_pack_rgba(color);
    atom_min(&samples[index], packed);
}

void reyes_rasterize(perma_ctx *ctx, __local const struct reyes_quad *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    __global ulong *samples = ctx->buf.samples;
    struct reyes_quad q = *item;
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
    for (int py = y0; py <= y1; ++py) {
        for (int px = x0; px <= x1; ++px) {
            for (uint s = 0; s < spp; ++s) {
                float2 pos = reyes_sample_position((uint)px, (uint)py, s, spp);
                uint index = (((uint)py - tile_y) * tile_width + ((uint)px - tile_x)) * spp + s;
                reyes_sample_triangle(samples, index, pos, &q, 0, 1, 2);
                reyes_sample_triangle(samples, index, pos, &q, 0, 2, 3);
            }
        }
    }
}
