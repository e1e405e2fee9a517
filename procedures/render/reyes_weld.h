/*
 * Welding base patch seams for the polyline crack fix (reyes_polyline.cl
 * needs both sides of a seam to have the same boundary curve, bit for
 * bit): the boundaries reyes_glue_boundaries glues, near seams included
 * (each control point within a fiftieth of the curve's polygon: models
 * converted patch by patch, like the killeroo, leave gaps of that size),
 * are made identical.  Corners that glued seams or equal coordinates join
 * become their cluster's mean; each glued pair's two inner boundary points
 * become their pair's mean.  Nothing else moves, so seams that already
 * agreed stay as they were.  The boundaries left unglued (open edges, and
 * gaps wider than the tolerance) are marked, a bit per REYES_EDGE_*, in
 * the w of each patch's first control point (otherwise 1 and unread).
 */
#ifndef REYES_WELD_H
#define REYES_WELD_H

#include "reyes.h"

/* The scene's points (patch_count * 64 floats) welded into *out (malloc'd;
 * free it); *moved: how many control points changed. */
reyes_status reyes_weld_points(const reyes_scene *scene, float **out, size_t *moved, reyes_error *error);

/* A hash of the scene's points and count (the renderer keeps the welded
 * points of the last scene it saw). */
uint64_t reyes_points_hash(const reyes_scene *scene);

#endif
