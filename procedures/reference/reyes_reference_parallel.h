/*
 * The C reference's full render on every core with OpenMP
 * (reyes_reference_parallel.c, in its own library: perma-bench and the
 * tests link it, the renderer does not need OpenMP).
 */
#ifndef REYES_REFERENCE_PARALLEL_H
#define REYES_REFERENCE_PARALLEL_H

#include "reyes_reference.h"

/* reyes_reference_render on `threads` OpenMP threads (0: OpenMP's default,
 * one per online CPU): the same image and counts, bit for bit; in
 * out->seconds the same span of the render. */
reyes_status reyes_reference_render_parallel(const reyes_scene *scene, const reyes_camera *camera,
                                             const reyes_options *options, unsigned threads, reyes_image *image,
                                             reyes_reference_counts *out, reyes_error *error);

#endif
