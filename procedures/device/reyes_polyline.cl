/*
 * The polyline crack fix (REYES_CRACK_FIX_POLYLINE, reyes_params.polyline;
 * docs/reyes-dicing.md): with a shading rate, each edge of a diced
 * sub-patch follows the polyline of a segment of its base patch's line
 * that the sub-patches on both sides of the edge choose alone, so both put
 * the same vertices on it, bit for bit; where a sub-patch's corner falls
 * inside a piece of that polyline (a T-junction), the sub-patch fills the
 * sliver between the piece and its own boundary.  One pass; no
 * communication between patches.
 *
 * Settling.  An edge lies on a line of its base patch (reyes_edge_line).
 * Its chain is the line's dyadic segments that hold it, from the one on
 * which the line became an edge (the base patch's boundary, or the split
 * that made it: both of that split's halves start from it) down to the
 * edge.  The sub-patches on both sides of an edge share the chain down to
 * the coarser of their two edges, and their ancestors' edges on the line
 * are its segments, in order: bound tests each unsettled edge once per
 * span (reyes_polyline_test_edges), and the edge settles on the first
 * segment whose control points, blossomed in the canonical direction, lie
 * in front of the near plane and ask for at most REYES_POLYLINE_MOST
 * micropolygons (reyes_rate_span).  Children keep a settled edge; a
 * split's two new edges start unsettled.  So both sides settle on the same
 * segment S with the same count N, computed from the same bits.  A
 * sub-patch is diced only with four settled edges (an unsettled one is a
 * reason to split across it), except at the depth limit.
 *
 * The polyline.  S's N + 1 corners lie at parameters
 * t_j = s (1 - j/N) + (s + span) j/N of the line (s, span: S's start and
 * length), each evaluated as the surface point there (in the base patch,
 * or, on a boundary line of the base patch, on that line's curve in its
 * canonical direction: the glued neighbour's bits).  An edge [a, b] inside
 * S takes as its vertices its two ends (its sub-patch's corners, surface
 * points too) and the corners strictly between them; dice puts them in the
 * grid's boundary slots (reyes_edge_step).  An end that is a corner is the
 * same point either way.  An end inside a piece t_j .. t_{j+1} is a
 * T-junction: the sub-patches on the other side may run straight from
 * P_j to P_{j+1}.  The sub-patch fills the triangles P_j, X, Y and
 * P_j, Y, P_{j+1} for the part X .. Y of its boundary in that piece (a
 * fan from P_j), whose edge P_j P_{j+1} is the other side's, bit for bit;
 * the fans of all sub-patches along a piece cover the region between its
 * chord and their boundaries whatever its shape (a fan from a vertex of a
 * closed polygon has the polygon's winding number).
 *
 * Seams and open boundaries.  The renderer welds the scene's seams once
 * (procedures/render/reyes_weld.c), so both sides of a seam have the same
 * boundary curve, and marks the boundaries no patch shares: there a
 * chord cutting inside the curve would show what lies behind, and dice
 * adds bulges (reyes_polyline_bulges).
 *
 * Storage in the work item (struct reyes_subpatch): a byte of edge_levels
 * per edge, the settled segment's level (S is 2^-level of the line), or
 * REYES_POLYLINE_FAILED | level when the edge's own span, 2^-level of
 * the line, asked for too many (0xff: not tested); and N - 1 in the
 * nibble at bit 16 + 4 edge of dice_size (whose two low bytes are the
 * grid's size, reyes_dice_size); REYES_POLYLINE_HAS_FILLERS when dice
 * has fillers to draw.  Parameters are exact dyadic numbers to 24 splits
 * of a line.
 */

/* A settled segment's pieces: at most this many (a nibble). */
#define REYES_POLYLINE_MOST 15u
/* An edge_levels byte with this bit: unsettled (0xff: never tested). */
#define REYES_POLYLINE_FAILED 0x80u
/* Set by bound in the last edge's byte of a sub-patch to dice that has
 * fillers (a T-junction or an open boundary): dice looks for them only
 * then.  Levels are at most REYES_MAX_DEPTH (40), under this bit. */
#define REYES_POLYLINE_HAS_FILLERS (0x40u << (8 * REYES_EDGE_U0))
#define REYES_POLYLINE_LEVEL_MASK 0x3fu

REYES_INLINE uint reyes_polyline_byte(const struct reyes_subpatch *sp, int edge)
{
    return (sp->edge_levels >> (8 * edge)) & 0xffu;
}

REYES_INLINE int reyes_polyline_settled(const struct reyes_subpatch *sp, int edge)
{
    return reyes_polyline_byte(sp, edge) < REYES_POLYLINE_FAILED;
}

REYES_INLINE uint reyes_polyline_pieces(const struct reyes_subpatch *sp, int edge)
{
    return ((sp->dice_size >> (16 + 4 * edge)) & 0xfu) + 1u;
}

REYES_INLINE void reyes_polyline_mark(struct reyes_subpatch *sp, int edge, uint byte)
{
    sp->edge_levels = (sp->edge_levels & ~(0xffu << (8 * edge))) | (byte << (8 * edge));
}

REYES_INLINE void reyes_polyline_settle(struct reyes_subpatch *sp, int edge, uint level, uint pieces)
{
    reyes_polyline_mark(sp, edge, level);
    uint shift = 16u + 4u * (uint)edge;
    sp->dice_size = (sp->dice_size & ~(0xfu << shift)) | ((pieces - 1u) << shift);
}

/* The level of a dyadic interval of length `length` (2^-level). */
REYES_INLINE uint reyes_dyadic_level(float length)
{
    return (uint)(-ilogb(length));
}

/* Whether the line (along_u, fixed) is a boundary of base patch `patch`
 * that no other patch shares: the renderer welds the scene's seams and
 * marks those boundaries, a bit per REYES_EDGE_*, in the w of the patch's
 * first control point (reyes_weld.h). */
REYES_INLINE int reyes_polyline_open(__global const float4 *patches, uint patch, int along_u, float fixed)
{
    if (fixed != 0.0f && fixed != 1.0f)
        return 0;
    int boundary = along_u ? (fixed == 0.0f ? REYES_EDGE_V0 : REYES_EDGE_V1)
                           : (fixed == 0.0f ? REYES_EDGE_U0 : REYES_EDGE_U1);
    return ((uint)patches[patch * 16u].w >> boundary) & 1u;
}

/* bound: test every unsettled edge of sp at its own span, once per span
 * (the chain's next segment), and settle it there if that span is in
 * front of the near plane and asks for at most REYES_POLYLINE_MOST (and
 * the grid's) micropolygons.  `forced` (the depth limit): settle every
 * edge at its own span anyway, with at most that many. */
void reyes_polyline_test_edges(__global const struct reyes_params *p, __global const float4 *patches,
                               struct reyes_subpatch *sp, int forced)
{
    uint most = min(p->grid - 1u, REYES_POLYLINE_MOST);
    float3 base[16];
    int loaded = 0;
    for (int edge = 0; edge < 4; ++edge) {
        if (reyes_polyline_settled(sp, edge))
            continue;
        int along_u;
        float fixed, a, b;
        reyes_edge_line(sp, edge, &along_u, &fixed, &a, &b);
        uint level = reyes_dyadic_level(b - a);
        if (!forced && reyes_polyline_byte(sp, edge) == (REYES_POLYLINE_FAILED | level))
            continue;
        if (!loaded)
            reyes_load_patch(patches, sp->patch, base);
        loaded = 1;
        float count = reyes_rate_span(p, base, along_u, fixed, a, b);
        if (count >= 0.0f && count <= (float)most)
            reyes_polyline_settle(sp, edge, level, (uint)count);
        else if (forced)
            reyes_polyline_settle(sp, edge, level, most);
        else
            reyes_polyline_mark(sp, edge, REYES_POLYLINE_FAILED | level);
    }
}

/* A settled edge [a, b] of the line (along_u, fixed) on its segment S =
 * [s, s + span] (in the line's own direction) of N pieces: the edge is
 * 2^-d of S, and in units of span / (N 2^d) from s its ends are at lo and
 * hi and corner j of S at j 2^d.  boundary: the base patch boundary the
 * line is (REYES_EDGE_*), or -1. */
struct reyes_polyline_edge {
    int along_u, boundary;
    float fixed, a, b, s, span;
    uint pieces, d;
    ulong lo, hi;
};

struct reyes_polyline_edge reyes_polyline_edge_of(const struct reyes_subpatch *sp, int edge)
{
    struct reyes_polyline_edge e;
    reyes_edge_line(sp, edge, &e.along_u, &e.fixed, &e.a, &e.b);
    uint level = reyes_polyline_byte(sp, edge) & REYES_POLYLINE_LEVEL_MASK;
    e.pieces = reyes_polyline_pieces(sp, edge);
    e.span = ldexp(1.0f, -(int)level);
    e.s = reyes_segment_start(e.a, level);
    e.d = reyes_dyadic_level(e.b - e.a) - level;
    e.lo = (ulong)((e.a - e.s) / (e.b - e.a)) * e.pieces;
    e.hi = e.lo + e.pieces;
    e.boundary = -1;
    if (e.fixed == 0.0f)
        e.boundary = e.along_u ? REYES_EDGE_V0 : REYES_EDGE_U0;
    else if (e.fixed == 1.0f)
        e.boundary = e.along_u ? REYES_EDGE_V1 : REYES_EDGE_U1;
    return e;
}

/* The corners of S at or before a and at or after b (j_lo, j_hi). */
REYES_INLINE ulong reyes_polyline_first_corner(const struct reyes_polyline_edge *e)
{
    return e->lo >> e->d;
}

REYES_INLINE ulong reyes_polyline_last_corner(const struct reyes_polyline_edge *e)
{
    return (e->hi + ((1ul << e->d) - 1ul)) >> e->d;
}

/* Whether an end of the edge lies inside a piece of S (a T-junction). */
REYES_INLINE int reyes_polyline_partial(const struct reyes_polyline_edge *e)
{
    ulong mask = (1ul << e->d) - 1ul;
    return ((e->lo | e->hi) & mask) != 0ul;
}

/* bound, for a sub-patch to dice: each edge's segments (counts[], in
 * REYES_EDGE_* order); the sub-patch flagged when it has T-junction
 * fillers or an edge on an open boundary (bulges).  Returns whether it
 * has T-junction fillers. */
int reyes_polyline_prepare_dice(__global const float4 *patches, struct reyes_subpatch *sp, uint counts[4])
{
    int partial = 0, open = 0;
    for (int edge = 0; edge < 4; ++edge) {
        struct reyes_polyline_edge e = reyes_polyline_edge_of(sp, edge);
        counts[edge] = (uint)(reyes_polyline_last_corner(&e) - reyes_polyline_first_corner(&e));
        partial |= reyes_polyline_partial(&e);
        open |= e.boundary >= 0 && reyes_polyline_open(patches, sp->patch, e.along_u, e.fixed);
    }
    if (partial || open)
        sp->edge_levels |= REYES_POLYLINE_HAS_FILLERS;
    return partial;
}

/* The vertices along the edge, in the line's own direction: S's corners
 * from j_lo to j_hi, with a and b between them where they are not
 * corners (at most N + 1 = 16 when the edge is S, else at most 12).  t:
 * their parameters on the line; tau: on a boundary line, the parameter in
 * the line's canonical direction (reversed: the line runs against it), the
 * bits the glued neighbour computes; first, last: the indices of a and b.
 * Returns the count. */
int reyes_polyline_vertices(const struct reyes_polyline_edge *e, int reversed, float t[REYES_LANES],
                            float tau[REYES_LANES], int *first, int *last)
{
    ulong unit = 1ul << e->d, j_lo = reyes_polyline_first_corner(e), j_hi = reyes_polyline_last_corner(e);
    float n = (float)e->pieces, end = e->s + e->span;
    /* The canonical direction's start of S. */
    float s_canonical = 1.0f - end;
    int count = 0;
    for (ulong j = j_lo; j <= j_hi; ++j) {
        ulong at = j * unit;
        if (j == j_hi && at > e->hi) {
            /* b, inside the last piece. */
            *last = count;
            t[count] = e->b;
            tau[count++] = reversed ? 1.0f - e->b : e->b;
        }
        if (at == e->lo || at == e->hi) {
            if (at == e->lo)
                *first = count;
            else
                *last = count;
            float x = at == e->lo ? e->a : e->b;
            t[count] = x;
            tau[count++] = reversed ? 1.0f - x : x;
        } else {
            float f = (float)j / n, g = (float)(e->pieces - (uint)j) / n;
            float x = e->s * (1.0f - f) + end * f;
            t[count] = x;
            tau[count++] = reversed ? s_canonical * (1.0f - g) + (s_canonical + e->span) * g : x;
        }
        if (j == j_lo && at < e->lo) {
            /* a, inside the first piece. */
            *first = count;
            t[count] = e->a;
            tau[count++] = reversed ? 1.0f - e->a : e->a;
        }
    }
    return count;
}

/* The control points of boundary `line` (REYES_EDGE_*) of base patch h in
 * the line's own direction. */
REYES_INLINE void reyes_boundary_curve(const struct reyes_hull *h, int line, float3 q[4])
{
    for (int k = 0; k < 4; ++k) {
        int i = line == REYES_EDGE_V0 ? k : line == REYES_EDGE_V1 ? 12 + k : line == REYES_EDGE_U0 ? 4 * k : 4 * k + 3;
        q[k] = (float3)(h->x[i], h->y[i], h->z[i]);
    }
}

/* The point at canonical parameter tau of boundary `line` of h: its curve
 * evaluated in its canonical direction (reyes_curve_reversed), so a glued
 * neighbour, whose boundary has the same control points in either order,
 * gets the same bits. */
float3 reyes_boundary_point(const struct reyes_hull *h, int line, float tau)
{
    float3 q[4];
    reyes_boundary_curve(h, line, q);
    int reversed = reyes_curve_reversed(q);
    float w[4], x[4], y[4], z[4];
    reyes_bernstein_one(tau, w);
    for (int k = 0; k < 4; ++k) {
        float3 c = q[reversed ? 3 - k : k];
        x[k] = c.x;
        y[k] = c.y;
        z[k] = c.z;
    }
    return (float3)(reyes_curve_at_scalar(w, x), reyes_curve_at_scalar(w, y), reyes_curve_at_scalar(w, z));
}

reyes_lane_mask reyes_polyline_place(__global const struct reyes_params *p, const struct reyes_hull *h,
                                     const struct reyes_polyline_edge *e, float t[REYES_LANES],
                                     float tau[REYES_LANES], int count, const struct reyes_lighting *light,
                                     const struct reyes_subpatch *sp, uint base, int shade,
                                     struct reyes_vertex_lanes *out, reyes_lanes *u, reyes_lanes *v);

/* The edge's vertices (reyes_polyline_vertices) evaluated in lanes into
 * out, placed and shaded as dice's (reyes_dice_place_lanes, with sp's
 * shading), and their parameters (u, v).  Every vertex is the surface
 * point at its (u, v) as the lattice evaluates it, except on a boundary
 * line of the base patch, where it is reyes_boundary_point's.  Returns the
 * count; first and last as reyes_polyline_vertices; *degenerate: the
 * lanes whose normal vanished (reyes_dice_place_lanes). */
int reyes_polyline_eval(__global const struct reyes_params *p, const struct reyes_hull *h,
                        const struct reyes_polyline_edge *e, const struct reyes_lighting *light,
                        const struct reyes_subpatch *sp, uint base, int shade, struct reyes_vertex_lanes *out,
                        reyes_lanes *u, reyes_lanes *v, reyes_lane_mask *degenerate, int *first, int *last)
{
    float t[REYES_LANES], tau[REYES_LANES];
    int reversed = 0;
    if (e->boundary >= 0) {
        float3 q[4];
        reyes_boundary_curve(h, e->boundary, q);
        reversed = reyes_curve_reversed(q);
    }
    int count = reyes_polyline_vertices(e, reversed, t, tau, first, last);
    *degenerate = reyes_polyline_place(p, h, e, t, tau, count, light, sp, base, shade, out, u, v);
    return count;
}

/* The points of the edge's line at parameters t[0 .. count - 1] (tau:
 * on a boundary line, in its canonical direction), as
 * reyes_polyline_eval evaluates them; the lanes past count repeat the
 * last.  Returns the lanes whose normal vanished. */
reyes_lane_mask reyes_polyline_place(__global const struct reyes_params *p, const struct reyes_hull *h,
                                     const struct reyes_polyline_edge *e, float t[REYES_LANES],
                                     float tau[REYES_LANES], int count, const struct reyes_lighting *light,
                                     const struct reyes_subpatch *sp, uint base, int shade,
                                     struct reyes_vertex_lanes *out, reyes_lanes *u, reyes_lanes *v)
{
    for (int k = count; k < REYES_LANES; ++k)
        t[k] = tau[k] = t[count - 1];
    reyes_lanes along = reyes_vload_lanes(0, t);
    *u = e->along_u ? along : (reyes_lanes)e->fixed;
    *v = e->along_u ? (reyes_lanes)e->fixed : along;
    /* Normals only where vertices are lit (sample shading packs their
     * parameters instead). */
    int lit = shade && !p->sample_shading;
    reyes_lanes x[3], normal[3] = { (reyes_lanes)0.0f, (reyes_lanes)0.0f, (reyes_lanes)0.0f };
    reyes_lane_mask collapsed = (reyes_lane_mask)0;
    struct reyes_row_curves_lanes rc;
    if (lit || e->boundary < 0)
        reyes_row_curves_lanes(h, *v, &rc);
    if (lit)
        collapsed = reyes_row_normal_lanes(&rc, *u, normal);
    if (e->boundary >= 0) {
        /* Every vertex on the boundary's curve, in lanes (its ends at the
         * base patch's corners are its control points either way). */
        float3 q[4];
        reyes_boundary_curve(h, e->boundary, q);
        int reversed = reyes_curve_reversed(q);
        reyes_lanes w[4];
        reyes_bernstein_lanes(reyes_vload_lanes(0, tau), w);
        float cx[4], cy[4], cz[4];
        for (int k = 0; k < 4; ++k) {
            float3 c = q[reversed ? 3 - k : k];
            cx[k] = c.x;
            cy[k] = c.y;
            cz[k] = c.z;
        }
        x[0] = reyes_curve_at_one(w, cx);
        x[1] = reyes_curve_at_one(w, cy);
        x[2] = reyes_curve_at_one(w, cz);
    } else {
        reyes_row_point_lanes(&rc, *u, x);
        /* An end on a boundary of the base patch across the line. */
        for (int k = 0; k < count; k += count - 1 > 0 ? count - 1 : 1) {
            float uk = e->along_u ? t[k] : e->fixed, vk = e->along_u ? e->fixed : t[k];
            int line = vk == 0.0f ? REYES_EDGE_V0 : vk == 1.0f ? REYES_EDGE_V1
                       : uk == 0.0f ? REYES_EDGE_U0 : uk == 1.0f ? REYES_EDGE_U1 : -1;
            if (line < 0)
                continue;
            float3 q[4];
            reyes_boundary_curve(h, line, q);
            float along_line = line == REYES_EDGE_V0 || line == REYES_EDGE_V1 ? uk : vk;
            float3 point = reyes_boundary_point(h, line, reyes_curve_reversed(q) ? 1.0f - along_line : along_line);
            ((float *)&x[0])[k] = point.x;
            ((float *)&x[1])[k] = point.y;
            ((float *)&x[2])[k] = point.z;
        }
    }
    return reyes_dice_place_lanes(p, light, x, normal, collapsed, *u, *v, sp, base, shade, out);
}

/* The colour (or packed normal) of a vertex at (u, v) whose normal
 * vanished, as reyes_grid_vertex_color. */
REYES_INLINE uint reyes_polyline_pole_color(__global const struct reyes_params *p, const struct reyes_hull *h,
                                            float u, float v, uint base)
{
    float3 cp[16];
    for (int k = 0; k < 16; ++k)
        cp[k] = (float3)(h->x[k], h->y[k], h->z[k]);
    return reyes_vertex_color_at(p, cp, u, v, base);
}

/* Whether an edge that is its whole segment, with as many pieces as the
 * lattice has along it, is already the lattice's row: inside the base
 * patch (the same parameters, the same arithmetic), and on a boundary
 * that runs in its canonical direction (the lattice's row there is that
 * curve evaluated as reyes_boundary_point does: the rows' weights at
 * v = 0 or 1, the columns' at u = 0 or 1, are 1 and 0). */
REYES_INLINE int reyes_polyline_as_lattice(const struct reyes_hull *h, const struct reyes_polyline_edge *e)
{
    if (e->boundary < 0)
        return 1;
    float3 q[4];
    reyes_boundary_curve(h, e->boundary, q);
    return !reyes_curve_reversed(q);
}

/* dice: put every edge's polyline vertices in the lattice's boundary slots
 * (reyes_edge_step), but where the lattice's row is the polyline
 * already (reyes_polyline_as_lattice). */
void reyes_polyline_edges(__global const struct reyes_params *p, const struct reyes_subpatch *sp,
                          const struct reyes_hull *h, const struct reyes_lighting *light, uint base,
                          __local struct reyes_grid *g, int shade)
{
    int columns = (int)g->columns, rows = (int)g->rows;
    for (int edge = 0; edge < 4; ++edge) {
        struct reyes_polyline_edge e = reyes_polyline_edge_of(sp, edge);
        int n = (e.along_u ? columns : rows) - 1;
        if (e.d == 0u && (int)e.pieces == n && reyes_polyline_as_lattice(h, &e))
            continue;
        struct reyes_vertex_lanes out;
        reyes_lanes u, v;
        reyes_lane_mask degenerate;
        int first = 0, last = 0;
        reyes_polyline_eval(p, h, &e, light, sp, base, shade, &out, &u, &v, &degenerate, &first, &last);
        int c = last - first;
        int fix = shade && !p->sample_shading && reyes_any16(degenerate);
        for (int i = 0; i <= n; ++i) {
            int slot = reyes_edge_slot(edge, i, columns, rows), k = first + reyes_edge_step(i, c, n);
            g->x[slot] = ((float *)&out.x)[k];
            g->y[slot] = ((float *)&out.y)[k];
            g->z[slot] = ((float *)&out.z)[k];
            g->rgba[slot] = ((uint *)&out.rgba)[k];
#ifdef REYES_VERTEX_MOTION
            g->mx[slot] = ((float *)&out.motion[0])[k];
            g->my[slot] = ((float *)&out.motion[1])[k];
            g->mw[slot] = ((float *)&out.motion[2])[k];
#endif
            if (fix && ((int *)&degenerate)[k])
                g->rgba[slot] = reyes_polyline_pole_color(p, h, ((float *)&u)[k], ((float *)&v)[k], base);
        }
    }
}

/* Vertices for the filler grid: placed lanes and their colours (with the
 * poles' fixed). */
struct reyes_filler_vertices {
    struct reyes_vertex_lanes out;
    uint rgba[REYES_LANES];
};

/* Vertex k of `from` into slot `slot` of the filler grid f. */
REYES_INLINE void reyes_polyline_put(__local struct reyes_grid *f, int slot, const struct reyes_filler_vertices *from,
                                     int k)
{
    f->x[slot] = ((const float *)&from->out.x)[k];
    f->y[slot] = ((const float *)&from->out.y)[k];
    f->z[slot] = ((const float *)&from->out.z)[k];
    f->rgba[slot] = from->rgba[k];
#ifdef REYES_VERTEX_MOTION
    f->mx[slot] = ((const float *)&from->out.motion[0])[k];
    f->my[slot] = ((const float *)&from->out.motion[1])[k];
    f->mw[slot] = ((const float *)&from->out.motion[2])[k];
#endif
}

/* Append triangle (vertex a of va, b of vb, c of vc) to the filler grid f
 * (2 columns: rows [a, b] and [c, c], a quad with two equal corners). */
REYES_INLINE void reyes_polyline_add_triangle(__local struct reyes_grid *f, const struct reyes_filler_vertices *va,
                                              int a, const struct reyes_filler_vertices *vb, int b,
                                              const struct reyes_filler_vertices *vc, int c)
{
    int row = (int)f->rows;
    reyes_polyline_put(f, 2 * row, va, a);
    reyes_polyline_put(f, 2 * row + 1, vb, b);
    reyes_polyline_put(f, 2 * row + 2, vc, c);
    reyes_polyline_put(f, 2 * row + 3, vc, c);
    f->quad_rows |= 1u << row;
    f->rows = (uint)row + 2u;
}

/* Rasterize the filler grid's triangles (a full render) and count them. */
REYES_INLINE void reyes_polyline_flush(const struct reyes_raster_target *target, __local struct reyes_grid *f, int full)
{
    uint triangles = f->rows / 2u;
    if (triangles == 0u)
        return;
    atomic_add(&target->counters[REYES_COUNT_FILLERS], triangles);
    if (full)
        reyes_rasterize(target, f);
    f->rows = 0u;
    f->quad_rows = 0u;
}

/* The bulges of an open boundary edge: each piece's chord cuts inside the
 * curve by up to the rate's sag, and an open boundary (or a gap the weld
 * left) shows what lies behind that sliver; three points at a quarter,
 * half and three quarters of each piece and a fan of three triangles from
 * its first corner cover it to a sixteenth of the sag.  The piece corners
 * are the grid's boundary vertices (v, first .. last), bit for bit. */
void reyes_polyline_bulges(const struct reyes_raster_target *target, const struct reyes_hull *h,
                           const struct reyes_polyline_edge *e, const struct reyes_lighting *light,
                           const struct reyes_subpatch *rect, uint base, const struct reyes_filler_vertices *v,
                           int first, int last, __local struct reyes_grid *f, uint room, int full)
{
    __global const struct reyes_params *p = target->params;
    float3 q[4];
    reyes_boundary_curve(h, e->boundary, q);
    int reversed = reyes_curve_reversed(q);
    /* The corners' parameters: the list the edge was evaluated at. */
    float t_of[REYES_LANES], tau_of[REYES_LANES];
    int a, b;
    reyes_polyline_vertices(e, reversed, t_of, tau_of, &a, &b);
    /* Up to five pieces (15 points) a batch. */
    for (int k0 = first; k0 < last; k0 += 5) {
        int pieces = min(5, last - k0);
        float t[REYES_LANES], tau[REYES_LANES];
        for (int i = 0; i < 3 * pieces; ++i) {
            int k = k0 + i / 3;
            float w = 0.25f * (float)(i % 3 + 1);
            t[i] = t_of[k] * (1.0f - w) + t_of[k + 1] * w;
            tau[i] = reversed ? 1.0f - t[i] : t[i];
        }
        struct reyes_filler_vertices qv;
        reyes_lanes u, vv;
        reyes_lane_mask degenerate = reyes_polyline_place(p, h, e, t, tau, 3 * pieces, light, rect, base, 1, &qv.out,
                                                          &u, &vv);
        for (int i = 0; i < REYES_LANES; ++i) {
            qv.rgba[i] = ((uint *)&qv.out.rgba)[i];
            if (i < 3 * pieces && !p->sample_shading && ((int *)&degenerate)[i])
                qv.rgba[i] = reyes_polyline_pole_color(p, h, ((float *)&u)[i], ((float *)&vv)[i], base);
        }
        for (int j = 0; j < pieces; ++j) {
            if (f->rows / 2u + 3u > room)
                reyes_polyline_flush(target, f, full);
            int k = k0 + j, i = 3 * j;
            reyes_polyline_add_triangle(f, v, k, &qv, i, &qv, i + 1);
            reyes_polyline_add_triangle(f, v, k, &qv, i + 1, &qv, i + 2);
            reyes_polyline_add_triangle(f, v, k, &qv, i + 2, v, k + 1);
        }
    }
}

/* dice: the fillers of every edge end inside a piece of its segment (the
 * fans from the piece's first corner, above) and, with `bulges`, the
 * bulges of the edges on open boundaries, rasterized from the scratch
 * grid f (with sample shading lit with the patch's normal at each
 * sample's parameters: f's rectangle holds every segment).  Also for a
 * grid occlusion culling skips (without bulges): its fillers may reach
 * past its hull. */
void reyes_polyline_fillers(const struct reyes_raster_target *target, const struct reyes_subpatch *sp,
                            __global const float4 *patches, uint base, __local struct reyes_grid *f, int full,
                            int bulges)
{
    __global const struct reyes_params *p = target->params;
    struct reyes_polyline_edge edges[4];
    int partial[4], open[4], any = 0;
    float2 lo = (float2)(sp->u0, sp->v0), hi = (float2)(sp->u1, sp->v1);
    for (int edge = 0; edge < 4; ++edge) {
        edges[edge] = reyes_polyline_edge_of(sp, edge);
        partial[edge] = reyes_polyline_partial(&edges[edge]);
        open[edge] = bulges && edges[edge].boundary >= 0
                     && reyes_polyline_open(patches, sp->patch, edges[edge].along_u, edges[edge].fixed);
        any |= partial[edge] | open[edge];
        if (edges[edge].along_u) {
            lo.x = fmin(lo.x, edges[edge].s);
            hi.x = fmax(hi.x, edges[edge].s + edges[edge].span);
        } else {
            lo.y = fmin(lo.y, edges[edge].s);
            hi.y = fmax(hi.y, edges[edge].s + edges[edge].span);
        }
    }
    if (!any)
        return;
    struct reyes_hull h;
    reyes_load_hull(patches, sp->patch, &h);
    struct reyes_lighting light = reyes_lighting_of(p);
    struct reyes_subpatch rect = *sp;
    rect.u0 = lo.x;
    rect.v0 = lo.y;
    rect.u1 = hi.x;
    rect.v1 = hi.y;
    f->columns = 2u;
    f->rows = 0u;
    f->quad_rows = 0u;
    f->counted = 0u;
    reyes_grid_shading(p, f, &rect, base, REYES_SHADE_SURFACE);
    /* Triangles per batch: four vertices each, at most 16 (quad_rows). */
    uint room = min((uint)REYES_GRID_CAPACITY(p->grid) / 4u, 16u);
    for (int edge = 0; edge < 4; ++edge) {
        const struct reyes_polyline_edge *e = &edges[edge];
        if (!partial[edge] && !open[edge])
            continue;
        struct reyes_filler_vertices v;
        reyes_lanes u, vv;
        reyes_lane_mask degenerate;
        int first = 0, last = 0;
        int count = reyes_polyline_eval(p, &h, e, &light, &rect, base, 1, &v.out, &u, &vv, &degenerate, &first,
                                        &last);
        for (int k = 0; k < REYES_LANES; ++k) {
            v.rgba[k] = ((uint *)&v.out.rgba)[k];
            if (k < count && !p->sample_shading && ((int *)&degenerate)[k])
                v.rgba[k] = reyes_polyline_pole_color(p, &h, ((float *)&u)[k], ((float *)&vv)[k], base);
        }
        if (partial[edge]) {
            if (f->rows / 2u + 2u > room)
                reyes_polyline_flush(target, f, full);
            /* a inside the first piece: P_0, A, then the next vertex (P_1,
             * or b and P_1 when b is in the same piece). */
            if (first > 0) {
                reyes_polyline_add_triangle(f, &v, 0, &v, first, &v, first + 1);
                if (first + 1 == last && last < count - 1)
                    reyes_polyline_add_triangle(f, &v, 0, &v, last, &v, count - 1);
            }
            /* b inside the last piece (another one): P_j, B, P_{j+1}. */
            if (last < count - 1 && !(first > 0 && first + 1 == last))
                reyes_polyline_add_triangle(f, &v, last - 1, &v, last, &v, count - 1);
        }
        if (open[edge])
            reyes_polyline_bulges(target, &h, e, &light, &rect, base, &v, first, last, f, room, full);
    }
    reyes_polyline_flush(target, f, full);
}
