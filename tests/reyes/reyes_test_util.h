/* Helpers for the Reyes rendering tests. */
#ifndef REYES_TEST_UTIL_H
#define REYES_TEST_UTIL_H

#include "reyes.h"

/* Sum of the covered samples over all pixels. */
uint64_t reyes_test_covered_samples(const reyes_image *image);

/* Uncovered pixels in regions of fewer than max_region uncovered pixels
 * that do not touch the border: cracks between micropolygons or patches.
 * (Real background seen through a model, like the teapot handle, makes
 * larger regions.) */
size_t reyes_test_hole_pixels(const reyes_image *image, size_t max_region);

/* Render or fail the test with the library's message. */
void reyes_test_render(reyes_renderer *renderer, const reyes_scene *scene,
                       const reyes_camera *camera, const reyes_options *options,
                       reyes_image *image, reyes_stats *stats);

/* The megakernel's splits, culled, grids and micropolygons equal those of
 * the single-threaded C reference (reyes_reference.c). */
void reyes_test_expect_reference_counts(const reyes_scene *scene, const reyes_camera *camera,
                                        const reyes_options *options, const reyes_stats *stats);

/* A renderer created once per process for `work_groups` groups (0 or
 * 1..2) with default grid; destroyed at exit. */
reyes_renderer *reyes_test_renderer(unsigned work_groups);

#endif
