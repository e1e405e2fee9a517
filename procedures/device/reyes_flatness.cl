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

/* The projection terms of `count` clip points, in front of the near plane:
 * .x, .y = pixels per world unit of a displacement perpendicular to the
 * view, times the depth (0.5 width (|r0| + max |x/w| |r3|), likewise in y;
 * r the view-projection rows), .z = |r3| (how far a unit displacement can
 * move w), .w = the nearest w.  Shared by the flatness scale below and the
 * bound's growth of a displaced hull (reyes_grow_box). */
float4 reyes_projection_terms(__global const struct reyes_params *p, const float4 *clip, int count)
{
    __global const float *m = p->view_proj;
    float r0 = length((float3)(m[0], m[1], m[2])), r1 = length((float3)(m[4], m[5], m[6]));
    float r3 = length((float3)(m[12], m[13], m[14]));
    float w_min = INFINITY, ndc_x = 0.0f, ndc_y = 0.0f;
    for (int k = 0; k < count; ++k) {
        w_min = fmin(w_min, clip[k].w);
        ndc_x = fmax(ndc_x, fabs(clip[k].x / clip[k].w));
        ndc_y = fmax(ndc_y, fabs(clip[k].y / clip[k].w));
    }
    return (float4)(0.5f * p->width * (r0 + ndc_x * r3), 0.5f * p->height * (r1 + ndc_y * r3), r3, w_min);
}

/* Pixels per world unit at the nearest depth of `count` clip points (an
 * upper bound over them for a displacement perpendicular to the view). */
float reyes_pixels_per_unit(__global const struct reyes_params *p, const float4 *clip, int count)
{
    float4 terms = reyes_projection_terms(p, clip, count);
    return fmax(terms.x, terms.y) / terms.w;
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
    float scale = reyes_pixels_per_unit(p, clip, 16);
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

/*
 * Wedges (REYES_CRACK_FIX_WEDGE): crack-free subdivision without
 * communication between patches.  An edge of a sub-patch lies on a line of
 * its base patch (u or v fixed); the dyadic segments of that line holding
 * the edge form a chain that the sub-patches on both sides share.  The
 * edge is settled at the coarsest segment of the chain that is flat
 * (edge tier alone, measured from the segment's own control points), and
 * both sides then reach to the same polyline close to it: dice adds a
 * wedge strip between its true boundary and the polyline (reyes_polyline
 * below).  Segment control points
 * come from the base patch by blossoming in a canonical direction, and a
 * base-patch boundary line is the control net's own row or column, so two
 * sides compute the same bits even across base patches.
 */

#define REYES_EDGE_UNSETTLED 0xffu

/* The cubic along a line of a base patch: v = fixed (along_u) or u = fixed. */
void reyes_line_curve(const float3 base[16], int along_u, float fixed, float3 out[4])
{
    for (int k = 0; k < 4; ++k) {
        int first = along_u ? k : k * 4, stride = along_u ? 4 : 1;
        if (fixed == 0.0f)
            out[k] = base[first];
        else if (fixed == 1.0f)
            out[k] = base[first + 3 * stride];
        else
            out[k] = reyes_blossom(base[first], base[first + stride], base[first + 2 * stride],
                                   base[first + 3 * stride], fixed, fixed, fixed);
    }
}

/* 1 when the curve runs against the canonical order of its end points. */
int reyes_curve_reversed(const float3 q[4])
{
    return q[0].x > q[3].x
           || (q[0].x == q[3].x && (q[0].y > q[3].y || (q[0].y == q[3].y && q[0].z > q[3].z)));
}

/* Control points of the line curve over [a,b] (dyadic), blossomed in the
 * canonical direction; out[] in the line's own direction. */
void reyes_restrict_canonical(const float3 q[4], float a, float b, float3 out[4])
{
    if (reyes_curve_reversed(q)) {
        float ra = 1.0f - b, rb = 1.0f - a;
        out[3] = reyes_blossom(q[3], q[2], q[1], q[0], ra, ra, ra);
        out[2] = reyes_blossom(q[3], q[2], q[1], q[0], ra, ra, rb);
        out[1] = reyes_blossom(q[3], q[2], q[1], q[0], ra, rb, rb);
        out[0] = reyes_blossom(q[3], q[2], q[1], q[0], rb, rb, rb);
    } else {
        out[0] = reyes_blossom(q[0], q[1], q[2], q[3], a, a, a);
        out[1] = reyes_blossom(q[0], q[1], q[2], q[3], a, a, b);
        out[2] = reyes_blossom(q[0], q[1], q[2], q[3], a, b, b);
        out[3] = reyes_blossom(q[0], q[1], q[2], q[3], b, b, b);
    }
}

/* The edge tier for one curve, from its own four points only. */
int reyes_edge_flat(__global const struct reyes_params *p, const float3 e[4])
{
    float4 clip[4];
    for (int k = 0; k < 4; ++k) {
        clip[k] = reyes_to_clip(p, e[k]);
        if (clip[k].w <= p->near_w)
            return 0;
    }
    float scale = reyes_pixels_per_unit(p, clip, 4);
    float2 d = reyes_curve_deviation(e[0], e[1], e[2], e[3]);
    return scale * mix(d.x, d.y, p->flat_lambda) <= p->flat_epsilon;
}

/* Start of the level-`level` dyadic segment holding [a, ...). */
float reyes_segment_start(float a, uint level)
{
    float span = ldexp(1.0f, -(int)level);
    return floor(a / span) * span;
}

/* Coarsest level at which the segment of the line holding [a,b] is flat,
 * or REYES_EDGE_UNSETTLED. */
uint reyes_settled_level(__global const struct reyes_params *p, const float3 line[4], float a,
                         float b)
{
    float length = b - a;
    uint level = 0u;
    for (float span = 1.0f; span >= length; span *= 0.5f, ++level) {
        float start = reyes_segment_start(a, level);
        float3 e[4];
        reyes_restrict_canonical(line, start, start + span, e);
        if (reyes_edge_flat(p, e))
            return level;
    }
    return REYES_EDGE_UNSETTLED;
}

/* The line of edge `edge` (REYES_EDGE_*) of a sub-patch: direction, the
 * fixed parameter and the edge's interval along it. */
void reyes_edge_line(const struct reyes_subpatch *sp, int edge, int *along_u, float *fixed,
                     float *a, float *b)
{
    *along_u = edge == REYES_EDGE_V0 || edge == REYES_EDGE_V1;
    *fixed = edge == REYES_EDGE_V0 ? sp->v0 : edge == REYES_EDGE_V1 ? sp->v1
             : edge == REYES_EDGE_U0 ? sp->u0 : sp->u1;
    *a = *along_u ? sp->u0 : sp->v0;
    *b = *along_u ? sp->u1 : sp->v1;
}

/* Settled levels of the four edges, a byte each in REYES_EDGE_* order. */
uint reyes_edge_levels(__global const struct reyes_params *p, const float3 base[16],
                       const struct reyes_subpatch *sp)
{
    uint levels = 0u;
    for (int edge = 0; edge < 4; ++edge) {
        int along_u;
        float fixed, a, b;
        reyes_edge_line(sp, edge, &along_u, &fixed, &a, &b);
        float3 line[4];
        reyes_line_curve(base, along_u, fixed, line);
        levels |= reyes_settled_level(p, line, a, b) << (8 * edge);
    }
    return levels;
}

/* Where an edge's wedge strip reaches: the settled segment's curve
 * sampled at grid - 1 equal steps (its *polyline*), made once per edge
 * and then sampled by reyes_strip_point at the edge's own grid steps.
 * Every sub-patch edge inside the segment is a dyadic part of it, diced
 * at grid - 1 steps too, so the polyline's corners fall on grid steps of
 * every such edge: each side follows the polyline exactly, corner for
 * corner, and between corners the points lie on the same straight piece.
 * The polyline strays from the curve by about epsilon / (grid - 1)^2
 * (the segment is flat within epsilon), so a strip overhangs an open
 * boundary or a fold by that much at most; the segment's straight chord,
 * which the strips reached before, strays by up to epsilon. */
struct reyes_polyline {
    float3 c[4];        /* the segment's control points in the canonical direction */
    ulong first;        /* the edge's first vertex: step units from the canonical start */
    ulong steps;        /* step units across the segment: side << shift */
    uint side;          /* the polyline's pieces (grid - 1) */
    uint shift;         /* step units per polyline piece, log2: the edge is 2^-shift of the segment */
    int reversed;       /* the edge runs against the canonical direction */
};

struct reyes_polyline reyes_edge_polyline(const float3 base[16], const struct reyes_subpatch *sp, int edge,
                                    uint level, uint side)
{
    int along_u;
    float fixed, a, b;
    reyes_edge_line(sp, edge, &along_u, &fixed, &a, &b);
    float3 line[4], e[4];
    reyes_line_curve(base, along_u, fixed, line);
    float span = ldexp(1.0f, -(int)level), start = reyes_segment_start(a, level);
    reyes_restrict_canonical(line, start, start + span, e);
    struct reyes_polyline c;
    c.reversed = reyes_curve_reversed(line);
    for (int k = 0; k < 4; ++k)
        c.c[k] = c.reversed ? e[3 - k] : e[k];
    c.side = side;
    /* Interval lengths are powers of two: the edge is 2^-shift of the
     * segment and its offset inside it a whole number of edges. */
    c.shift = (uint)(ilogb(span) - ilogb(b - a));
    c.steps = (ulong)side << c.shift;
    ulong offset = (ulong)((a - start) / (b - a)) * side; /* along the line */
    c.first = offset;
    return c;
}

/* The strip point of the edge's grid step `step` (0 at the edge's a end):
 * on the polyline, at the same parameter as the grid vertex. */
float3 reyes_strip_point(const struct reyes_polyline *c, int step)
{
    ulong along = c->first + (ulong)step;
    ulong at = c->reversed ? c->steps - along : along; /* canonical */
    ulong piece = at >> c->shift;
    float3 p0 = reyes_blossom(c->c[0], c->c[1], c->c[2], c->c[3], (float)piece / (float)c->side,
                              (float)piece / (float)c->side, (float)piece / (float)c->side);
    ulong rest = at - (piece << c->shift);
    if (rest == 0ul)
        return p0;
    float next = (float)(piece + 1ul) / (float)c->side;
    float3 p1 = reyes_blossom(c->c[0], c->c[1], c->c[2], c->c[3], next, next, next);
    return p0 + (p1 - p0) * ldexp((float)rest, -(int)c->shift);
}
