/* The pieces of one render, shared by the bucket loop (reyes_render.c),
 * the device parameters (reyes_render_params.c), the crack-stitching
 * passes (reyes_render_stitch.c) and the run over one tile that both of
 * those last call (reyes_render_tile.c). */
#ifndef REYES_RENDER_INTERNAL_H
#define REYES_RENDER_INTERNAL_H

#include "reyes.h"
#include "reyes_blur_tuples.h"
#include "reyes_shared.h"
#include "reyes_stitch_plan.h"

/* The per-render buffers handed to perma_bind_host. */
typedef struct render_buffers {
    const float *points;            /* the patches' control points: the scene's, or welded */
    struct reyes_params params;
    uint32_t counters[REYES_COUNTERS];
    struct reyes_subpatch *seeds;   /* one per base patch */
    /* Crack stitching: the leaves of the first pass, the plan, and the
     * seeds of one bucket (dice: leaves, stitch: items). */
    int stitched;
    struct reyes_leaf *leaves;
    size_t leaf_count, leaf_capacity;
    size_t *near_order;             /* leaf indices in seeding order (nearest hull first when culling) */
    reyes_stitch_plan plan;
    struct reyes_subpatch *dice_seeds;
    struct reyes_stitch *stitch_seeds;
    size_t dice_seed_count, stitch_seed_count;
    reyes_gray_map map;             /* displacement map (or none) */
    reyes_blur_tuple *tuples;       /* motion blur and defocus (or none) */
    size_t tuple_count;
} render_buffers;

/* A bucket: pixels [x0,x1) x [y0,y1) of the image. */
typedef struct tile {
    unsigned x0, y0, x1, y1;
} tile;

/* The parameters of a render from its scene, camera and options (all but
 * the tile, the displacement map's size and the leaf recording). */
reyes_status render_fill_params(const reyes_scene *scene, const reyes_camera *camera, const reyes_options *o,
                                struct reyes_params *p, reyes_error *error);

/* Point the parameters at one tile: its pixel rectangle and its
 * sub-frustum in normalised device coordinates (reyes_render_tile.c). */
void render_set_tile(struct reyes_params *p, const reyes_options *o, tile t);

/* One perma run over the tile in b->params with the seeds of the current
 * mode; adds its statistics.  *call names what failed (reyes_render_tile.c). */
perma_status render_run_tile(reyes_renderer *r, const reyes_scene *scene, render_buffers *b, reyes_stats *stats,
                             size_t *peak_bytes, const char **call);

/* First pass of crack stitching, over the whole image: record the
 * sub-patches to dice and build the stitch plan and the seed arrays. */
reyes_status render_subdivide_and_plan(reyes_renderer *r, const reyes_scene *scene, const reyes_options *o,
                                       render_buffers *b, reyes_stats *stats, reyes_error *error);

/* The stitched seeds of tile t (leaves and stitch items that reach it). */
void render_select_stitched_seeds(const reyes_options *o, tile t, render_buffers *b);

#endif
