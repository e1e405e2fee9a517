/* The C reference on several OpenMP threads (reyes_reference_parallel.c):
 * the same image, bit for bit, and the same counts as on one thread, and
 * the same refusals; and its occlusion culling (reyes_reference_occlusion.c):
 * the same image with it and without, fewer micropolygons where grids
 * are hidden.  Built a second time with REYES_MODELS_DIR (suite shared):
 * then the culling on ../shared's models only. */
#include <check.h>
#include <string.h>

#include "reyes_reference_parallel.h"
#include "reyes_test_util.h"

/* The C reference's render of scene with o, checked to succeed. */
static reyes_reference_counts render(const reyes_scene *scene, const reyes_camera *camera, const reyes_options *o,
                                     unsigned threads, reyes_image *image)
{
    reyes_reference_counts counts;
    reyes_error error;
    reyes_status status = threads ? reyes_reference_render_parallel(scene, camera, o, threads, image, &counts, &error)
                                  : reyes_reference_render(scene, camera, o, image, &counts, &error);
    ck_assert_msg(status == REYES_OK, "%s", error.message);
    return counts;
}

#ifndef REYES_MODELS_DIR

/* Render on one thread and on 1, 2 and 3 threads; every image and count
 * equal.  With occlusion culling (at a shading rate) which grids the
 * threads skip depends on their timing: on 2 and 3 threads the counts of
 * dicing (micropolygons, occluded) are not compared, but the sub-patches
 * are diced in the single-threaded order, so on 1 they are. */
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
        ck_assert_uint_eq(counts.samples_written, expected.samples_written);
        ck_assert_uint_le(counts.occluded, counts.grids);
        if (!(o->occlusion_cull && o->shading_rate > 0.0f && threads > 1)) {
            ck_assert_uint_eq(counts.micropolygons, expected.micropolygons);
            ck_assert_uint_eq(counts.occluded, expected.occluded);
        }
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
    reyes_options o;
    reyes_test_small_builtin(&scene, &camera, &o);
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
    o.occlusion_cull = 0;
    expect_identical(&scene, &camera, &o, "shading rate 1");
    o.occlusion_cull = 1;
    expect_identical(&scene, &camera, &o, "shading rate 1, occlusion culling");
    reyes_camera inside = { .eye = {0.0f, 0.0f, 0.6f}, .at = {1.0f, 1.0f, 0.4f}, .fov_deg = 90.0f };
    o.shading_rate = 0.0f;
    expect_identical(&scene, &inside, &o, "inside the scene");
    reyes_scene_free(&scene);
}
END_TEST

/* Occlusion culling in the C reference, as test_occluded_grids
 * (reyes_quality) has it in the renderer: 64 squares of about 1.5 pixels
 * behind a near one that hides them all, the far ones first in the scene.
 * On one thread the near square is diced first (front to back) and every
 * far grid is skipped: the micropolygons of the near square alone; on 2
 * threads at most as many as without the culling; the image is the same
 * bytes in each case.  Without a shading rate nothing is culled. */
START_TEST(test_occlusion_culling)
{
    reyes_scene scene, near_only;
    reyes_scene_init(&scene);
    reyes_scene_init(&near_only);
    const uint64_t side = 8, far = side * side;
    for (uint64_t i = 0; i < side; ++i) /* the far ones first: only the order of dicing puts them last */
        for (uint64_t j = 0; j < side; ++j)
            reyes_test_add_square(&scene, -0.5f + 0.13f * (float)i, -0.5f + 0.13f * (float)j, -2.0f, 0.1f);
    reyes_test_add_square(&scene, -1.0f, -1.0f, 0.0f, 2.0f);
    reyes_test_add_square(&near_only, -1.0f, -1.0f, 0.0f, 2.0f);
    reyes_camera camera = { {0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, 40.0f };
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 64;
    o.crack_fix = REYES_CRACK_FIX_NONE;
    o.shading_rate = 1.0f;
    ck_assert_uint_eq(o.occlusion_cull, 1); /* the default, as the renderer's */
    reyes_image culled, kept, alone, threaded;
    reyes_reference_counts on = render(&scene, &camera, &o, 0, &culled);
    reyes_reference_counts near = render(&near_only, &camera, &o, 0, &alone);
    reyes_reference_counts two = render(&scene, &camera, &o, 2, &threaded);
    o.occlusion_cull = 0;
    reyes_reference_counts off = render(&scene, &camera, &o, 0, &kept);
    printf("C reference, a square hiding %llu small ones: %llu grids (%llu near), %llu skipped as hidden, %llu "
           "micropolygons (%llu without occlusion culling, %llu the near square alone; 2 threads: %llu skipped, "
           "%llu micropolygons)\n",
           (unsigned long long)far, (unsigned long long)on.grids, (unsigned long long)near.grids,
           (unsigned long long)on.occluded, (unsigned long long)on.micropolygons,
           (unsigned long long)off.micropolygons, (unsigned long long)near.micropolygons,
           (unsigned long long)two.occluded, (unsigned long long)two.micropolygons);
    ck_assert_uint_eq(off.grids, near.grids + far);
    ck_assert_uint_eq(on.grids, off.grids);
    ck_assert_uint_eq(two.grids, off.grids);
    ck_assert_uint_eq(off.occluded, 0);
    ck_assert_uint_eq(on.occluded, far);
    ck_assert_uint_eq(on.micropolygons, near.micropolygons);
    ck_assert_uint_lt(on.micropolygons, off.micropolygons);
    ck_assert_uint_le(two.occluded, far);
    ck_assert_uint_ge(two.micropolygons, near.micropolygons);
    ck_assert_uint_le(two.micropolygons, off.micropolygons);
    ck_assert_uint_eq(on.samples_written, off.samples_written);
    reyes_test_expect_same_image(&kept, &culled, "C reference, occlusion culling");
    reyes_test_expect_same_image(&kept, &threaded, "C reference, occlusion culling, 2 threads");
    reyes_test_expect_same_image(&alone, &culled, "C reference, the near square alone");
    reyes_image fixed, fixed_kept;
    o.shading_rate = 0.0f;
    reyes_reference_counts grids_kept = render(&scene, &camera, &o, 0, &fixed_kept);
    o.occlusion_cull = 1;
    reyes_reference_counts grids = render(&scene, &camera, &o, 0, &fixed);
    ck_assert_uint_eq(grids.occluded, 0);
    ck_assert_uint_eq(grids.micropolygons, grids_kept.micropolygons);
    reyes_image_free(&fixed_kept);
    reyes_image_free(&culled);
    reyes_image_free(&kept);
    reyes_image_free(&alone);
    reyes_image_free(&threaded);
    reyes_image_free(&fixed);
    reyes_scene_free(&scene);
    reyes_scene_free(&near_only);
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
    tcase_add_test(tc, test_occlusion_culling);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) == 0 ? 0 : 1;
}

#else

/* Occlusion culling on the models of perma-bench reyes's defaults
 * workload (its cameras, 512x512, a shading rate of 1): the same image
 * bytes with and without it, on one thread and on two, and fewer
 * micropolygons. */
START_TEST(test_models_occlusion)
{
    static const struct { const char *file; reyes_camera camera; } models[] = {
        { "teapot.bpt", { {8.0f, -8.0f, 6.0f}, {0.0f, 0.0f, 1.5f}, 40.0f } },
        { "killeroo.bpt", { {8.0f, 0.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 45.0f } },
    };
    for (size_t m = 0; m < sizeof models / sizeof models[0]; ++m) {
        reyes_scene scene;
        reyes_test_load_model(&scene, REYES_MODELS_DIR, models[m].file);
        reyes_options o;
        reyes_options_init(&o);
        o.width = o.height = 512;
        o.crack_fix = REYES_CRACK_FIX_NONE;
        o.shading_rate = 1.0f;
        reyes_image culled, kept, threaded;
        reyes_reference_counts on = render(&scene, &models[m].camera, &o, 0, &culled);
        reyes_reference_counts two = render(&scene, &models[m].camera, &o, 2, &threaded);
        o.occlusion_cull = 0;
        reyes_reference_counts off = render(&scene, &models[m].camera, &o, 0, &kept);
        printf("C reference, %s 512x512, shading rate 1: %llu of %llu grids skipped as hidden, %llu micropolygons "
               "(%llu without occlusion culling; 2 threads: %llu skipped, %llu micropolygons)\n",
               models[m].file, (unsigned long long)on.occluded, (unsigned long long)on.grids,
               (unsigned long long)on.micropolygons, (unsigned long long)off.micropolygons,
               (unsigned long long)two.occluded, (unsigned long long)two.micropolygons);
        ck_assert_uint_eq(on.grids, off.grids);
        ck_assert_uint_gt(on.occluded, on.grids / 4);
        ck_assert_uint_lt(on.micropolygons, off.micropolygons);
        ck_assert_uint_lt(two.micropolygons, off.micropolygons);
        reyes_test_expect_same_image(&kept, &culled, models[m].file);
        reyes_test_expect_same_image(&kept, &threaded, models[m].file);
        reyes_image_free(&culled);
        reyes_image_free(&kept);
        reyes_image_free(&threaded);
        reyes_scene_free(&scene);
    }
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_reference_parallel_models");
    TCase *tc = tcase_create("models");
    tcase_add_test(tc, test_models_occlusion);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) == 0 ? 0 : 1;
}

#endif
