/*
 * Surface evaluation and shading shared by dice and stitch: a grid vertex
 * of a sub-patch is evaluated on its base patch at global (u,v) by
 * reyes_grid_vertex, so the same vertex computed by either procedure is
 * bit-identical.
 */

struct reyes_vertex {
    float4 clip;
    uint rgba;
#ifdef REYES_VERTEX_MOTION
    float4 motion;         /* clip-space motion over the shutter */
#endif
};

/* Set a vertex's clip position (and, with per-vertex motion, its motion)
 * from its world position. */
REYES_INLINE void reyes_vertex_place(__global const struct reyes_params *p, float3 x, struct reyes_vertex *v)
{
    v->clip = reyes_to_clip(p, x);
#ifdef REYES_VERTEX_MOTION
    v->motion = reyes_motion_at(p, x);
#endif
}

/* A blurred quad of `count` vertices (clip x, y, w in q) with its
 * vertices' motions: their own with per-vertex motion, else the one
 * motion of the parameters. */
struct reyes_moving_quad reyes_vertex_moving(__global const struct reyes_params *p,
                                             const struct reyes_quad *q,
                                             const struct reyes_vertex *v, int count)
{
#ifdef REYES_VERTEX_MOTION
    struct reyes_moving_quad m;
    m.quad = *q;
    for (int k = 0; k < 4; ++k) {
        float4 motion = v[k < count ? k : 0].motion;
        m.mx[k] = motion.x;
        m.my[k] = motion.y;
        m.mw[k] = motion.w;
    }
    return m;
#else
    (void)v;
    (void)count;
    return reyes_moving_uniform(p, q);
#endif
}

/* The patch arithmetic below evaluates REYES_LANES points at once, in
 * OpenCL vector types (float16): dice fills a grid row of 16 vertices at a
 * time with it (one AVX-512 register, two AVX2 ones), in SIMD code whatever the OpenCL compiler does across
 * work-items, and every other caller (stitch, displacement, the poles)
 * takes lane 0 of the same code, so a vertex gets the same bits wherever it
 * is computed.  Dot products, cross products and normalize round as
 * PoCL's built-ins (no fused multiply-add; see reyes_dot3). */
#define REYES_LANES 16
typedef float16 reyes_lanes;
typedef int16 reyes_lane_mask;
typedef uint16 reyes_lane_uint;
#define reyes_convert_lanes convert_float16
#define reyes_convert_lane_uint convert_uint16
#define reyes_channel_byte_lanes reyes_channel_byte16
#define reyes_vstore_lanes vstore16
#define reyes_vload_lanes vload16

/* Cubic Bernstein weights at t and their derivatives, in lanes and (the
 * same arithmetic, so the same bits) for one parameter. */
#define REYES_DEFINE_BERNSTEIN(suffix, type)                                   \
    REYES_INLINE void reyes_bernstein##suffix(type t, type b[4])               \
    {                                                                          \
        type s = 1.0f - t;                                                     \
        b[0] = s * s * s;                                                      \
        b[1] = 3.0f * t * s * s;                                               \
        b[2] = 3.0f * t * t * s;                                               \
        b[3] = t * t * t;                                                      \
    }                                                                          \
    REYES_INLINE void reyes_bernstein_deriv##suffix(type t, type d[4])         \
    {                                                                          \
        type s = 1.0f - t;                                                     \
        d[0] = -3.0f * s * s;                                                  \
        d[1] = 3.0f * s * s - 6.0f * t * s;                                    \
        d[2] = 6.0f * t * s - 3.0f * t * t;                                    \
        d[3] = 3.0f * t * t;                                                   \
    }
REYES_DEFINE_BERNSTEIN(_lanes, reyes_lanes)
REYES_DEFINE_BERNSTEIN(_one, float)

/* Control points of a base patch as three arrays of scalars. */
struct reyes_hull {
    float x[16], y[16], z[16];
};

REYES_INLINE void reyes_load_hull(__global const float4 *patches, uint patch, struct reyes_hull *h)
{
    __global const float *f = (__global const float *)(patches + patch * 16u);
    for (int k = 0; k < 16; ++k) {
        h->x[k] = f[4 * k];
        h->y[k] = f[4 * k + 1];
        h->z[k] = f[4 * k + 2];
    }
}

REYES_INLINE struct reyes_hull reyes_hull_of(const float3 cp[16])
{
    struct reyes_hull h;
    for (int k = 0; k < 16; ++k) {
        h.x[k] = cp[k].x;
        h.y[k] = cp[k].y;
        h.z[k] = cp[k].z;
    }
    return h;
}

/* a . (x, y, z, 1), lane by lane, as reyes_dot4. */
REYES_INLINE reyes_lanes reyes_dot4_lanes(float ax, float ay, float az, float aw, reyes_lanes x, reyes_lanes y,
                                          reyes_lanes z)
{
    reyes_lanes px = ax * x;
    reyes_lanes py = ay * y;
    reyes_lanes pz = az * z;
    float pw = aw * 1.0f;
    reyes_lanes xy = px + py;
    reyes_lanes zw = pz + pw;
    return xy + zw;
}

/* The shading arithmetic, written once and defined for lanes (suffix
 * _lanes, in reyes_lanes) and for one point (suffix _one, in float): the
 * same expressions, so a vertex shaded alone (stitch, displacement, the
 * poles) gets the bits dice's lanes give it, at a sixteenth of the work of
 * taking lane 0 of sixteen.  a . b (as reyes_dot3); a vector over its
 * length (the zero vector unchanged). */
#define REYES_DEFINE_VECTOR_MATH(suffix, type, mask)                                                 \
    REYES_INLINE type reyes_dot3##suffix(type ax, type ay, type az, type bx, type by, type bz)      \
    {                                                                                                \
        type x = ax * bx;                                                                            \
        type y = ay * by;                                                                            \
        type z = az * bz;                                                                            \
        type xy = x + y;                                                                             \
        return xy + z;                                                                               \
    }                                                                                                \
    REYES_INLINE void reyes_normalize##suffix(type *x, type *y, type *z)                            \
    {                                                                                                \
        type ax = *x, ay = *y, az = *z;                                                              \
        type l2 = reyes_dot3##suffix(ax, ay, az, ax, ay, az);                                        \
        type inv = 1.0f / sqrt(l2);                                                                  \
        mask zero = l2 == 0.0f;                                                                      \
        *x = select(ax * inv, ax, zero);                                                             \
        *y = select(ay * inv, ay, zero);                                                             \
        *z = select(az * inv, az, zero);                                                             \
    }                                                                                                \
    /* cross(tu, tv), products rounded apart as PoCL's cross. */                                    \
    REYES_INLINE void reyes_cross##suffix(const type tu[3], const type tv[3], type n[3])            \
    {                                                                                                \
        type yz = tu[1] * tv[2], zy = tu[2] * tv[1];                                                 \
        type zx = tu[2] * tv[0], xz = tu[0] * tv[2];                                                 \
        type xy = tu[0] * tv[1], yx = tu[1] * tv[0];                                                 \
        n[0] = yz - zy;                                                                              \
        n[1] = zx - xz;                                                                              \
        n[2] = xy - yx;                                                                              \
    }                                                                                                \
    /* Whether normals n = cross(tu, tv) are unusable: they vanish, or one                          \
     * derivative is a millionth of the other or less, where a patch edge                           \
     * collapses to a point (a pole) and rounding leaves that derivative a                          \
     * few ulps long in an arbitrary direction.  Sample shading lights every                        \
     * sample with these normals, so it tests them this way; fixed grids                            \
     * keep the plain test of a vanishing normal (their bytes are                                   \
     * unchanged). */                                                                               \
    REYES_INLINE mask reyes_collapsed##suffix(const type tu[3], const type tv[3], const type n[3])  \
    {                                                                                                \
        type uu = reyes_dot3##suffix(tu[0], tu[1], tu[2], tu[0], tu[1], tu[2]);                      \
        type vv = reyes_dot3##suffix(tv[0], tv[1], tv[2], tv[0], tv[1], tv[2]);                      \
        type nn = reyes_dot3##suffix(n[0], n[1], n[2], n[0], n[1], n[2]);                            \
        return (nn < 1e-24f) | (uu < 1e-12f * vv) | (vv < 1e-12f * uu);                              \
    }
REYES_DEFINE_VECTOR_MATH(_lanes, reyes_lanes, reyes_lane_mask)
REYES_DEFINE_VECTOR_MATH(_one, float, int)

/* A patch is evaluated separably, the same way for every caller: at
 * parameter v its four rows of control points collapse to a cubic curve
 * in u (q) and the derivative curve in v (qv), whose four control points
 * are then weighted by the Bernstein weights of u.  dice makes the curves
 * once per grid row and shares them by every vertex of the row. */
#define REYES_DEFINE_ROW_CURVES(suffix, type)                                                                  \
    struct reyes_row_curves##suffix {                                                                          \
        type q[3][4], qv[3][4];                                                                                \
    };                                                                                                         \
    REYES_INLINE void reyes_row_curves##suffix(const struct reyes_hull *h, type v,                             \
                                               struct reyes_row_curves##suffix *rc)                            \
    {                                                                                                          \
        type bv[4], dv[4];                                                                                     \
        reyes_bernstein##suffix(v, bv);                                                                        \
        reyes_bernstein_deriv##suffix(v, dv);                                                                  \
        for (int c = 0; c < 4; ++c) {                                                                          \
            rc->q[0][c] = bv[0] * h->x[c] + bv[1] * h->x[4 + c] + bv[2] * h->x[8 + c] + bv[3] * h->x[12 + c];  \
            rc->q[1][c] = bv[0] * h->y[c] + bv[1] * h->y[4 + c] + bv[2] * h->y[8 + c] + bv[3] * h->y[12 + c];  \
            rc->q[2][c] = bv[0] * h->z[c] + bv[1] * h->z[4 + c] + bv[2] * h->z[8 + c] + bv[3] * h->z[12 + c];  \
            rc->qv[0][c] = dv[0] * h->x[c] + dv[1] * h->x[4 + c] + dv[2] * h->x[8 + c] + dv[3] * h->x[12 + c]; \
            rc->qv[1][c] = dv[0] * h->y[c] + dv[1] * h->y[4 + c] + dv[2] * h->y[8 + c] + dv[3] * h->y[12 + c]; \
            rc->qv[2][c] = dv[0] * h->z[c] + dv[1] * h->z[4 + c] + dv[2] * h->z[8 + c] + dv[3] * h->z[12 + c]; \
        }                                                                                                      \
    }
/* The row curves in lanes (struct reyes_row_curves_lanes) and, for dice's
 * rows (v is the same for every vertex of a row), as scalars (struct
 * reyes_row_curves_one): the same arithmetic, so the same bits. */
REYES_DEFINE_ROW_CURVES(_lanes, reyes_lanes)
REYES_DEFINE_ROW_CURVES(_one, float)

/* w[0] q[0] + w[1] q[1] + w[2] q[2] + w[3] q[3], with the curve's
 * control points in lanes or the same for every lane, or for one
 * parameter. */
#define REYES_DEFINE_CURVE_AT(suffix, type, weight)                                                \
    REYES_INLINE weight reyes_curve_at##suffix(const weight w[4], const type q[4])                 \
    {                                                                                              \
        return w[0] * q[0] + w[1] * q[1] + w[2] * q[2] + w[3] * q[3];                              \
    }
REYES_DEFINE_CURVE_AT(, reyes_lanes, reyes_lanes)
REYES_DEFINE_CURVE_AT(_one, float, reyes_lanes)
REYES_DEFINE_CURVE_AT(_scalar, float, float)

/* Points, and unnormalised normals (cross products of the derivatives),
 * at u on the row curves. */
REYES_INLINE void reyes_row_point_lanes(const struct reyes_row_curves_lanes *rc, reyes_lanes u, reyes_lanes x[3])
{
    reyes_lanes bu[4];
    reyes_bernstein_lanes(u, bu);
    for (int d = 0; d < 3; ++d)
        x[d] = reyes_curve_at(bu, rc->q[d]);
}

/* The unnormalised normals at u on the row curves; returns the lanes
 * where they are collapsed (reyes_collapsed_lanes). */
REYES_INLINE reyes_lane_mask reyes_row_normal_lanes(const struct reyes_row_curves_lanes *rc, reyes_lanes u,
                                                    reyes_lanes n[3])
{
    reyes_lanes bu[4], du[4], tu[3], tv[3];
    reyes_bernstein_lanes(u, bu);
    reyes_bernstein_deriv_lanes(u, du);
    for (int d = 0; d < 3; ++d) {
        tu[d] = reyes_curve_at(du, rc->q[d]);
        tv[d] = reyes_curve_at(bu, rc->qv[d]);
    }
    reyes_cross_lanes(tu, tv, n);
    return reyes_collapsed_lanes(tu, tv, n);
}

/* Points and unnormalised normals at (u,v) of a hull. */
REYES_INLINE void reyes_hull_point_lanes(const struct reyes_hull *h, reyes_lanes u, reyes_lanes v,
                                         reyes_lanes x[3])
{
    struct reyes_row_curves_lanes rc;
    reyes_row_curves_lanes(h, v, &rc);
    reyes_row_point_lanes(&rc, u, x);
}

REYES_INLINE reyes_lane_mask reyes_hull_normal_lanes(const struct reyes_hull *h, reyes_lanes u, reyes_lanes v,
                                                     reyes_lanes n[3])
{
    struct reyes_row_curves_lanes rc;
    reyes_row_curves_lanes(h, v, &rc);
    return reyes_row_normal_lanes(&rc, u, n);
}

/* Surface point and unnormalised normal at (u,v), from the row curves at
 * v made once: the arithmetic of the above for one point (so lane for
 * lane the same bits); returns whether the normal is collapsed
 * (reyes_collapsed_lanes). */
REYES_INLINE int reyes_patch_point_normal(const float3 cp[16], float u, float v, float3 *x, float3 *normal)
{
    struct reyes_hull h = reyes_hull_of(cp);
    struct reyes_row_curves_one rc;
    reyes_row_curves_one(&h, v, &rc);
    float bu[4], du[4], tu[3], tv[3], n[3];
    reyes_bernstein_one(u, bu);
    reyes_bernstein_deriv_one(u, du);
    for (int d = 0; d < 3; ++d) {
        tu[d] = reyes_curve_at_scalar(du, rc.q[d]);
        tv[d] = reyes_curve_at_scalar(bu, rc.qv[d]);
    }
    reyes_cross_one(tu, tv, n);
    *x = (float3)(reyes_curve_at_scalar(bu, rc.q[0]), reyes_curve_at_scalar(bu, rc.q[1]),
                  reyes_curve_at_scalar(bu, rc.q[2]));
    *normal = (float3)(n[0], n[1], n[2]);
    return reyes_collapsed_one(tu, tv, n) != 0;
}

/* Unnormalised surface normal at (u,v); *collapsed as
 * reyes_collapsed_lanes. */
REYES_INLINE float3 reyes_patch_normal_of(const float3 cp[16], float u, float v, int *collapsed)
{
    float3 x, n;
    *collapsed = reyes_patch_point_normal(cp, u, v, &x, &n);
    return n;
}

REYES_INLINE float3 reyes_patch_normal(const float3 cp[16], float u, float v)
{
    int collapsed;
    return reyes_patch_normal_of(cp, u, v, &collapsed);
}

REYES_INLINE float3 reyes_patch_point(const float3 cp[16], float u, float v)
{
    float3 x, n;
    reyes_patch_point_normal(cp, u, v, &x, &n);
    return x;
}

/* Normal at (u,v); where a patch edge collapses to a point (a pole) the
 * derivative cross product vanishes, so take it slightly inside.  n: the
 * normal at (u,v) already made. */
float3 reyes_safe_normal_from(const float3 cp[16], float u, float v, float3 n)
{
    for (int step = 1; step <= 3 && dot(n, n) < 1e-24f; ++step) {
        float nudge = 1e-3f * (float)step;
        n = reyes_patch_normal(cp, mix(u, 0.5f, nudge), mix(v, 0.5f, nudge));
    }
    return n;
}

float3 reyes_safe_normal(const float3 cp[16], float u, float v)
{
    return reyes_safe_normal_from(cp, u, v, reyes_patch_normal(cp, u, v));
}

/* The same for sample shading, where a pole is a collapsed normal
 * (reyes_collapsed_lanes) and fixed grids' bytes do not constrain it.
 * n, collapsed: the normal at (u,v) already made and whether it is. */
float3 reyes_lit_normal_from(const float3 cp[16], float u, float v, float3 n, int collapsed)
{
    for (int step = 1; step <= 3 && collapsed; ++step) {
        float nudge = 1e-3f * (float)step;
        n = reyes_patch_normal_of(cp, mix(u, 0.5f, nudge), mix(v, 0.5f, nudge), &collapsed);
    }
    return n;
}

/* The normal a vertex is shaded with: reyes_lit_normal_from with sample
 * shading, else reyes_safe_normal_from (n, collapsed as there). */
REYES_INLINE float3 reyes_vertex_normal_from(__global const struct reyes_params *p, const float3 cp[16], float u,
                                             float v, float3 n, int collapsed)
{
    return p->sample_shading ? reyes_lit_normal_from(cp, u, v, n, collapsed) : reyes_safe_normal_from(cp, u, v, n);
}

/* The light's parameters, loaded once per grid. */
struct reyes_lighting {
    float eye[3], light[3];
    float ambient, diffuse, specular, shininess;
};

REYES_INLINE struct reyes_lighting reyes_lighting_of(__global const struct reyes_params *p)
{
    struct reyes_lighting l;
    for (int k = 0; k < 3; ++k) {
        l.eye[k] = p->eye[k];
        l.light[k] = p->light_dir[k];
    }
    l.ambient = p->ambient;
    l.diffuse = p->diffuse;
    l.specular = p->specular;
    l.shininess = p->shininess;
    return l;
}

/* Lambert plus Blinn-Phong, two-sided, one directional light plus
 * ambient, at points x with normals n: a colour c shades to
 * c * diffuse + specular (reyes_light_color).  The shaded colours of base
 * colour rgba (its alpha ignored), packed.  For lanes and for one point,
 * as REYES_DEFINE_VECTOR_MATH. */
#define REYES_DEFINE_LIGHTING(suffix, type, mask, packed, channel_byte, power)                                       \
    REYES_INLINE void reyes_light##suffix(const struct reyes_lighting *l, const type x[3], const type n[3],         \
                                          type *diffuse, type *specular)                                             \
    {                                                                                                                \
        type vx = l->eye[0] - x[0], vy = l->eye[1] - x[1], vz = l->eye[2] - x[2];                                  \
        reyes_normalize##suffix(&vx, &vy, &vz);                                                                      \
        type mx = n[0], my = n[1], mz = n[2];                                                                        \
        reyes_normalize##suffix(&mx, &my, &mz);                                                                      \
        mask has_normal = reyes_dot3##suffix(n[0], n[1], n[2], n[0], n[1], n[2]) > 0.0f;                             \
        mx = select(vx, mx, has_normal);                                                                             \
        my = select(vy, my, has_normal);                                                                             \
        mz = select(vz, mz, has_normal);                                                                             \
        mask away = reyes_dot3##suffix(mx, my, mz, vx, vy, vz) < 0.0f;                                               \
        mx = select(mx, -mx, away);                                                                                  \
        my = select(my, -my, away);                                                                                  \
        mz = select(mz, -mz, away);                                                                                  \
        float lx = l->light[0], ly = l->light[1], lz = l->light[2];                                                  \
        type lambert = fmax(reyes_dot3##suffix(mx, my, mz, (type)lx, (type)ly, (type)lz), 0.0f);                   \
        type hx = lx + vx, hy = ly + vy, hz = lz + vz;                                                               \
        reyes_normalize##suffix(&hx, &hy, &hz);                                                                      \
        type cos_h = reyes_dot3##suffix(mx, my, mz, hx, hy, hz);                                                     \
        type highlight_power = power(cos_h, l->shininess);                                                           \
        type highlight = select((type)0.0f, highlight_power, lambert > 0.0f & cos_h > 0.0f);                         \
        *diffuse = l->ambient + l->diffuse * lambert;                                                                \
        *specular = l->specular * highlight;                                                                         \
    }                                                                                                                \
    REYES_INLINE packed reyes_light_color##suffix(uint rgba, type diffuse, type specular)                            \
    {                                                                                                                \
        float r = reyes_channel(rgba, 0u), g = reyes_channel(rgba, 8u), b = reyes_channel(rgba, 16u);              \
        return channel_byte(r * diffuse + specular) | (channel_byte(g * diffuse + specular) << 8)                    \
               | (channel_byte(b * diffuse + specular) << 16) | (packed)(255u << 24);                                \
    }
REYES_DEFINE_LIGHTING(_lanes, reyes_lanes, reyes_lane_mask, reyes_lane_uint, reyes_channel_byte_lanes,
                      reyes_power_lanes)
REYES_DEFINE_LIGHTING(_one, float, int, uint, reyes_channel_byte, reyes_power)

/* A vertex's colour (base colour rgba lit at point x with normal n) or,
 * with sample shading, its unit normal packed (reyes_pack_normal16). */
REYES_INLINE uint reyes_shade(__global const struct reyes_params *p, float3 x, float3 n, uint rgba)
{
    const float xs[3] = {x.x, x.y, x.z}, ns[3] = {n.x, n.y, n.z};
    if (p->sample_shading)
        return reyes_pack_normal16((float16)n.x, (float16)n.y, (float16)n.z).s0;
    struct reyes_lighting l = reyes_lighting_of(p);
    float diffuse, specular;
    reyes_light_one(&l, xs, ns, &diffuse, &specular);
    return reyes_light_color_one(rgba, diffuse, specular);
}

/* The displaced surface point at (u,v): the patch point moved along its
 * unit normal by displace(). */
float3 reyes_displaced_point(const struct reyes_displacement *d, const float3 cp[16], float u,
                             float v)
{
    float3 x = reyes_patch_point(cp, u, v);
    float3 n = reyes_safe_normal(cp, u, v);
    n = dot(n, n) > 0.0f ? normalize(n) : (float3)(0.0f);
    return x + displace(d, (float2)(u, v), x, n) * n;
}

/* Normal of the displaced surface at (u,v) from central differences in
 * the base patch's parameters (one-sided at its borders): a function of
 * (patch, u, v) only, so grids sharing a vertex give it the same normal. */
float3 reyes_displaced_normal(const struct reyes_displacement *d, const float3 cp[16], float u,
                              float v)
{
    const float h = 1.0f / 1024.0f;
    float u0 = fmax(u - h, 0.0f), u1 = fmin(u + h, 1.0f);
    float v0 = fmax(v - h, 0.0f), v1 = fmin(v + h, 1.0f);
    float3 du = reyes_displaced_point(d, cp, u1, v) - reyes_displaced_point(d, cp, u0, v);
    float3 dv = reyes_displaced_point(d, cp, u, v1) - reyes_displaced_point(d, cp, u, v0);
    float3 n = cross(du, dv);
    return dot(n, n) > 1e-30f ? n : reyes_safe_normal(cp, u, v);
}

/* Vertices of a sub-patch's grid along u and v: those bound chose for it
 * with a shading rate (dice_size), else the renderer's grid x grid. */
REYES_INLINE int2 reyes_dice_size(__global const struct reyes_params *p, uint dice_size)
{
    if (dice_size == 0u)
        return (int2)((int)p->grid, (int)p->grid);
    return (int2)((int)(dice_size & 0xffu), (int)((dice_size >> 8) & 0xffu));
}

/* Base-patch parameters (u,v) of grid vertex (i,j) of the sub-patch
 * [u0,u1] x [v0,v1] diced to size.x x size.y vertices. */
REYES_INLINE void reyes_grid_uv_of(int2 size, float u0, float v0, float u1, float v1, int i, int j, float *u,
                                   float *v)
{
    /* mix(a, b, 1) == b exactly, so shared patch edges get equal u, v. */
    float tu = (float)i / (float)(size.x - 1), tv = (float)j / (float)(size.y - 1);
    *u = u0 * (1.0f - tu) + u1 * tu;
    *v = v0 * (1.0f - tv) + v1 * tv;
}

/* With a shading rate: the segments bound chose for edge `edge`
 * (REYES_EDGE_*) of sp (reyes_rate.cl), a byte of edge_levels. */
REYES_INLINE int reyes_edge_count(const struct reyes_subpatch *sp, int edge)
{
    return (int)((sp->edge_levels >> (8 * edge)) & 0xffu);
}

/* Grid coordinates (i, j) of vertex k along edge `edge` (k in the edge's
 * own direction: increasing u or v) of a grid of size.x x size.y. */
REYES_INLINE int2 reyes_edge_vertex(uint edge, int k, int2 size)
{
    switch (edge) {
    case REYES_EDGE_V0: return (int2)(k, 0);
    case REYES_EDGE_U1: return (int2)(size.x - 1, k);
    case REYES_EDGE_V1: return (int2)(k, size.y - 1);
    default: return (int2)(0, k);
    }
}

/* sp with the grid size whose vertices along edge `edge` are the edge's
 * own (reyes_edge_count + 1 of them with a shading rate; the grid's
 * without one), for reyes_grid_vertex and reyes_edge_vertex. */
REYES_INLINE struct reyes_subpatch reyes_edge_subpatch(__global const struct reyes_params *p,
                                                      const struct reyes_subpatch *sp, int edge)
{
    struct reyes_subpatch out = *sp;
    if (sp->dice_size == 0u || p->shading_rate <= 0.0f)
        return out;
    uint c = (uint)reyes_edge_count(sp, edge) + 1u;
    if (edge == REYES_EDGE_V0 || edge == REYES_EDGE_V1)
        out.dice_size = (sp->dice_size & ~0xffu) | c;
    else
        out.dice_size = (sp->dice_size & ~0xff00u) | (c << 8);
    return out;
}

REYES_INLINE float2 reyes_grid_uv(__global const struct reyes_params *p, const struct reyes_subpatch *sp, int i,
                                  int j)
{
    float u, v;
    reyes_grid_uv_of(reyes_dice_size(p, sp->dice_size), sp->u0, sp->v0, sp->u1, sp->v1, i, j, &u, &v);
    return (float2)(u, v);
}

/* The colour (or packed normal, reyes_shade) of the undisplaced point at
 * (u,v), or of grid vertex (i,j), for the patch's packed base colour
 * rgba, the normal taken slightly inside where it vanishes
 * (reyes_vertex_normal_from). */
uint reyes_vertex_color_at(__global const struct reyes_params *p, const float3 cp[16], float u, float v, uint rgba)
{
    float3 x, n;
    int collapsed = reyes_patch_point_normal(cp, u, v, &x, &n);
    return reyes_shade(p, x, reyes_vertex_normal_from(p, cp, u, v, n, collapsed), rgba);
}

uint reyes_grid_vertex_color(__global const struct reyes_params *p, const float3 cp[16],
                             const struct reyes_subpatch *sp, uint rgba, int i, int j)
{
    float2 uv = reyes_grid_uv(p, sp, i, j);
    return reyes_vertex_color_at(p, cp, uv.x, uv.y, rgba);
}

/* Position (clip space) of grid vertex (i,j), and its color when `shade`
 * (`rgba`: the patch's packed base color); displaced when the parameters
 * ask for it.
 *
 * The base color comes in packed, not as a float3 argument: this function
 * is too big to inline and is called from two procedures, so Intel's CPU
 * compiler (2026.22) calls a 16-wide vector variant of it, and that variant
 * reads a varying float3 argument with the wrong per-lane stride (lanes got
 * the channels of their neighbours, some zeros: grey images with a black
 * stripe per grid column).  A float3 passed by value or through a pointer
 * to one is affected; float4, scalars, arrays and structs are not. */
struct reyes_vertex reyes_grid_vertex(const struct reyes_displacement *d, const float3 cp[16],
                                      const struct reyes_subpatch *sp, uint rgba, int i, int j,
                                      int shade)
{
    __global const struct reyes_params *p = d->params;
    float2 uv = reyes_grid_uv(p, sp, i, j);
    float u = uv.x, v = uv.y;
    struct reyes_vertex out;
    if (p->displace_mode == REYES_DISPLACE_NONE) {
        float3 x, n;
        int collapsed = reyes_patch_point_normal(cp, u, v, &x, &n);
        reyes_vertex_place(p, x, &out);
        out.rgba = shade ? reyes_shade(p, x, reyes_vertex_normal_from(p, cp, u, v, n, collapsed), rgba) : 0u;
    } else {
        float3 x = reyes_displaced_point(d, cp, u, v);
        reyes_vertex_place(p, x, &out);
        out.rgba = shade ? reyes_shade(p, x, reyes_displaced_normal(d, cp, u, v), rgba) : 0u;
    }
    return out;
}
