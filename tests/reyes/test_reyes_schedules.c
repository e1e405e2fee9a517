/* Every technique and strategy, with 1 or 2 work-groups, renders the
 * built-in scene to byte-identical images with identical counts. */
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
    reyes_image first = {0};
    reyes_stats first_stats;
    memset(&first_stats, 0, sizeof first_stats);
    unsigned rendered = 0;
    for (unsigned s = 0; s < reyes_test_schedule_count; ++s) {
        for (unsigned groups = 1; groups <= 2; ++groups) {
            char label[128];
            snprintf(label, sizeof label, "%s groups=%u", reyes_test_schedules[s], groups);
            reyes_test_apply_schedule(reyes_test_schedules[s], groups, &o);
            reyes_image image;
            reyes_stats stats;
            reyes_test_render_once(&scene, &camera, &o, &image, &stats);
            /* The runtime ran what was asked for. */
            ck_assert_msg(stats.run.technique == o.schedule.technique, "%s: ran another technique", label);
            ck_assert_msg(o.schedule.technique != PERMA_TECHNIQUE_MEGAKERNEL
                              || stats.run.strategy == o.schedule.strategy,
                          "%s: ran another strategy", label);
            ck_assert_msg(stats.run.work_groups == groups, "%s: ran %u groups", label,
                          stats.run.work_groups);
            if (rendered++ == 0) {
                first = image;
                first_stats = stats;
                ck_assert_uint_gt(stats.splits, 100);
                ck_assert_uint_gt(stats.samples_written, 0);
                reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
                continue;
            }
            reyes_test_expect_same_image(&first, &image, label);
            reyes_test_expect_same_counts(&first_stats, &stats, label);
            reyes_image_free(&image);
        }
    }
    reyes_image_free(&first);
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
