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

/* Columns of the stratification lattice of spp samples per pixel. */
uint reyes_sample_columns(uint spp)
{
    return (uint)ceil(sqrt((float)spp));
}

/* Jittered sample position inside pixel (px, py): stratified on a
 * columns x rows lattice (reyes_sample_columns, rows = ceil(spp /
 * columns)) with a hashed offset in each cell.  Callers that test many
 * samples compute the lattice once. */
float2 reyes_sample_position_on(uint px, uint py, uint s, uint columns, uint rows)
{
    uint h = reyes_hash(px * 0x9e3779b9u ^ reyes_hash(py * 0x85ebca6bu ^ reyes_hash(s)));
    float jx = (float)(h & 0xffffu) * (1.0f / 65536.0f);
    float jy = (float)(h >> 16) * (1.0f / 65536.0f);
    return (float2)((float)px + ((float)(s % columns) + jx) / (float)columns,
                    (float)py + ((float)(s / columns) + jy) / (float)rows);
}

float2 reyes_sample_position(uint px, uint py, uint s, uint spp)
{
    uint columns = reyes_sample_columns(spp);
    return reyes_sample_position_on(px, py, s, columns, (spp + columns - 1u) / columns);
}

/* Edge function of the directed edge a->b at p, computed with the two end
 * points in a fixed order so that edge(a,b,p) == -edge(b,a,p) exactly: a
 * sample on an edge shared by two triangles is then inside exactly the same
 * way for both.  The order is decided once per edge (reyes_edge_order),
 * the function per sample (reyes_edge_at). */
struct reyes_edge_setup {
    float2 lo, hi;
    int swap;
};

struct reyes_edge_setup reyes_edge_order(float2 a, float2 b)
{
    struct reyes_edge_setup e;
    e.swap = a.x > b.x || (a.x == b.x && a.y > b.y);
    e.lo = e.swap ? b : a;
    e.hi = e.swap ? a : b;
    return e;
}

float reyes_edge_at(const struct reyes_edge_setup *e, float2 p)
{
    float v = (e->hi.x - e->lo.x) * (p.y - e->lo.y) - (e->hi.y - e->lo.y) * (p.x - e->lo.x);
    return e->swap ? -v : v;
}

float reyes_edge(float2 a, float2 b, float2 p)
{
    struct reyes_edge_setup e = reyes_edge_order(a, b);
    return reyes_edge_at(&e, p);
}

/* Triangle (a,b,c) of a quad, set up once for all the samples it is
 * tested against: its edges (b,c), (c,a), (a,b) and signed area. */
struct reyes_triangle {
    struct reyes_edge_setup edge[3];
    float area;
    int a, b, c;
};

struct reyes_triangle reyes_triangle_setup(const struct reyes_quad *q, int a, int b, int c)
{
    float2 pa = (float2)(q->x[a], q->y[a]);
    float2 pb = (float2)(q->x[b], q->y[b]);
    float2 pc = (float2)(q->x[c], q->y[c]);
    struct reyes_triangle t;
    t.edge[0] = reyes_edge_order(pb, pc);
    t.edge[1] = reyes_edge_order(pc, pa);
    t.edge[2] = reyes_edge_order(pa, pb);
    t.area = reyes_edge_at(&t.edge[2], pc);
    t.a = a;
    t.b = b;
    t.c = c;
    return t;
}

/* Write the sample if p is inside the triangle. */
void reyes_sample_in_triangle(__global ulong *samples, uint index, float2 p, const struct reyes_quad *q,
                              const struct reyes_triangle *t)
{
    float area = t->area;
    if (area == 0.0f)
        return;
    float wa = reyes_edge_at(&t->edge[0], p), wb = reyes_edge_at(&t->edge[1], p);
    float wc = reyes_edge_at(&t->edge[2], p);
    int inside = area > 0.0f ? (wa >= 0.0f && wb >= 0.0f && wc >= 0.0f)
                             : (wa <= 0.0f && wb <= 0.0f && wc <= 0.0f);
    if (!inside)
        return;
    int a = t->a, b = t->b, c = t->c;
    float inv_area = 1.0f / area;
    float ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
    float depth = fmax(ba * q->z[a] + bb * q->z[b] + bc * q->z[c], 0.0f);
    float3 color = ba * reyes_unpack_rgb(q->rgba[a]) + bb * reyes_unpack_rgb(q->rgba[b])
                   + bc * reyes_unpack_rgb(q->rgba[c]);
    /* depth >= 0, so its bit pattern orders like the float. */
    ulong packed = ((ulong)as_uint(depth) << 32) | (ulong)reyes_pack_rgba(color);
    atom_min(&samples[index], packed);
}

/* Write the sample if p is inside triangle (a,b,c) of the quad. */
void reyes_sample_triangle(__global ulong *samples, uint index, float2 p,
                           const struct reyes_quad *q, int a, int b, int c)
{
    struct reyes_triangle t = reyes_triangle_setup(q, a, b, c);
    reyes_sample_in_triangle(samples, index, p, q, &t);
}

/* Pixels (x0, y0)..(x1, y1) of screen box lo..hi inside the tile; 0 if
 * the box misses the tile.  Clamped in float first: the box may lie far
 * outside int range. */
int reyes_tile_pixels(__global const struct reyes_params *p, float2 lo, float2 hi, int4 *range)
{
    if (hi.x < p->tile_x0 || hi.y < p->tile_y0 || lo.x > p->tile_x1 || lo.y > p->tile_y1)
        return 0;
    *range = (int4)((int)floor(clamp(lo.x, p->tile_x0, p->tile_x1 - 1.0f)),
                    (int)floor(clamp(lo.y, p->tile_y0, p->tile_y1 - 1.0f)),
                    (int)floor(clamp(hi.x, p->tile_x0, p->tile_x1 - 1.0f)),
                    (int)floor(clamp(hi.y, p->tile_y0, p->tile_y1 - 1.0f)));
    return 1;
}

/* Test every sample of the pixels of screen box lo..hi inside the tile
 * against `count` triangles set up once (reyes_triangle_setup) — the
 * unblurred rasterization of micropolygons and crack-filling triangles. */
void reyes_sample_box(__global const struct reyes_params *p, __global ulong *samples, float2 lo, float2 hi,
                      const struct reyes_quad *q, const struct reyes_triangle *triangles, int count)
{
    int4 r;
    if (!reyes_tile_pixels(p, lo, hi, &r))
        return;
    uint tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0;
    uint tile_width = (uint)p->tile_x1 - tile_x, spp = p->spp;
    uint columns = reyes_sample_columns(spp), rows = (spp + columns - 1u) / columns;
    for (int py = r.y; py <= r.w; ++py) {
        for (int px = r.x; px <= r.z; ++px) {
            for (uint s = 0; s < spp; ++s) {
                float2 pos = reyes_sample_position_on((uint)px, (uint)py, s, columns, rows);
                uint index = (((uint)py - tile_y) * tile_width + ((uint)px - tile_x)) * spp + s;
                for (int k = 0; k < count; ++k)
                    reyes_sample_in_triangle(samples, index, pos, q, &triangles[k]);
            }
        }
    }
}
