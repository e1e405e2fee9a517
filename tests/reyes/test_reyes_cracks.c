/* Crack-free subdivision: a closed sphere of patches seen from random
 * views at 1 sample per pixel shows no holes with stitching.  Coarse grids
 * (4x4 vertices) and a large bound make the cracks between grids diced at
 * different rates wide enough to catch samples. */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "reyes_shared.h"
#include "reyes_stitch_glue.h"
#include "reyes_weld.h"
#include "reyes_test_util.h"

#define VIEWS 24
#define SEED 12345u
#define MAX_HOLE 48
#define GRID 4
#define BOUND_PX 16.0f

static void crack_options(reyes_options *o, unsigned crack_fix)
{
    reyes_options_init(o);
    o->width = 128;
    o->height = 128;
    o->spp = 1;
    o->crack_fix = crack_fix;
    o->grid = GRID;
    o->bound_px = BOUND_PX;
}

START_TEST(test_sphere_watertight)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    const float center[3] = {0.3f, -0.2f, 0.1f};
    ck_assert_int_eq(reyes_scene_add_sphere(&scene, center, 1.0f, REYES_RGBA(200, 200, 200), &error),
                     REYES_OK);
    reyes_options o;
    crack_options(&o, REYES_CRACK_FIX_NONE);
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    size_t without = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                        SEED, MAX_HOLE);
    crack_options(&o, REYES_CRACK_FIX_STITCH);
    size_t with = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                     SEED, MAX_HOLE);
    printf("sphere, %d views at 1 spp: %zu hole pixels without crack fix, %zu with stitching\n",
           VIEWS, without, with);
    ck_assert_uint_eq(with, 0);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

/* Polylines (one pass, no communication between patches) with a shading
 * rate.  At rate 100 a piece is at least 5 pixels long, so an edge's
 * chords stray from the curve by a tenth of a pixel or more where the
 * sphere bends, and the T-junctions where sub-patches meet others split
 * deeper open cracks; back faces culled, they show the background.  With
 * polylines none shows; both halves of the fix are needed (without the
 * T-junction fillers 12 hole pixels remain, without the shared polylines
 * on the edges 54). */
START_TEST(test_watertight_polylines)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    const float center[3] = {0.3f, -0.2f, 0.1f};
    ck_assert_int_eq(reyes_scene_add_sphere(&scene, center, 1.0f, REYES_RGBA(200, 200, 200), &error), REYES_OK);
    reyes_options o;
    crack_options(&o, REYES_CRACK_FIX_NONE);
    o.shading_rate = 100.0f;
    o.backface_cull = 1;
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    /* Holes are the ones a fine render covers. */
    reyes_options fine = o;
    fine.shading_rate = 0.25f;
    fine.crack_fix = REYES_CRACK_FIX_STITCH;
    size_t without = reyes_test_holes_from_random_views(renderer, &scene, &o, &fine, VIEWS, SEED + 2, MAX_HOLE);
    o.crack_fix = REYES_CRACK_FIX_POLYLINE;
    size_t with = reyes_test_holes_from_random_views(renderer, &scene, &o, &fine, VIEWS, SEED + 2, MAX_HOLE);
    reyes_camera camera;
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &camera, &error), REYES_OK);
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(renderer, &scene, &camera, &o, &image, &stats);
    printf("sphere, rate 100, back faces culled, %d views at 1 spp: %zu hole pixels without crack fix, %zu with "
           "polylines (%llu T-junction fillers framed)\n", VIEWS, without, with, (unsigned long long)stats.fillers);
    ck_assert_uint_gt(without, 0);
    ck_assert_uint_eq(with, 0);
    ck_assert_uint_gt(stats.fillers, 0);
    ck_assert_uint_eq(stats.stitches, 0);
    reyes_image_free(&image);
    reyes_stats_free(&stats);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

/* The tiered subdivision criterion, with coarse grids and sub-patches up
 * to BOUND_PX so that cracks are wide: sub-patches are split to different
 * depths by curvature, not only by size.  Both crack fixes close them:
 * stitching (two passes) and wedges (one pass, no communication between
 * patches). */
START_TEST(test_sphere_watertight_tiered)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    const float center[3] = {-0.2f, 0.1f, 0.3f};
    ck_assert_int_eq(reyes_scene_add_torus(&scene, center, 1.0f, 0.35f, REYES_RGBA(200, 200, 200),
                                           &error),
                     REYES_OK);
    reyes_options o;
    crack_options(&o, REYES_CRACK_FIX_NONE);
    o.subdivision = REYES_SUBDIVISION_TIERED;
    o.flat_bound_px = BOUND_PX;
    o.flat_epsilon = 0.5f;
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    size_t without = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                        SEED + 1, MAX_HOLE);
    o.crack_fix = REYES_CRACK_FIX_STITCH;
    size_t stitched = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                         SEED + 1, MAX_HOLE);
    o.crack_fix = REYES_CRACK_FIX_WEDGE;
    size_t wedged = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                       SEED + 1, MAX_HOLE);
    printf("torus, tiered criterion, %d views at 1 spp: %zu hole pixels without crack fix, "
           "%zu with stitching, %zu with wedges\n", VIEWS, without, stitched, wedged);
    ck_assert_uint_eq(stitched, 0);
    ck_assert_uint_eq(wedged, 0);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

/* The built-in scene framed at 512x512 with the tiered criterion, coarse
 * 4x4 grids of sub-patches up to 48 px and 1 sample per pixel: without a
 * fix, pinholes show through the spheres; wedges and stitching close every
 * one of them. */
START_TEST(test_builtin_wedges)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_add_builtin(&scene, &error), REYES_OK);
    reyes_options o;
    crack_options(&o, REYES_CRACK_FIX_NONE);
    o.width = o.height = 512;
    o.subdivision = REYES_SUBDIVISION_TIERED;
    o.flat_bound_px = 48.0f;
    o.flat_epsilon = 1.0f;
    reyes_camera camera;
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &camera, &error), REYES_OK);
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    const unsigned fixes[3] = {REYES_CRACK_FIX_NONE, REYES_CRACK_FIX_STITCH, REYES_CRACK_FIX_WEDGE};
    size_t holes[3];
    uint64_t fillers[3];
    for (int k = 0; k < 3; ++k) {
        o.crack_fix = fixes[k];
        reyes_image image;
        reyes_stats stats;
        reyes_test_render(renderer, &scene, &camera, &o, &image, &stats);
        holes[k] = reyes_test_hole_pixels(&image, MAX_HOLE);
        fillers[k] = stats.fillers;
        reyes_image_free(&image);
        reyes_stats_free(&stats);
    }
    printf("built-in scene, tiered, 4x4 grids up to 48 px, 1 spp: %zu hole pixels without crack "
           "fix, %zu with stitching, %zu with wedges (%llu wedge triangles)\n", holes[0], holes[1],
           holes[2], (unsigned long long)fillers[2]);
    ck_assert_uint_gt(holes[0], 0);
    ck_assert_uint_eq(holes[1], 0);
    ck_assert_uint_eq(holes[2], 0);
    ck_assert_uint_eq(fillers[0], 0);
    ck_assert_uint_gt(fillers[2], 0);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* A square of side `size` in the plane x = 0 from (y0, z0). */
static void add_upright_square(reyes_scene *scene, float y0, float z0, float size)
{
    float cp[4][4][3];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            cp[r][c][0] = 0.0f;
            cp[r][c][1] = y0 + size * (float)c / 3.0f;
            cp[r][c][2] = z0 + size * (float)r / 3.0f;
        }
    reyes_error error;
    ck_assert_int_eq(reyes_scene_add_patch(scene, cp, REYES_RGBA(200, 200, 200), &error), REYES_OK);
}

#define SEAM_SIDE 300        /* squares per side of the grid */
#define SEAM_COPIES 10000    /* coincident copies of one square */

/* 10^5 patches whose boundaries the stitch must glue nearly: a grid of
 * 300 x 300 squares in one plane, each shifted by up to 2e-4 of its side
 * (near seams, not exact ones), and 10^4 copies of one square.  Gluing
 * compared every pair of loose boundaries: 10^4 such patches took 15 s,
 * 10^5 did not finish in 300 s; it indexes them now, and the render takes
 * seconds.  The seams are glued: no crack shows at 1 sample per pixel. */
START_TEST(test_many_near_seams_render_in_seconds)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    const float side = 1.0f / SEAM_SIDE;
    for (unsigned i = 0; i < SEAM_SIDE * SEAM_SIDE; ++i) {
        float shift = side * 1e-4f * (float)(i % 3);
        add_upright_square(&scene, (float)(i % SEAM_SIDE) * side + shift, (float)(i / SEAM_SIDE) * side - shift,
                           side);
    }
    for (unsigned k = 0; k < SEAM_COPIES; ++k)
        add_upright_square(&scene, 0.25f, 0.25f, 0.5f);
    ck_assert_uint_eq(scene.patch_count, 100000);
    /* Every seam of the grid glued (2 x 300 x 299 of them), and the first
     * two copies' boundaries (more than two patches on one curve: the
     * first two glue, the rest stay loose). */
    boundary_link *links = malloc(scene.patch_count * 4 * sizeof *links);
    ck_assert_ptr_nonnull(links);
    reyes_error error;
    double start = now();
    ck_assert_int_eq(reyes_glue_boundaries(&scene, 1, links, &error), REYES_OK);
    double glue_seconds = now() - start;
    size_t glued = 0;
    for (size_t b = 0; b < scene.patch_count * 4; ++b)
        glued += links[b].patch >= 0;
    ck_assert_uint_eq(glued, 2 * (2 * SEAM_SIDE * (SEAM_SIDE - 1)) + 8);
    for (uint32_t b = 0; b < 4; ++b) {
        const boundary_link *first = &links[(size_t)SEAM_SIDE * SEAM_SIDE * 4 + b];
        ck_assert_int_eq(first->patch, SEAM_SIDE * SEAM_SIDE + 1);
        ck_assert_uint_eq(first->boundary, b);
        ck_assert_uint_eq(first->reversed, 0);
    }
    free(links);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 64;
    o.spp = 1;
    o.crack_fix = REYES_CRACK_FIX_STITCH;
    const reyes_camera camera = { { 1.2f, 0.5f, 0.5f }, { 0.0f, 0.5f, 0.5f }, 40.0f };
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    reyes_image image;
    reyes_stats stats;
    start = now();
    reyes_test_render(renderer, &scene, &camera, &o, &image, &stats);
    double seconds = now() - start;
    printf("%zu patches with near seams: glued in %.2f s, rendered in %.2f s\n", scene.patch_count, glue_seconds,
           seconds);
    ck_assert_msg(glue_seconds < 20.0 && seconds < 60.0, "gluing took %.1f s, the render %.1f s", glue_seconds,
                  seconds);
    ck_assert_uint_eq(reyes_test_hole_pixels(&image, MAX_HOLE), 0);
    ck_assert_uint_eq(reyes_test_covered_samples(&image), (uint64_t)o.width * o.height);
    reyes_image_free(&image);
    reyes_stats_free(&stats);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

/* The seams polylines need identical: three squares in a row, the first
 * two sharing their seam exactly, the third shifted by 1e-4 of its side
 * (a near seam); welded, the near seam's two curves are the same points
 * (corners at their cluster's mean, inner points at their pair's), the
 * exact seam's are unchanged, and every other boundary is marked open in
 * the w of each patch's first control point. */
START_TEST(test_weld_near_seams)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    add_upright_square(&scene, 0.0f, 0.0f, 1.0f);
    add_upright_square(&scene, 1.0f, 0.0f, 1.0f);
    add_upright_square(&scene, 2.0f + 1e-4f, 1e-4f, 1.0f);
    float *welded;
    size_t moved;
    reyes_error error;
    ck_assert_int_eq(reyes_weld_points(&scene, &welded, &moved, &error), REYES_OK);
    /* Patch k's column 3 (u = 1) meets patch k + 1's column 0. */
    for (int k = 0; k < 2; ++k)
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 3; ++c) {
                float a = welded[(size_t)k * 64 + (size_t)(r * 4 + 3) * 4 + c];
                float b = welded[(size_t)(k + 1) * 64 + (size_t)(r * 4) * 4 + c];
                ck_assert_msg(a == b, "seam %d row %d: %.9g != %.9g", k, r, (double)a, (double)b);
            }
    /* The exact seam did not move; the near one met halfway. */
    ck_assert_float_eq(welded[(size_t)(1 * 4 + 3) * 4 + 1], 1.0f);
    ck_assert_float_eq_tol(welded[64 + (size_t)(1 * 4 + 3) * 4 + 1], 2.0f + 0.5e-4f, 1e-6f);
    /* The near seam's 4 points on each side, and nothing else. */
    ck_assert_uint_eq(moved, 8);
    /* Open: every boundary but the glued ones (u = 1 of the first, both u
     * sides of the second, u = 0 of the third). */
    ck_assert_float_eq(welded[3], (float)(1u << REYES_EDGE_V0 | 1u << REYES_EDGE_V1 | 1u << REYES_EDGE_U0));
    ck_assert_float_eq(welded[64 + 3], (float)(1u << REYES_EDGE_V0 | 1u << REYES_EDGE_V1));
    ck_assert_float_eq(welded[128 + 3], (float)(1u << REYES_EDGE_V0 | 1u << REYES_EDGE_V1 | 1u << REYES_EDGE_U1));
    free(welded);
    reyes_scene_free(&scene);
}
END_TEST

/* A grid of 60 x 60 squares whose seams agree only nearly (shifted by up
 * to 1.2 % of a side, within the glue's fiftieth), at a shading rate with
 * polylines: welded, no crack shows at 1 sample per pixel, every sample
 * covered; without a crack fix the gaps let the background through. */
START_TEST(test_near_seams_polylines)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    const unsigned side_count = 60;
    const float side = 1.0f / (float)side_count;
    for (unsigned i = 0; i < side_count * side_count; ++i) {
        float shift = side * 6e-3f * (float)(i % 3);
        add_upright_square(&scene, (float)(i % side_count) * side + shift, (float)(i / side_count) * side - shift,
                           side);
    }
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 96;
    o.spp = 1;
    o.shading_rate = 1.0f;
    o.crack_fix = REYES_CRACK_FIX_POLYLINE;
    const reyes_camera camera = { { 1.2f, 0.5f, 0.5f }, { 0.0f, 0.5f, 0.5f }, 40.0f };
    reyes_renderer *renderer;
    reyes_error error;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(renderer, &scene, &camera, &o, &image, &stats);
    ck_assert_uint_eq(reyes_test_hole_pixels(&image, MAX_HOLE), 0);
    ck_assert_uint_eq(reyes_test_covered_samples(&image), (uint64_t)o.width * o.height);
    reyes_image_free(&image);
    reyes_stats_free(&stats);
    /* Without the weld (no crack fix) the seams let the background through. */
    o.crack_fix = REYES_CRACK_FIX_NONE;
    reyes_test_render(renderer, &scene, &camera, &o, &image, &stats);
    printf("3600 squares with near seams, rate 1, 1 spp: %llu of %u samples uncovered without a crack fix, "
           "0 with polylines\n", (unsigned long long)((uint64_t)o.width * o.height - reyes_test_covered_samples(&image)),
           o.width * o.height);
    ck_assert_uint_lt(reyes_test_covered_samples(&image), (uint64_t)o.width * o.height);
    reyes_image_free(&image);
    reyes_stats_free(&stats);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_cracks");
    TCase *tc = tcase_create("cracks");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_sphere_watertight);
    tcase_add_test(tc, test_sphere_watertight_tiered);
    tcase_add_test(tc, test_watertight_polylines);
    tcase_add_test(tc, test_weld_near_seams);
    tcase_add_test(tc, test_near_seams_polylines);
    tcase_add_test(tc, test_builtin_wedges);
    tcase_add_test(tc, test_many_near_seams_render_in_seconds);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
