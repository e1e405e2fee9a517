/*
 * Renders held against the brute-force reference (reyes_brute.h): the
 * built-in scene from several views and, with REYES_MODELS_DIR (suite
 * 'shared'), the teapot.  Each comparison prints its numbers
 * (docs/reyes.md quotes them).
 */
#include <check.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_brute.h"
#include "reyes_test_util.h"

/* The camera of `framed` turned about its target by azimuth degrees
 * (about z) and raised to `elevation` degrees above the target's
 * horizontal plane, at `distance` times its distance. */
static reyes_camera orbit(const reyes_camera *framed, float azimuth, float elevation, float distance)
{
    float d[3], length = 0.0f;
    for (int k = 0; k < 3; ++k) {
        d[k] = framed->eye[k] - framed->at[k];
        length += d[k] * d[k];
    }
    length = sqrtf(length) * distance;
    float a = atan2f(d[1], d[0]) + azimuth * 0.017453293f, e = elevation * 0.017453293f;
    reyes_camera camera = *framed;
    camera.eye[0] = framed->at[0] + length * cosf(e) * cosf(a);
    camera.eye[1] = framed->at[1] + length * cosf(e) * sinf(a);
    camera.eye[2] = framed->at[2] + length * sinf(e);
    return camera;
}

/* Render with keep_samples and hold against the reference (tessellation 64). */
static reyes_brute_comparison compare(const reyes_scene *scene, const reyes_camera *camera,
                                      const reyes_options *options, const char *label)
{
    reyes_options o = *options;
    o.keep_samples = 1;
    reyes_image image;
    reyes_test_render(reyes_test_renderer(0), scene, camera, &o, &image, NULL);
    reyes_brute_image reference;
    reyes_error error;
    ck_assert_msg(reyes_brute_render(scene, camera, &o, 64, &reference, &error) == REYES_OK, "%s", error.message);
    reyes_brute_comparison c;
    ck_assert_msg(reyes_brute_compare(&image, &reference, &c, &error) == REYES_OK, "%s", error.message);
    reyes_brute_print(stdout, label, &c);
    reyes_image_free(&image);
    reyes_brute_free(&reference);
    return c;
}

/* What every correct render of an opaque scene meets: the same coverage
 * and surfaces away from edges, a handful of disagreements along them,
 * and colours within a few levels. */
static void expect_close(const reyes_brute_comparison *c, const char *label)
{
    ck_assert_msg(c->reference_covered > c->samples / 20, "%s: the view shows little (%zu samples)", label,
                  c->reference_covered);
    ck_assert_msg(c->interior_extra == 0 && c->interior_missing == 0,
                  "%s: coverage differs away from edges: %zu extra, %zu missing samples", label, c->interior_extra,
                  c->interior_missing);
    ck_assert_msg(c->interior_other_surface == 0, "%s: %zu samples away from edges see another surface", label,
                  c->interior_other_surface);
    size_t edge_disagreements = c->extra + c->missing + c->other_surface;
    ck_assert_msg(edge_disagreements * 100 <= c->edge_samples,
                  "%s: %zu samples disagree along edges (more than 1 %% of %zu)", label, edge_disagreements,
                  c->edge_samples);
    ck_assert_msg(c->mean_error <= 0.5 && c->interior_mean_error <= 0.5,
                  "%s: mean colour error %.3f (interior %.3f) levels", label, c->mean_error, c->interior_mean_error);
    ck_assert_msg(c->interior_pixels_over_8 * 2000 <= c->interior_pixels,
                  "%s: %zu interior pixels differ by more than 8 levels", label, c->interior_pixels_over_8);
}

#ifndef REYES_MODELS_DIR

/* The built-in scene at 192x144, 4 spp, from the framed view and three
 * orbits (beside, from above, from low down behind). */
START_TEST(test_builtin_views)
{
    reyes_scene scene;
    reyes_camera framed;
    reyes_test_builtin_scene(&scene, &framed, 192, 144);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 192;
    o.height = 144;
    const struct { float azimuth, elevation, distance; } views[] = {
        {0, 25, 1.0f}, {70, 10, 0.9f}, {150, 60, 1.1f}, {230, 5, 0.8f},
    };
    for (size_t v = 0; v < sizeof views / sizeof views[0]; ++v) {
        reyes_camera camera = orbit(&framed, views[v].azimuth, views[v].elevation, views[v].distance);
        char label[64];
        snprintf(label, sizeof label, "builtin view %zu", v);
        reyes_brute_comparison c = compare(&scene, &camera, &o, label);
        expect_close(&c, label);
    }
    reyes_scene_free(&scene);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("reyes_reference");
    TCase *tc = tcase_create("builtin");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_builtin_views);
    suite_add_tcase(s, tc);
    return s;
}

#else

static void load(reyes_scene *scene, const char *file)
{
    char path[1024];
    reyes_error error;
    snprintf(path, sizeof path, "%s/%s", REYES_MODELS_DIR, file);
    reyes_scene_init(scene);
    ck_assert_msg(reyes_scene_load_bpt(scene, path, reyes_model_color(0), &error) == REYES_OK, "%s", error.message);
}

/* The teapot at 256x256, 4 spp, from four views. */
START_TEST(test_teapot_views)
{
    reyes_scene scene;
    reyes_camera framed;
    reyes_error error;
    load(&scene, "teapot.bpt");
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &framed, &error), REYES_OK);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 256;
    const struct { float azimuth, elevation, distance; } views[] = {
        {0, 25, 1.0f}, {90, 5, 0.9f}, {200, 50, 1.0f}, {300, -20, 1.1f},
    };
    for (size_t v = 0; v < sizeof views / sizeof views[0]; ++v) {
        reyes_camera camera = orbit(&framed, views[v].azimuth, views[v].elevation, views[v].distance);
        char label[64];
        snprintf(label, sizeof label, "teapot view %zu", v);
        reyes_brute_comparison c = compare(&scene, &camera, &o, label);
        expect_close(&c, label);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* The view of issue 15 at 1 spp where wedges overhung the rim, under each
 * crack fix. */
START_TEST(test_teapot_rim_crack_fixes)
{
    reyes_scene scene;
    load(&scene, "teapot.bpt");
    reyes_camera camera = { {6.12f, -1.91f, 7.79f}, {0.84f, -0.78f, 1.96f}, 33.3f };
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 512;
    o.spp = 1;
    reyes_brute_comparison stitch = compare(&scene, &camera, &o, "teapot rim, stitch");
    expect_close(&stitch, "teapot rim, stitch");
    o.subdivision = REYES_SUBDIVISION_TIERED;
    reyes_brute_comparison tiered = compare(&scene, &camera, &o, "teapot rim, tiered stitch");
    expect_close(&tiered, "teapot rim, tiered stitch");
    o.crack_fix = REYES_CRACK_FIX_WEDGE;
    reyes_brute_comparison wedge = compare(&scene, &camera, &o, "teapot rim, tiered wedge");
    o.crack_fix = REYES_CRACK_FIX_NONE;
    reyes_brute_comparison none = compare(&scene, &camera, &o, "teapot rim, tiered none");
    (void)none;
    expect_close(&wedge, "teapot rim, tiered wedge");
    reyes_scene_free(&scene);
}
END_TEST

static Suite *suite(void)
{
    Suite *s = suite_create("reyes_reference_models");
    TCase *tc = tcase_create("teapot");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_teapot_views);
    tcase_add_test(tc, test_teapot_rim_crack_fixes);
    suite_add_tcase(s, tc);
    return s;
}

#endif

int main(void)
{
    return reyes_test_run_suite(suite()) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
