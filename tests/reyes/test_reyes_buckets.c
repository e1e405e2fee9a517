/* Screen-space buckets: a bucketed render is byte-identical to the
 * unbucketed one, and small buckets bound the queue memory. */
#include <check.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_test_util.h"

/* Two bucket sizes (one not dividing the image) give the unbucketed bytes;
 * the per-bucket list has one entry per bucket and its maximum is the
 * render's peak. */
START_TEST(test_buckets_identical)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_options o;
    reyes_test_small_builtin(&scene, &camera, &o);
    reyes_image whole, tiled;
    reyes_stats whole_stats, tiled_stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &whole, &whole_stats);
    ck_assert_uint_eq(whole_stats.bucket_columns * whole_stats.bucket_rows, 1);
    ck_assert_ptr_null(whole_stats.bucket_peak_queue_bytes);
    const unsigned sizes[2][2] = { {64, 64}, {48, 20} };
    for (int k = 0; k < 2; ++k) {
        o.bucket_width = sizes[k][0];
        o.bucket_height = sizes[k][1];
        reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &tiled, &tiled_stats);
        reyes_test_expect_same_image(&whole, &tiled, "buckets");
        ck_assert_uint_eq(tiled_stats.samples_written, whole_stats.samples_written);
        ck_assert_uint_eq(tiled_stats.bucket_columns, (160 + sizes[k][0] - 1) / sizes[k][0]);
        ck_assert_uint_eq(tiled_stats.bucket_rows, (120 + sizes[k][1] - 1) / sizes[k][1]);
        reyes_test_expect_bucket_peaks(&tiled_stats);
        /* Culling per tile: patches outside a tile never reach dice there. */
        ck_assert_uint_gt(tiled_stats.culled, whole_stats.culled);
        reyes_image_free(&tiled);
        reyes_stats_free(&tiled_stats);
    }
    reyes_image_free(&whole);
    reyes_scene_free(&scene);
}
END_TEST

/* Polylines at a shading rate (the command's default) too: every bucket
 * settles the same edges and draws the same fillers, so buckets of two
 * sizes give the unbucketed bytes, with occlusion culling and blur. */
START_TEST(test_buckets_identical_polylines)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_options o;
    reyes_test_small_builtin(&scene, &camera, &o);
    o.shading_rate = 1.0f;
    o.crack_fix = REYES_CRACK_FIX_POLYLINE;
    for (int blurred = 0; blurred < 2; ++blurred) {
        o.motion[0] = blurred ? 0.3f : 0.0f;
        o.bucket_width = o.bucket_height = 0;
        reyes_image whole, tiled;
        reyes_stats whole_stats, tiled_stats;
        reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &whole, &whole_stats);
        ck_assert_uint_gt(whole_stats.fillers, 0);
        const unsigned sizes[2][2] = { {64, 64}, {48, 20} };
        for (int k = 0; k < 2; ++k) {
            o.bucket_width = sizes[k][0];
            o.bucket_height = sizes[k][1];
            reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &tiled, &tiled_stats);
            reyes_test_expect_same_image(&whole, &tiled, blurred ? "buckets, polylines, blurred" : "buckets, polylines");
            reyes_image_free(&tiled);
            reyes_stats_free(&tiled_stats);
        }
        reyes_image_free(&whole);
        reyes_stats_free(&whole_stats);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* Kernel-per-procedure holds a whole breadth-first level of micropolygons
 * in its queues: with 32x32 buckets the peak queue memory is smaller than
 * for the whole image, and the image is the same.  (Its steps reserve room
 * for at least 16 batches per group, about 1.3 MB here with 2 groups: the
 * image is large enough for a level to need more.) */
START_TEST(test_buckets_bound_queue_memory)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 384, 288);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 384;
    o.height = 288;
    o.spp = 1;
    o.work_groups = 2;
    o.schedule.technique = PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE;
    reyes_image whole, tiled;
    reyes_stats whole_stats, tiled_stats;
    reyes_test_render_once(&scene, &camera, &o, &whole, &whole_stats);
    o.bucket_width = o.bucket_height = 32;
    reyes_test_render_once(&scene, &camera, &o, &tiled, &tiled_stats);
    reyes_test_expect_same_image(&whole, &tiled, "32x32 buckets, kernel-per-procedure");
    printf("peak queue bytes: whole image %zu, 32x32 buckets %zu\n", whole_stats.peak_queue_bytes,
           tiled_stats.peak_queue_bytes);
    ck_assert_uint_lt(tiled_stats.peak_queue_bytes, whole_stats.peak_queue_bytes);
    reyes_image_free(&whole);
    reyes_image_free(&tiled);
    reyes_stats_free(&tiled_stats);
    reyes_scene_free(&scene);
}
END_TEST

/* Displaced surfaces too: bound and the buckets' leaf selection grow by
 * the amplitude, so nothing a bucket needs is left out; with and without
 * crack stitching. */
START_TEST(test_buckets_identical_displaced)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 128, 96);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 128;
    o.height = 96;
    o.displace_mode = REYES_DISPLACE_BUMPS;
    o.displace_amplitude = 0.1f;
    for (unsigned fix = 0; fix < 2; ++fix) {
        reyes_image whole, tiled;
        o.crack_fix = fix;
        o.bucket_width = o.bucket_height = 0;
        reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &whole, NULL);
        o.bucket_width = 40;
        o.bucket_height = 24;
        reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &tiled, NULL);
        reyes_test_expect_same_image(&whole, &tiled, fix ? "displaced, stitched" : "displaced");
        reyes_image_free(&whole);
        reyes_image_free(&tiled);
    }
    reyes_scene_free(&scene);
}
END_TEST

START_TEST(test_bucket_arguments)
{
    reyes_options o;
    reyes_error error;
    reyes_options_init(&o);
    o.bucket_width = 16;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert(strstr(error.message, "bucket") != NULL);
    o.bucket_height = 600; /* larger than the image: one row of buckets */
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    o.width = o.height = 16384;
    o.spp = 1;
    o.bucket_width = o.bucket_height = 1;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert(strstr(error.message, "buckets") != NULL);
    /* Buckets combine with motion blur and depth of field
     * (test_reyes_bucket_blur.c checks the images). */
    reyes_options_init(&o);
    o.bucket_width = o.bucket_height = 64;
    o.motion[0] = 0.1f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    o.aperture = 0.2f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_buckets");
    TCase *tc = tcase_create("buckets");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_buckets_identical);
    tcase_add_test(tc, test_buckets_identical_polylines);
    tcase_add_test(tc, test_buckets_bound_queue_memory);
    tcase_add_test(tc, test_buckets_identical_displaced);
    tcase_add_test(tc, test_bucket_arguments);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
