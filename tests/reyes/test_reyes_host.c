/* Host pieces without OpenCL: built-in scene, camera, options, PNG, JSON. */
#include <check.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "reyes.h"

START_TEST(test_builtin_scene)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_add_builtin(&scene, &error), REYES_OK);
    /* Two spheres (8 each), a torus (16) and a ribbon (6). */
    ck_assert_uint_eq(scene.patch_count, 8 + 8 + 16 + 6);
    for (size_t i = 0; i < scene.patch_count * 64; ++i)
        ck_assert(isfinite(scene.points[i]));
    reyes_scene_free(&scene);
}
END_TEST

/* Every surface point of the sphere patches lies at the radius (cubic
 * quarter circles err by 0.027%, twice that where profile and sweep add). */
START_TEST(test_sphere_patches_on_sphere)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    const float center[3] = {1, 2, 3};
    ck_assert_int_eq(reyes_scene_add_sphere(&scene, center, 2.0f, 0, &error), REYES_OK);
    ck_assert_uint_eq(scene.patch_count, 8);
    for (size_t p = 0; p < scene.patch_count; ++p) {
        const float *cp = scene.points + p * 64;
        for (int i = 0; i <= 8; ++i) {
            for (int j = 0; j <= 8; ++j) {
                float u = (float)i / 8, v = (float)j / 8;
                float bu[4] = {(1 - u) * (1 - u) * (1 - u), 3 * u * (1 - u) * (1 - u), 3 * u * u * (1 - u), u * u * u};
                float bv[4] = {(1 - v) * (1 - v) * (1 - v), 3 * v * (1 - v) * (1 - v), 3 * v * v * (1 - v), v * v * v};
                float x[3] = {0, 0, 0};
                for (int r = 0; r < 4; ++r)
                    for (int c = 0; c < 4; ++c)
                        for (int k = 0; k < 3; ++k)
                            x[k] += bv[r] * bu[c] * cp[(r * 4 + c) * 4 + k];
                float d = sqrtf((x[0] - 1) * (x[0] - 1) + (x[1] - 2) * (x[1] - 2) + (x[2] - 3) * (x[2] - 3));
                ck_assert_float_eq_tol(d, 2.0f, 2.0f * 6e-4f);
            }
        }
    }
    ck_assert_int_eq(reyes_scene_add_sphere(&scene, center, -1.0f, 0, &error), REYES_ERR_ARGUMENT);
    reyes_scene_free(&scene);
}
END_TEST

START_TEST(test_camera_projection)
{
    reyes_camera camera = { .eye = {0, -10, 0}, .at = {0, 0, 0}, .fov_deg = 90 };
    float m[16], px, py, depth;
    reyes_error error;
    ck_assert_int_eq(reyes_camera_matrix(&camera, 2.0f, 0.01f, m, &error), REYES_OK);
    const float at[3] = {0, 0, 0}, up[3] = {0, 0, 5}, right[3] = {10, 0, 0}, behind[3] = {0, -20, 0};
    ck_assert(reyes_camera_project(m, 200, 100, at, &px, &py, &depth));
    ck_assert_float_eq_tol(px, 100, 1e-3f);
    ck_assert_float_eq_tol(py, 50, 1e-3f);
    ck_assert_float_eq_tol(depth, 10, 1e-4f);
    /* fov 90: at distance 10 the top edge is z = 10; z = 5 is a quarter down. */
    ck_assert(reyes_camera_project(m, 200, 100, up, &px, &py, &depth));
    ck_assert_float_eq_tol(py, 25, 1e-3f);
    /* aspect 2: x = 10 is halfway to the right edge (x = 20). */
    ck_assert(reyes_camera_project(m, 200, 100, right, &px, &py, &depth));
    ck_assert_float_eq_tol(px, 150, 1e-3f);
    ck_assert(!reyes_camera_project(m, 200, 100, behind, &px, &py, &depth));
    /* Looking straight down still works. */
    reyes_camera down = { .eye = {0, 0, 10}, .at = {0, 0, 0}, .fov_deg = 60 };
    ck_assert_int_eq(reyes_camera_matrix(&down, 1.0f, 0.01f, m, &error), REYES_OK);
    ck_assert(reyes_camera_project(m, 64, 64, at, &px, &py, &depth));
    ck_assert_float_eq_tol(px, 32, 1e-3f);
    reyes_camera same = { .eye = {1, 1, 1}, .at = {1, 1, 1}, .fov_deg = 60 };
    ck_assert_int_eq(reyes_camera_matrix(&same, 1.0f, 0.01f, m, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "camera eye and target are the same point");
    /* A camera far out is said to be so (it was "the same point": the
     * distance overflowed). */
    reyes_camera far = { .eye = {2e19f, -10, 3}, .at = {0, 0, 1}, .fov_deg = 60 };
    ck_assert_int_eq(reyes_camera_matrix(&far, 1.0f, 0.01f, m, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "camera eye (2e+19, -10, 3) is beyond +-1e+18, the supported range of coordinates");
    far = (reyes_camera){ .eye = {0, -10, 3}, .at = {1e30f, 0, 1}, .fov_deg = 60 };
    ck_assert_int_eq(reyes_camera_matrix(&far, 1.0f, 0.01f, m, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "camera target (1e+30, 0, 1) is beyond +-1e+18, the supported range of coordinates");
}
END_TEST

/* Auto-framing puts every control point of the scene inside the image
 * (the built-in scene has no point far from the rest). */
START_TEST(test_camera_frames_scene)
{
    reyes_scene scene;
    reyes_error error;
    reyes_camera camera;
    float m[16];
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_add_builtin(&scene, &error), REYES_OK);
    const float aspects[] = {1.0f, 2.0f, 0.5f};
    for (int a = 0; a < 3; ++a) {
        ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, aspects[a], &camera, &error), REYES_OK);
        ck_assert_int_eq(reyes_camera_matrix(&camera, aspects[a], 0.01f, m, &error), REYES_OK);
        unsigned w = (unsigned)(200 * aspects[a]), h = 200;
        for (size_t i = 0; i < scene.patch_count * 16; ++i) {
            float px, py, depth;
            ck_assert(reyes_camera_project(m, w, h, scene.points + i * 4, &px, &py, &depth));
            ck_assert(px >= 0 && px <= (float)w && py >= 0 && py <= (float)h);
        }
    }
    ck_assert_int_eq(reyes_camera_frame(&scene, 0.0f, 1.0f, &camera, &error), REYES_ERR_ARGUMENT);
    reyes_scene_free(&scene);
}
END_TEST

/* One control point 1e6 units away is left out of the framing (and
 * counted): the rest fills the view instead of shrinking to a dot. */
START_TEST(test_camera_frames_the_bulk)
{
    reyes_scene scene;
    reyes_error error;
    reyes_camera camera;
    float m[16];
    reyes_scene_init(&scene);
    ck_assert_int_eq(reyes_scene_add_builtin(&scene, &error), REYES_OK);
    size_t builtin = scene.patch_count;
    reyes_bulk bulk;
    ck_assert(reyes_scene_bulk(&scene, &bulk));
    ck_assert_uint_eq(bulk.left_out, 0);
    float cp[4][4][3] = { { { 1e6f, 0.0f, 0.0f } } }; /* a patch at the origin but its first point */
    ck_assert_int_eq(reyes_scene_add_patch(&scene, cp, REYES_RGBA(90, 170, 90), &error), REYES_OK);
    ck_assert(reyes_scene_bulk(&scene, &bulk));
    ck_assert_uint_eq(bulk.left_out, 1);
    ck_assert_uint_eq(bulk.first_left_out, builtin * 16);
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &camera, &error), REYES_OK);
    ck_assert_int_eq(reyes_camera_matrix(&camera, 1.0f, 0.01f, m, &error), REYES_OK);
    float lo = 200.0f, hi = 0.0f, px, py, depth;
    for (size_t i = 0; i < builtin * 16; ++i) {
        ck_assert(reyes_camera_project(m, 200, 200, scene.points + i * 4, &px, &py, &depth));
        ck_assert(px >= 0 && px <= 200 && py >= 0 && py <= 200);
        lo = fminf(lo, px);
        hi = fmaxf(hi, px);
    }
    ck_assert_float_gt(hi - lo, 100.0f);
    ck_assert(!reyes_camera_project(m, 200, 200, scene.points + builtin * 16 * 4, &px, &py, &depth)
              || px > 200.0f || px < 0.0f || py > 200.0f || py < 0.0f);
    reyes_scene_free(&scene);
}
END_TEST

START_TEST(test_options_check)
{
    reyes_options o;
    reyes_error error;
    reyes_options_init(&o);
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    ck_assert_uint_eq(o.grid, 16);
    ck_assert_uint_eq(o.spp, 4);
    ck_assert_uint_eq(o.max_depth, 20);
    ck_assert_float_eq(o.bound_px, 8.0f);
    o.grid = 1;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert(strstr(error.message, "grid") != NULL);
    /* Shading rate: 0 (fixed grids, the default) or 0.01..10000, not with wedges. */
    reyes_options_init(&o);
    ck_assert_float_eq(o.shading_rate, 0.0f);
    o.shading_rate = 0.001f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "shading rate 0.001 px is not 0 (fixed grids) or in 0.01..10000");
    o.shading_rate = 2.0f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    o.subdivision = REYES_SUBDIVISION_TIERED;
    o.crack_fix = REYES_CRACK_FIX_WEDGE;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert(strstr(error.message, "crack fix wedge needs fixed grids") != NULL);
    /* Polylines: a shading rate, no displacement. */
    reyes_options_init(&o);
    o.crack_fix = REYES_CRACK_FIX_POLYLINE;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "crack fix polyline needs a shading rate (fixed grids stitch or use wedges)");
    o.shading_rate = 1.0f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    o.displace_mode = REYES_DISPLACE_BUMPS;
    o.displace_amplitude = 0.1f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "crack fix polyline cannot be combined with displacement (its polylines are of "
                                    "the undisplaced surface; stitch instead)");
    o.crack_fix = 4;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "crack fix 4 is not 0 (none), 1 (stitch), 2 (wedge) or 3 (polyline)");
    /* Occlusion culling: on by default, 0 or 1. */
    reyes_options_init(&o);
    ck_assert_uint_eq(o.occlusion_cull, 1);
    o.occlusion_cull = 2;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "occlusion_cull 2 is not 0 (off) or 1 (on)");
    reyes_options_init(&o);
    o.width = 16384;
    o.height = 16384;
    o.spp = 64;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    /* Blur sampling: the defaults, and out-of-range values named. */
    reyes_options_init(&o);
    ck_assert_uint_eq(o.blur_algo, REYES_BLUR_INTERLEAVED);
    ck_assert_uint_eq(o.blur_tile, 4);
    ck_assert_uint_eq(o.blur_permutations, 8);
    struct { unsigned algo, tile, permutations; const char *needle; } bad[] = {
        { 3, 4, 8, "blur_algo 3" }, { 0, 0, 8, "blur_tile 0" }, { 1, 9, 8, "blur_tile 9" },
        { 2, 4, 0, "blur_permutations 0" }, { 1, 4, 65, "blur_permutations 65" },
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        o.blur_algo = bad[k].algo;
        o.blur_tile = bad[k].tile;
        o.blur_permutations = bad[k].permutations;
        ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
        ck_assert_msg(strstr(error.message, bad[k].needle) != NULL, "'%s' lacks '%s'", error.message,
                      bad[k].needle);
    }
    o.blur_algo = REYES_BLUR_BBOX;
    o.blur_tile = 8;
    o.blur_permutations = 64;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    /* The rotation over the shutter: default axis z, angle 0; a zero axis
     * only matters when something rotates. */
    reyes_options_init(&o);
    ck_assert_float_eq(o.motion_axis[2], 1.0f);
    ck_assert_float_eq(o.motion_angle_deg, 0.0f);
    o.motion_angle_deg = -360.0f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    const struct { float axis[3], deg; const char *needle; } rotations[] = {
        { {0, 0, 1}, 360.5f, "motion rotation angle 360.5" },
        { {0, 0, 1}, NAN, "motion rotation angle nan" },
        { {0, 0, 0}, 10.0f, "motion rotation axis is zero-length" },
        { {INFINITY, 0, 1}, 10.0f, "motion rotation axis inf" },
        { {0, 2e6f, 1}, 0.0f, "motion rotation axis 2e+06" },
    };
    for (size_t k = 0; k < sizeof rotations / sizeof rotations[0]; ++k) {
        memcpy(o.motion_axis, rotations[k].axis, sizeof o.motion_axis);
        o.motion_angle_deg = rotations[k].deg;
        ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
        ck_assert_msg(strstr(error.message, rotations[k].needle) != NULL, "'%s' lacks '%s'",
                      error.message, rotations[k].needle);
    }
    o.motion_axis[0] = o.motion_axis[1] = o.motion_axis[2] = 0.0f;
    o.motion_angle_deg = 0.0f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    unsigned algo = 99;
    ck_assert(reyes_blur_algo_parse("simple", &algo) && algo == REYES_BLUR_SIMPLE);
    ck_assert(!reyes_blur_algo_parse("uvt", &algo) && algo == REYES_BLUR_SIMPLE);
    ck_assert_ptr_null(reyes_blur_algo_name(3));
}
END_TEST

START_TEST(test_png_roundtrip)
{
    uint8_t rgb[3 * 4 * 3], coverage[12];
    for (int i = 0; i < 36; ++i)
        rgb[i] = (uint8_t)(i * 7);
    reyes_image image = { .width = 4, .height = 3, .rgb = rgb, .coverage = coverage };
    char path[] = "/tmp/reyes-png-XXXXXX";
    int fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    close(fd);
    reyes_error error;
    ck_assert_int_eq(reyes_write_png(path, &image, &error), REYES_OK);
    png_image read;
    memset(&read, 0, sizeof read);
    read.version = PNG_IMAGE_VERSION;
    ck_assert(png_image_begin_read_from_file(&read, path));
    read.format = PNG_FORMAT_RGB;
    ck_assert_uint_eq(read.width, 4);
    ck_assert_uint_eq(read.height, 3);
    uint8_t back[36];
    ck_assert(png_image_finish_read(&read, NULL, back, 0, NULL));
    ck_assert_mem_eq(back, rgb, 36);
    unlink(path);
    ck_assert_int_eq(reyes_write_png("/nonexistent-dir/x.png", &image, &error), REYES_ERR_IO);
    ck_assert(strstr(error.message, "/nonexistent-dir/x.png") != NULL);
}
END_TEST

START_TEST(test_stats_json)
{
    reyes_stats stats;
    reyes_options o;
    reyes_error error;
    memset(&stats, 0, sizeof stats);
    reyes_options_init(&o);
    stats.patches_in = 32;
    stats.splits = 1234;
    stats.grids = 1267;
    stats.occluded = 45;
    stats.procedures[REYES_PROC_BOUND].name = "bound";
    stats.procedures[REYES_PROC_BOUND].emit_count = 3;
    stats.procedures[REYES_PROC_BOUND].emitted[2] = 1267;
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    ck_assert_int_eq(reyes_write_stats_json(f, &stats, &o, &error), REYES_OK);
    fclose(f);
    const char *keys[] = {"\"patches_in\": 32", "\"splits\": 1234", "\"culled\": 0",
                          "\"grids\": 1267", "\"occlusion\": \"on\", \"occluded\": 45", "\"micropolygons\"", "\"samples_written\"",
                          "\"peak_queue_bytes\"", "\"seconds\"", "\"procedures\"",
                          "\"bound\": {\"items\": 0", "\"emitted\": [0, 0, 1267]",
                          "\"blur_algo\": \"interleaved\", \"blur_tile\": 4, \"blur_permutations\": 8",
                          "\"motion_axis\": [0, 0, 1], \"motion_angle_deg\": 0",
                          "\"grid\": 16, \"shading_rate\": 0"};
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; ++k)
        ck_assert_msg(strstr(text, keys[k]) != NULL, "missing %s in\n%s", keys[k], text);
    ck_assert_msg(strstr(text, "\"micropolygon_area\": null") != NULL, "no area statistics asked for:\n%s", text);
    free(text);
    /* With the areas: 4 micropolygons of 4.8 square pixels in all, in the
     * bin from 1 to 1.5 (percentiles interpolated geometrically in it). */
    o.area_stats = 1;
    stats.micropolygons = 4;
    stats.micropolygon_area = 4.8;
    ck_assert(reyes_area_bin_lower(21) == 1.0 && reyes_area_bin_lower(22) == 1.5);
    stats.micropolygon_area_bins[21] = 4;
    f = open_memstream(&text, &size);
    ck_assert_int_eq(reyes_write_stats_json(f, &stats, &o, &error), REYES_OK);
    fclose(f);
    ck_assert_msg(strstr(text, "\"micropolygon_area\": {\"mean\": 1.2, \"p10\": 1.04138, ") != NULL
                      && strstr(text, "\"p50\": 1.22474, ") != NULL
                      && strstr(text, "\"bins\": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 4, 0,")
                             != NULL,
                  "areas in\n%s", text);
    free(text);
}
END_TEST

static Suite *host_suite(void)
{
    Suite *s = suite_create("reyes_host");
    TCase *tc = tcase_create("host");
    tcase_add_test(tc, test_builtin_scene);
    tcase_add_test(tc, test_sphere_patches_on_sphere);
    tcase_add_test(tc, test_camera_projection);
    tcase_add_test(tc, test_camera_frames_scene);
    tcase_add_test(tc, test_camera_frames_the_bulk);
    tcase_add_test(tc, test_options_check);
    tcase_add_test(tc, test_png_roundtrip);
    tcase_add_test(tc, test_stats_json);
    suite_add_tcase(s, tc);
    return s;
}

int main(void)
{
    SRunner *runner = srunner_create(host_suite());
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
