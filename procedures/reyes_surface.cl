/*
 * Surface evaluation and shading shared by dice and stitch: a grid vertex
 * of a sub-patch is evaluated on its base patch at global (u,v) by
 * reyes_grid_vertex, so the same vertex computed by either procedure is
 * bit-identical.
 */

struct reyes_vertex {      /* REYES_DICE_VERTEX_BYTES (32) bytes */
    float4 clip;
    uint rgba;
};

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
    float highlight = lambert > 0.0f ? pow(fmax(dot(normal, half_vector), 0.0f), p->shininess) : 0.0f;
    float3 color = base * (p->ambient + p->diffuse * lambert) + (float3)(p->specular * highlight);
    return reyes_pack_rgba(color);
}

/* Position (clip space) of grid vertex (i,j), and its color when `shade`. */
struct reyes_vertex reyes_grid_vertex(__global const struct reyes_params *p, const float3 cp[16],
                                      const struct reyes_subpatch *sp, float3 base, int i, int j,
                                      int shade)
{
    float last = (float)(p->grid - 1u);
    /* mix(a, b, 1) == b exactly, so shared patch edges get equal u, v. */
    float tu = (float)i / last, tv = (float)j / last;
    float u = sp->u0 * (1.0f - tu) + sp->u1 * tu;
    float v = sp->v0 * (1.0f - tv) + sp->v1 * tv;
    float3 x = reyes_patch_point(cp, u, v);
    struct reyes_vertex out;
    out.clip = reyes_to_clip(p, x);
    out.rgba = shade ? reyes_shade(p, x, reyes_safe_normal(cp, u, v), base) : 0u;
    return out;
}
