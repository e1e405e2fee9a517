/*
 * Occlusion culling (reyes_params.occlusion_cull): dice skips a small grid
 * whose every sample position under its projected hull already holds a
 * surface nearer than the nearest point the grid can have, so that
 * dicing, shading and rasterizing it could not change a sample.  The
 * hull's octagon is also the sampleless test's (reyes_hull_has_sample,
 * reyes_bound.cl).  The constants (REYES_SAMPLE_BOX_MARGIN,
 * REYES_OCCLUSION_*) are in reyes_shared.h: the C reference makes the
 * same test.
 */

/* The octagon around a projected hull s[16] with screen box lo..hi: the
 * box cut by the extremes of x + y and x - y (diag_lo, diag_hi: .x for
 * x + y, .y for x - y), each side moved out by REYES_SAMPLE_BOX_MARGIN. */
struct reyes_octagon {
    float2 lo, hi, diag_lo, diag_hi;
};

struct reyes_octagon reyes_hull_octagon(const float2 s[16], float2 lo, float2 hi)
{
    struct reyes_octagon o;
    o.lo = lo - REYES_SAMPLE_BOX_MARGIN;
    o.hi = hi + REYES_SAMPLE_BOX_MARGIN;
    o.diag_lo = (float2)(INFINITY, INFINITY);
    o.diag_hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < 16; ++k) {
        float2 d = (float2)(s[k].x + s[k].y, s[k].x - s[k].y);
        o.diag_lo = fmin(o.diag_lo, d);
        o.diag_hi = fmax(o.diag_hi, d);
    }
    o.diag_lo -= 2.0f * REYES_SAMPLE_BOX_MARGIN;
    o.diag_hi += 2.0f * REYES_SAMPLE_BOX_MARGIN;
    return o;
}

REYES_INLINE int reyes_octagon_contains(const struct reyes_octagon *o, float2 at)
{
    float2 d = (float2)(at.x + at.y, at.x - at.y);
    return all(at >= o->lo) && all(at <= o->hi) && all(d >= o->diag_lo) && all(d <= o->diag_hi);
}

/* 1 when the sub-patch cannot change the image because every sample of
 * the tile inside its projected hull's octagon already holds a depth
 * nearer than the hull's nearest clip w (less the margins): the surface
 * lies in its control hull, so each point of it has a w at least that
 * nearest one, and a sample keeps the smallest (depth, colour).  0 when
 * the hull crosses the near plane, spans more than REYES_OCCLUSION_PIXELS
 * pixels, or any sample under it is farther or empty.
 *
 * Other groups write the samples concurrently (atom_min).  The values
 * only ever decrease, so a stale read is a depth too far, never too near:
 * it can only keep a grid that could have been culled, never cull one
 * that shows.  Which grids are culled therefore depends on the order
 * grids are rasterized in (the schedule, the timing), the image does not. */
int reyes_grid_occluded(__global const struct reyes_params *p, __global const float4 *patches,
                        __global ulong *samples, const struct reyes_subpatch *sp)
{
    float3 cp[16];
    reyes_subpatch_points(patches, sp, cp);
    __global const float *m = p->view_proj;
    float largest = 0.0f, nearest = INFINITY;
    float2 s[16];
    float2 lo = (float2)(INFINITY, INFINITY), hi = (float2)(-INFINITY, -INFINITY);
    for (int k = 0; k < 16; ++k) {
        float4 clip = reyes_to_clip(p, cp[k]);
        if (!(clip.w > p->near_w))
            return 0;
        nearest = fmin(nearest, clip.w);
        largest = fmax(largest, fabs(cp[k].x) + fabs(cp[k].y) + fabs(cp[k].z));
        s[k] = reyes_to_screen(p, clip);
        lo = fmin(lo, s[k]);
        hi = fmax(hi, s[k]);
    }
    struct reyes_octagon o = reyes_hull_octagon(s, lo, hi);
    if (!(o.hi.x >= p->tile_x0 && o.hi.y >= p->tile_y0 && o.lo.x < p->tile_x1 && o.lo.y < p->tile_y1))
        return 0; /* off the tile or NaN */
    float2 first = fmax(floor(o.lo), (float2)(p->tile_x0, p->tile_y0));
    float2 last = fmin(floor(o.hi), (float2)(p->tile_x1 - 1.0f, p->tile_y1 - 1.0f));
    if ((last.x - first.x + 1.0f) * (last.y - first.y + 1.0f) > (float)REYES_OCCLUSION_PIXELS)
        return 0;
    float row_w = fabs(m[12]) + fabs(m[13]) + fabs(m[14]);
    float slack = nearest * REYES_OCCLUSION_RELATIVE
                  + REYES_OCCLUSION_ULPS * FLT_EPSILON * (largest * row_w + fabs(m[15]));
    float limit = nearest - slack;
    if (!(limit > 0.0f))
        return 0;
    uint limit_bits = as_uint(limit); /* depths >= 0 order like their bits */
    uint spp = p->spp, columns = reyes_sample_columns(spp), rows = (spp + columns - 1u) / columns;
    uint tile_x = (uint)p->tile_x0, tile_y = (uint)p->tile_y0, tile_width = (uint)p->tile_x1 - tile_x;
    for (uint py = (uint)first.y; py <= (uint)last.y; ++py)
        for (uint px = (uint)first.x; px <= (uint)last.x; ++px)
            for (uint k = 0; k < spp; ++k) {
                /* The depth first: a sample nearer than the limit needs no
                 * position (a hidden grid's test makes none). */
                uint index = ((py - tile_y) * tile_width + (px - tile_x)) * spp + k;
                if (reyes_sample_depth_bits(samples, index) < limit_bits)
                    continue;
                if (reyes_octagon_contains(&o, reyes_sample_position_on(px, py, k, columns, rows)))
                    return 0;
            }
    return 1;
}
