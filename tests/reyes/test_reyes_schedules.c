/* Every technique and strategy, with 1 or 2 work-groups, renders the
 * built-in scene to byte-identical images with identical counts. */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_test_util.h"

#define WIDTH 128u
#define HEIGHT 96u

static void expect_same_render(const char *label, const reyes_image *expected,
                               const reyes_stats *expected_stats, const reyes_image *image,
                               const reyes_stats *stats)
{
    size_t pixels = (size_t)WIDTH * HEIGHT;
    ck_assert_msg(memcmp(expected->rgb, image->rgb, pixels * 3) == 0, "%s: image differs", label);
    ck_assert_msg(memcmp(expected->coverage, image->coverage, pixels) == 0, "%s: coverage differs",
                  label);
    ck_assert_msg(stats->splits == expected_stats->splits && stats->grids == expected_stats->grids
                      && stats->culled == expected_stats->culled
                      && stats->micropolygons == expected_stats->micropolygons
                      && stats->samples_written == expected_stats->samples_written,
                  "%s: counts differ (splits %llu vs %llu, grids %llu vs %llu)", label,
                  (unsigned long long)stats->splits, (unsigned long long)expected_stats->splits,
                  (unsigned long long)stats->grids, (unsigned long long)expected_stats->grids);
    for (int p = 0; p < REYES_PROC_COUNT; ++p)
        ck_assert_msg(stats->procedures[p].items == expected_stats->procedures[p].items,
                      "%s: %s ran %llu items, expected %llu", label, stats->procedures[p].name,
                      (unsigned long long)stats->procedures[p].items,
                      (unsigned long long)expected_stats->procedures[p].items);
}

START_TEST(test_every_schedule_identical)
{
    reyes_scene scene;
    reyes_error error;
    reyes_camera camera;
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_add_builtin(&scene, &error), REYES_OK);
    reyes_options o;
    reyes_options_init(&o);
    o.width = WIDTH;
    o.height = HEIGHT;
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, (float)WIDTH / (float)HEIGHT, &camera, &error),
                     REYES_OK);
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
            expect_same_render(label, &first, &first_stats, &image, &stats);
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
