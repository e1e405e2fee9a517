/*
 * Sampling of sharp (unblurred) quads for reyes_rasterize
 * (reyes_rasterize.cl, which follows this file).
 *
 * Sharp quads are set up sixteen at a time in SIMD lanes (OpenCL vector
 * types, so the code is SIMD whatever the compiler does across
 * work-items).  A sample lies in its own stratum of the pixel (a cell of
 * the columns x rows lattice of reyes_sample_xy), so the strata that a
 * quad's screen box reaches are the only places its covered samples can
 * be: a micropolygon of the default bound and grid reaches two or three
 * of them across and down, where its pixel box holds up to sixteen
 * samples, and one of a shading rate of 1 (about a pixel) up to four.  The
 * quads whose box reaches at most 4 x 4 strata (nearly all) are sampled
 * side by side, one quad per lane, stepping through the strata; the few
 * larger ones one by one, four sample indices of both triangles per pixel
 * in eight lanes.  Every path tests the same samples of a quad with the
 * same arithmetic.
 */

/* Sixteen quads (slots first .. first + 15 of a lattice), set up in SIMD
 * lanes as reyes_triangle_setup and reyes_tile_pixels would one by one:
 * whether each is a visible quad on the tile, its pixel box and its
 * triangles (0,1,2) and (0,2,3) (edge e of a triangle: the lower end
 * point, the difference to the upper one and whether they were swapped;
 * the signed area). */
struct reyes_quad_lanes {
    int16 live;
    float16 box_lo_x, box_lo_y, box_hi_x, box_hi_y; /* screen box */
    int16 x0, y0, x1, y1;           /* pixel box on the tile */
    float16 lo_x[2][3], lo_y[2][3], dx[2][3], dy[2][3];
    int16 swap[2][3];
    float16 area[2];
};

REYES_INLINE void reyes_edge_order_lanes(float16 ax, float16 ay, float16 bx, float16 by, float16 *lo_x,
                                         float16 *lo_y, float16 *dx, float16 *dy, int16 *swap)
{
    *swap = (ax > bx) | ((ax == bx) & (ay > by));
    *lo_x = select(ax, bx, *swap);
    *lo_y = select(ay, by, *swap);
    *dx = select(bx, ax, *swap) - *lo_x;
    *dy = select(by, ay, *swap) - *lo_y;
}

REYES_INLINE float16 reyes_edge_value_lanes(float16 lo_x, float16 lo_y, float16 dx, float16 dy, int16 swap, float16 x,
                                            float16 y)
{
    float16 v = dx * (y - lo_y) - dy * (x - lo_x);
    return select(v, -v, swap);
}

REYES_INLINE struct reyes_quad_lanes reyes_quad_setup_lanes(__global const struct reyes_params *p,
                                                            __local const struct reyes_grid *g, int first, int slots)
{
    const int16 lane = (int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    int c = (int)g->columns;
    int16 k = first + lane;
    int16 row = reyes_lattice_row_lanes(k, c);
    int16 has = (k < slots) & (row + 1 < (int)g->rows) & (k - row * c != c - 1)
                & (convert_int16((uint16)g->quad_rows >> convert_uint16(row)) & 1) != 0;
    const int corner[4] = { 0, 1, c + 1, c };
    float16 x[4], y[4];
    int16 front = (int16)(-1);
    for (int i = 0; i < 4; ++i) {
        x[i] = vload16(0, g->x + first + corner[i]);
        y[i] = vload16(0, g->y + first + corner[i]);
        front &= vload16(0, g->z + first + corner[i]) > p->near_w;
    }
    float16 lo_x = fmin(fmin(x[0], x[1]), fmin(x[2], x[3])), lo_y = fmin(fmin(y[0], y[1]), fmin(y[2], y[3]));
    float16 hi_x = fmax(fmax(x[0], x[1]), fmax(x[2], x[3])), hi_y = fmax(fmax(y[0], y[1]), fmax(y[2], y[3]));
    struct reyes_quad_lanes q;
    q.box_lo_x = lo_x;
    q.box_lo_y = lo_y;
    q.box_hi_x = hi_x;
    q.box_hi_y = hi_y;
    q.live = has & front & (hi_x >= p->tile_x0) & (hi_y >= p->tile_y0) & (lo_x <= p->tile_x1)
             & (lo_y <= p->tile_y1);
    /* floor of the clamped box, which is at least the tile's corner (>= 0). */
    q.x0 = convert_int16(clamp(lo_x, p->tile_x0, p->tile_x1 - 1.0f));
    q.y0 = convert_int16(clamp(lo_y, p->tile_y0, p->tile_y1 - 1.0f));
    q.x1 = convert_int16(clamp(hi_x, p->tile_x0, p->tile_x1 - 1.0f));
    q.y1 = convert_int16(clamp(hi_y, p->tile_y0, p->tile_y1 - 1.0f));
    const int vertices[2][3] = { {0, 1, 2}, {0, 2, 3} };
    for (int t = 0; t < 2; ++t) {
        int a = vertices[t][0], b = vertices[t][1], cc = vertices[t][2];
        reyes_edge_order_lanes(x[b], y[b], x[cc], y[cc], &q.lo_x[t][0], &q.lo_y[t][0], &q.dx[t][0], &q.dy[t][0],
                               &q.swap[t][0]);
        reyes_edge_order_lanes(x[cc], y[cc], x[a], y[a], &q.lo_x[t][1], &q.lo_y[t][1], &q.dx[t][1], &q.dy[t][1],
                               &q.swap[t][1]);
        reyes_edge_order_lanes(x[a], y[a], x[b], y[b], &q.lo_x[t][2], &q.lo_y[t][2], &q.dx[t][2], &q.dy[t][2],
                               &q.swap[t][2]);
        q.area[t] = reyes_edge_value_lanes(q.lo_x[t][2], q.lo_y[t][2], q.dx[t][2], q.dy[t][2], q.swap[t][2], x[cc],
                                           y[cc]);
    }
    return q;
}

REYES_INLINE float8 reyes_edge_value8(float8 lo_x, float8 lo_y, float8 dx, float8 dy, int8 swap, float8 x, float8 y)
{
    float8 v = dx * (y - lo_y) - dy * (x - lo_x);
    return select(v, -v, swap);
}

#define REYES_LANE_F(v, l) (((const float *)&(v))[l])
#define REYES_LANE_I(v, l) (((const int *)&(v))[l])

/* A value of triangle 0 in lanes 0-3 and of triangle 1 in lanes 4-7. */
REYES_INLINE float8 reyes_pair(float first, float second)
{
    return (float8)((float4)first, (float4)second);
}

/* The sample indices s0 .. s0 + 3 of a chunk in eight lanes (twice, for
 * the two triangles): which are below spp, their hash and their lattice
 * cell; the same for every quad, so made once per item. */
struct reyes_sample_chunk {
    int8 valid;
    uint8 index_hash;
    float8 cell_x, cell_y;
};

struct reyes_sample_chunks {
    struct reyes_sample_chunk chunk[REYES_MAX_SPP_CHUNKS];
    uint count, spp;
    float columns, rows;
    /* 1 / columns and 1 / rows when they are powers of two (then a
     * product is the quotient exactly), else 0. */
    float inv_columns, inv_rows;
};

REYES_INLINE float reyes_exact_inverse(uint n)
{
    /* A power of two (n small and positive) has no mantissa bits as a
     * float.  Not (n & (n - 1)) == 0: LLVM turns that into llvm.ctpop,
     * which Oclgrind 21.10 cannot run. */
    return (as_uint((float)n) & 0x7fffffu) == 0u ? 1.0f / (float)n : 0.0f;
}

void reyes_sample_chunks_init(struct reyes_sample_chunks *c, uint spp)
{
    uint columns = reyes_sample_columns(spp), rows = (spp + columns - 1u) / columns;
    const uint8 index = (uint8)(0, 1, 2, 3, 0, 1, 2, 3);
    c->count = (spp + 3u) / 4u;
    c->spp = spp;
    c->columns = (float)columns;
    c->rows = (float)rows;
    c->inv_columns = reyes_exact_inverse(columns);
    c->inv_rows = reyes_exact_inverse(rows);
    for (uint k = 0; k < c->count; ++k) {
        uint8 s = 4u * k + index;
        c->chunk[k].valid = s < spp;
        c->chunk[k].index_hash = reyes_hash8(s);
        for (uint i = 0; i < 8u; ++i) {
            ((float *)&c->chunk[k].cell_x)[i] = (float)((4u * k + i % 4u) % columns);
            ((float *)&c->chunk[k].cell_y)[i] = (float)((4u * k + i % 4u) / columns);
        }
    }
}

/* (cell + jitter) / n, as a product when that is exact. */
REYES_INLINE float8 reyes_cell_offset(float8 cell, float8 jitter, float n, float inverse)
{
    return inverse != 0.0f ? (cell + jitter) * inverse : (cell + jitter) / n;
}

REYES_INLINE int reyes_any8(int8 m)
{
    int4 a = m.lo | m.hi;
    int2 b = a.lo | a.hi;
    return (b.x | b.y) != 0;
}

/* Quad l of the lanes (its slot k), over its pixel box: per pixel, four
 * sample indices against both triangles in eight SIMD lanes (triangle 0
 * in lanes 0-3, triangle 1 in 4-7), with the tests and values of
 * reyes_triangle_sample; the nearer of the two triangles' values of each
 * covered sample is merged into the samples. */
void reyes_quad_pixels(__global const struct reyes_params *p, __global ulong *samples,
                       __local const struct reyes_grid *g, const struct reyes_quad_lanes *ql, int l, int k,
                       const struct reyes_sample_chunks *chunks, const struct reyes_derivative_net *net)
{
    uint spp = chunks->spp, tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0;
    uint tile_width = (uint)p->tile_x1 - tile_x;
    int x0 = REYES_LANE_I(ql->x0, l), y0 = REYES_LANE_I(ql->y0, l);
    int x1 = REYES_LANE_I(ql->x1, l), y1 = REYES_LANE_I(ql->y1, l);
    float8 lo_x[3], lo_y[3], dx[3], dy[3];
    int8 swap[3];
    for (int e = 0; e < 3; ++e) {
        lo_x[e] = reyes_pair(REYES_LANE_F(ql->lo_x[0][e], l), REYES_LANE_F(ql->lo_x[1][e], l));
        lo_y[e] = reyes_pair(REYES_LANE_F(ql->lo_y[0][e], l), REYES_LANE_F(ql->lo_y[1][e], l));
        dx[e] = reyes_pair(REYES_LANE_F(ql->dx[0][e], l), REYES_LANE_F(ql->dx[1][e], l));
        dy[e] = reyes_pair(REYES_LANE_F(ql->dy[0][e], l), REYES_LANE_F(ql->dy[1][e], l));
        swap[e] = (int8)((int4)REYES_LANE_I(ql->swap[0][e], l), (int4)REYES_LANE_I(ql->swap[1][e], l));
    }
    float area0 = REYES_LANE_F(ql->area[0], l), area1 = REYES_LANE_F(ql->area[1], l);
    float8 area = reyes_pair(area0, area1);
    int8 inside_positive = area > 0.0f, has_area = area != 0.0f;
    /* The vertices' depths and colours, once a sample is covered. */
    int c = (int)g->columns;
    const int corner[4] = { k, k + 1, k + c + 1, k + c };
    int loaded = 0;
    float8 inv_area, za, zb, zc, ca[3], cb[3], cc[3];
    for (uint chunk = 0; chunk < chunks->count; ++chunk) {
        const struct reyes_sample_chunk *sc = &chunks->chunk[chunk];
        uint s0 = 4u * chunk;
        for (int py = y0; py <= y1; ++py) {
            uint8 row_hash = reyes_hash8((uint)py * 0x85ebca6bu ^ sc->index_hash);
            for (int px = x0; px <= x1; ++px) {
                uint8 h = reyes_hash8((uint)px * 0x9e3779b9u ^ row_hash);
                float8 jx = convert_float8(h & 0xffffu) * (1.0f / 65536.0f);
                float8 jy = convert_float8(h >> 16) * (1.0f / 65536.0f);
                float8 x = (float)px + reyes_cell_offset(sc->cell_x, jx, chunks->columns, chunks->inv_columns);
                float8 y = (float)py + reyes_cell_offset(sc->cell_y, jy, chunks->rows, chunks->inv_rows);
                float8 wa = reyes_edge_value8(lo_x[0], lo_y[0], dx[0], dy[0], swap[0], x, y);
                float8 wb = reyes_edge_value8(lo_x[1], lo_y[1], dx[1], dy[1], swap[1], x, y);
                float8 wc = reyes_edge_value8(lo_x[2], lo_y[2], dx[2], dy[2], swap[2], x, y);
                int8 inside = select((wa <= 0.0f) & (wb <= 0.0f) & (wc <= 0.0f),
                                     (wa >= 0.0f) & (wb >= 0.0f) & (wc >= 0.0f), inside_positive);
                int8 covered = inside & has_area & sc->valid;
                if (!reyes_any8(covered))
                    continue;
                if (!loaded) {
                    loaded = 1;
                    inv_area = reyes_pair(1.0f / area0, 1.0f / area1);
                    za = (float8)g->z[corner[0]];
                    zb = reyes_pair(g->z[corner[1]], g->z[corner[2]]);
                    zc = reyes_pair(g->z[corner[2]], g->z[corner[3]]);
                    /* The corners' colour channels, or their normals or
                     * parameters. */
                    float v[4][3];
                    for (int i = 0; i < 4; ++i) {
                        uint rgba = g->rgba[corner[i]];
                        if (g->shading == REYES_SHADE_SURFACE) {
                            reyes_unpack_surface(rgba, &v[i][0], &v[i][1]);
                            v[i][2] = 0.0f;
                        } else if (g->shading == REYES_SHADE_NORMALS) {
                            reyes_unpack_normal(rgba, &v[i][0], &v[i][1], &v[i][2]);
                        } else {
                            for (int ch = 0; ch < 3; ++ch)
                                v[i][ch] = reyes_channel(rgba, 8u * (uint)ch);
                        }
                    }
                    for (int ch = 0; ch < 3; ++ch) {
                        ca[ch] = (float8)v[0][ch];
                        cb[ch] = reyes_pair(v[1][ch], v[2][ch]);
                        cc[ch] = reyes_pair(v[2][ch], v[3][ch]);
                    }
                }
                float8 ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
                float8 depth = reyes_interpolated_depth8(ba, bb, bc, za, zb, zc);
                uint8 rgba;
                if (g->shading != REYES_SHADE_VERTICES) {
                    float8 n[3] = {ba * ca[0] + bb * cb[0] + bc * cc[0], ba * ca[1] + bb * cb[1] + bc * cc[1],
                                   ba * ca[2] + bb * cb[2] + bc * cc[2]};
                    if (g->shading == REYES_SHADE_SURFACE)
                        reyes_net_normal8(net, g->u0 + n[0] * (g->u1 - g->u0), g->v0 + n[1] * (g->v1 - g->v0), n);
                    rgba = reyes_sample_light8(p, n[0], n[1], n[2], x, y, g->base);
                } else
                    rgba = reyes_channel_byte8(ba * ca[0] + bb * cb[0] + bc * cc[0])
                           | (reyes_channel_byte8(ba * ca[1] + bb * cb[1] + bc * cc[1]) << 8)
                           | (reyes_channel_byte8(ba * ca[2] + bb * cb[2] + bc * cc[2]) << 16)
                           | (uint8)(255u << 24);
                ulong8 packed = convert_ulong8(as_uint8(depth)) << 32 | convert_ulong8(rgba);
                packed = select((ulong8)REYES_EMPTY_SAMPLE, packed, convert_long8(covered));
                ulong4 nearest = min(packed.lo, packed.hi);
                uint base = (((uint)py - tile_y) * tile_width + ((uint)px - tile_x)) * spp + s0;
                for (int i = 0; i < 4; ++i) {
                    ulong value = ((ulong *)&nearest)[i];
                    if (value != REYES_EMPTY_SAMPLE)
                        reyes_sample_merge(samples, base + (uint)i, value);
                }
            }
        }
    }
}

/* PoCL (which defines POCL_DEVICE_ADDRESS_BITS for kernels) lowers
 * __builtin_reduce_or to a mask test (kortest on AVX-512); oclgrind's
 * interpreter has no llvm.vector.reduce.or and refuses the kernel, so
 * other implementations take the halving reduction. */
#if defined(POCL_DEVICE_ADDRESS_BITS) && defined(__has_builtin)
#if __has_builtin(__builtin_reduce_or)
#define REYES_REDUCE_OR 1
#endif
#endif

REYES_INLINE int reyes_any16(int16 m)
{
#ifdef REYES_REDUCE_OR
    return __builtin_reduce_or(m) != 0;
#else
    return reyes_any8(m.lo | m.hi);
#endif
}

/* Bit l set where lane l of m is set. */
REYES_INLINE uint reyes_lane_bits16(int16 m)
{
    const uint16 bit = (uint16)(1u, 2u, 4u, 8u, 16u, 32u, 64u, 128u, 256u, 512u, 1024u, 2048u, 4096u, 8192u,
                                16384u, 32768u);
    uint16 b = as_uint16(m) & bit;
    uint8 a = b.lo | b.hi;
    uint4 c = a.lo | a.hi;
    uint2 d = c.lo | c.hi;
    return d.x | d.y;
}

/* Bit l set where lane l of a is set, bit 16 + l where lane l of b is:
 * both masks in one reduction. */
REYES_INLINE uint reyes_lane_bits_pair16(int16 a, int16 b)
{
    const uint16 bit = (uint16)(1u, 2u, 4u, 8u, 16u, 32u, 64u, 128u, 256u, 512u, 1024u, 2048u, 4096u, 8192u,
                                16384u, 32768u);
    uint16 m = (as_uint16(a) & bit) | (as_uint16(b) & (bit << 16));
    uint8 c = m.lo | m.hi;
    uint4 d = c.lo | c.hi;
    uint2 e = d.lo | d.hi;
    return e.x | e.y;
}

/* The edge function of an edge in canonical order (its sign not yet
 * applied), as reyes_edge_value_lanes. */
REYES_INLINE float16 reyes_edge_raw16(const struct reyes_quad_lanes *q, int t, int e, float16 x, float16 y)
{
    return q->dx[t][e] * (y - q->lo_y[t][e]) - q->dy[t][e] * (x - q->lo_x[t][e]);
}

/* (cell + jitter) / n in sixteen lanes, as reyes_cell_offset. */
REYES_INLINE float16 reyes_cell_offset16(float cell, float16 jitter, float n, float inverse)
{
    return inverse != 0.0f ? (cell + jitter) * inverse : (cell + jitter) / n;
}

/* The packed (depth, colour) of a triangle with corners a, b, c in
 * sixteen lanes from its barycentric weights' numerators (edge values
 * with the sign of the area folded in, so inv_area is 1 / |area| with the
 * same products as wa / area), REYES_EMPTY_SAMPLE where not covered. */
REYES_INLINE ulong16 reyes_triangle_values16(float16 wa, float16 wb, float16 wc, float16 inv_area,
                                             const float16 z[4], const float16 color[4][3], int a, int b, int c,
                                             int16 covered)
{
    float16 ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
    float16 depth = reyes_interpolated_depth16(ba, bb, bc, z[a], z[b], z[c]);
    uint16 rgba = reyes_channel_byte16(ba * color[a][0] + bb * color[b][0] + bc * color[c][0])
                  | (reyes_channel_byte16(ba * color[a][1] + bb * color[b][1] + bc * color[c][1]) << 8)
                  | (reyes_channel_byte16(ba * color[a][2] + bb * color[b][2] + bc * color[c][2]) << 16)
                  | (uint16)(255u << 24);
    ulong16 packed = convert_ulong16(as_uint16(depth)) << 32 | convert_ulong16(rgba);
    return select((ulong16)REYES_EMPTY_SAMPLE, packed, convert_long16(covered));
}

/* The same with sample shading: `normal` holds the corners' unit normals
 * (REYES_SHADE_NORMALS) or their parameters s and t in the sub-patch
 * (REYES_SHADE_SURFACE) where `color` holds their channels, and each
 * covered sample at (x, y) is lit with the normal interpolated from them
 * or the patch's own at the interpolated parameters
 * (reyes_sample_light16). */
REYES_INLINE ulong16 reyes_triangle_lit16(__global const struct reyes_params *p, __local const struct reyes_grid *g,
                                          const struct reyes_derivative_net *net, float16 wa, float16 wb,
                                          float16 wc, float16 inv_area, const float16 z[4],
                                          const float16 normal[4][3], int a, int b, int c, int16 covered,
                                          float16 x, float16 y)
{
    float16 ba = wa * inv_area, bb = wb * inv_area, bc = wc * inv_area;
    float16 depth = reyes_interpolated_depth16(ba, bb, bc, z[a], z[b], z[c]);
    float16 n[3];
    for (int k = 0; k < 3; ++k)
        n[k] = ba * normal[a][k] + bb * normal[b][k] + bc * normal[c][k];
    if (g->shading == REYES_SHADE_SURFACE) /* n holds the sub-patch parameters s, t */
        reyes_net_normal16(net, g->u0 + n[0] * (g->u1 - g->u0), g->v0 + n[1] * (g->v1 - g->v0), n);
    uint16 rgba = reyes_sample_light16(p, n[0], n[1], n[2], x, y, g->base);
    ulong16 packed = convert_ulong16(as_uint16(depth)) << 32 | convert_ulong16(rgba);
    return select((ulong16)REYES_EMPTY_SAMPLE, packed, convert_long16(covered));
}

/* Samples further than this outside a quad's screen box are not tested:
 * rounding never puts a covered sample anywhere near that far out (the
 * edge functions' errors are millionths of a pixel), so the samples
 * covered are those of testing every sample of the pixel box. */
#define REYES_BOX_MARGIN (1.0f / 64.0f)

/* n / d for 0 <= n < 2^20 and 1 <= d <= 64, in float lanes (exact, as
 * reyes_lattice_row). */
REYES_INLINE int16 reyes_quotient16(int16 n, float d)
{
    return convert_int16((convert_float16(n) + 0.5f) / d);
}

/* The strata a quad's samples may lie in: sample s of pixel (px, py) lies
 * in column px * columns + s % columns and row py * rows + s / columns of
 * the image's lattice of strata (reyes_sample_xy), so only the strata that
 * the screen box (with the margin) reaches, inside the pixel box, can hold
 * covered samples. */
struct reyes_strata_lanes {
    int16 x0, y0, x1, y1;
};

REYES_INLINE struct reyes_strata_lanes reyes_strata_of(const struct reyes_quad_lanes *q,
                                                       const struct reyes_sample_chunks *chunks)
{
    int columns = (int)chunks->columns, rows = (int)chunks->rows;
    struct reyes_strata_lanes b;
    b.x0 = max(convert_int16(floor((q->box_lo_x - REYES_BOX_MARGIN) * chunks->columns)), q->x0 * columns);
    b.y0 = max(convert_int16(floor((q->box_lo_y - REYES_BOX_MARGIN) * chunks->rows)), q->y0 * rows);
    b.x1 = min(convert_int16(floor((q->box_hi_x + REYES_BOX_MARGIN) * chunks->columns)), q->x1 * columns + columns - 1);
    b.y1 = min(convert_int16(floor((q->box_hi_y + REYES_BOX_MARGIN) * chunks->rows)), q->y1 * rows + rows - 1);
    return b;
}

/* Largest lane of m. */
REYES_INLINE int reyes_max16(int16 m)
{
    int8 a = max(m.lo, m.hi);
    int4 b = max(a.lo, a.hi);
    int2 c = max(b.lo, b.hi);
    return max(c.x, c.y);
}

/* The quads of the lanes set in `small` (at most REYES_SMALL_STRATA
 * strata across and down), sampled side by side: one lane per quad,
 * stepping through the strata of its box (one sample each), both
 * triangles tested in every step, with the tests and values of
 * reyes_triangle_sample; each covered sample's nearer value is merged
 * into the samples. */
#define REYES_SMALL_STRATA 4

/* The stratum `cell` steps past the last of its pixel's cells (of n):
 * on into the next pixel (at most REYES_SMALL_STRATA - 1 times, n = 1). */
REYES_INLINE void reyes_carry16(int16 *cell, int16 *pixel, int n)
{
    for (int k = 1; k < REYES_SMALL_STRATA; ++k) {
        int16 over = *cell >= n;
        *cell -= n & over;
        *pixel -= over;
    }
}

REYES_INLINE void reyes_small_quads_on(__global const struct reyes_params *p, __global ulong *samples,
                                       __local const struct reyes_grid *g, const struct reyes_quad_lanes *q,
                                       const struct reyes_strata_lanes *strata, int16 small, int first,
                                       const struct reyes_sample_chunks *chunks,
                                       const struct reyes_derivative_net *net, int exact)
{
    uint spp = chunks->spp, tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0;
    uint tile_width = (uint)p->tile_x1 - tile_x;
    int columns = (int)chunks->columns, rows = (int)chunks->rows;
    int c = (int)g->columns;
    const int corner[4] = { 0, 1, c + 1, c };
    /* The corners' colour channels, or with sample shading their normals
     * or parameters. */
    float16 z[4], color[4][3];
    int lit = g->shading != REYES_SHADE_VERTICES;
    for (int i = 0; i < 4; ++i) {
        z[i] = vload16(0, g->z + first + corner[i]);
        uint16 rgba = vload16(0, g->rgba + first + corner[i]);
        if (g->shading == REYES_SHADE_SURFACE) {
            reyes_unpack_surface16(rgba, &color[i][0], &color[i][1]);
            color[i][2] = 0.0f;
        } else if (lit) {
            reyes_unpack_normal16(rgba, &color[i][0], &color[i][1], &color[i][2]);
        } else {
            for (int ch = 0; ch < 3; ++ch)
                color[i][ch] = convert_float16((rgba >> (uint)(8 * ch)) & 255u) * (1.0f / 255.0f);
        }
    }
    /* Each edge value's sign: the edge's own (canonical order) and, where
     * the area is not positive, the flip that makes "inside" every value
     * >= 0, as for a positive area. */
    uint16 flip[2][3];
    float16 inv_area[2];
    int16 has_area[2];
    for (int t = 0; t < 2; ++t) {
        uint16 negative = as_uint16(~(q->area[t] > 0.0f)) & 0x80000000u;
        for (int e = 0; e < 3; ++e)
            flip[t][e] = (as_uint16(q->swap[t][e]) & 0x80000000u) ^ negative;
        inv_area[t] = as_float16(as_uint16(1.0f / q->area[t]) ^ negative);
        has_area[t] = q->area[t] != 0.0f;
    }
    int width = reyes_max16(select((int16)0, strata->x1 - strata->x0 + 1, small));
    int height = reyes_max16(select((int16)0, strata->y1 - strata->y0 + 1, small));
    /* Per lane, the pixel and cell of each stratum across (one division
     * for the first, then a carry into the next pixel), made once for
     * every row of strata. */
    int16 px[REYES_SMALL_STRATA], cx[REYES_SMALL_STRATA];
    int16 first_px = reyes_quotient16(strata->x0, chunks->columns);
    int16 first_py = reyes_quotient16(strata->y0, chunks->rows);
    for (int dx = 0; dx < width; ++dx) {
        px[dx] = first_px;
        cx[dx] = strata->x0 - first_px * columns + dx;
        reyes_carry16(&cx[dx], &px[dx], columns);
    }
    for (int dy = 0; dy < height; ++dy) {
        int16 row = small & (strata->y0 + dy <= strata->y1);
        int16 py = first_py, cy = strata->y0 - first_py * rows + dy;
        reyes_carry16(&cy, &py, rows);
        float16 y_cell = convert_float16(py);
        float16 cell_y = convert_float16(cy);
        uint16 row_index = (as_uint16(py) - tile_y) * tile_width - tile_x;
        for (int dx = 0; dx < width; ++dx) {
            int16 sample = cy * columns + cx[dx];
            int16 lanes = row & (strata->x0 + dx <= strata->x1) & (sample < (int)spp);
            uint16 row_hash = reyes_hash16(as_uint16(py) * 0x85ebca6bu ^ reyes_hash16(as_uint16(sample)));
            uint16 h = reyes_hash16(as_uint16(px[dx]) * 0x9e3779b9u ^ row_hash);
            float16 jx = convert_float16(h & 0xffffu) * (1.0f / 65536.0f);
            float16 jy = convert_float16(h >> 16) * (1.0f / 65536.0f);
            float16 x = convert_float16(px[dx])
                        + (exact ? (convert_float16(cx[dx]) + jx) * chunks->inv_columns
                                 : (convert_float16(cx[dx]) + jx) / chunks->columns);
            float16 y = y_cell + (exact ? (cell_y + jy) * chunks->inv_rows : (cell_y + jy) / chunks->rows);
            /* Triangle 1's edge (0, 2) is triangle 0's (2, 0): the same
             * canonical value. */
            float16 diagonal = reyes_edge_raw16(q, 0, 1, x, y);
            float16 w0a = as_float16(as_uint16(reyes_edge_raw16(q, 0, 0, x, y)) ^ flip[0][0]);
            float16 w0b = as_float16(as_uint16(diagonal) ^ flip[0][1]);
            float16 w0c = as_float16(as_uint16(reyes_edge_raw16(q, 0, 2, x, y)) ^ flip[0][2]);
            float16 w1a = as_float16(as_uint16(reyes_edge_raw16(q, 1, 0, x, y)) ^ flip[1][0]);
            float16 w1b = as_float16(as_uint16(reyes_edge_raw16(q, 1, 1, x, y)) ^ flip[1][1]);
            float16 w1c = as_float16(as_uint16(diagonal) ^ flip[1][2]);
            int16 covered0 = lanes & has_area[0] & (w0a >= 0.0f) & (w0b >= 0.0f) & (w0c >= 0.0f);
            int16 covered1 = lanes & has_area[1] & (w1a >= 0.0f) & (w1b >= 0.0f) & (w1c >= 0.0f);
            if (!reyes_any16(covered0 | covered1))
                continue;
            uint both = reyes_lane_bits_pair16(covered0, covered1);
            uint bits0 = both & 0xffffu, bits1 = both >> 16, bits = bits0 | bits1;
            ulong16 nearest = (ulong16)REYES_EMPTY_SAMPLE;
            if (lit) {
                if (bits0)
                    nearest = reyes_triangle_lit16(p, g, net, w0a, w0b, w0c, inv_area[0], z, color, 0, 1, 2, covered0,
                                                   x, y);
                if (bits1)
                    nearest = min(nearest, reyes_triangle_lit16(p, g, net, w1a, w1b, w1c, inv_area[1], z, color, 0, 2,
                                                                3, covered1, x, y));
            } else {
                if (bits0)
                    nearest = reyes_triangle_values16(w0a, w0b, w0c, inv_area[0], z, color, 0, 1, 2, covered0);
                if (bits1)
                    nearest = min(nearest, reyes_triangle_values16(w1a, w1b, w1c, inv_area[1], z, color, 0, 2, 3,
                                                                   covered1));
            }
            uint16 index = (row_index + as_uint16(px[dx])) * spp + as_uint16(sample);
            while (bits) {
                uint l = 31u - clz(bits & (0u - bits));
                bits &= bits - 1u;
                reyes_sample_merge(samples, ((uint *)&index)[l], ((ulong *)&nearest)[l]);
            }
        }
    }
}

/* reyes_small_quads_on with the lattice's divisions as products where
 * those are exact (columns and rows powers of two), decided once. */
void reyes_small_quads(__global const struct reyes_params *p, __global ulong *samples,
                       __local const struct reyes_grid *g, const struct reyes_quad_lanes *q,
                       const struct reyes_strata_lanes *strata, int16 small, int first,
                       const struct reyes_sample_chunks *chunks, const struct reyes_derivative_net *net)
{
    if (chunks->inv_columns != 0.0f && chunks->inv_rows != 0.0f)
        reyes_small_quads_on(p, samples, g, q, strata, small, first, chunks, net, 1);
    else
        reyes_small_quads_on(p, samples, g, q, strata, small, first, chunks, net, 0);
}
