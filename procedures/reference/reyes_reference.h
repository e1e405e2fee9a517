/*
 * Single-threaded C reference of the Reyes pipeline (depth-first
 * recursion, no OpenCL), mirroring the procedures' decisions.  Used to
 * cross-check the counts and images of the megakernel and as the CPU
 * baseline of the benchmarks.
 */
#ifndef REYES_REFERENCE_H
#define REYES_REFERENCE_H

#include "reyes.h"

typedef struct reyes_reference_counts {
    uint64_t splits;
    uint64_t culled;
    uint64_t grids;
    uint64_t forced_dice;
    uint64_t micropolygons; /* quads dice would emit (in front, on the image) */
    uint64_t occluded;      /* grids not diced as hidden (occlusion culling; order-dependent with threads) */
    uint64_t samples_written; /* covered samples of a full render */
    unsigned max_depth_seen;
    double seconds;
} reyes_reference_counts;

/* Bound, split and dice's geometry (the positions and visibility of every
 * quad; with options->stages == REYES_STAGES_SUBDIVIDE grids are counted,
 * not diced): the counts, and its time in out->seconds. */
reyes_status reyes_reference_run(const reyes_scene *scene, const reyes_camera *camera,
                                 const reyes_options *options, reyes_reference_counts *out,
                                 reyes_error *error);

/* The full pipeline: bound, split, dice, normals, shading, sampling and
 * the resolve into *image (free with reyes_image_free), the counts, and in
 * out->seconds the time from the sample positions and the first bound to
 * the last sample written (what perma_run does in a render: the clearing
 * of the samples before and the resolve after are left out on both
 * sides).  Renders without a crack fix (a stitched or wedged render
 * differs along the cracks), and refuses motion blur, depth of field and
 * displacement.  With a shading rate and options->occlusion_cull (the
 * default) it culls hidden grids as the renderer does (reyes_occlusion.cl):
 * it dices the sub-patches front to back, by their control hulls' nearest
 * clip w, and skips each whose every sample under its hull's octagon
 * already holds a nearer surface (counted in occluded; still in grids).
 * The image is the same bytes as with occlusion_cull 0. */
reyes_status reyes_reference_render(const reyes_scene *scene, const reyes_camera *camera,
                                    const reyes_options *options, reyes_image *image,
                                    reyes_reference_counts *out, reyes_error *error);

/* The color reyes_shade (reyes_surface.cl) gives a surface point x with
 * normal n (any length, either side) and packed base color rgba, seen from
 * `eye`: rgb in [0,1].  The device computes it per grid vertex at native
 * precision; this is the expectation tests hold rendered pixels to. */
void reyes_reference_shade(const float eye[3], const float x[3], const float n[3], uint32_t rgba,
                           float rgb[3]);

#endif
