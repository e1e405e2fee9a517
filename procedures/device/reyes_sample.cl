/*
 * Sampling helpers shared by rasterize and stitch: jittered sample
 * positions, canonical edge functions and the per-sample atomic min of
 * (depth, color).
 */

/* Integer hash (lowbias32), for deterministic jitter: reyes_hash, and the
 * same steps lane by lane for rasterize's vectors (reyes_hash8,
 * reyes_hash16). */
#define REYES_DEFINE_HASH(name, type)                                          \
    REYES_INLINE type name(type x)                                             \
    {                                                                          \
        x ^= x >> 16;                                                          \
        x *= 0x7feb352du;                                                      \
        x ^= x >> 15;                                                          \
        x *= 0x846ca68bu;                                                      \
        x ^= x >> 16;                                                          \
        return x;                                                              \
    }
REYES_DEFINE_HASH(reyes_hash, uint)
REYES_DEFINE_HASH(reyes_hash8, uint8)
REYES_DEFINE_HASH(reyes_hash16, uint16)

/* Columns of the stratification lattice of spp samples per pixel. */
REYES_INLINE uint reyes_sample_columns(uint spp)
{
    return (uint)ceil(sqrt((float)spp));
}

/* Jittered sample position inside pixel (px, py): stratified on a
 * columns x rows lattice (reyes_sample_columns, rows = ceil(spp /
 * columns)) with a hashed offset in each cell.  Callers that test many
 * samples compute the lattice once.  (rasterize computes the same in SIMD
 * lanes: reyes_quad_pixels, reyes_small_quads.) */
REYES_INLINE void reyes_sample_xy(uint px, uint py, uint s, uint columns, uint rows, float *x, float *y)
{
    uint h = reyes_hash(px * 0x9e3779b9u ^ reyes_hash(py * 0x85ebca6bu ^ reyes_hash(s)));
    float jx = (float)(h & 0xffffu) * (1.0f / 65536.0f);
    float jy = (float)(h >> 16) * (1.0f / 65536.0f);
    *x = (float)px + ((float)(s % columns) + jx) / (float)columns;
    *y = (float)py + ((float)(s / columns) + jy) / (float)rows;
}

REYES_INLINE float2 reyes_sample_position_on(uint px, uint py, uint s, uint columns, uint rows)
{
    float x, y;
    reyes_sample_xy(px, py, s, columns, rows, &x, &y);
    return (float2)(x, y);
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
    float lo_x, lo_y, hi_x, hi_y;
    int swap;
};

REYES_INLINE struct reyes_edge_setup reyes_edge_order(float ax, float ay, float bx, float by)
{
    struct reyes_edge_setup e;
    e.swap = ax > bx || (ax == bx && ay > by);
    e.lo_x = e.swap ? bx : ax;
    e.lo_y = e.swap ? by : ay;
    e.hi_x = e.swap ? ax : bx;
    e.hi_y = e.swap ? ay : by;
    return e;
}

REYES_INLINE float reyes_edge_at(const struct reyes_edge_setup *e, float px, float py)
{
    float v = (e->hi_x - e->lo_x) * (py - e->lo_y) - (e->hi_y - e->lo_y) * (px - e->lo_x);
    return e->swap ? -v : v;
}

/* Triangle (a,b,c) of a quad, set up once for all the samples it is
 * tested against: its edges (b,c), (c,a), (a,b) and signed area. */
struct reyes_triangle {
    struct reyes_edge_setup edge[3];
    float area;
    int a, b, c;
};

REYES_INLINE struct reyes_triangle reyes_triangle_setup(const struct reyes_quad *q, int a, int b, int c)
{
    struct reyes_triangle t;
    t.edge[0] = reyes_edge_order(q->x[b], q->y[b], q->x[c], q->y[c]);
    t.edge[1] = reyes_edge_order(q->x[c], q->y[c], q->x[a], q->y[a]);
    t.edge[2] = reyes_edge_order(q->x[a], q->y[a], q->x[b], q->y[b]);
    t.area = reyes_edge_at(&t.edge[2], q->x[c], q->y[c]);
    t.a = a;
    t.b = b;
    t.c = c;
    return t;
}

/* Whether (x, y) is inside the triangle (edges inclusive; never for a
 * triangle without area), as reyes_triangle_sample decides. */
REYES_INLINE int reyes_triangle_covers(float x, float y, const struct reyes_triangle *t)
{
    float area = t->area;
    float wa = reyes_edge_at(&t->edge[0], x, y), wb = reyes_edge_at(&t->edge[1], x, y);
    float wc = reyes_edge_at(&t->edge[2], x, y);
    int inside = area > 0.0f ? (wa >= 0.0f && wb >= 0.0f && wc >= 0.0f)
                             : (wa <= 0.0f && wb <= 0.0f && wc <= 0.0f);
    return inside && area != 0.0f;
}

/* The depth at barycentric weights (ba, bb, bc) of corners at depths za,
 * zb, zc: never below the least of them (nor 0).  Rounding makes the
 * weights sum to a little less than 1 on thin triangles; occlusion
 * culling (reyes_occlusion.cl) relies on a surface's depth being at
 * least its control hull's nearest w, less the rounding of its vertices. */
#define REYES_DEFINE_INTERPOLATED_DEPTH(name, type)                                  \
    REYES_INLINE type name(type ba, type bb, type bc, type za, type zb, type zc)     \
    {                                                                                \
        return fmax(ba * za + bb * zb + bc * zc, fmax(fmin(fmin(za, zb), zc), 0.0f)); \
    }
REYES_DEFINE_INTERPOLATED_DEPTH(reyes_interpolated_depth, float)
REYES_DEFINE_INTERPOLATED_DEPTH(reyes_interpolated_depth8, float8)
REYES_DEFINE_INTERPOLATED_DEPTH(reyes_interpolated_depth16, float16)

/* An empty sample (the host clears the buffer to all ones). */
#define REYES_EMPTY_SAMPLE 0xfffffffffffffffful

/* The (depth, colour) that the triangle writes at (x, y): depth's bits
 * above the packed colour, so the nearest surface is the smallest value
 * (depth >= 0 orders like its bit pattern) and equal depths break ties by
 * colour; REYES_EMPTY_SAMPLE if the point is outside (edges are
 * inclusive) or the triangle has no area. */
REYES_INLINE ulong reyes_triangle_sample(float x, float y, const struct reyes_quad *q, const struct reyes_triangle *t)
{
    float area = t->area;
    float wa = reyes_edge_at(&t->edge[0], x, y), wb = reyes_edge_at(&t->edge[1], x, y);
    float wc = reyes_edge_at(&t->edge[2], x, y);
    int inside = area > 0.0f ? (wa >= 0.0f && wb >= 0.0f && wc >= 0.0f)
                             : (wa <= 0.0f && wb <= 0.0f && wc <= 0.0f);
    uint qa = q->rgba[t->a], qb = q->rgba[t->b], qc = q->rgba[t->c];
    float inv_area = 1.0f / area;
    float ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
    float depth = reyes_interpolated_depth(ba, bb, bc, q->z[t->a], q->z[t->b], q->z[t->c]);
    float ra = reyes_channel(qa, 0u), rb = reyes_channel(qb, 0u), rc = reyes_channel(qc, 0u);
    float ga = reyes_channel(qa, 8u), gb = reyes_channel(qb, 8u), gc = reyes_channel(qc, 8u);
    float la = reyes_channel(qa, 16u), lb = reyes_channel(qb, 16u), lc = reyes_channel(qc, 16u);
    uint rgba = reyes_pack_channels(ba * ra + bb * rb + bc * rc, ba * ga + bb * gb + bc * gc,
                                    ba * la + bb * lb + bc * lc);
    ulong packed = ((ulong)as_uint(depth) << 32) | (ulong)rgba;
    return inside && area != 0.0f ? packed : REYES_EMPTY_SAMPLE;
}

/* The depth bits (the high half) of a sample, read while other groups
 * may lower it: possibly stale, so never smaller than the sample's
 * current depth (values only ever decrease).  perma_load: a volatile
 * load (an atomic under the race check). */
REYES_INLINE uint reyes_sample_depth_bits(__global ulong *samples, uint index)
{
#ifdef __ENDIAN_LITTLE__
    const uint high = 1u;
#else
    const uint high = 0u;
#endif
    return perma_load((__global uint *)(samples + index) + high);
}

/* Keep the smaller of the sample's value and `value`.  A depth word that
 * is already below ours means the atomic would not change anything: most
 * hidden fragments skip it. */
REYES_INLINE void reyes_sample_merge(__global ulong *samples, uint index, ulong value)
{
    if ((uint)(value >> 32) <= reyes_sample_depth_bits(samples, index))
        atom_min(&samples[index], value);
}

/* The same with sample shading: the quad's rgba hold its vertices'
 * packed normals, and the sample is lit with base colour `base` and the
 * normal interpolated as reyes_triangle_sample interpolates colours. */
REYES_INLINE ulong reyes_triangle_sample_lit(__global const struct reyes_params *p, float x, float y,
                                            const struct reyes_quad *q, const struct reyes_triangle *t, uint base)
{
    float area = t->area;
    float wa = reyes_edge_at(&t->edge[0], x, y), wb = reyes_edge_at(&t->edge[1], x, y);
    float wc = reyes_edge_at(&t->edge[2], x, y);
    int inside = area > 0.0f ? (wa >= 0.0f && wb >= 0.0f && wc >= 0.0f)
                             : (wa <= 0.0f && wb <= 0.0f && wc <= 0.0f);
    if (!inside || area == 0.0f)
        return REYES_EMPTY_SAMPLE;
    float inv_area = 1.0f / area;
    float ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
    float depth = reyes_interpolated_depth(ba, bb, bc, q->z[t->a], q->z[t->b], q->z[t->c]);
    const int corner[3] = {t->a, t->b, t->c};
    const float weight[3] = {ba, bb, bc};
    float n[3] = {0.0f, 0.0f, 0.0f};
    for (int i = 0; i < 3; ++i) {
        float v[3];
        reyes_unpack_normal(q->rgba[corner[i]], &v[0], &v[1], &v[2]);
        for (int k = 0; k < 3; ++k)
            n[k] += weight[i] * v[k];
    }
    uint rgba = reyes_sample_light(p, n[0], n[1], n[2], x, y, base);
    return ((ulong)as_uint(depth) << 32) | (ulong)rgba;
}

/* Write the sample if p is inside the triangle. */
void reyes_sample_in_triangle(__global ulong *samples, uint index, float2 p, const struct reyes_quad *q,
                              const struct reyes_triangle *t)
{
    if (t->area == 0.0f)
        return;
    ulong packed = reyes_triangle_sample(p.x, p.y, q, t);
    if (packed != REYES_EMPTY_SAMPLE)
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
 * unblurred rasterization of crack-filling triangles; with sample
 * shading lit with base colour `base`. */
void reyes_sample_box(__global const struct reyes_params *p, __global ulong *samples, float2 lo, float2 hi,
                      const struct reyes_quad *q, const struct reyes_triangle *triangles, int count, uint base)
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
                for (int k = 0; k < count; ++k) {
                    if (!p->sample_shading) {
                        reyes_sample_in_triangle(samples, index, pos, q, &triangles[k]);
                        continue;
                    }
                    ulong packed = reyes_triangle_sample_lit(p, pos.x, pos.y, q, &triangles[k], base);
                    if (packed != REYES_EMPTY_SAMPLE)
                        atom_min(&samples[index], packed);
                }
            }
        }
    }
}
