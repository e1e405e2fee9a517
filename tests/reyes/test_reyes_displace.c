/* Displacement: amplitude 0 is exactly no displacement; a sphere displaced
 * by a white map grows by the amplitude; bumps stay watertight. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "reyes_test_util.h"

#define PI 3.14159265358979323846
#define SIZE 160
#define DISTANCE 5.0f
#define FOV 35.0f

static const reyes_camera camera = { .eye = {0, -DISTANCE, 0}, .at = {0, 0, 0}, .fov_deg = FOV };

/* Projected area (pixels) of a sphere of this radius at the camera. */
static double sphere_area(double radius)
{
    double focal = 0.5 * SIZE / tan(0.5 * FOV * PI / 180.0);
    double r = focal * tan(asin(radius / DISTANCE));
    return PI * r * r;
}

/* Write a uniform gray PNG; returns its path (static storage). */
static const char *gray_png(uint8_t value)
{
    static char path[64];
    snprintf(path, sizeof path, "/tmp/reyes_displace_XXXXXX");
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    close(fd);
    uint8_t rgb[8 * 8 * 3];
    memset(rgb, value, sizeof rgb);
    reyes_image image = { .width = 8, .height = 8, .rgb = rgb };
    reyes_error error;
    ck_assert_int_eq(reyes_write_png(path, &image, &error), REYES_OK);
    return path;
}

static void render(const reyes_scene *scene, const reyes_options *o, reyes_image *image)
{
    reyes_test_render(reyes_test_renderer(0), scene, &camera, o, image, NULL);
}

START_TEST(test_zero_amplitude_is_no_displacement)
{
    reyes_scene scene;
    reyes_test_sphere_scene(&scene);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = SIZE;
    reyes_image plain, bumps, map;
    render(&scene, &o, &plain);
    o.displace_mode = REYES_DISPLACE_BUMPS;
    render(&scene, &o, &bumps);
    const char *path = gray_png(255);
    o.displace_mode = REYES_DISPLACE_MAP;
    o.displace_map = path;
    render(&scene, &o, &map);
    ck_assert_mem_eq(plain.rgb, bumps.rgb, (size_t)SIZE * SIZE * 3);
    ck_assert_mem_eq(plain.rgb, map.rgb, (size_t)SIZE * SIZE * 3);
    ck_assert_mem_eq(plain.coverage, map.coverage, (size_t)SIZE * SIZE);
    unlink(path);
    reyes_image_free(&plain);
    reyes_image_free(&bumps);
    reyes_image_free(&map);
    reyes_scene_free(&scene);
}
END_TEST

/* A white map moves every point out by the amplitude: the silhouette is
 * that of a sphere of radius 1 + amplitude (within 1 %).  Bumps (0 to the
 * amplitude) land in between, and leave no cracks. */
START_TEST(test_sphere_grows_by_amplitude)
{
    reyes_scene scene;
    reyes_test_sphere_scene(&scene);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = SIZE;
    const float amplitude = 0.2f;
    const char *path = gray_png(255);
    o.displace_mode = REYES_DISPLACE_MAP;
    o.displace_map = path;
    o.displace_amplitude = amplitude;
    reyes_image image;
    render(&scene, &o, &image);
    double area = (double)reyes_test_covered_samples(&image) / o.spp;
    double expected = sphere_area(1.0 + amplitude);
    ck_assert_msg(fabs(area - expected) < 0.01 * expected, "area %g, expected %g", area, expected);
    ck_assert_uint_eq(reyes_test_hole_pixels(&image, 64), 0);
    reyes_image_free(&image);
    unlink(path);

    o.displace_mode = REYES_DISPLACE_BUMPS;
    render(&scene, &o, &image);
    area = (double)reyes_test_covered_samples(&image) / o.spp;
    printf("bumps of 0..%g: area %g between %g and %g\n", (double)amplitude, area, sphere_area(1.0),
           expected);
    ck_assert(area > sphere_area(1.0) * 1.02 && area < expected);
    ck_assert_uint_eq(reyes_test_hole_pixels(&image, 64), 0);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* bound grows the hull by the amplitude: a flat patch just below the
 * view is culled, but pushed up by a white map it enters the view and is
 * drawn. */
START_TEST(test_bound_grows_by_amplitude)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    float cp[4][4][3];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            cp[r][c][0] = -1.0f + 2.0f * (float)c / 3.0f;
            cp[r][c][1] = -1.0f + 2.0f * (float)r / 3.0f;
            cp[r][c][2] = 0.0f;
        }
    ck_assert_int_eq(reyes_scene_add_patch(&scene, cp, REYES_RGBA(255, 255, 255), &error), REYES_OK);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 64;
    o.cull_margin = 0.0f;
    const char *path = gray_png(255);
    o.displace_mode = REYES_DISPLACE_MAP;
    o.displace_map = path;
    o.displace_amplitude = 1.0f;
    /* The patch (z = 0, normal +z) is 22 to 32 degrees below the view
     * axis of a 30 degree field of view; at z = 1 its far edge is 11. */
    reyes_camera side = { .eye = {0, -4, 1.5f}, .at = {0, 0, 1.9f}, .fov_deg = 30.0f };
    reyes_image image;
    reyes_stats stats;
    reyes_test_render(reyes_test_renderer(0), &scene, &side, &o, &image, &stats);
    uint64_t displaced = reyes_test_covered_samples(&image);
    reyes_image_free(&image);
    o.displace_amplitude = 0.0f;
    reyes_test_render(reyes_test_renderer(0), &scene, &side, &o, &image, &stats);
    ck_assert_uint_eq(reyes_test_covered_samples(&image), 0);
    ck_assert_uint_eq(stats.culled, 1);
    ck_assert_uint_gt(displaced, 0);
    reyes_image_free(&image);
    unlink(path);
    reyes_scene_free(&scene);
}
END_TEST

START_TEST(test_map_errors_name_the_file)
{
    reyes_scene scene;
    reyes_test_sphere_scene(&scene);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 32;
    o.displace_mode = REYES_DISPLACE_MAP;
    o.displace_amplitude = 0.1f;
    o.displace_map = "/nonexistent/bumps.png";
    reyes_image image;
    reyes_error error;
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL, &error),
                     REYES_ERR_IO);
    ck_assert(strstr(error.message, "/nonexistent/bumps.png") != NULL);
    o.displace_map = NULL;
    ck_assert_int_eq(reyes_render(reyes_test_renderer(0), &scene, &camera, &o, &image, NULL, &error),
                     REYES_ERR_ARGUMENT);
    reyes_scene_free(&scene);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_displace");
    TCase *tc = tcase_create("displace");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_zero_amplitude_is_no_displacement);
    tcase_add_test(tc, test_sphere_grows_by_amplitude);
    tcase_add_test(tc, test_bound_grows_by_amplitude);
    tcase_add_test(tc, test_map_errors_name_the_file);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
