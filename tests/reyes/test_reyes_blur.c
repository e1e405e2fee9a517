/* Motion blur and depth of field (simple UVT sampling): zero motion and
 * aperture change nothing; a moving square smears by its motion; a lens
 * keeps the focus plane sharp and blurs the rest. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "reyes_test_util.h"

#define W 128
#define H 96

/* A square z = 0 over [-0.6,0.6]^2, seen from straight above at distance 4. */
static void square_scene(reyes_scene *scene)
{
    reyes_error error;
    reyes_scene_init(scene);
    float cp[4][4][3];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            cp[r][c][0] = -0.6f + 1.2f * (float)c / 3.0f;
            cp[r][c][1] = -0.6f + 1.2f * (float)r / 3.0f;
            cp[r][c][2] = 0.0f;
        }
    ck_assert_int_eq(reyes_scene_add_patch(scene, cp, REYES_RGBA(255, 255, 255), &error), REYES_OK);
}

static const reyes_camera top = { .eye = {0.0f, 0.0f, 4.0f}, .at = {0.0f, 0.0f, 0.0f}, .fov_deg = 40 };

static float pixel_x(float world_x)
{
    float m[16], px, py, depth;
    reyes_error error;
    ck_assert_int_eq(reyes_camera_matrix(&top, (float)W / H, 1e-3f, m, &error), REYES_OK);
    const float x[3] = {world_x, 0.0f, 0.0f};
    ck_assert(reyes_camera_project(m, W, H, x, &px, &py, &depth));
    return px;
}

static void options(reyes_options *o)
{
    reyes_options_init(o);
    o->width = W;
    o->height = H;
    o->spp = 16;
}

START_TEST(test_zero_motion_and_aperture_identical)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_error error;
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_add_builtin(&scene, &error), REYES_OK);
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 96.0f / 72.0f, &camera, &error), REYES_OK);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 96;
    o.height = 72;
    reyes_image plain, zero;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &plain, NULL);
    o.focus = 3.0f;
    o.time_samples = 2;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &zero, NULL);
    ck_assert_mem_eq(plain.rgb, zero.rgb, (size_t)96 * 72 * 3);
    ck_assert_mem_eq(plain.coverage, zero.coverage, (size_t)96 * 72);
    reyes_image_free(&plain);
    reyes_image_free(&zero);
    reyes_scene_free(&scene);
}
END_TEST

/* The square moves by 0.5 along x: along the middle row coverage starts at
 * its left edge at time 0 and ends at its right edge at time 1 (within a
 * pixel or two: the very ends are covered only at the shutter's ends),
 * keeps the square's width with its centroid moved by half the motion,
 * rises linearly over the first motion length (about half covered
 * on average), and is full where it is covered all the time. */
START_TEST(test_moving_square_blur_extent)
{
    reyes_scene scene;
    square_scene(&scene);
    reyes_options o;
    options(&o);
    o.motion[0] = 0.5f;
    reyes_image image;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &image, NULL);
    float left = pixel_x(-0.6f), right = pixel_x(0.6f), shift = pixel_x(0.5f) - pixel_x(0.0f);
    const uint8_t *row = image.coverage + (size_t)(H / 2) * W;
    int first = -1, last = -1;
    for (int x = 0; x < W; ++x) {
        if (row[x]) {
            first = first < 0 ? x : first;
            last = x;
        }
    }
    printf("moving square: covered columns %d..%d, expected %.1f..%.1f (motion %.1f px)\n", first,
           last, (double)left, (double)(right + shift), (double)shift);
    ck_assert(fabsf((float)first - left) <= 1.5f);
    ck_assert(fabsf((float)last + 1.0f - (right + shift)) <= 2.0f);
    /* Coverage is conserved and its centroid moves by half the motion. */
    double sum = 0.0, moment = 0.0;
    for (int x = 0; x < W; ++x) {
        sum += row[x];
        moment += row[x] * (x + 0.5);
    }
    double width = sum / o.spp, centroid = moment / sum;
    printf("  coverage width %.2f px (square %.2f), centroid %.2f (expected %.2f)\n", width,
           (double)(right - left), centroid, 0.5 * (double)(left + right + shift));
    ck_assert(fabs(width - (double)(right - left)) < 0.5);
    ck_assert(fabs(centroid - 0.5 * (double)(left + right + shift)) < 0.5);
    double ramp = 0.0;
    int ramp_pixels = 0;
    for (int x = (int)ceilf(left) + 1; x + 1 < (int)(left + shift); ++x, ++ramp_pixels)
        ramp += row[x];
    ramp /= (double)ramp_pixels * o.spp;
    ck_assert_msg(ramp > 0.35 && ramp < 0.65, "mean coverage over the ramp %g", ramp);
    for (int x = (int)ceilf(left + shift) + 1; x + 1 < (int)right; ++x)
        ck_assert_uint_eq(row[x], o.spp);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* Partially covered pixels: few for a sharp square (its outline), many
 * when a lens of radius 0.2 focuses at half its distance; focused on the
 * square itself the outline stays as sharp as without a lens. */
static unsigned partial_pixels(const reyes_image *image, unsigned spp)
{
    unsigned partial = 0;
    for (size_t k = 0; k < (size_t)image->width * image->height; ++k)
        partial += image->coverage[k] > 0 && image->coverage[k] < spp;
    return partial;
}

START_TEST(test_lens_focus)
{
    reyes_scene scene;
    square_scene(&scene);
    reyes_options o;
    options(&o);
    reyes_image sharp, focused, blurred;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &sharp, NULL);
    o.aperture = 0.2f;
    o.focus = 4.0f;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &focused, NULL);
    o.focus = 2.0f;
    reyes_test_render(reyes_test_renderer(0), &scene, &top, &o, &blurred, NULL);
    unsigned p_sharp = partial_pixels(&sharp, o.spp), p_focused = partial_pixels(&focused, o.spp);
    unsigned p_blurred = partial_pixels(&blurred, o.spp);
    printf("partially covered pixels: no lens %u, in focus %u, out of focus %u\n", p_sharp,
           p_focused, p_blurred);
    ck_assert_uint_le(p_focused, p_sharp + p_sharp / 4);
    ck_assert_uint_gt(p_blurred, 3 * p_sharp);
    /* The covered area is about the same: defocus spreads, it does not add. */
    double a_sharp = (double)reyes_test_covered_samples(&sharp);
    double a_blurred = (double)reyes_test_covered_samples(&blurred);
    ck_assert_msg(fabs(a_blurred - a_sharp) < 0.05 * a_sharp, "area %g vs %g", a_blurred, a_sharp);
    reyes_image_free(&sharp);
    reyes_image_free(&focused);
    reyes_image_free(&blurred);
    reyes_scene_free(&scene);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_blur");
    TCase *tc = tcase_create("blur");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_zero_motion_and_aperture_identical);
    tcase_add_test(tc, test_moving_square_blur_extent);
    tcase_add_test(tc, test_lens_focus);
    suite_add_tcase(s, tc);
    SRunner *runner = srunner_create(s);
    srunner_set_fork_status(runner, CK_NOFORK);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
