/* Renders of the models in ../shared/models (suite 'shared'). */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_shared.h"
#include "reyes_test_util.h"

#ifndef REYES_MODELS_DIR
#error "REYES_MODELS_DIR must name the shared models directory"
#endif

/* A model and a camera framing it at 40 degrees for a width x height
 * image. */
static void load_framed(reyes_scene *scene, reyes_camera *camera, const char *file, unsigned width,
                        unsigned height)
{
    reyes_error error;
    reyes_test_load_model(scene, REYES_MODELS_DIR, file);
    ck_assert_int_eq(reyes_camera_frame(scene, 40.0f, (float)width / (float)height, camera, &error), REYES_OK);
}

START_TEST(test_load_all_models)
{
    const struct { const char *file; size_t patches; } models[] = {
        {"teapot.bpt", 32}, {"killeroo.bpt", 11532}, {"newell-teapot.bpt", 28},
        {"teacup.bpt", 26}, {"teaspoon.bpt", 16},
    };
    for (size_t m = 0; m < sizeof models / sizeof models[0]; ++m) {
        reyes_scene scene;
        reyes_test_load_model(&scene, REYES_MODELS_DIR, models[m].file);
        ck_assert_uint_eq(scene.patch_count, models[m].patches);
        reyes_scene_free(&scene);
    }
}
END_TEST

/* The teapot: same splits, grids and image with 1 and 2 work-groups, and
 * no crack pixels at the default 8 px bound and 16x16 grid. */
START_TEST(test_teapot_groups_and_holes)
{
    reyes_scene scene;
    reyes_camera camera;
    load_framed(&scene, &camera, "teapot.bpt", 192, 144);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 192;
    o.height = 144;
    reyes_image one, two;
    reyes_stats stats_one, stats_two;
    reyes_test_render(reyes_test_renderer(1), &scene, &camera, &o, &one, &stats_one);
    reyes_test_render(reyes_test_renderer(2), &scene, &camera, &o, &two, &stats_two);
    ck_assert_uint_gt(stats_one.splits, 32);
    reyes_test_expect_same_counts(&stats_one, &stats_two, "teapot, 2 groups");
    ck_assert_uint_eq(stats_one.forced_dice, 0);
    reyes_test_expect_same_image(&one, &two, "teapot, 2 groups");
    reyes_test_expect_reference_counts(&scene, &camera, &o, &stats_one);
    ck_assert_uint_eq(reyes_test_hole_pixels(&one, 16), 0);
    reyes_image_free(&one);
    reyes_image_free(&two);
    reyes_scene_free(&scene);
}
END_TEST

/* Counts: splits and grids (and every other count) for the teapot are
 * identical across techniques and strategies, and equal the C reference's. */
START_TEST(test_teapot_counts_every_schedule)
{
    reyes_scene scene;
    reyes_camera camera;
    load_framed(&scene, &camera, "teapot.bpt", 256, 192);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 256;
    o.height = 192;
    o.spp = 1;
    reyes_stats first;
    memset(&first, 0, sizeof first);
    for (unsigned s = 0; s < reyes_test_schedule_count(); ++s) {
        const char *label = reyes_test_schedule(s);
        reyes_test_apply_schedule(label, 2, &o);
        reyes_image image;
        reyes_stats stats;
        reyes_test_render_once(&scene, &camera, &o, &image, &stats);
        reyes_image_free(&image);
        ck_assert_msg(stats.run.technique == o.schedule.technique, "%s: ran another technique", label);
        if (s == 0) {
            first = stats;
            ck_assert_uint_gt(stats.splits, 1000);
            reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
            continue;
        }
        reyes_test_expect_same_counts(&first, &stats, label);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* Killeroo (11532 patches) renders at a small size. */
START_TEST(test_killeroo)
{
    reyes_scene scene;
    reyes_camera camera;
    load_framed(&scene, &camera, "killeroo.bpt", 128, 128);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 128;
    o.height = 128;
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &stats);
    ck_assert_uint_eq(stats.patches_in + stats.splits, stats.grids + stats.culled);
    ck_assert_uint_gt(stats.samples_written, 128 * 128 * o.spp / 10);
    reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* The teapot and killeroo with the cameras of the speed benchmark
 * (docs/reyes-measurements.md) equal the C reference's images within rounding. */
START_TEST(test_models_match_reference)
{
    static const struct {
        const char *file;
        reyes_camera camera;
    } views[] = {
        { "teapot.bpt", { .eye = {8.0f, -8.0f, 6.0f}, .at = {0.0f, 0.0f, 1.5f}, .fov_deg = 40.0f } },
        { "killeroo.bpt", { .eye = {8.0f, 0.0f, 2.0f}, .at = {0.0f, 0.0f, 0.0f}, .fov_deg = 45.0f } },
    };
    for (size_t v = 0; v < sizeof views / sizeof views[0]; ++v) {
        reyes_scene scene;
        reyes_test_load_model(&scene, REYES_MODELS_DIR, views[v].file);
        reyes_options o;
        reyes_options_init(&o);
        o.width = 256;
        o.height = 256;
        o.crack_fix = REYES_CRACK_FIX_NONE;
        reyes_image image;
        reyes_test_render(reyes_test_renderer(0), &scene, &views[v].camera, &o, &image, NULL);
        reyes_test_expect_reference_image(&scene, &views[v].camera, &o, &image, views[v].file);
        reyes_image_free(&image);
        reyes_scene_free(&scene);
    }
}
END_TEST

/* The teapot of the watertightness tests: 128x128 at 1 sample per pixel
 * with coarse 6x6 grids, and the finer render (3 px bound, stitched) whose
 * coverage tells a model's real gaps from cracks. */
static void coarse_teapot(reyes_scene *scene, reyes_options *o, reyes_options *fine)
{
    reyes_test_load_model(scene, REYES_MODELS_DIR, "teapot.bpt");
    reyes_options_init(o);
    o->width = o->height = 128;
    o->spp = 1;
    o->grid = 6;
    *fine = *o;
    fine->bound_px = 3.0f;
}

/* Crack-free subdivision of the teapot: from random views at 1 sample per
 * pixel, no holes with stitching at coarse 6x6 grids and a 12 px bound
 * (wide cracks).  Holes are enclosed uncovered pixels that a finer render
 * (3 px bound, stitched) covers, so the gaps of the handle and spout do not
 * count.  The count without stitching is printed. */
START_TEST(test_teapot_watertight)
{
    reyes_scene scene;
    reyes_options o, fine;
    reyes_error error;
    coarse_teapot(&scene, &o, &fine);
    o.bound_px = 12.0f;
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    o.crack_fix = REYES_CRACK_FIX_NONE;
    size_t without = reyes_test_holes_from_random_views(renderer, &scene, &o, &fine, 24, 777u, 16);
    o.crack_fix = REYES_CRACK_FIX_STITCH;
    size_t with = reyes_test_holes_from_random_views(renderer, &scene, &o, &fine, 24, 777u, 16);
    printf("teapot, 24 views at 128x128, grid 6, bound 12 px, 1 spp: %zu hole pixels without crack fix, %zu with "
           "stitching\n", without, with);
    ck_assert_uint_eq(with, 0);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

/* The tiered subdivision criterion on real models: the teapot stays
 * watertight with stitching, and the killeroo's decisions match the C
 * reference's. */
START_TEST(test_models_tiered)
{
    reyes_scene scene;
    reyes_options o, fine;
    reyes_error error;
    coarse_teapot(&scene, &o, &fine);
    o.subdivision = REYES_SUBDIVISION_TIERED;
    o.flat_bound_px = 12.0f;
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    o.crack_fix = REYES_CRACK_FIX_NONE;
    size_t without = reyes_test_holes_from_random_views(renderer, &scene, &o, &fine, 24, 778u, 16);
    o.crack_fix = REYES_CRACK_FIX_STITCH;
    size_t stitched = reyes_test_holes_from_random_views(renderer, &scene, &o, &fine, 24, 778u, 16);
    o.crack_fix = REYES_CRACK_FIX_WEDGE;
    size_t wedged = reyes_test_holes_from_random_views(renderer, &scene, &o, &fine, 24, 778u, 16);
    printf("teapot, tiered criterion, 24 views at 128x128, grid 6, bound 12 px, 1 spp: %zu hole "
           "pixels without crack fix, %zu with stitching, %zu with wedges\n", without, stitched,
           wedged);
    ck_assert_uint_eq(stitched, 0);
    ck_assert_uint_eq(wedged, 0);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);

    reyes_scene_init(&scene);
    reyes_test_load_model(&scene, REYES_MODELS_DIR, "killeroo.bpt");
    reyes_options_init(&o);
    o.width = o.height = 256;
    o.subdivision = REYES_SUBDIVISION_TIERED;
    reyes_camera camera;
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &camera, &error), REYES_OK);
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &stats);
    reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
    ck_assert_uint_eq(stats.split_bound + stats.split_edge + stats.split_inner + stats.split_near,
                      stats.splits);
    ck_assert_uint_gt(stats.split_edge + stats.split_inner, 0);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

static Suite *models_suite(void)
{
    Suite *s = suite_create("reyes_models");
    TCase *tc = tcase_create("models");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_load_all_models);
    tcase_add_test(tc, test_teapot_groups_and_holes);
    tcase_add_test(tc, test_teapot_counts_every_schedule);
    tcase_add_test(tc, test_killeroo);
    tcase_add_test(tc, test_models_match_reference);
    tcase_add_test(tc, test_teapot_watertight);
    tcase_add_test(tc, test_models_tiered);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    return reyes_test_run_suite(models_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
