/*
 * dice: evaluate a sub-patch on a grid x grid vertex lattice, shade each
 * vertex and emit the (grid-1)^2 quads as micropolygons.  The threads of an
 * item share the vertices, then the quads (v, q = thread, thread + threads,
 * ...), with one barrier between, through REYES_DICE_VERTEX_BYTES of
 * __local scratch per vertex.  Vertices are evaluated on the base patch at
 * global (u,v), so a vertex shared by two sub-patches is bit-identical
 * wherever it is computed.
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

/* Cooperative: every work-item of the group calls it.  The item's threads
 * first evaluate and shade each grid vertex once into __local scratch, then,
 * after the barrier, assemble the quads from it. */
void reyes_dice(perma_ctx *ctx, __local const struct reyes_subpatch *item)
{
    __global const struct reyes_params *p = ctx->buf.params;
    __global uint *counters = ctx->buf.counters;
    __local struct reyes_vertex *grid = (__local struct reyes_vertex *)ctx->scratch;
    int n = (int)p->grid, side = n - 1;
    int threads = (int)p->dice_threads;
    int diced = ctx->active && p->stages != REYES_STAGES_SUBDIVIDE;
    int full = p->stages == REYES_STAGES_ALL;
    struct reyes_subpatch sp;
    if (ctx->active) {
        sp = *item;
        if (ctx->thread == 0)
            atomic_inc(&counters[REYES_COUNT_GRIDS]);
    }
    if (diced) {
        float3 cp[16];
        reyes_load_patch(ctx->buf.patches, sp.patch, cp);
        float3 base = reyes_unpack_rgb(ctx->buf.colors[sp.patch]);
        for (int v = (int)ctx->thread; v < n * n; v += threads)
            grid[v] = reyes_grid_vertex(p, cp, &sp, base, v % n, v / n, full);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (!diced)
        return;

    const int corner_i[4] = {0, 1, 1, 0}, corner_j[4] = {0, 0, 1, 1};
    for (int q = (int)ctx->thread; q < side * side; q += threads) {
        int i = q % side, j = q / side;
        struct reyes_quad quad;
        int visible = 1;
        float2 lo = (float2)(INFINITY, INFINITY), hi = (float2)(-INFINITY, -INFINITY);
        for (int k = 0; k < 4; ++k) {
            struct reyes_vertex vtx = grid[(j + corner_j[k]) * n + i + corner_i[k]];
            visible &= vtx.clip.w > p->near_w;
            float2 s = reyes_to_screen(p, vtx.clip);
            quad.x[k] = s.x;
            quad.y[k] = s.y;
            quad.z[k] = vtx.clip.w;
            quad.rgba[k] = vtx.rgba;
            lo = fmin(lo, s);
            hi = fmax(hi, s);
        }
        /* Quads through the near plane or wholly off the tile (the image
         * without buckets) are dropped. */
        visible &= hi.x >= p->tile_x0 && hi.y >= p->tile_y0 && lo.x <= p->tile_x1
                   && lo.y <= p->tile_y1;
        if (visible) {
            atomic_inc(&counters[REYES_COUNT_MICROPOLYGONS]);
            if (full)
                emit_rasterize(ctx, &quad);
        }
    }
}
