/* Buckets together with motion blur and depth of field: for every blur
 * algorithm, with crack stitching and without (and once with wedges), a
 * bucketed render gives the unbucketed bytes, coverage and covered
 * samples.  Besides the built-in scene, a small square whose blur alone
 * reaches the next bucket column: that bucket must still get its
 * micropolygons (the buckets' culling and leaf selection grow boxes by
 * the motion and by the circle of confusion). */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_test_util.h"

#define W 128
#define H 96
#define ALGORITHMS 3 /* loop tests run once per REYES_BLUR_* (_i) */

/* Two bucket sizes: one dividing the image, one not. */
static const unsigned bucket_sizes[2][2] = { {32, 32}, {40, 24} };

/* A flat square [x0,x1] x [y0,y1] at z = 0. */
static void square_scene(reyes_scene *scene, float x0, float x1, float y0, float y1)
{
    reyes_error error;
    float cp[4][4][3];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            cp[r][c][0] = x0 + (x1 - x0) * (float)c / 3.0f;
            cp[r][c][1] = y0 + (y1 - y0) * (float)r / 3.0f;
            cp[r][c][2] = 0.0f;
        }
    reyes_scene_init(scene);
    ck_assert_int_eq(reyes_scene_add_patch(scene, cp, REYES_RGBA(255, 255, 255), &error), REYES_OK);
}

/* Straight down on the square from distance 4. */
static const reyes_camera top = { .eye = {0.0f, 0.0f, 4.0f}, .at = {0.0f, 0.0f, 0.0f}, .fov_deg = 40 };

/* Pixel column of world point (x, 0, 0) seen from `top`. */
static float pixel_x(float x)
{
    float m[16], px, py, depth;
    reyes_error error;
    ck_assert_int_eq(reyes_camera_matrix(&top, (float)W / (float)H, 1e-3f, m, &error), REYES_OK);
    const float point[3] = {x, 0.0f, 0.0f};
    ck_assert(reyes_camera_project(m, W, H, point, &px, &py, &depth));
    return px;
}

static void blur_options(reyes_options *o, unsigned algo, unsigned crack_fix)
{
    reyes_options_init(o);
    o->width = W;
    o->height = H;
    o->spp = 4;
    o->blur_algo = algo;
    o->crack_fix = crack_fix;
}

/* Render without buckets, then with each bucket size: the same image and
 * covered samples, one peak queue memory per bucket, more culled.
 * Returns the unbucketed image (caller frees). */
static reyes_image expect_buckets_identical(const reyes_scene *scene, const reyes_camera *camera,
                                            reyes_options o, const char *what)
{
    reyes_image whole, tiled;
    reyes_stats whole_stats, tiled_stats;
    o.bucket_width = o.bucket_height = 0;
    reyes_test_render(reyes_test_renderer_for(&o, 0), scene, camera, &o, &whole, &whole_stats);
    ck_assert_uint_gt(whole_stats.samples_written, 0);
    for (int k = 0; k < 2; ++k) {
        char label[160];
        snprintf(label, sizeof label, "%s, %s, crack fix %u, %ux%u buckets", what,
                 reyes_blur_algo_name(o.blur_algo), o.crack_fix, bucket_sizes[k][0], bucket_sizes[k][1]);
        o.bucket_width = bucket_sizes[k][0];
        o.bucket_height = bucket_sizes[k][1];
        reyes_test_render(reyes_test_renderer_for(&o, 0), scene, camera, &o, &tiled, &tiled_stats);
        reyes_test_expect_same_image(&whole, &tiled, label);
        ck_assert_msg(tiled_stats.samples_written == whole_stats.samples_written,
                      "%s: %llu covered samples, unbucketed %llu", label,
                      (unsigned long long)tiled_stats.samples_written,
                      (unsigned long long)whole_stats.samples_written);
        reyes_test_expect_bucket_peaks(&tiled_stats);
        /* Culling per tile goes on with blur (with a lens too: the hull is
         * grown by its circle of confusion, not left unculled). */
        ck_assert_uint_gt(tiled_stats.culled, whole_stats.culled);
        reyes_image_free(&tiled);
        reyes_stats_free(&tiled_stats);
    }
    reyes_stats_free(&whole_stats);
    return whole;
}

/* The built-in scene moving diagonally (several pixels), per algorithm,
 * stitched and not. */
START_TEST(test_builtin_motion)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, W, H);
    for (unsigned fix = REYES_CRACK_FIX_NONE; fix <= REYES_CRACK_FIX_STITCH; ++fix) {
        reyes_options o;
        blur_options(&o, (unsigned)_i, fix);
        o.motion[0] = 0.5f;
        o.motion[1] = -0.3f;
        o.motion[2] = 0.2f;
        reyes_image whole = expect_buckets_identical(&scene, &camera, o, "built-in scene, motion");
        reyes_image_free(&whole);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* The built-in scene through a lens focused at half the target's
 * distance (everything well out of focus). */
START_TEST(test_builtin_defocus)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, W, H);
    float distance = 0.0f;
    for (int k = 0; k < 3; ++k)
        distance += (camera.at[k] - camera.eye[k]) * (camera.at[k] - camera.eye[k]);
    for (unsigned fix = REYES_CRACK_FIX_NONE; fix <= REYES_CRACK_FIX_STITCH; ++fix) {
        reyes_options o;
        blur_options(&o, (unsigned)_i, fix);
        o.aperture = 0.05f * sqrtf(distance); /* about 6 px out of focus */
        o.focus = 0.5f * sqrtf(distance);
        reyes_image whole = expect_buckets_identical(&scene, &camera, o, "built-in scene, lens");
        reyes_image_free(&whole);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* Covered samples in pixel columns [x0, x1). */
static unsigned covered_in_columns(const reyes_image *image, unsigned x0, unsigned x1)
{
    unsigned covered = 0;
    for (unsigned y = 0; y < image->height; ++y)
        for (unsigned x = x0; x < x1; ++x)
            covered += image->coverage[y * image->width + x];
    return covered;
}

/* The square's unblurred box, widened by the cull margin, ends left of
 * the bucket border `border` (and right of `left`); the blurred image
 * covers samples beyond it, which only that bucket can write. */
static void expect_blur_only_beyond(const reyes_image *whole, const reyes_options *o, float x0,
                                    float x1, unsigned left, unsigned border)
{
    float margin = o->cull_margin * 0.5f * (float)W;
    ck_assert_float_lt(pixel_x(x1) + margin, (float)border);
    ck_assert_float_gt(pixel_x(x0) - margin, (float)left);
    unsigned beyond = covered_in_columns(whole, border, W);
    printf("%s, crack fix %u: %u covered samples right of column %u (square %.1f..%.1f px)\n",
           reyes_blur_algo_name(o->blur_algo), o->crack_fix, beyond, border, (double)pixel_x(x0),
           (double)pixel_x(x1));
    ck_assert_uint_gt(beyond, 20);
}

/* Square over x in [-0.6, -0.2] (pixels 44..57, inside bucket column
 * 32..63 and 40..79 with its margin; about 33 px per unit) moving by 1.1
 * (about 36 px): columns 64.. and 80.. are reached by the blur only. */
START_TEST(test_square_motion_crosses_buckets)
{
    const float x0 = -0.6f, x1 = -0.2f;
    reyes_scene scene;
    square_scene(&scene, x0, x1, -0.2f, 0.2f);
    for (unsigned fix = REYES_CRACK_FIX_NONE; fix <= REYES_CRACK_FIX_STITCH; ++fix) {
        reyes_options o;
        blur_options(&o, (unsigned)_i, fix);
        o.motion[0] = 1.1f;
        reyes_image whole = expect_buckets_identical(&scene, &top, o, "moving square");
        expect_blur_only_beyond(&whole, &o, x0, x1, 40, 64);
        ck_assert_uint_gt(covered_in_columns(&whole, 80, W), 20);
        reyes_image_free(&whole);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* The same square through a lens of radius 0.9 focused at half its
 * distance: the lens moves it by up to (4/2 - 1) * 0.9 units, a circle of
 * confusion of about 30 px, into the bucket columns on both sides. */
START_TEST(test_square_defocus_crosses_buckets)
{
    const float x0 = -0.6f, x1 = -0.2f;
    reyes_scene scene;
    square_scene(&scene, x0, x1, -0.2f, 0.2f);
    for (unsigned fix = REYES_CRACK_FIX_NONE; fix <= REYES_CRACK_FIX_STITCH; ++fix) {
        reyes_options o;
        blur_options(&o, (unsigned)_i, fix);
        o.aperture = 0.9f;
        o.focus = 2.0f;
        reyes_image whole = expect_buckets_identical(&scene, &top, o, "defocused square");
        expect_blur_only_beyond(&whole, &o, x0, x1, 40, 64);
        ck_assert_uint_gt(covered_in_columns(&whole, 0, 40), 20);
        reyes_image_free(&whole);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* The built-in scene rotating by 25 degrees about z through the camera
 * target, then moving a little (per-vertex motion), stitched and not. */
START_TEST(test_builtin_rotation)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, W, H);
    for (unsigned fix = REYES_CRACK_FIX_NONE; fix <= REYES_CRACK_FIX_STITCH; ++fix) {
        reyes_options o;
        blur_options(&o, (unsigned)_i, fix);
        o.motion_angle_deg = 25.0f;
        o.motion[2] = 0.1f;
        reyes_image whole = expect_buckets_identical(&scene, &camera, o, "built-in scene, rotation");
        reyes_image_free(&whole);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* The square of test_square_motion_crosses_buckets rotating by 90 degrees
 * about z through the target (the origin): it ends over x in [-0.2, 0.2]
 * (pixels 57..70), reaching bucket column 64.. by its own motions only
 * (a uniform motion would not move it at all). */
START_TEST(test_square_rotation_crosses_buckets)
{
    const float x0 = -0.6f, x1 = -0.2f;
    reyes_scene scene;
    square_scene(&scene, x0, x1, -0.2f, 0.2f);
    for (unsigned fix = REYES_CRACK_FIX_NONE; fix <= REYES_CRACK_FIX_STITCH; ++fix) {
        reyes_options o;
        blur_options(&o, (unsigned)_i, fix);
        o.motion_angle_deg = 90.0f;
        reyes_image whole = expect_buckets_identical(&scene, &top, o, "rotating square");
        expect_blur_only_beyond(&whole, &o, x0, x1, 40, 64);
        reyes_image_free(&whole);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* Wedges (tiered subdivision): each bucket runs bound and split with its
 * sub-frustum, moving and defocused at once. */
START_TEST(test_wedges_motion_and_defocus)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, W, H);
    reyes_options o;
    blur_options(&o, REYES_BLUR_INTERLEAVED, REYES_CRACK_FIX_WEDGE);
    o.subdivision = REYES_SUBDIVISION_TIERED;
    o.motion[0] = 0.4f;
    o.aperture = 0.2f;
    reyes_image whole = expect_buckets_identical(&scene, &camera, o, "built-in scene, wedges");
    reyes_image_free(&whole);
    reyes_scene_free(&scene);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_bucket_blur");
    TCase *tc = tcase_create("bucket_blur");
    tcase_set_timeout(tc, 300);
    tcase_add_loop_test(tc, test_builtin_motion, 0, ALGORITHMS);
    tcase_add_loop_test(tc, test_builtin_defocus, 0, ALGORITHMS);
    tcase_add_loop_test(tc, test_square_motion_crosses_buckets, 0, ALGORITHMS);
    tcase_add_loop_test(tc, test_square_defocus_crosses_buckets, 0, ALGORITHMS);
    tcase_add_test(tc, test_wedges_motion_and_defocus);
    tcase_add_loop_test(tc, test_builtin_rotation, 0, ALGORITHMS);
    tcase_add_loop_test(tc, test_square_rotation_crosses_buckets, 0, ALGORITHMS);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
