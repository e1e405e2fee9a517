/*
 * Dicing to a shading rate (reyes_params.shading_rate > 0): how many
 * micropolygons each curve of a sub-patch asks for, and the count along
 * each of its edges, chosen from the edge's own control points only, as
 * GPU tessellation chooses an edge's factor: the sub-patches on both
 * sides of an edge of equal span compute the same count from the same
 * bits and so put the same vertices on it (reyes_dice.cl makes the grid's
 * boundary follow its edges' counts).  Edges of different spans (a
 * coarser neighbour: T-junctions) are stitched (reyes_stitch.cl).
 */

/* Micropolygons along a cubic curve with control points b[0..3] (world)
 * projecting to pixels s[0..3] (clip points clip[0..3]): its length on
 * screen over the rate's side sqrt(R), rounded to nearest, and where it
 * bends, enough that each piece's chord stays within rate_sag pixels of
 * it on screen, though no piece shorter than rate_min_piece sides in
 * space (pixels at the curve's nearest depth: distant patches are not
 * diced finer than they show, while a curve seen end-on at a silhouette
 * still is).  The length lies between the chord's and the control
 * polygon's (their mean is within a few percent for a cubic's arcs).  A
 * cubic strays from its chord by at most 3/4 of its inner control points'
 * distance from it, which falls with the square of the number of equal
 * pieces; that distance counts both the part across the chord and how far
 * past its ends the curve reaches (where the surface folds away from the
 * eye its lines double back on screen).  At least 1. */
float reyes_rate_curve(__global const struct reyes_params *p, const float3 b[4], const float4 clip[4],
                       const float2 s[4])
{
    float polygon = distance(s[0], s[1]) + distance(s[1], s[2]) + distance(s[2], s[3]);
    float2 chord = s[3] - s[0];
    float chord2 = dot(chord, chord), stray = 0.0f;
    for (int k = 1; k <= 2; ++k) {
        float2 inner = s[k] - s[0];
        if (chord2 > 0.0f) {
            float t = dot(inner, chord) / chord2;
            float across = fabs(inner.x * chord.y - inner.y * chord.x) * rsqrt(chord2);
            float beyond = fmax(fmax(-t, t - 1.0f), 0.0f) * sqrt(chord2);
            stray = fmax(stray, fmax(across, beyond));
        } else {
            stray = fmax(stray, length(inner));
        }
    }
    float space = distance(b[0], b[1]) + distance(b[1], b[2]) + distance(b[2], b[3]);
    float side = rsqrt(p->shading_rate);
    float by_rate = floor(0.5f * (polygon + sqrt(chord2)) * side + 0.5f);
    float by_stray = ceil(sqrt(0.75f * stray / p->rate_sag));
    float finest = ceil(space * reyes_pixels_per_unit(p, clip, 4) * side / p->rate_min_piece);
    return fmax(fmax(by_rate, fmin(by_stray, finest)), 1.0f);
}

/* Micropolygons a projected sub-patch needs along u and v: the most that
 * three of its lines along u ask for (its two edges and the middle line
 * v = 1/2, whose control points are the rows' blend 1/8, 3/8, 3/8, 1/8:
 * lines of the surface, not the control net's inner rows, which bulge
 * out past it), and likewise along v. */
float2 reyes_rate_segments(__global const struct reyes_params *p, const float3 cp[16], const float4 clip[16],
                           const float2 s[16])
{
    float need[2] = {0.0f, 0.0f};
    for (int along = 0; along < 2; ++along) {
        for (int line = 0; line < 3; ++line) {
            float3 b[4];
            float4 c[4];
            float2 t[4];
            for (int k = 0; k < 4; ++k) {
                if (line < 2) {
                    int i = along ? k * 4 + 3 * line : 3 * line * 4 + k;
                    b[k] = cp[i];
                    c[k] = clip[i];
                    t[k] = s[i];
                } else {
                    int stride = along ? 1 : 4, first = along ? k * 4 : k;
                    b[k] = (cp[first] + 3.0f * (cp[first + stride] + cp[first + 2 * stride]) + cp[first + 3 * stride])
                           * 0.125f;
                    c[k] = reyes_to_clip(p, b[k]);
                    t[k] = reyes_to_screen(p, c[k]);
                }
            }
            need[along] = fmax(need[along], reyes_rate_curve(p, b, c, t));
        }
    }
    return (float2)(need[0], need[1]);
}

/* Micropolygons along segment [a,b] of the line (along_u, fixed) of base
 * patch `base` (reyes_line_curve): the rate's count (reyes_rate_curve) of
 * its control points blossomed in the canonical direction
 * (reyes_restrict_canonical) and measured in that order, so the
 * neighbour across it (in this or a glued base patch) computes the same
 * bits; -1 if a point is not in front of the near plane. */
float reyes_rate_span(__global const struct reyes_params *p, const float3 base[16], int along_u, float fixed,
                      float a, float b)
{
    float3 line[4], e[4];
    reyes_line_curve(base, along_u, fixed, line);
    /* The whole line is its own control points (both sides: the same
     * rule), without blossoming them. */
    if (a == 0.0f && b == 1.0f) {
        for (int k = 0; k < 4; ++k)
            e[k] = line[k];
    } else {
        reyes_restrict_canonical(line, a, b, e);
    }
    int reversed = reyes_curve_reversed(line);
    float3 c[4];
    float4 clip[4];
    float2 s[4];
    for (int k = 0; k < 4; ++k) {
        c[k] = e[reversed ? 3 - k : k];
        clip[k] = reyes_to_clip(p, c[k]);
        if (clip[k].w <= p->near_w)
            return -1.0f;
        s[k] = reyes_to_screen(p, clip[k]);
    }
    return reyes_rate_curve(p, c, clip, s);
}

/* Segments along edge `edge` (REYES_EDGE_*) of sub-patch sp, from the
 * edge's own control points (reyes_rate_span).  At most grid - 1; grid - 1
 * if a point is not in front of the near plane. */
uint reyes_rate_edge(__global const struct reyes_params *p, const float3 base[16], const struct reyes_subpatch *sp,
                     int edge)
{
    int along_u;
    float fixed, a, b;
    reyes_edge_line(sp, edge, &along_u, &fixed, &a, &b);
    uint most = p->grid - 1u;
    float count = reyes_rate_span(p, base, along_u, fixed, a, b);
    return count < 0.0f ? most : (uint)fmin(count, (float)most);
}

/* The four edges' segments, a byte each in REYES_EDGE_* order (kept in
 * reyes_subpatch.edge_levels for dice and the stitches). */
uint reyes_rate_edges(__global const struct reyes_params *p, __global const float4 *patches,
                      const struct reyes_subpatch *sp)
{
    float3 base[16];
    reyes_load_patch(patches, sp->patch, base);
    uint counts = 0u;
    for (int edge = 0; edge < 4; ++edge)
        counts |= reyes_rate_edge(p, base, sp, edge) << (8 * edge);
    return counts;
}
