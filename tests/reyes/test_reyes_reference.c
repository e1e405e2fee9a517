/*
 * Renders held against the brute-force reference (reyes_brute.h): the
 * built-in scene from several views and, with REYES_MODELS_DIR (suite
 * 'shared'), the teapot.  Each comparison prints its numbers
 * (docs/reyes-measurements.md quotes them).
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

/* The reference of a view, each patch tessellated into `tessellation`
 * squared quads. */
static reyes_brute_image reference_of(const reyes_scene *scene, const reyes_camera *camera,
                                      const reyes_options *options, unsigned tessellation)
{
    reyes_brute_image reference;
    reyes_error error;
    ck_assert_msg(reyes_brute_render(scene, camera, options, tessellation, &reference, &error) == REYES_OK, "%s",
                  error.message);
    return reference;
}

/* Render with keep_samples and hold the image against the reference. */
static reyes_brute_comparison hold(const reyes_brute_image *reference, const reyes_scene *scene,
                                   const reyes_camera *camera, const reyes_options *options, const char *label)
{
    reyes_options o = *options;
    o.keep_samples = 1;
    reyes_image image;
    reyes_test_render(reyes_test_renderer(0), scene, camera, &o, &image, NULL);
    reyes_brute_comparison c;
    reyes_error error;
    ck_assert_msg(reyes_brute_compare(&image, reference, &c, &error) == REYES_OK, "%s", error.message);
    reyes_brute_print(stdout, label, &c);
    fflush(stdout);
    reyes_image_free(&image);
    return c;
}

/* One render against the reference of its view (tessellation 64). */
static reyes_brute_comparison compare(const reyes_scene *scene, const reyes_camera *camera,
                                      const reyes_options *options, const char *label)
{
    reyes_brute_image reference = reference_of(scene, camera, options, 64);
    reyes_brute_comparison c = hold(&reference, scene, camera, options, label);
    reyes_brute_free(&reference);
    return c;
}

/* What every correct render of an opaque scene meets: the same coverage
 * and surfaces away from edges, a handful of disagreements along them,
 * and colours within a few levels (at most 1 in `per_pixel_over_8`
 * interior pixels off by more than 8). */
static void expect_close_within(const reyes_brute_comparison *c, size_t per_pixel_over_8, const char *label)
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
    ck_assert_msg(c->interior_pixels_over_8 * per_pixel_over_8 <= c->interior_pixels,
                  "%s: %zu interior pixels differ by more than 8 levels", label, c->interior_pixels_over_8);
}

static void expect_close(const reyes_brute_comparison *c, const char *label)
{
    expect_close_within(c, 2000, label);
}

/* A camera orbiting the framed one (see orbit). */
typedef struct view {
    float azimuth, elevation, distance;
} view;

/* Every view of a scene passes expect_close; labels "NAME view K". */
static void expect_views_close(const reyes_scene *scene, const reyes_camera *framed, const reyes_options *options,
                               const view *views, size_t count, const char *name)
{
    for (size_t v = 0; v < count; ++v) {
        reyes_camera camera = orbit(framed, views[v].azimuth, views[v].elevation, views[v].distance);
        char label[64];
        snprintf(label, sizeof label, "%s view %zu", name, v);
        reyes_brute_comparison c = compare(scene, &camera, options, label);
        expect_close(&c, label);
    }
}

/* Wedges overhang nothing (docs/reyes-dicing.md): they add no more samples that
 * the reference leaves empty or sees on another surface, and no more
 * badly wrong pixels, than the same render without a crack fix (the
 * grids alone), give or take `slack`. */
static void expect_no_overhang(const reyes_brute_comparison *wedge, const reyes_brute_comparison *none,
                               size_t slack, const char *label)
{
    ck_assert_msg(wedge->extra <= none->extra + slack && wedge->other_surface <= none->other_surface + slack,
                  "%s: wedges overhang: %zu extra samples and %zu on another surface, against %zu and %zu "
                  "without a crack fix",
                  label, wedge->extra, wedge->other_surface, none->extra, none->other_surface);
    ck_assert_msg(wedge->pixels_over_32 <= none->pixels_over_32 + slack,
                  "%s: %zu pixels off by more than 32 levels with wedges, %zu without a crack fix", label,
                  wedge->pixels_over_32, none->pixels_over_32);
}

/* Micropolygons per covered pixel of a render. */
static double micropolygons_per_pixel(const reyes_image *image, const reyes_stats *stats)
{
    size_t covered = 0;
    for (size_t k = 0; k < (size_t)image->width * image->height; ++k)
        covered += image->coverage[k] > 0;
    return covered ? (double)stats->micropolygons / (double)covered : 0.0;
}

/* Shading-rate dicing against fixed 16x16 grids on one view: the rate's
 * micropolygons per covered pixel (at most `most`), and its image held
 * to the reference as every render is (expect_close, but see below), with
 * no more pixels off by over 32 levels than the fixed grids' but 0.1 %,
 * and within half a level on average of the fixed grids' image. */
static void expect_rate_close(const reyes_scene *scene, const reyes_camera *camera, const reyes_options *fixed,
                              float rate, double most, unsigned tessellation, const char *label)
{
    reyes_options o = *fixed;
    o.keep_samples = 1;
    reyes_image fixed_image, rate_image;
    reyes_stats fixed_stats, rate_stats;
    reyes_test_render(reyes_test_renderer(0), scene, camera, &o, &fixed_image, &fixed_stats);
    o.shading_rate = rate;
    reyes_test_render(reyes_test_renderer(0), scene, camera, &o, &rate_image, &rate_stats);
    reyes_brute_image reference = reference_of(scene, camera, &o, tessellation);
    reyes_brute_comparison fixed_c, rate_c;
    reyes_error error;
    ck_assert_msg(reyes_brute_compare(&fixed_image, &reference, &fixed_c, &error) == REYES_OK, "%s", error.message);
    ck_assert_msg(reyes_brute_compare(&rate_image, &reference, &rate_c, &error) == REYES_OK, "%s", error.message);
    double fixed_density = micropolygons_per_pixel(&fixed_image, &fixed_stats);
    double density = micropolygons_per_pixel(&rate_image, &rate_stats);
    double difference = 0.0;
    size_t pixels = 0;
    for (size_t k = 0; k < (size_t)rate_image.width * rate_image.height; ++k) {
        if (!rate_image.coverage[k] && !fixed_image.coverage[k])
            continue;
        ++pixels;
        for (int c = 0; c < 3; ++c)
            difference += abs((int)rate_image.rgb[3 * k + c] - (int)fixed_image.rgb[3 * k + c]);
    }
    difference /= 3.0 * (double)(pixels ? pixels : 1);
    char line[160];
    snprintf(line, sizeof line, "%s, fixed 16x16 (%llu grids, %.2f micropolygons per covered pixel)", label,
             (unsigned long long)fixed_stats.grids, fixed_density);
    reyes_brute_print(stdout, line, &fixed_c);
    snprintf(line, sizeof line, "%s, shading rate %g (%llu grids, %.2f micropolygons per covered pixel)", label,
             (double)rate, (unsigned long long)rate_stats.grids, density);
    reyes_brute_print(stdout, line, &rate_c);
    printf("%s: shading rate %g against fixed 16x16: mean difference %.3f levels over %zu pixels\n", label,
           (double)rate, difference, pixels);
    fflush(stdout);
    ck_assert_msg(density <= most, "%s: %.2f micropolygons per covered pixel (at most %.1f)", label, density, most);
    /* Micropolygons of a pixel interpolate their vertices' colours across
     * creases inside patches and across highlights: twice as many
     * interior pixels may be off by more than 8 levels. */
    expect_close_within(&rate_c, 1000, label);
    ck_assert_msg(rate_c.pixels_over_32 <= fixed_c.pixels_over_32 + 2 + fixed_c.pixels / 1000,
                  "%s: %zu pixels off by more than 32 levels, fixed grids %zu", label, rate_c.pixels_over_32,
                  fixed_c.pixels_over_32);
    ck_assert_msg(difference <= 0.5, "%s: mean difference %.3f levels from the fixed grids' image", label,
                  difference);
    reyes_image_free(&fixed_image);
    reyes_image_free(&rate_image);
    reyes_stats_free(&fixed_stats);
    reyes_stats_free(&rate_stats);
    reyes_brute_free(&reference);
}

#ifndef REYES_MODELS_DIR

/* A fur-like model: `count` hairs, each one bicubic patch, a thin ribbon
 * (width about a pixel at 256x256) curving out of a unit sphere, roots
 * and directions from a fixed hash. */
static void add_fur(reyes_scene *scene, unsigned count, float length, float width)
{
    uint32_t state = 12345u;
    reyes_error error;
    for (unsigned h = 0; h < count; ++h) {
        float r[6];
        for (int k = 0; k < 6; ++k) {
            state = state * 1664525u + 1013904223u;
            r[k] = (float)(state >> 8) / 16777216.0f;
        }
        float z = 2.0f * r[0] - 1.0f, phi = 6.2831853f * r[1], ring = sqrtf(1.0f - z * z);
        float root[3] = {ring * cosf(phi), ring * sinf(phi), z};
        /* Across the hair: perpendicular to the root direction, turned by r[2]. */
        float t1[3] = {-sinf(phi), cosf(phi), 0.0f}, t2[3] = {-z * cosf(phi), -z * sinf(phi), ring};
        float turn = 3.1415927f * r[2], across[3], bend[3];
        for (int k = 0; k < 3; ++k) {
            across[k] = cosf(turn) * t1[k] + sinf(turn) * t2[k];
            bend[k] = (r[3] - 0.5f) * t1[k] + (r[4] - 0.5f) * t2[k];
        }
        float cp[4][4][3];
        for (int row = 0; row < 4; ++row) {
            float t = (float)row / 3.0f, reach = length * (0.7f + 0.6f * r[5]) * t;
            for (int col = 0; col < 4; ++col) {
                float offset = width * ((float)col / 3.0f - 0.5f) * (1.0f - 0.7f * t);
                for (int k = 0; k < 3; ++k)
                    cp[row][col][k] = root[k] * (1.0f + reach) + bend[k] * reach * t + across[k] * offset;
            }
        }
        ck_assert_int_eq(reyes_scene_add_patch(scene, cp, REYES_RGBA(150, 110, 70), &error), REYES_OK);
    }
}

/* Fur: thin open patches, all boundary, one reference for three renders.
 * Wedges cover what the grids cover: the chords they reached before
 * added 7383 samples to the reference's 49889. */
START_TEST(test_fur_wedges)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    add_fur(&scene, 1500, 0.5f, 0.012f);
    reyes_camera camera;
    reyes_error error;
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &camera, &error), REYES_OK);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 256;
    o.subdivision = REYES_SUBDIVISION_TIERED;
    o.crack_fix = REYES_CRACK_FIX_NONE;
    reyes_brute_image reference = reference_of(&scene, &camera, &o, 64);
    reyes_brute_comparison none = hold(&reference, &scene, &camera, &o, "fur, tiered none");
    o.crack_fix = REYES_CRACK_FIX_WEDGE;
    reyes_brute_comparison wedge = hold(&reference, &scene, &camera, &o, "fur, tiered wedge");
    o.subdivision = REYES_SUBDIVISION_BOUND;
    o.crack_fix = REYES_CRACK_FIX_STITCH;
    reyes_brute_comparison stitch = hold(&reference, &scene, &camera, &o, "fur, stitch");
    reyes_brute_free(&reference);
    expect_no_overhang(&wedge, &none, wedge.reference_covered / 1000, "fur");
    ck_assert_msg((wedge.extra + wedge.missing) * 100 <= wedge.reference_covered,
                  "fur: wedges' coverage differs from the reference's in %zu of %zu samples",
                  wedge.extra + wedge.missing, wedge.reference_covered);
    ck_assert_msg((stitch.extra + stitch.missing) * 100 <= stitch.reference_covered,
                  "fur: the stitched coverage differs from the reference's in %zu of %zu samples",
                  stitch.extra + stitch.missing, stitch.reference_covered);
    reyes_scene_free(&scene);
}
END_TEST

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
    const view views[] = { {0, 25, 1.0f}, {70, 10, 0.9f}, {150, 60, 1.1f}, {230, 5, 0.8f} };
    expect_views_close(&scene, &framed, &o, views, sizeof views / sizeof views[0], "builtin");
    reyes_scene_free(&scene);
}
END_TEST

/* Shading rate 1 on the built-in scene (two views) and the fur: at most
 * 4 micropolygons per covered pixel, the image as good as fixed grids'. */
START_TEST(test_shading_rate)
{
    reyes_scene scene;
    reyes_camera framed;
    reyes_test_builtin_scene(&scene, &framed, 256, 192);
    reyes_options o;
    reyes_options_init(&o);
    o.width = 256;
    o.height = 192;
    reyes_camera camera = orbit(&framed, 0, 25, 1.0f);
    expect_rate_close(&scene, &camera, &o, 1.0f, 4.0, 64, "builtin framed");
    camera = orbit(&framed, 150, 60, 1.1f);
    expect_rate_close(&scene, &camera, &o, 1.0f, 4.0, 64, "builtin from above");
    o.subdivision = REYES_SUBDIVISION_TIERED;
    expect_rate_close(&scene, &camera, &o, 1.0f, 4.0, 64, "builtin from above, tiered");
    reyes_scene_free(&scene);
    reyes_scene_init(&scene);
    add_fur(&scene, 1500, 0.5f, 0.012f);
    reyes_error error;
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &camera, &error), REYES_OK);
    reyes_options_init(&o);
    o.width = o.height = 256;
    expect_rate_close(&scene, &camera, &o, 1.0f, 4.0, 64, "fur");
    reyes_scene_free(&scene);
}
END_TEST

/* Shading-rate dicing decides from the sub-patch and the camera only: the
 * same bytes in 48x40 buckets, stitched and not, and under another
 * schedule on 2 groups. */
START_TEST(test_shading_rate_identical)
{
    reyes_scene scene;
    reyes_camera camera;
    reyes_options o;
    reyes_test_small_builtin(&scene, &camera, &o);
    o.shading_rate = 1.0f;
    for (int stitched = 0; stitched < 2; ++stitched) {
        o.crack_fix = stitched ? REYES_CRACK_FIX_STITCH : REYES_CRACK_FIX_NONE;
        o.bucket_width = o.bucket_height = 0;
        reyes_image whole, tiled, other;
        reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &whole, NULL);
        o.bucket_width = 48;
        o.bucket_height = 40;
        reyes_test_render(reyes_test_renderer(0), &scene, &camera, &o, &tiled, NULL);
        reyes_test_expect_same_image(&whole, &tiled, stitched ? "rate 1, stitched, buckets" : "rate 1, buckets");
        o.bucket_width = o.bucket_height = 0;
        reyes_test_apply_schedule("megakernel/stealing", 2, &o);
        reyes_test_render_once(&scene, &camera, &o, &other, NULL);
        reyes_test_expect_same_image(&whole, &other, stitched ? "rate 1, stitched, stealing" : "rate 1, stealing");
        reyes_options_init(&o);
        o.width = 160;
        o.height = 120;
        o.shading_rate = 1.0f;
        reyes_image_free(&whole);
        reyes_image_free(&tiled);
        reyes_image_free(&other);
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
    tcase_add_test(tc, test_fur_wedges);
    tcase_add_test(tc, test_shading_rate);
    tcase_add_test(tc, test_shading_rate_identical);
    suite_add_tcase(s, tc);
    return s;
}

#else

/* The teapot at 256x256, 4 spp, from four views. */
START_TEST(test_teapot_views)
{
    reyes_scene scene;
    reyes_camera framed;
    reyes_error error;
    reyes_test_load_model(&scene, REYES_MODELS_DIR, "teapot.bpt");
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &framed, &error), REYES_OK);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 256;
    const view views[] = { {0, 25, 1.0f}, {90, 5, 0.9f}, {200, 50, 1.0f}, {300, -20, 1.1f} };
    expect_views_close(&scene, &framed, &o, views, sizeof views / sizeof views[0], "teapot");
    reyes_scene_free(&scene);
}
END_TEST

/* The view of issue 15 at 1 spp where wedges overhung the rim, under each
 * crack fix. */
START_TEST(test_teapot_rim_crack_fixes)
{
    reyes_scene scene;
    reyes_test_load_model(&scene, REYES_MODELS_DIR, "teapot.bpt");
    reyes_camera camera = { {6.12f, -1.91f, 7.79f}, {0.84f, -0.78f, 1.96f}, 33.3f };
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 512;
    o.spp = 1;
    reyes_brute_image reference = reference_of(&scene, &camera, &o, 64);
    reyes_brute_comparison stitch = hold(&reference, &scene, &camera, &o, "teapot rim, stitch");
    expect_close(&stitch, "teapot rim, stitch");
    o.subdivision = REYES_SUBDIVISION_TIERED;
    reyes_brute_comparison tiered = hold(&reference, &scene, &camera, &o, "teapot rim, tiered stitch");
    expect_close(&tiered, "teapot rim, tiered stitch");
    o.crack_fix = REYES_CRACK_FIX_WEDGE;
    reyes_brute_comparison wedge = hold(&reference, &scene, &camera, &o, "teapot rim, tiered wedge");
    o.crack_fix = REYES_CRACK_FIX_NONE;
    reyes_brute_comparison none = hold(&reference, &scene, &camera, &o, "teapot rim, tiered none");
    expect_close(&wedge, "teapot rim, tiered wedge");
    expect_no_overhang(&wedge, &none, 2, "teapot rim");
    reyes_brute_free(&reference);
    reyes_scene_free(&scene);
}
END_TEST

/* Shading rate 1 on the teapot at 512x512 (issue 15: 31 micropolygons
 * per covered pixel with fixed 16x16 grids): at most 4, the image as good
 * as the fixed grids' (stitched, so no sample away from an edge sees
 * through: expect_close); without a crack fix some do. */
START_TEST(test_teapot_shading_rate)
{
    reyes_scene scene;
    reyes_camera framed;
    reyes_error error;
    reyes_test_load_model(&scene, REYES_MODELS_DIR, "teapot.bpt");
    ck_assert_int_eq(reyes_camera_frame(&scene, 40.0f, 1.0f, &framed, &error), REYES_OK);
    reyes_options o;
    reyes_options_init(&o);
    o.width = o.height = 512;
    expect_rate_close(&scene, &framed, &o, 1.0f, 4.0, 64, "teapot 512");
    reyes_camera camera = orbit(&framed, 200, 50, 1.0f);
    expect_rate_close(&scene, &camera, &o, 1.0f, 4.0, 64, "teapot 512 from above");
    /* Without a crack fix the T-junctions between grids of different
     * rates let samples through to surfaces behind, away from any edge. */
    o.shading_rate = 1.0f;
    o.crack_fix = REYES_CRACK_FIX_NONE;
    reyes_brute_comparison open = compare(&scene, &framed, &o, "teapot 512, shading rate 1, no crack fix");
    ck_assert_uint_gt(open.interior_other_surface + open.interior_missing, 0);
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
    tcase_add_test(tc, test_teapot_shading_rate);
    suite_add_tcase(s, tc);
    return s;
}

#endif

int main(void)
{
    return reyes_test_run_suite(suite()) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
