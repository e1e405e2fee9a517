/*
 * The tiered subdivision criterion (REYES_SUBDIVISION_TIERED), after the
 * view-adaptive criterion of Tabaei, Kuth, Oberberger and Meyer (2026):
 * a sub-patch is flat when each of its control-net curves is close to
 * the straight, uniformly parametrised line between its end points.
 *
 * For a curve b0..b3 the deviation of b1 (b2) from the chord point at
 * 1/3 (2/3) has a geometric part, perpendicular to the chord (the shape
 * is not straight), and a parametric part along it (the parametrisation
 * is not uniform, so grid vertices bunch up).  The distance of a curve is
 * mix(geometric, full deviation, lambda) in pixels, lambda in [0,1]
 * (0: shape only; 1: the whole deviation).
 *
 * Tiers: the edge tier is the four boundary curves, a function of the
 * edge's own control points only, so two sub-patches sharing an edge
 * agree on it; the inner tier is the two inner rows and columns.  With
 * straight, uniform rows and columns the patch is exactly bilinear.
 */

/* Bit flags of reyes_tiers.failed: which tier exceeds epsilon. */
#define REYES_TIER_EDGE 1
#define REYES_TIER_INNER 2

struct reyes_tiers {
    float along_u;  /* largest distance of the rows (curves along u), pixels */
    float along_v;  /* of the columns */
    int failed;     /* REYES_TIER_* over epsilon */
};

/* Geometric and full deviation (world units) of a cubic's inner control
 * points from its uniform chord.  The end points are put in a canonical
 * order first, so a curve and its reverse give the same bits. */
float2 reyes_curve_deviation(float3 b0, float3 b1, float3 b2, float3 b3)
{
    int swap = b0.x > b3.x || (b0.x == b3.x && (b0.y > b3.y || (b0.y == b3.y && b0.z > b3.z)));
    if (swap) {
        float3 t = b0;
        b0 = b3;
        b3 = t;
        t = b1;
        b1 = b2;
        b2 = t;
    }
    float3 chord = b3 - b0;
    float3 e1 = b1 - (b0 + chord * (1.0f / 3.0f));
    float3 e2 = b2 - (b0 + chord * (2.0f / 3.0f));
    float full = fmax(length(e1), length(e2));
    float chord_length = length(chord);
    if (!(chord_length > 0.0f))
        return (float2)(full, full); /* a closed or collapsed curve */
    float3 t = chord / chord_length;
    float geometric = fmax(length(e1 - dot(e1, t) * t), length(e2 - dot(e2, t) * t));
    return (float2)(geometric, full);
}

/* Pixels per world unit at the hull's nearest depth (an upper bound over
 * the hull for a displacement perpendicular to the view; cf. grow_box). */
float reyes_pixels_per_unit(__global const struct reyes_params *p, const float4 clip[16])
{
    __global const float *m = p->view_proj;
    float r0 = length((float3)(m[0], m[1], m[2])), r1 = length((float3)(m[4], m[5], m[6]));
    float r3 = length((float3)(m[12], m[13], m[14]));
    float w_min = INFINITY, ndc_x = 0.0f, ndc_y = 0.0f;
    for (int k = 0; k < 16; ++k) {
        w_min = fmin(w_min, clip[k].w);
        ndc_x = fmax(ndc_x, fabs(clip[k].x / clip[k].w));
        ndc_y = fmax(ndc_y, fabs(clip[k].y / clip[k].w));
    }
    return fmax(0.5f * p->width * (r0 + ndc_x * r3), 0.5f * p->height * (r1 + ndc_y * r3)) / w_min;
}

/* Distance of curve `line` (a row when along_u, else a column) in pixels. */
float reyes_curve_distance(__global const struct reyes_params *p, const float3 cp[16], int line,
                           int along_u, float scale)
{
    int first = along_u ? line * 4 : line, stride = along_u ? 1 : 4;
    float2 d = reyes_curve_deviation(cp[first], cp[first + stride], cp[first + 2 * stride],
                                     cp[first + 3 * stride]);
    return scale * mix(d.x, d.y, p->flat_lambda);
}

/* Evaluate both tiers of a projectable sub-patch. */
struct reyes_tiers reyes_flatness(__global const struct reyes_params *p, const float3 cp[16],
                                  const float4 clip[16])
{
    float scale = reyes_pixels_per_unit(p, clip);
    struct reyes_tiers tiers = { 0.0f, 0.0f, 0 };
    for (int line = 0; line < 4; ++line) {
        int tier = (line == 0 || line == 3) ? REYES_TIER_EDGE : REYES_TIER_INNER;
        float row = reyes_curve_distance(p, cp, line, 1, scale);
        float column = reyes_curve_distance(p, cp, line, 0, scale);
        tiers.along_u = fmax(tiers.along_u, row);
        tiers.along_v = fmax(tiers.along_v, column);
        if (fmax(row, column) > p->flat_epsilon)
            tiers.failed |= tier;
    }
    return tiers;
}
