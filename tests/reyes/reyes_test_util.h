/* Helpers for the Reyes rendering tests. */
#ifndef REYES_TEST_UTIL_H
#define REYES_TEST_UTIL_H

#include <check.h>

#include "reyes.h"

/* Sum of the covered samples over all pixels. */
uint64_t reyes_test_covered_samples(const reyes_image *image);

/* Uncovered pixels in regions of fewer than max_region uncovered pixels
 * that do not touch the border: cracks between micropolygons or patches.
 * (Real background seen through a model, like the teapot handle, makes
 * larger regions.) */
size_t reyes_test_hole_pixels(const reyes_image *image, size_t max_region);

/* Hole pixels (reyes_test_enclosed_pixels with regions under max_region)
 * summed over `views` renders of a scene at options (1 sample per pixel,
 * crack_fix as given...), from random eyes (fixed seed) at 2.5 to 6
 * bounding radii around its center.  With a reference (NULL: none), only
 * hole regions that a render of the same view with the reference options
 * covers entirely count: a model's real see-through gaps (the teapot's
 * handle and spout) are open there too. */
size_t reyes_test_holes_from_random_views(reyes_renderer *renderer, const reyes_scene *scene,
                                          const reyes_options *options,
                                          const reyes_options *reference, unsigned views,
                                          unsigned seed, size_t max_region);

/* The same with 8-connected regions: at 1 sample per pixel a pixel on a
 * convex silhouette can have all four edge neighbours covered, but it
 * touches the outside diagonally; a crack does not. */
size_t reyes_test_enclosed_pixels(const reyes_image *image, size_t max_region);

/* The built-in scene, and a camera framing it at 40 degrees for a
 * width x height image. */
void reyes_test_builtin_scene(reyes_scene *scene, reyes_camera *camera, unsigned width, unsigned height);

/* The built-in scene framed for 160x120 and default options of that size:
 * the small render most tests compare. */
void reyes_test_small_builtin(reyes_scene *scene, reyes_camera *camera, reyes_options *options);

/* The model dir/file (a .bpt file, in the first model colour); fails the
 * test with the loader's message if it cannot be read. */
void reyes_test_load_model(reyes_scene *scene, const char *dir, const char *file);

/* A sphere of radius 1 at the origin, light gray. */
void reyes_test_sphere_scene(reyes_scene *scene);

/* Append a copy of the scene's first patch whose first control point is
 * moved to (distance, 0, 0): one stray point far from the rest. */
void reyes_test_add_far_patch(reyes_scene *scene, float distance);

/* Append a flat square patch in the plane z = `z`, x and y from x0, y0,
 * `size` wide. */
void reyes_test_add_square(reyes_scene *scene, float x0, float y0, float z, float size);

/* The two renders are byte-identical: size, colors and coverage; the
 * failure names `label` and how many pixels differ. */
void reyes_test_expect_same_image(const reyes_image *expected, const reyes_image *image, const char *label);

/* The two renders did the same work: splits, grids, culled patches,
 * micropolygons, covered samples and every procedure's items. */
void reyes_test_expect_same_counts(const reyes_stats *expected, const reyes_stats *stats, const char *label);

/* A bucketed render has one peak queue memory per bucket, the largest of
 * which is the render's. */
void reyes_test_expect_bucket_peaks(const reyes_stats *stats);

/* Render or fail the test with the library's message. */
void reyes_test_render(reyes_renderer *renderer, const reyes_scene *scene,
                       const reyes_camera *camera, const reyes_options *options,
                       reyes_image *image, reyes_stats *stats);

/* The megakernel's splits, culled, grids and micropolygons equal those of
 * the single-threaded C reference (reyes_reference.c). */
void reyes_test_expect_reference_counts(const reyes_scene *scene, const reyes_camera *camera,
                                        const reyes_options *options, const reyes_stats *stats);

/* The image equals the C reference's render of the same scene, camera and
 * options (reyes_reference_render: the same pipeline written in plain C)
 * within rounding: the two evaluate, light and sample with the same
 * formulas, but the OpenCL compiler fuses multiply-adds and the light's
 * highlight is native_exp2/native_log2 there, so a vertex colour may
 * differ by one level and a sample on an edge may flip.  At most 1 % of
 * the pixels may differ at all, at most 0.1 % by more than 4 levels in a
 * channel, and coverage by at most one sample in 0.1 % of the pixels. */
void reyes_test_expect_reference_image(const reyes_scene *scene, const reyes_camera *camera,
                                       const reyes_options *options, const reyes_image *image, const char *label);

/* A renderer created once per process for `work_groups` groups (0 or
 * 1..2) with default grid; destroyed at exit. */
reyes_renderer *reyes_test_renderer(unsigned work_groups);
/* The same made for per-vertex motion (created with a rotation). */
reyes_renderer *reyes_test_moving_renderer(unsigned work_groups);
/* reyes_test_moving_renderer if options rotate, else reyes_test_renderer. */
reyes_renderer *reyes_test_renderer_for(const reyes_options *options, unsigned work_groups);

/* Schedule labels (perma_schedule_parse): every schedule of the runtime
 * (perma_schedule_all: every technique, every megakernel strategy, every
 * victim under one stealing strategy), then a local front queue and a small
 * batch limit.  "megakernel/stealing/round-robin", "bounded-batches/p=64", ... */
unsigned reyes_test_schedule_count(void);
const char *reyes_test_schedule(unsigned index);

/* Set the scheduling fields of *options from a schedule label and a group
 * count; fails the test with the parser's message if the label is bad. */
void reyes_test_apply_schedule(const char *label, unsigned work_groups, reyes_options *options);

/* Create a renderer for options (its scheduling fields), render once,
 * destroy it; fails the test with the library's message. */
void reyes_test_render_once(const reyes_scene *scene, const reyes_camera *camera,
                            const reyes_options *options, reyes_image *image, reyes_stats *stats);

/* Run a suite in this process (no fork per test, so one OpenCL runtime and
 * its compiled programs serve all tests) and return its failure count. */
int reyes_test_run_suite(Suite *suite);

#endif
