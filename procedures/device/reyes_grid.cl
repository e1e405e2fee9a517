/*
 * A diced grid, what dice rasterizes: a lattice of shaded vertices from one
 * sub-patch (or the wedge strips along its edges), in screen space.
 * REYES_GRID_VERTICES comes from the renderer (reyes_renderer.c: the
 * length of the vertex arrays, reyes_shared.h's REYES_GRID_ARRAY).
 *
 * Vertex k of the lattice is (k % columns, k / columns); the quad whose
 * first corner is vertex k has the corners k, k + 1, k + columns + 1,
 * k + columns (around it, as dice has always made them).  Quads in the
 * last column do not exist, and quad row j exists when bit j of
 * quad_rows is set: all rows of a grid, every other row of the strips
 * (each strip is a row of grid vertices followed by a row of chord
 * points).
 */

struct reyes_grid {
    uint columns;    /* vertices per row */
    uint rows;       /* rows of vertices */
    uint quad_rows;  /* bit j: the quads between vertex rows j and j + 1 exist */
    /* 1: rasterize adds the visible quads to REYES_COUNT_MICROPOLYGONS as
     * it sets them up (a full render's grids; dice counts the others). */
    uint counted;
    /* What rgba hold (REYES_SHADE_*); with sample shading the packed base
     * colour every sample is lit with, and for REYES_SHADE_SURFACE the base
     * patch and the sub-patch's parameter rectangle. */
    uint shading;
    uint base;
    uint patch;
    float u0, v0, u1, v1;
    /* Pixels (y down), or clip x and y when blurred; z is the clip w. */
    float x[REYES_GRID_VERTICES];
    float y[REYES_GRID_VERTICES];
    float z[REYES_GRID_VERTICES];
    uint rgba[REYES_GRID_VERTICES];
#ifdef REYES_VERTEX_MOTION
    /* Each vertex's clip-space motion (x, y, w) over the shutter. */
    float mx[REYES_GRID_VERTICES];
    float my[REYES_GRID_VERTICES];
    float mw[REYES_GRID_VERTICES];
#endif
};

/* k / columns for 0 <= k < 2^20 and 1 <= columns <= 64, in float (the
 * SIMD lanes have no integer division): (k + 1/2) / columns lies at least
 * 1/128 from an integer, far more than the rounding error. */
REYES_INLINE int reyes_lattice_row(int k, int columns)
{
    return (int)(((float)k + 0.5f) / (float)columns);
}

REYES_INLINE int16 reyes_lattice_row_lanes(int16 k, int columns)
{
    return convert_int16((convert_float16(k) + 0.5f) / (float)columns);
}

/* Whether quad slot k (its first corner's vertex index) is a quad of g. */
REYES_INLINE int reyes_grid_has_quad(__local const struct reyes_grid *g, int k)
{
    int columns = (int)g->columns, row = reyes_lattice_row(k, columns);
    return row + 1 < (int)g->rows && k - row * columns != columns - 1 && ((g->quad_rows >> row) & 1u);
}

/* The quad at slot k of a lattice of c columns, corners around it
 * (k = c = 0 reads vertices 0 and 1 only, whatever the item holds). */
REYES_INLINE struct reyes_quad reyes_grid_quad_at(__local const struct reyes_grid *g, int k, int c)
{
    const int corner[4] = { k, k + 1, k + c + 1, k + c };
    struct reyes_quad q;
    for (int i = 0; i < 4; ++i) {
        q.x[i] = g->x[corner[i]];
        q.y[i] = g->y[corner[i]];
        q.z[i] = g->z[corner[i]];
        q.rgba[i] = g->rgba[corner[i]];
    }
    return q;
}

/* The quad at slot k (a quad of g), corners around it. */
REYES_INLINE struct reyes_quad reyes_grid_quad(__local const struct reyes_grid *g, int k)
{
    return reyes_grid_quad_at(g, k, (int)g->columns);
}

/* The blurred quad at slot k with its vertices' motions (their own with
 * per-vertex motion, else the parameters' one motion). */
struct reyes_moving_quad reyes_grid_moving(__global const struct reyes_params *p,
                                           __local const struct reyes_grid *g, int k)
{
    struct reyes_quad q = reyes_grid_quad(g, k);
#ifdef REYES_VERTEX_MOTION
    int c = (int)g->columns;
    const int corner[4] = { k, k + 1, k + c + 1, k + c };
    struct reyes_moving_quad m;
    m.quad = q;
    for (int i = 0; i < 4; ++i) {
        m.mx[i] = g->mx[corner[i]];
        m.my[i] = g->my[corner[i]];
        m.mw[i] = g->mw[corner[i]];
    }
    return m;
#else
    return reyes_moving_uniform(p, &q);
#endif
}

/* Screen box of a sharp quad. */
REYES_INLINE void reyes_quad_box(const struct reyes_quad *q, float2 *lo, float2 *hi)
{
    *lo = (float2)(fmin(fmin(q->x[0], q->x[1]), fmin(q->x[2], q->x[3])),
                   fmin(fmin(q->y[0], q->y[1]), fmin(q->y[2], q->y[3])));
    *hi = (float2)(fmax(fmax(q->x[0], q->x[1]), fmax(q->x[2], q->x[3])),
                   fmax(fmax(q->y[0], q->y[1]), fmax(q->y[2], q->y[3])));
}

/* Whether a sharp quad is rasterized: in front of the near plane and on
 * the tile (the image without buckets). */
REYES_INLINE int reyes_sharp_visible(__global const struct reyes_params *p, const struct reyes_quad *q)
{
    float2 lo, hi;
    reyes_quad_box(q, &lo, &hi);
    float near_w = p->near_w;
    int front = q->z[0] > near_w && q->z[1] > near_w && q->z[2] > near_w && q->z[3] > near_w;
    return front && hi.x >= p->tile_x0 && hi.y >= p->tile_y0 && lo.x <= p->tile_x1 && lo.y <= p->tile_y1;
}

/* Whether the quad at slot k of g is rasterized: a quad of g, in front of
 * the near plane and on the tile; blurred, when its box over the shutter
 * and lens meets the tile. */
int reyes_grid_visible(__global const struct reyes_params *p, __local const struct reyes_grid *g, int k)
{
    if (!reyes_grid_has_quad(g, k))
        return 0;
    if (!p->blur) {
        struct reyes_quad q = reyes_grid_quad(g, k);
        return reyes_sharp_visible(p, &q);
    }
    struct reyes_moving_quad m = reyes_grid_moving(p, g, k);
    float near_w = p->near_w;
    int front = m.quad.z[0] > near_w && m.quad.z[1] > near_w && m.quad.z[2] > near_w && m.quad.z[3] > near_w;
    return front && reyes_blur_meets_tile(p, &m);
}

/* Store vertex k of a lattice: its clip position (pixels when sharp),
 * colour and, with per-vertex motion, its motion. */
REYES_INLINE void reyes_grid_store(__global const struct reyes_params *p, __local struct reyes_grid *g, int k,
                                   const struct reyes_vertex *v)
{
    float2 s = p->blur ? v->clip.xy : reyes_to_screen(p, v->clip);
    g->x[k] = s.x;
    g->y[k] = s.y;
    g->z[k] = v->clip.w;
    g->rgba[k] = v->rgba;
#ifdef REYES_VERTEX_MOTION
    g->mx[k] = v->motion.x;
    g->my[k] = v->motion.y;
    g->mw[k] = v->motion.w;
#endif
}

/* Copy vertex `from` of a to vertex `to` of b. */
REYES_INLINE void reyes_grid_copy_vertex(__local const struct reyes_grid *a, int from, __local struct reyes_grid *b,
                                         int to)
{
    b->x[to] = a->x[from];
    b->y[to] = a->y[from];
    b->z[to] = a->z[from];
    b->rgba[to] = a->rgba[from];
#ifdef REYES_VERTEX_MOTION
    b->mx[to] = a->mx[from];
    b->my[to] = a->my[from];
    b->mw[to] = a->mw[from];
#endif
}
