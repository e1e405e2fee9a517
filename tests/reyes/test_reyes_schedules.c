/* Every technique and strategy, with 1 or 2 work-groups, renders the
 * built-in scene to byte-identical images with identical counts, with
 * fixed grids (the library's default) and with a shading rate of 1 (the
 * command's: edge counts, stitches across seams, sample shading).  At
 * the rate with occlusion culling (the default) which grids are skipped
 * depends on the order they run in, so the counts are compared without
 * it, and the culled render's image with the unculled one's.  The
 * command's crack fix at the rate, polylines (with the culling), renders
 * the same bytes and splits and grids on every schedule too. */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_test_util.h"

#define WIDTH 128u
#define HEIGHT 96u

START_TEST(test_every_schedule_identical)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, WIDTH, HEIGHT);
    reyes_options o;
    reyes_options_init(&o);
    o.width = WIDTH;
    o.height = HEIGHT;
    reyes_image first = {0}, first_rate = {0}, first_polyline = {0};
    uint64_t polyline_splits = 0, polyline_grids = 0;
    reyes_stats first_stats, first_rate_stats;
    memset(&first_stats, 0, sizeof first_stats);
    memset(&first_rate_stats, 0, sizeof first_rate_stats);
    unsigned rendered = 0;
    for (unsigned s = 0; s < reyes_test_schedule_count(); ++s) {
        for (unsigned groups = 1; groups <= 2; ++groups) {
            char label[128];
            snprintf(label, sizeof label, "%s groups=%u", reyes_test_schedule(s), groups);
            reyes_test_apply_schedule(reyes_test_schedule(s), groups, &o);
            reyes_image image, rate_image, culled_image;
            reyes_stats stats, rate_stats, culled_stats;
            reyes_renderer *renderer;
            reyes_error error;
            ck_assert_msg(reyes_renderer_create(&o, &renderer, &error) == REYES_OK, "%s: %s", label, error.message);
            reyes_test_render(renderer, &scene, &camera, &o, &image, &stats);
            reyes_options rate = o;
            rate.shading_rate = 1.0f;
            rate.occlusion_cull = 0;
            reyes_test_render(renderer, &scene, &camera, &rate, &rate_image, &rate_stats);
            reyes_options culled = rate;
            culled.occlusion_cull = 1;
            reyes_test_render(renderer, &scene, &camera, &culled, &culled_image, &culled_stats);
            reyes_options polyline = culled;
            polyline.crack_fix = REYES_CRACK_FIX_POLYLINE;
            reyes_image polyline_image;
            reyes_stats polyline_stats;
            reyes_test_render(renderer, &scene, &camera, &polyline, &polyline_image, &polyline_stats);
            reyes_renderer_destroy(renderer);
            char polyline_label[160];
            snprintf(polyline_label, sizeof polyline_label, "%s, shading rate 1, polylines", label);
            if (rendered == 0) {
                first_polyline = polyline_image;
                polyline_splits = polyline_stats.splits;
                polyline_grids = polyline_stats.grids;
                ck_assert_uint_gt(polyline_stats.fillers, 0);
                ck_assert_uint_eq(polyline_stats.stitches, 0);
            } else {
                reyes_test_expect_same_image(&first_polyline, &polyline_image, polyline_label);
                ck_assert_uint_eq(polyline_stats.splits, polyline_splits);
                ck_assert_uint_eq(polyline_stats.grids, polyline_grids);
                reyes_image_free(&polyline_image);
            }
            reyes_stats_free(&polyline_stats);
            /* The runtime ran what was asked for. */
            ck_assert_msg(stats.run.technique == o.schedule.technique, "%s: ran another technique", label);
            ck_assert_msg(o.schedule.technique != PERMA_TECHNIQUE_MEGAKERNEL
                              || stats.run.strategy == o.schedule.strategy,
                          "%s: ran another strategy", label);
            ck_assert_msg(stats.run.work_groups == groups, "%s: ran %u groups", label,
                          stats.run.work_groups);
            char rate_label[160];
            snprintf(rate_label, sizeof rate_label, "%s, shading rate 1", label);
            if (rendered++ == 0) {
                reyes_test_expect_same_image(&rate_image, &culled_image, rate_label);
                reyes_image_free(&culled_image);
                first = image;
                first_stats = stats;
                first_rate = rate_image;
                first_rate_stats = rate_stats;
                ck_assert_uint_gt(stats.splits, 100);
                ck_assert_uint_gt(stats.samples_written, 0);
                ck_assert_uint_gt(rate_stats.samples_written, 0);
                reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
                continue;
            }
            reyes_test_expect_same_image(&first, &image, label);
            reyes_test_expect_same_counts(&first_stats, &stats, label);
            reyes_test_expect_same_image(&first_rate, &rate_image, rate_label);
            reyes_test_expect_same_counts(&first_rate_stats, &rate_stats, rate_label);
            char culled_label[200];
            snprintf(culled_label, sizeof culled_label, "%s, occlusion culling (%llu grids skipped)", rate_label,
                     (unsigned long long)culled_stats.occluded);
            reyes_test_expect_same_image(&first_rate, &culled_image, culled_label);
            reyes_image_free(&image);
            reyes_image_free(&rate_image);
            reyes_image_free(&culled_image);
        }
    }
    reyes_image_free(&first);
    reyes_image_free(&first_rate);
    reyes_image_free(&first_polyline);
    reyes_scene_free(&scene);
}
END_TEST

static Suite *schedules_suite(void)
{
    Suite *s = suite_create("reyes_schedules");
    TCase *tc = tcase_create("schedules");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_every_schedule_identical);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    return reyes_test_run_suite(schedules_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
