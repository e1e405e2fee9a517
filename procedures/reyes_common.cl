/*
 * Device helpers shared by the Reyes procedures: Bézier evaluation,
 * restriction of a base patch to a sub-patch rectangle, projection.
 * Control points are row-major: P[row][col], u runs along a row (col),
 * v along a column (row).
 */
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable

/* Small helpers that the vectorisable stretches of dice and rasterize call:
 * PoCL vectorises a work-group loop across work-items only when its body
 * has no calls left, so these are always inlined. */
#define REYES_INLINE inline __attribute__((always_inline))

/* Cubic Bernstein weights at t. */
REYES_INLINE float4 reyes_bernstein(float t)
{
    float s = 1.0f - t;
    return (float4)(s * s * s, 3.0f * t * s * s, 3.0f * t * t * s, t * t * t);
}

/* Derivatives of the cubic Bernstein weights at t. */
REYES_INLINE float4 reyes_bernstein_deriv(float t)
{
    float s = 1.0f - t;
    return (float4)(-3.0f * s * s, 3.0f * s * s - 6.0f * t * s,
                    6.0f * t * s - 3.0f * t * t, 3.0f * t * t);
}

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

/* Clip-space position of a world point. */
REYES_INLINE float4 reyes_to_clip(__global const struct reyes_params *p, float3 x)
{
    float4 h = (float4)(x, 1.0f);
    __global const float *m = p->view_proj;
    return (float4)(dot((float4)(m[0], m[1], m[2], m[3]), h),
                    dot((float4)(m[4], m[5], m[6], m[7]), h),
                    dot((float4)(m[8], m[9], m[10], m[11]), h),
                    dot((float4)(m[12], m[13], m[14], m[15]), h));
}

/* Clip-space motion (x, y, 0, w) over the shutter of a vertex at world
 * point x: the affine map motion_rows, or the one motion of every vertex
 * when nothing rotates (exactly the uniform values then). */
REYES_INLINE float4 reyes_motion_at(__global const struct reyes_params *p, float3 x)
{
    if (!p->motion_rotates)
        return (float4)(p->motion_rows[3], p->motion_rows[7], 0.0f, p->motion_rows[11]);
    __global const float *r = p->motion_rows;
    float4 h = (float4)(x, 1.0f);
    return (float4)(dot((float4)(r[0], r[1], r[2], r[3]), h), dot((float4)(r[4], r[5], r[6], r[7]), h),
                    0.0f, dot((float4)(r[8], r[9], r[10], r[11]), h));
}

/* Pixel coordinates (y down) of a clip-space point with w > 0. */
REYES_INLINE float2 reyes_to_screen(__global const struct reyes_params *p, float4 clip)
{
    float inv_w = 1.0f / clip.w;
    return (float2)((clip.x * inv_w * 0.5f + 0.5f) * p->width,
                    (0.5f - clip.y * inv_w * 0.5f) * p->height);
}

/* A colour channel in [0,1] as a byte: clamped (NaN as 0), scaled and
 * rounded to nearest, ties to even (adding and subtracting 2^23 rounds a
 * float in [0, 2^23) so), as convert_uint_sat_rte would. */
REYES_INLINE uint reyes_channel_byte(float c)
{
    float scaled = clamp(c, 0.0f, 1.0f) * 255.0f;
    float rounded = (scaled + 8388608.0f) - 8388608.0f;
    return (uint)rounded;
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
