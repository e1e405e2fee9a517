/*
 * Single-threaded C reference of bound / split / dice (depth-first
 * recursion, no OpenCL), mirroring the procedures' decisions.  Used to
 * cross-check the counts of the megakernel and as a CPU baseline.  With
 * options->stages == REYES_STAGES_SUBDIVIDE grids are counted, not diced.
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
    unsigned max_depth_seen;
    double seconds;
} reyes_reference_counts;

reyes_status reyes_reference_run(const reyes_scene *scene, const reyes_camera *camera,
                                 const reyes_options *options, reyes_reference_counts *out,
                                 reyes_error *error);

/* The color reyes_shade (reyes_surface.cl) gives a surface point x with
 * normal n (any length, either side) and packed base color rgba, seen from
 * `eye`: rgb in [0,1].  The device computes it per grid vertex at native
 * precision; this is the expectation tests hold rendered pixels to. */
void reyes_reference_shade(const float eye[3], const float x[3], const float n[3], uint32_t rgba,
                           float rgb[3]);

#endif
