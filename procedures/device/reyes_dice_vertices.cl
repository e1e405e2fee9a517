/*
 * Grid vertices in SIMD lanes, shared by dice (reyes_dice.cl) and the
 * polyline crack fix (reyes_polyline.cl): placing and shading REYES_LANES
 * vertices at once, where a shading-rate grid's boundary slots take an
 * edge's own vertices, and the grid header's shading.
 */

/* REYES_LANES vertices as a lattice stores them: x, y (pixels, or clip x
 * and y when blurred), z (clip w), rgba and, with per-vertex motion, the
 * motion. */
struct reyes_vertex_lanes {
    reyes_lanes x, y, z;
    reyes_lane_uint rgba;
#ifdef REYES_VERTEX_MOTION
    reyes_lanes motion[3];
#endif
};

/* The vertices with points x and unnormalised normals `normal` (collapsed:
 * the lanes where those are, reyes_collapsed_lanes) at parameters (u, v),
 * placed and shaded with base colour `base` when `shade` (else colour 0;
 * with sample shading their parameters in sub-patch sp,
 * REYES_SHADE_SURFACE), in SIMD lanes.  The normal is not fixed up at
 * poles here: the returned mask has the lanes whose normal vanished, for
 * reyes_grid_vertex_color; otherwise each vertex is reyes_grid_vertex's,
 * bit for bit. */
REYES_INLINE reyes_lane_mask reyes_dice_place_lanes(__global const struct reyes_params *p,
                                                    const struct reyes_lighting *light, const reyes_lanes x[3],
                                                    const reyes_lanes normal[3], reyes_lane_mask collapsed,
                                                    reyes_lanes u, reyes_lanes v, const struct reyes_subpatch *sp,
                                                    uint base, int shade, struct reyes_vertex_lanes *out)
{
    __global const float *m = p->view_proj;
    reyes_lanes clip[4];
    for (int r = 0; r < 4; ++r)
        clip[r] = reyes_dot4_lanes(m[4 * r], m[4 * r + 1], m[4 * r + 2], m[4 * r + 3], x[0], x[1], x[2]);
    reyes_lanes inv_w = 1.0f / clip[3];
    reyes_lanes sx = (clip[0] * inv_w * 0.5f + 0.5f) * p->width;
    reyes_lanes sy = (0.5f - clip[1] * inv_w * 0.5f) * p->height;
    out->x = p->blur ? clip[0] : sx;
    out->y = p->blur ? clip[1] : sy;
    out->z = clip[3];
#ifdef REYES_VERTEX_MOTION
    __global const float *mr = p->motion_rows;
    for (int k = 0; k < 3; ++k) {
        out->motion[k] = (reyes_lanes)mr[4 * k + 3];
        if (p->motion_rotates)
            out->motion[k] = reyes_dot4_lanes(mr[4 * k], mr[4 * k + 1], mr[4 * k + 2], mr[4 * k + 3], x[0], x[1],
                                              x[2]);
    }
#endif
    out->rgba = (reyes_lane_uint)0u;
    if (shade && p->sample_shading) {
        out->rgba = reyes_pack_surface16((u - sp->u0) / (sp->u1 - sp->u0), (v - sp->v0) / (sp->v1 - sp->v0));
    } else if (shade) {
        reyes_lanes diffuse, specular;
        reyes_light_lanes(light, x, normal, &diffuse, &specular);
        out->rgba = reyes_light_color_lanes(base, diffuse, specular);
    }
    if (p->sample_shading)
        return collapsed;
    return reyes_dot3_lanes(normal[0], normal[1], normal[2], normal[0], normal[1], normal[2]) < 1e-24f;
}

/* The vertices at parameters (u, v) on the row curves rc (made at v per
 * lane), as reyes_dice_place_lanes. */
REYES_INLINE reyes_lane_mask reyes_dice_vertex_lanes(__global const struct reyes_params *p,
                                                     const struct reyes_row_curves_lanes *rc,
                                                     const struct reyes_lighting *light, reyes_lanes u, reyes_lanes v,
                                                     const struct reyes_subpatch *sp, uint base, int shade,
                                                     struct reyes_vertex_lanes *out)
{
    reyes_lanes x[3], normal[3];
    reyes_row_point_lanes(rc, u, x);
    reyes_lane_mask collapsed = reyes_row_normal_lanes(rc, u, normal);
    return reyes_dice_place_lanes(p, light, x, normal, collapsed, u, v, sp, base, shade, out);
}

/* Shading-rate grids follow their edges (reyes_rate.cl): an edge with
 * fewer segments c than the lattice's n along it gets its own c + 1
 * vertices, at the parameters a grid of c segments puts there, in the
 * lattice's n + 1 boundary slots: slot i holds edge vertex
 * (i c + n / 2) / n (integer division), which visits every edge vertex
 * in order, each one or more times.  The boundary quads then join the
 * edge's segments to the lattice's next row, a quad whose two edge
 * corners are the same vertex being a triangle, so the grid's border is
 * exactly the edge's polyline on both sides of the edge.  These give
 * edge `edge`'s vertex count c, the lattice's segments n along it, and
 * slot i's lattice index. */
REYES_INLINE int reyes_edge_step(int i, int c, int n)
{
    return (i * c + n / 2) / n;
}

REYES_INLINE int reyes_edge_slot(int edge, int i, int columns, int rows)
{
    switch (edge) {
    case REYES_EDGE_V0: return i;
    case REYES_EDGE_U1: return i * columns + columns - 1;
    case REYES_EDGE_V1: return (rows - 1) * columns + i;
    default: return i * columns;
    }
}

/* The grid's header for rasterize's shading: vertex colours, or with
 * sample shading `mode` (REYES_SHADE_*), the base colour and the
 * sub-patch. */
REYES_INLINE void reyes_grid_shading(__global const struct reyes_params *p, __local struct reyes_grid *g,
                                     const struct reyes_subpatch *sp, uint base, uint mode)
{
    g->shading = p->sample_shading ? mode : REYES_SHADE_VERTICES;
    g->base = base;
    g->patch = sp->patch;
    g->u0 = sp->u0;
    g->v0 = sp->v0;
    g->u1 = sp->u1;
    g->v1 = sp->v1;
}
