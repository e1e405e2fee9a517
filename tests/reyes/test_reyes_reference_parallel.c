/* The C reference on several OpenMP threads (reyes_reference_parallel.c):
 * the same image, bit for bit, and the same counts as on one thread, and
 * the same refusals. */
#include <check.h>
#include <string.h>

#include "reyes_reference_parallel.h"
#include "reyes_test_util.h"

/* Render on one thread and on 1, 2 and 3 threads; every image and count
 * equal. */
static void expect_identical(const reyes_scene *scene, const reyes_camera *camera, const reyes_options *o,
                             const char *label)
{
    reyes_image single;
    reyes_reference_counts expected;
    reyes_error error;
    ck_assert_msg(reyes_reference_render(scene, camera, o, &single, &expected, &error) == REYES_OK, "%s: %s",
                  label, error.message);
    ck_assert_uint_gt(expected.samples_written, 0);
    size_t pixels = (size_t)single.width * single.height;
    for (unsigned threads = 1; threads <= 3; ++threads) {
        reyes_image image;
        reyes_reference_counts counts;
        ck_assert_msg(reyes_reference_render_parallel(scene, camera, o, threads, &image, &counts, &error)
                          == REYES_OK,
                      "%s, %u threads: %s", label, threads, error.message);
        ck_assert_uint_eq(image.width, single.width);
        ck_assert_uint_eq(image.height, single.height);
        ck_assert_msg(memcmp(image.rgb, single.rgb, pixels * 3) == 0, "%s: %u threads, other colours", label,
                      threads);
        ck_assert_msg(memcmp(image.coverage, single.coverage, pixels) == 0, "%s: %u threads, other coverage",
                      label, threads);
        ck_assert_uint_eq(counts.splits, expected.splits);
        ck_assert_uint_eq(counts.culled, expected.culled);
        ck_assert_uint_eq(counts.grids, expected.grids);
        ck_assert_uint_eq(counts.forced_dice, expected.forced_dice);
        ck_assert_uint_eq(counts.micropolygons, expected.micropolygons);
        ck_assert_uint_eq(counts.samples_written, expected.samples_written);
        ck_assert_uint_eq(counts.max_depth_seen, expected.max_depth_seen);
        reyes_image_free(&image);
    }
    reyes_image_free(&single);
}

/* Fixed grids (four samples, then five in a 3 x 2 lattice with a 3 px
 * bound and a depth limit), a shading rate of 1, and a view from inside
 * the scene (culling, splits at the near plane). */
START_TEST(test_parallel_identical)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 160, 120);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 160;
    o.height = 120;
    o.crack_fix = REYES_CRACK_FIX_NONE;
    expect_identical(&scene, &camera, &o, "fixed grids");
    o.spp = 5;
    o.bound_px = 3.0f;
    o.max_depth = 6;
    expect_identical(&scene, &camera, &o, "5 samples, 3 px bound, depth 6");
    reyes_options_init(&o);
    o.width = 160;
    o.height = 120;
    o.crack_fix = REYES_CRACK_FIX_NONE;
    o.shading_rate = 1.0f;
    expect_identical(&scene, &camera, &o, "shading rate 1");
    reyes_camera inside = { .eye = {0.0f, 0.0f, 0.6f}, .at = {1.0f, 1.0f, 0.4f}, .fov_deg = 90.0f };
    o.shading_rate = 0.0f;
    expect_identical(&scene, &inside, &o, "inside the scene");
    reyes_scene_free(&scene);
}
END_TEST

/* What the single-threaded reference refuses, the parallel one refuses
 * with the same message, and leaves no image. */
START_TEST(test_parallel_refusals)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 64, 48);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 64;
    o.height = 48;
    o.crack_fix = REYES_CRACK_FIX_NONE;
    o.motion[0] = 0.1f;
    reyes_image image;
    reyes_reference_counts counts;
    reyes_error single, parallel;
    ck_assert_int_eq(reyes_reference_render(&scene, &camera, &o, &image, &counts, &single), REYES_ERR_ARGUMENT);
    ck_assert_int_eq(reyes_reference_render_parallel(&scene, &camera, &o, 2, &image, &counts, &parallel),
                     REYES_ERR_ARGUMENT);
    ck_assert_str_eq(parallel.message, single.message);
    ck_assert_ptr_null(image.rgb);
    o.motion[0] = 0.0f;
    o.spp = 0;
    ck_assert_int_eq(reyes_reference_render_parallel(&scene, &camera, &o, 2, &image, &counts, &parallel),
                     REYES_ERR_ARGUMENT);
    ck_assert_ptr_nonnull(strstr(parallel.message, "samples per pixel 0"));
    reyes_scene_free(&scene);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_reference_parallel");
    TCase *tc = tcase_create("parallel");
    tcase_add_test(tc, test_parallel_identical);
    tcase_add_test(tc, test_parallel_refusals);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) == 0 ? 0 : 1;
}
