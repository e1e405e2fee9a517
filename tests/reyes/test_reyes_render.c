/* End-to-end renders of generated scenes through the perma runtime. */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_reference.h"
#include "reyes_shared.h"
#include "reyes_test_util.h"

#define PI 3.14159265358979323846

static void small_options(reyes_options *o, unsigned width, unsigned height)
{
    reyes_options_init(o);
    o->width = width;
    o->height = height;
}

/* A flat patch z = 0 over [-1,1] x [-0.6,0.6] seen from above: pixels more
 * than one pixel inside its projected rectangle are fully covered, pixels
 * more than one pixel outside are empty. */
START_TEST(test_flat_rectangle)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    float cp[4][4][3];
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            cp[r][c][0] = -1.0f + 2.0f * (float)c / 3.0f;
            cp[r][c][1] = -0.6f + 1.2f * (float)r / 3.0f;
            cp[r][c][2] = 0.0f;
        }
    }
    ck_assert_int_eq(reyes_scene_add_patch(&scene, cp, REYES_RGBA(255, 255, 255), &error), REYES_OK);
    reyes_options o;
    small_options(&o, 128, 96);
    reyes_camera camera = { .eye = {0.1f, 0.05f, 4.0f}, .at = {0.1f, 0.05f, 0.0f}, .fov_deg = 40.0f };
    float m[16], x0, y0, x1, y1, depth;
    ck_assert_int_eq(reyes_camera_matrix(&camera, 128.0f / 96.0f, 1e-4f, m, &error), REYES_OK);
    const float low[3] = {-1.0f, -0.6f, 0.0f}, high[3] = {1.0f, 0.6f, 0.0f};
    ck_assert(reyes_camera_project(m, 128, 96, low, &x0, &y0, &depth));
    ck_assert(reyes_camera_project(m, 128, 96, high, &x1, &y1, &depth));
    float left = fminf(x0, x1), right = fmaxf(x0, x1), top = fminf(y0, y1), bottom = fmaxf(y0, y1);
    ck_assert(left > 4 && right < 124 && top > 4 && bottom < 92);

    reyes_image image;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &stats);
    size_t checked = 0;
    for (unsigned y = 0; y < image.height; ++y) {
        for (unsigned x = 0; x < image.width; ++x) {
            /* Distance of the pixel square to the rectangle's edges. */
            float inside = fminf(fminf((float)x - left, right - (float)(x + 1)),
                                 fminf((float)y - top, bottom - (float)(y + 1)));
            float outside = fmaxf(fmaxf(left - (float)(x + 1), (float)x - right),
                                  fmaxf(top - (float)(y + 1), (float)y - bottom));
            unsigned coverage = image.coverage[y * image.width + x];
            if (inside >= 1.0f) {
                ck_assert_msg(coverage == o.spp, "pixel %u,%u inside has %u samples", x, y, coverage);
                ++checked;
            } else if (outside >= 1.0f) {
                ck_assert_msg(coverage == 0, "pixel %u,%u outside has %u samples", x, y, coverage);
                ++checked;
            }
        }
    }
    ck_assert_uint_gt(checked, 128 * 96 * 9 / 10);
    /* The covered area matches the rectangle's to within its perimeter. */
    double area = (double)reyes_test_covered_samples(&image) / o.spp;
    double expected = (double)(right - left) * (double)(bottom - top);
    ck_assert_double_eq_tol(area, expected, 0.5 * 2.0 * ((right - left) + (bottom - top)) * 0.25);
    ck_assert_uint_eq(stats.patches_in, 1);
    ck_assert_uint_eq(stats.grids, stats.splits + 1);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* A sphere of patches covers pi r^2 (r: the projected silhouette radius)
 * within 1%, and shows no cracks. */
START_TEST(test_sphere_area_and_no_holes)
{
    reyes_scene scene;
    reyes_test_sphere_scene(&scene);
    reyes_options o;
    small_options(&o, 160, 160);
    const float distance = 5.0f, fov = 35.0f;
    reyes_camera camera = { .eye = {0, -distance, 0}, .at = {0, 0, 0}, .fov_deg = fov };
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &stats);
    /* The silhouette cone has half-angle asin(r/d). */
    double focal = 80.0 / tan(0.5 * fov * PI / 180.0);
    double radius_px = focal * tan(asin(1.0 / distance));
    double expected = PI * radius_px * radius_px;
    double area = (double)reyes_test_covered_samples(&image) / o.spp;
    ck_assert_msg(fabs(area - expected) < 0.01 * expected, "area %g, expected %g", area, expected);
    ck_assert_uint_eq(reyes_test_hole_pixels(&image, 64), 0);
    ck_assert_uint_eq(stats.samples_written, reyes_test_covered_samples(&image));
    ck_assert_uint_eq(stats.forced_dice, 0);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* The built-in scene at the default 8 px bound and 16x16 grid: no crack
 * pixels, and a plausible pipeline. */
START_TEST(test_builtin_no_holes)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 192, 144);
    reyes_options o;
    small_options(&o, 192, 144);
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &stats);
    ck_assert_uint_eq(reyes_test_hole_pixels(&image, 32), 0);
    ck_assert_uint_eq(stats.patches_in, scene.patch_count);
    /* Every split makes one patch two; every patch ends culled or diced. */
    ck_assert_uint_eq(stats.patches_in + stats.splits, stats.grids + stats.culled);
    ck_assert_uint_eq(stats.procedures[REYES_PROC_DICE].items, stats.grids);
    /* Dice rasterizes its grids itself: it emits nothing. */
    ck_assert_uint_eq(stats.procedures[REYES_PROC_DICE].emit_count, 0);
    ck_assert_uint_eq(stats.procedures[REYES_PROC_SPLIT_U].items + stats.procedures[REYES_PROC_SPLIT_V].items,
                      stats.splits);
    ck_assert_uint_gt(stats.samples_written, 0);
    reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* 1 and 2 work-groups render byte-identical images with identical counts. */
START_TEST(test_groups_identical)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 128, 96);
    reyes_options o;
    small_options(&o, 128, 96);
    reyes_image one, two;
    reyes_stats stats_one, stats_two;
    o.work_groups = 1;
    reyes_test_render(reyes_test_renderer(1), &scene, &camera, &o, &one, &stats_one);
    o.work_groups = 2;
    reyes_test_render(reyes_test_renderer(2), &scene, &camera, &o, &two, &stats_two);
    ck_assert_uint_eq(stats_one.run.work_groups, 1);
    ck_assert_uint_eq(stats_two.run.work_groups, 2);
    reyes_test_expect_same_image(&one, &two, "2 groups");
    reyes_test_expect_same_counts(&stats_one, &stats_two, "2 groups");
    reyes_image_free(&one);
    reyes_image_free(&two);
    reyes_scene_free(&scene);
}
END_TEST

/* Patches behind the camera are culled, patches around it are split at the
 * near plane rather than projected through it: from inside a sphere every
 * pixel sees the sphere. */
START_TEST(test_camera_inside_and_behind)
{
    reyes_scene scene;
    reyes_test_sphere_scene(&scene);
    reyes_options o;
    small_options(&o, 64, 64);
    reyes_image image;
    reyes_stats stats;
    reyes_camera inside = { .eye = {0.1f, 0.0f, 0.2f}, .at = {0.1f, 1.0f, 0.2f}, .fov_deg = 60 };
    reyes_test_render(reyes_test_renderer(0), &scene, &inside, &o, &image, &stats);
    ck_assert_uint_eq(reyes_test_covered_samples(&image), (uint64_t)64 * 64 * o.spp);
    reyes_image_free(&image);

    reyes_camera away = { .eye = {0, -5, 0}, .at = {0, -10, 0}, .fov_deg = 40 };
    reyes_test_render(reyes_test_renderer(0), &scene, &away, &o, &image, &stats);
    ck_assert_uint_eq(reyes_test_covered_samples(&image), 0);
    ck_assert_uint_eq(stats.culled, scene.patch_count);
    ck_assert_uint_eq(stats.grids, 0);
    reyes_test_expect_reference_counts(&scene, &away, &o, &stats);
    ck_assert_uint_eq(image.rgb[0], o.background & 255u);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* One control point far away (1e6 units) must not move the near plane past
 * what the camera sees: the sphere in front of the camera renders, covering
 * at least the samples it covers alone (the near plane once came from the
 * scene's size, 50 units here, and culled it all). */
START_TEST(test_far_point_keeps_the_near_plane_close)
{
    reyes_scene scene;
    reyes_test_sphere_scene(&scene);
    reyes_options o;
    small_options(&o, 64, 64);
    reyes_camera camera = { .eye = {0, -5, 1}, .at = {0, 0, 0}, .fov_deg = 40 };
    reyes_image alone, with_far;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &alone, NULL);
    uint64_t sphere = reyes_test_covered_samples(&alone);
    ck_assert_uint_gt(sphere, 64 * 64 * o.spp / 8);
    reyes_test_add_far_patch(&scene, 1e6f);
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &with_far, &stats);
    ck_assert_uint_ge(reyes_test_covered_samples(&with_far), sphere);
    ck_assert_float_le(reyes_near_plane(&scene, &camera), 1e-3f);
    reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
    reyes_image_free(&alone);
    reyes_image_free(&with_far);
    reyes_scene_free(&scene);
}
END_TEST

/* Back-face culling, another bound and a depth limit that forces dicing:
 * the counts still equal the C reference's. */
START_TEST(test_options_match_reference)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 96, 64);
    reyes_options o;
    small_options(&o, 96, 64);
    o.backface_cull = 1;
    o.bound_px = 3.0f;
    o.max_depth = 4;
    o.spp = 1;
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &stats);
    ck_assert_uint_gt(stats.culled, 0);
    ck_assert_uint_gt(stats.forced_dice, 0);
    reyes_test_expect_reference_counts(&scene, &camera, &o, &stats);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* Stopping after dice's geometry or after subdivision: the same splits and
 * grids, micropolygons only with geometry, no samples, and the C
 * reference's counts for the same stages. */
START_TEST(test_stages)
{
    reyes_scene scene;
    reyes_error error;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 128, 96);
    reyes_options o;
    small_options(&o, 128, 96);
    reyes_image image;
    reyes_stats all, geometry, subdivide;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &all);
    reyes_image_free(&image);
    o.stages = REYES_STAGES_GEOMETRY;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &geometry);
    ck_assert_uint_eq(reyes_test_covered_samples(&image), 0);
    reyes_test_expect_reference_counts(&scene, &camera, &o, &geometry);
    reyes_image_free(&image);
    o.stages = REYES_STAGES_SUBDIVIDE;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &subdivide);
    reyes_test_expect_reference_counts(&scene, &camera, &o, &subdivide);
    reyes_image_free(&image);
    ck_assert_uint_eq(geometry.splits, all.splits);
    ck_assert_uint_eq(subdivide.grids, all.grids);
    ck_assert_uint_eq(geometry.micropolygons, all.micropolygons);
    ck_assert_uint_eq(subdivide.micropolygons, 0);
    o.stages = 3;
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL, &error),
                     REYES_ERR_ARGUMENT);
    reyes_scene_free(&scene);
}
END_TEST

/* The image is the C reference's within rounding (reyes_test_util.h):
 * the default options, nine samples per pixel (a stratification of
 * three columns) with larger micropolygons, one sample per pixel in
 * buckets, and a close view whose micropolygons span many pixels. */
START_TEST(test_image_matches_reference)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_test_builtin_scene(&scene, &camera, 256, 192);
    reyes_options o;
    small_options(&o, 256, 192);
    o.crack_fix = REYES_CRACK_FIX_NONE;
    reyes_image image;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL);
    reyes_test_expect_reference_image(&scene, &camera, &o, &image, "built-in scene");
    reyes_image_free(&image);
    o.spp = 9;
    o.bound_px = 12.0f;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL);
    reyes_test_expect_reference_image(&scene, &camera, &o, &image, "9 samples, 12 px bound");
    reyes_image_free(&image);
    o.spp = 1;
    o.bound_px = 8.0f;
    o.bucket_width = 64;
    o.bucket_height = 48;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL);
    reyes_test_expect_reference_image(&scene, &camera, &o, &image, "1 sample, buckets");
    reyes_image_free(&image);
    reyes_options_init(&o);
    o.width = 256;
    o.height = 192;
    o.crack_fix = REYES_CRACK_FIX_NONE;
    o.bound_px = 48.0f;
    reyes_camera close = { .eye = {0.0f, -3.0f, 0.5f}, .at = {0.0f, 0.0f, 0.5f}, .fov_deg = 70.0f };
    reyes_test_render(reyes_test_renderer(0), &scene, &close, &o, &image, NULL);
    reyes_test_expect_reference_image(&scene, &close, &o, &image, "close view, 48 px bound");
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* Solve the 3x3 system a x = b (Cramer); 0 if singular. */
static int solve3(const double a[3][3], const double b[3], double x[3])
{
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
                 - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
                 + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if (fabs(det) < 1e-12)
        return 0;
    for (int k = 0; k < 3; ++k) {
        double m[3][3];
        memcpy(m, a, sizeof m);
        for (int r = 0; r < 3; ++r)
            m[r][k] = b[r];
        x[k] = (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])) / det;
    }
    return 1;
}

/* The world point at view depth w on the ray through pixel position
 * (px, py) (y down) of a width x height image with view-projection m. */
static int unproject(const float m[16], unsigned width, unsigned height, double px, double py, double w,
                     double out[3])
{
    double ndc_x = 2.0 * px / width - 1.0, ndc_y = 1.0 - 2.0 * py / height;
    double a[3][3], b[3];
    for (int k = 0; k < 3; ++k) {
        a[0][k] = m[k] - ndc_x * m[12 + k];
        a[1][k] = m[4 + k] - ndc_y * m[12 + k];
        a[2][k] = m[12 + k];
    }
    b[0] = -(m[3] - ndc_x * m[15]);
    b[1] = -(m[7] - ndc_y * m[15]);
    b[2] = w - m[15];
    return solve3(a, b, out);
}

/* Shading, not only coverage: a sphere with a different value in each
 * channel, lit by the renderer's light with a highlight in view.  Away
 * from its silhouette every pixel must have the color reyes_reference_shade
 * gives the sphere point seen through the pixel's center (the renderer
 * shades grid vertices and interpolates, and averages 4 jittered samples,
 * hence the tolerance).  A lost or swapped channel, or a vertex shaded
 * with another's color (Intel's vector-call bug, reyes_surface.cl), is
 * off by tens of levels over most of the sphere. */
START_TEST(test_sphere_shading)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    const float center[3] = {0, 0, 0};
    const uint32_t rgba = REYES_RGBA(200, 90, 40);
    ck_assert_int_eq(reyes_scene_add_sphere(&scene, center, 1.0f, rgba, &error), REYES_OK);
    reyes_options o;
    small_options(&o, 160, 160);
    reyes_camera camera = { .eye = {1.5f, -4.5f, 1.2f}, .at = {0, 0, 0}, .fov_deg = 35.0f };
    float m[16];
    ck_assert_int_eq(reyes_camera_matrix(&camera, 1.0f, reyes_near_plane(&scene, &camera), m, &error), REYES_OK);
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &image, &stats);

    size_t checked = 0, over[3] = {0, 0, 0}, bright = 0;
    double total_error = 0.0;
    unsigned worst = 0;
    for (unsigned y = 1; y + 1 < image.height; ++y) {
        for (unsigned x = 1; x + 1 < image.width; ++x) {
            int interior = 1;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    interior &= image.coverage[(y + dy) * image.width + x + dx] == o.spp;
            if (!interior)
                continue;
            double near_point[3], far_point[3], dir[3], eye[3] = {camera.eye[0], camera.eye[1], camera.eye[2]};
            ck_assert(unproject(m, image.width, image.height, x + 0.5, y + 0.5, 1.0, near_point));
            ck_assert(unproject(m, image.width, image.height, x + 0.5, y + 0.5, 2.0, far_point));
            for (int k = 0; k < 3; ++k)
                dir[k] = far_point[k] - near_point[k];
            /* |eye + t dir - center|^2 = 1, the nearer root. */
            double a = 0, b = 0, c = -1.0;
            for (int k = 0; k < 3; ++k) {
                a += dir[k] * dir[k];
                b += 2.0 * dir[k] * (eye[k] - center[k]);
                c += (eye[k] - center[k]) * (eye[k] - center[k]);
            }
            double disc = b * b - 4 * a * c;
            ck_assert_msg(disc > 0, "covered pixel %u,%u misses the sphere", x, y);
            double t = (-b - sqrt(disc)) / (2 * a);
            float hit[3], rgb[3];
            for (int k = 0; k < 3; ++k)
                hit[k] = (float)(eye[k] + t * dir[k]);
            reyes_reference_shade(camera.eye, hit, hit, rgba, rgb);
            const uint8_t *got = image.rgb + ((size_t)y * image.width + x) * 3;
            for (int k = 0; k < 3; ++k) {
                unsigned diff = (unsigned)abs((int)got[k] - (int)lrintf(rgb[k] * 255.0f));
                total_error += diff;
                worst = diff > worst ? diff : worst;
                over[0] += diff > 3;
                over[1] += diff > 8;
                over[2] += diff > 16;
            }
            bright += rgb[1] > 0.6f; /* the highlight washes green up */
            ++checked;
        }
    }
    /* PoCL and Intel's runtime: mean 0.17 levels, worst 2; with Intel's
     * vector-call bug: mean 37, worst 199. */
    double mean = total_error / (3.0 * (double)checked);
    ck_assert_uint_gt(checked, 3000);
    ck_assert_uint_gt(bright, 10);
    ck_assert_msg(mean < 1.0 && over[0] * 200 < 3 * checked && over[2] == 0,
                  "sphere colors off the reference shading: %zu pixels, mean error %.2f levels, worst %u, "
                  "channels more than 3 off: %zu, 8: %zu, 16: %zu", checked, mean, worst, over[0], over[1],
                  over[2]);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

START_TEST(test_render_arguments)
{
    reyes_scene scene;
    reyes_error error;
    reyes_image image;
    reyes_scene_init(&scene);
    reyes_options o;
    small_options(&o, 32, 32);
    reyes_camera camera = { .eye = {0, -5, 0}, .at = {0, 0, 0}, .fov_deg = 40 };
    /* An empty scene renders the background without running anything. */
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL, &error),
                     REYES_OK);
    ck_assert_uint_eq(reyes_test_covered_samples(&image), 0);
    reyes_image_free(&image);
    o.grid = 8;
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL, &error),
                     REYES_ERR_ARGUMENT);
    ck_assert(strstr(error.message, "grid") != NULL);
    o.grid = 16;
    o.spp = 0;
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL, &error),
                     REYES_ERR_ARGUMENT);
    reyes_scene_free(&scene);
}
END_TEST

static Suite *render_suite(void)
{
    Suite *s = suite_create("reyes_render");
    TCase *tc = tcase_create("render");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_flat_rectangle);
    tcase_add_test(tc, test_sphere_area_and_no_holes);
    tcase_add_test(tc, test_builtin_no_holes);
    tcase_add_test(tc, test_groups_identical);
    tcase_add_test(tc, test_camera_inside_and_behind);
    tcase_add_test(tc, test_far_point_keeps_the_near_plane_close);
    tcase_add_test(tc, test_options_match_reference);
    tcase_add_test(tc, test_stages);
    tcase_add_test(tc, test_image_matches_reference);
    tcase_add_test(tc, test_render_arguments);
    tcase_add_test(tc, test_sphere_shading);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    return reyes_test_run_suite(render_suite()) ? EXIT_FAILURE : EXIT_SUCCESS;
}
