/*
 * Surface evaluation and shading shared by dice and stitch: a grid vertex
 * of a sub-patch is evaluated on its base patch at global (u,v) by
 * reyes_grid_vertex, so the same vertex computed by either procedure is
 * bit-identical.
 */

struct reyes_vertex {      /* REYES_DICE_VERTEX_BYTES (32) bytes */
    float4 clip;
    uint rgba;
#ifdef REYES_VERTEX_MOTION /* REYES_DICE_MOVING_VERTEX_BYTES (48) */
    float4 motion;         /* clip-space motion over the shutter */
#endif
};

/* Set a vertex's clip position (and, with per-vertex motion, its motion)
 * from its world position. */
void reyes_vertex_place(__global const struct reyes_params *p, float3 x, struct reyes_vertex *v)
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

/* Unnormalised surface normal at (u,v). */
float3 reyes_patch_normal(const float3 cp[16], float u, float v)
{
    float4 bu = reyes_bernstein(u), bv = reyes_bernstein(v);
    float4 du = reyes_bernstein_deriv(u), dv = reyes_bernstein_deriv(v);
    float bu_a[4] = {bu.x, bu.y, bu.z, bu.w}, bv_a[4] = {bv.x, bv.y, bv.z, bv.w};
    float du_a[4] = {du.x, du.y, du.z, du.w}, dv_a[4] = {dv.x, dv.y, dv.z, dv.w};
    float3 tu = (float3)(0.0f), tv = (float3)(0.0f);
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            tu += (bv_a[r] * du_a[c]) * cp[r * 4 + c];
            tv += (dv_a[r] * bu_a[c]) * cp[r * 4 + c];
        }
    }
    return cross(tu, tv);
}

float3 reyes_patch_point(const float3 cp[16], float u, float v)
{
    float4 bu = reyes_bernstein(u), bv = reyes_bernstein(v);
    float bu_a[4] = {bu.x, bu.y, bu.z, bu.w}, bv_a[4] = {bv.x, bv.y, bv.z, bv.w};
    float3 x = (float3)(0.0f);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            x += (bv_a[r] * bu_a[c]) * cp[r * 4 + c];
    return x;
}

/* Normal at (u,v); where a patch edge collapses to a point (a pole) the
 * derivative cross product vanishes, so take it slightly inside. */
float3 reyes_safe_normal(const float3 cp[16], float u, float v)
{
    float3 n = reyes_patch_normal(cp, u, v);
    for (int step = 1; step <= 3 && dot(n, n) < 1e-24f; ++step) {
        float nudge = 1e-3f * (float)step;
        n = reyes_patch_normal(cp, mix(u, 0.5f, nudge), mix(v, 0.5f, nudge));
    }
    return n;
}

/* The Blinn-Phong highlight cos_h^shininess.  pow() is PoCL's
 * full-precision library call and took about a fifth of a teapot render
 * (perf, 1280x1024); exp2(s log2 c) at native precision is plenty for an
 * 8-bit colour (the teapot's bytes did not change). */
float reyes_highlight(float cos_h, float shininess)
{
    return cos_h > 0.0f ? native_exp2(shininess * native_log2(cos_h)) : 0.0f;
}

/* Lambert plus Blinn-Phong, two-sided, one directional light plus ambient. */
uint reyes_shade(__global const struct reyes_params *p, float3 x, float3 n, float3 base)
{
    float3 view = normalize(vload3(0, p->eye) - x);
    float3 normal = dot(n, n) > 0.0f ? normalize(n) : view;
    if (dot(normal, view) < 0.0f)
        normal = -normal;
    float3 light = vload3(0, p->light_dir);
    float lambert = fmax(dot(normal, light), 0.0f);
    float3 half_vector = normalize(light + view);
    float highlight = lambert > 0.0f ? reyes_highlight(dot(normal, half_vector), p->shininess) : 0.0f;
    float3 color = base * (p->ambient + p->diffuse * lambert) + (float3)(p->specular * highlight);
    return reyes_pack_rgba(color);
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
    float3 base = reyes_unpack_rgb(rgba);
    float last = (float)(p->grid - 1u);
    /* mix(a, b, 1) == b exactly, so shared patch edges get equal u, v. */
    float tu = (float)i / last, tv = (float)j / last;
    float u = sp->u0 * (1.0f - tu) + sp->u1 * tu;
    float v = sp->v0 * (1.0f - tv) + sp->v1 * tv;
    struct reyes_vertex out;
    if (p->displace_mode == REYES_DISPLACE_NONE) {
        float3 x = reyes_patch_point(cp, u, v);
        reyes_vertex_place(p, x, &out);
        out.rgba = shade ? reyes_shade(p, x, reyes_safe_normal(cp, u, v), base) : 0u;
    } else {
        float3 x = reyes_displaced_point(d, cp, u, v);
        reyes_vertex_place(p, x, &out);
        out.rgba = shade ? reyes_shade(p, x, reyes_displaced_normal(d, cp, u, v), base) : 0u;
    }
    return out;
}
