/*
 * Device helpers shared by the Reyes procedures: Bézier evaluation,
 * restriction of a base patch to a sub-patch rectangle, projection.
 * Control points are row-major: P[row][col], u runs along a row (col),
 * v along a column (row).
 */
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

/* Small helpers of the per-vertex and per-sample code: always inlined
 * (PoCL otherwise keeps many of them as calls made once per work-item).
 * Not under Oclgrind's race check (PERMA_RACE_CHECK, run_on.sh): inlining
 * a function that returns a struct makes its compiler emit
 * llvm.experimental.noalias.scope.decl, which Oclgrind 21.10 cannot run
 * ("Undefined external function").  Inlining changes no result. */
#ifdef PERMA_RACE_CHECK
#define REYES_INLINE
#else
#define REYES_INLINE inline __attribute__((always_inline))
#endif

/* Load the 16 control points of a base patch. */
REYES_INLINE void reyes_load_patch(__global const float4 *patches, uint patch, float3 cp[16])
{
    for (int k = 0; k < 16; ++k)
        cp[k] = patches[patch * 16u + (uint)k].xyz;
}

/* Blossom of a cubic at (t1, t2, t3): De Casteljau with one parameter per
 * level.  blossom(a,a,a) is the curve point at a; the control points of the
 * piece over [a,b] are blossom(a,a,a), (a,a,b), (a,b,b), (b,b,b). */
float3 reyes_blossom(float3 p0, float3 p1, float3 p2, float3 p3, float t1, float t2, float t3)
{
    float3 a = mix(p0, p1, t1), b = mix(p1, p2, t1), c = mix(p2, p3, t1);
    float3 d = mix(a, b, t2), e = mix(b, c, t2);
    return mix(d, e, t3);
}

/* Replace the 4 points at cp[first], cp[first+stride], ... by the control
 * points of the same cubic restricted to [a,b]. */
void reyes_restrict_curve(float3 cp[16], int first, int stride, float a, float b)
{
    float3 p0 = cp[first], p1 = cp[first + stride];
    float3 p2 = cp[first + 2 * stride], p3 = cp[first + 3 * stride];
    cp[first] = reyes_blossom(p0, p1, p2, p3, a, a, a);
    cp[first + stride] = reyes_blossom(p0, p1, p2, p3, a, a, b);
    cp[first + 2 * stride] = reyes_blossom(p0, p1, p2, p3, a, b, b);
    cp[first + 3 * stride] = reyes_blossom(p0, p1, p2, p3, b, b, b);
}

/* Control points of a sub-patch, computed from its base patch. */
void reyes_subpatch_points(__global const float4 *patches, const struct reyes_subpatch *sp,
                           float3 cp[16])
{
    reyes_load_patch(patches, sp->patch, cp);
    for (int row = 0; row < 4; ++row)
        reyes_restrict_curve(cp, row * 4, 1, sp->u0, sp->u1);
    for (int col = 0; col < 4; ++col)
        reyes_restrict_curve(cp, col, 4, sp->v0, sp->v1);
}

/* a . b as PoCL's dot(float3): the products, then (x + y) + z, each
 * rounded (separate statements, so nothing is contracted into an fma). */
REYES_INLINE float reyes_dot3(float ax, float ay, float az, float bx, float by, float bz)
{
    float x = ax * bx;
    float y = ay * by;
    float z = az * bz;
    float xy = x + y;
    return xy + z;
}

/* a . b of 4-vectors as PoCL's dot(float4): (x + y) + (z + w). */
REYES_INLINE float reyes_dot4(float ax, float ay, float az, float aw, float bx, float by, float bz, float bw)
{
    float x = ax * bx;
    float y = ay * by;
    float z = az * bz;
    float w = aw * bw;
    float xy = x + y;
    float zw = z + w;
    return xy + zw;
}

/* Clip-space position of world point (x, y, z). */
REYES_INLINE void reyes_clip_of(__global const struct reyes_params *p, float x, float y, float z, float clip[4])
{
    __global const float *m = p->view_proj;
    #pragma unroll
    for (int r = 0; r < 4; ++r)
        clip[r] = reyes_dot4(m[4 * r], m[4 * r + 1], m[4 * r + 2], m[4 * r + 3], x, y, z, 1.0f);
}

REYES_INLINE float4 reyes_to_clip(__global const struct reyes_params *p, float3 x)
{
    float c[4];
    reyes_clip_of(p, x.x, x.y, x.z, c);
    return (float4)(c[0], c[1], c[2], c[3]);
}

/* Clip-space motion (x, y, w) over the shutter of a vertex at world point
 * (x, y, z): the affine map motion_rows, or the one motion of every
 * vertex when nothing rotates (exactly the uniform values then). */
REYES_INLINE void reyes_motion_of(__global const struct reyes_params *p, float x, float y, float z, float m[3])
{
    __global const float *r = p->motion_rows;
    const int rows[3] = {0, 4, 8};
    #pragma unroll
    for (int k = 0; k < 3; ++k) {
        int o = rows[k];
        m[k] = p->motion_rotates ? reyes_dot4(r[o], r[o + 1], r[o + 2], r[o + 3], x, y, z, 1.0f) : r[o + 3];
    }
}

REYES_INLINE float4 reyes_motion_at(__global const struct reyes_params *p, float3 x)
{
    float m[3];
    reyes_motion_of(p, x.x, x.y, x.z, m);
    return (float4)(m[0], m[1], 0.0f, m[2]);
}

/* Pixel coordinates (y down) of a clip-space point with w > 0. */
REYES_INLINE void reyes_screen_of(__global const struct reyes_params *p, float x, float y, float w, float *sx,
                                  float *sy)
{
    float inv_w = 1.0f / w;
    *sx = (x * inv_w * 0.5f + 0.5f) * p->width;
    *sy = (0.5f - y * inv_w * 0.5f) * p->height;
}

REYES_INLINE float2 reyes_to_screen(__global const struct reyes_params *p, float4 clip)
{
    float sx, sy;
    reyes_screen_of(p, clip.x, clip.y, clip.w, &sx, &sy);
    return (float2)(sx, sy);
}

/* A colour channel in [0,1] as a byte: clamped (NaN as 0), scaled and
 * rounded to nearest, ties to even (adding and subtracting 2^23 rounds a
 * float in [0, 2^23) so), as convert_uint_sat_rte would.  One definition
 * for one lane and for the 8 and 16 lanes of rasterize and shading. */
#define REYES_DEFINE_CHANNEL_BYTE(name, float_type, uint_type)                 \
    REYES_INLINE uint_type name(float_type c)                                  \
    {                                                                          \
        float_type scaled = clamp(c, 0.0f, 1.0f) * 255.0f;                     \
        float_type rounded = (scaled + 8388608.0f) - 8388608.0f;               \
        return convert_##uint_type(rounded);                                   \
    }
REYES_DEFINE_CHANNEL_BYTE(reyes_channel_byte, float, uint)
REYES_DEFINE_CHANNEL_BYTE(reyes_channel_byte8, float8, uint8)
REYES_DEFINE_CHANNEL_BYTE(reyes_channel_byte16, float16, uint16)

/* Sum of the sixteen lanes of m, halves added pairwise (dice's and
 * rasterize's quad counts). */
REYES_INLINE int reyes_sum16(int16 m)
{
    int8 a = m.lo + m.hi;
    int4 b = a.lo + a.hi;
    int2 c = b.lo + b.hi;
    return c.x + c.y;
}

/* Pack a color in [0,1]^3 as RGBA8 (alpha 255, red in the low byte). */
REYES_INLINE uint reyes_pack_channels(float r, float g, float b)
{
    return reyes_channel_byte(r) | (reyes_channel_byte(g) << 8) | (reyes_channel_byte(b) << 16) | (255u << 24);
}

REYES_INLINE uint reyes_pack_rgba(float3 c)
{
    return reyes_pack_channels(c.x, c.y, c.z);
}

REYES_INLINE float3 reyes_unpack_rgb(uint rgba)
{
    return (float3)((float)(rgba & 255u), (float)((rgba >> 8) & 255u),
                    (float)((rgba >> 16) & 255u)) * (1.0f / 255.0f);
}

/* Colour channel `shift` of a packed RGBA8 in [0,1]. */
REYES_INLINE float reyes_channel(uint rgba, uint shift)
{
    return (float)((rgba >> shift) & 255u) * (1.0f / 255.0f);
}
