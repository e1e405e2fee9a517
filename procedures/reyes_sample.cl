/*
 * Sampling helpers shared by rasterize and stitch: jittered sample
 * positions, canonical edge functions and the per-sample atomic min of
 * (depth, color).
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
