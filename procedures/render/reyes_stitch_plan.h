/*
 * Host side of crack stitching: from the sub-patches bound chose to dice
 * (the leaves of the first pass), find for every leaf edge the neighbours
 * across it that are diced finer (same base patch) or belong to another
 * base patch whose boundary curve has the same control points, and make
 * one stitch item per contiguous run of such neighbours.
 */
#ifndef REYES_STITCH_PLAN_H
#define REYES_STITCH_PLAN_H

#include "reyes.h"
#include "reyes_shared.h"

typedef struct reyes_stitch_plan {
    struct reyes_stitch *items;
    float (*item_boxes)[4];          /* per item: screen box lo_x lo_y hi_x hi_y */
    size_t item_count;
    struct reyes_stitch_piece *pieces;
    size_t piece_count;
} reyes_stitch_plan;

/* Sort leaves by base patch and rectangle (bound records them in any
 * order), so the plan and the seeds do not depend on the schedule. */
void reyes_leaves_sort(struct reyes_leaf *leaves, size_t count);

/* Build the plan for sorted leaves of `scene`; with near_seams also
 * across base patch boundaries that agree only nearly
 * (reyes_stitch_glue.h; shading-rate grids, whose two sides of such a
 * seam may be split and diced differently). */
reyes_status reyes_stitch_plan_build(const reyes_scene *scene, const struct reyes_leaf *leaves,
                                     size_t count, int near_seams, reyes_stitch_plan *plan, reyes_error *error);
void reyes_stitch_plan_free(reyes_stitch_plan *plan);

#endif
