/*
 * Which base patch boundaries the crack stitches cross (reyes_stitch_plan.c):
 * two patches meet along a boundary curve when their control points for
 * it are the same, in either direction, or (for shading-rate grids) nearly
 * the same: each of the four within a fiftieth of the curve's control
 * polygon length.  Models converted patch by patch, like the killeroo,
 * often agree only to rounding or a little more; fixed grids put the same
 * vertices on both sides of such a seam anyway, but shading-rate grids may
 * split and dice the two sides differently, and the stitch closes what
 * that opens.
 */
#ifndef REYES_STITCH_GLUE_H
#define REYES_STITCH_GLUE_H

#include "reyes.h"

/* A base patch boundary glued to another patch's boundary. */
typedef struct boundary_link {
    int32_t patch;      /* -1: none */
    uint32_t boundary;  /* REYES_EDGE_* of the other patch */
    uint32_t reversed;
} boundary_link;

/* links[patch * 4 + boundary] for every boundary of the scene: glued
 * exactly where exactly two patches share a curve, and with `near` also
 * where two curves left unglued are each other's nearest within the
 * tolerance; collapsed and symmetric curves are left alone. */
reyes_status reyes_glue_boundaries(const reyes_scene *scene, int near, boundary_link *links, reyes_error *error);

#endif
