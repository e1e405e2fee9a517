/* Helpers for the Reyes rendering tests. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_reference.h"
#include "reyes_test_util.h"

uint64_t reyes_test_covered_samples(const reyes_image *image)
{
    uint64_t total = 0;
    for (size_t i = 0; i < (size_t)image->width * image->height; ++i)
        total += image->coverage[i];
    return total;
}

/* Uncovered regions (4- or 8-connected) under max_region pixels that do
 * not touch the border; with a reference image, only regions the
 * reference covers entirely (a region it shows open too is a real gap). */
static size_t enclosed_pixels(const reyes_image *image, size_t max_region, int diagonal,
                              const reyes_image *reference)
{
    size_t w = image->width, h = image->height, holes = 0;
    size_t *stack = malloc(w * h * sizeof *stack);
    size_t *region = malloc(w * h * sizeof *region);
    uint8_t *seen = calloc(w * h, 1);
    ck_assert(stack && region && seen);
    for (size_t start = 0; start < w * h; ++start) {
        if (seen[start] || image->coverage[start])
            continue;
        /* Flood-fill the uncovered region around start. */
        size_t top = 0, size = 0;
        int touches_border = 0;
        stack[top++] = start;
        seen[start] = 1;
        while (top) {
            size_t p = stack[--top], x = p % w, y = p / w;
            region[size++] = p;
            touches_border |= x == 0 || y == 0 || x == w - 1 || y == h - 1;
            int left = x > 0, right = x + 1 < w, up = y > 0, down = y + 1 < h;
            size_t next[8] = {left ? p - 1 : p, right ? p + 1 : p, up ? p - w : p,
                              down ? p + w : p, left && up ? p - w - 1 : p,
                              right && up ? p - w + 1 : p, left && down ? p + w - 1 : p,
                              right && down ? p + w + 1 : p};
            for (int k = 0; k < (diagonal ? 8 : 4); ++k) {
                if (!seen[next[k]] && !image->coverage[next[k]]) {
                    seen[next[k]] = 1;
                    stack[top++] = next[k];
                }
            }
        }
        if (touches_border || size >= max_region)
            continue;
        int covered = 1;
        for (size_t k = 0; reference && k < size; ++k)
            covered &= reference->coverage[region[k]] > 0;
        holes += covered ? size : 0;
    }
    free(stack);
    free(region);
    free(seen);
    return holes;
}

size_t reyes_test_hole_pixels(const reyes_image *image, size_t max_region)
{
    return enclosed_pixels(image, max_region, 0, NULL);
}

size_t reyes_test_enclosed_pixels(const reyes_image *image, size_t max_region)
{
    return enclosed_pixels(image, max_region, 1, NULL);
}

void reyes_test_builtin_scene(reyes_scene *scene, reyes_camera *camera, unsigned width, unsigned height)
{
    reyes_error error;
    reyes_scene_init(scene);
    ck_assert_int_eq(reyes_scene_add_builtin(scene, &error), REYES_OK);
    ck_assert_int_eq(reyes_camera_frame(scene, 40.0f, (float)width / (float)height, camera, &error), REYES_OK);
}

void reyes_test_small_builtin(reyes_scene *scene, reyes_camera *camera, reyes_options *options)
{
    reyes_test_builtin_scene(scene, camera, 160, 120);
    reyes_options_init(options);
    options->width = 160;
    options->height = 120;
}

void reyes_test_load_model(reyes_scene *scene, const char *dir, const char *file)
{
    char path[1024];
    reyes_error error;
    snprintf(path, sizeof path, "%s/%s", dir, file);
    reyes_scene_init(scene);
    reyes_status status = reyes_scene_load_bpt(scene, path, reyes_model_color(0), &error);
    ck_assert_msg(status == REYES_OK, "%s", error.message);
}

void reyes_test_sphere_scene(reyes_scene *scene)
{
    reyes_error error;
    reyes_scene_init(scene);
    const float center[3] = {0, 0, 0};
    ck_assert_int_eq(reyes_scene_add_sphere(scene, center, 1.0f, REYES_RGBA(200, 200, 200), &error), REYES_OK);
}

void reyes_test_add_far_patch(reyes_scene *scene, float distance)
{
    float cp[4][4][3];
    for (int i = 0; i < 16; ++i)
        for (int k = 0; k < 3; ++k)
            cp[i / 4][i % 4][k] = scene->points[i * 4 + k];
    cp[0][0][0] = distance;
    cp[0][0][1] = cp[0][0][2] = 0.0f;
    reyes_error error;
    ck_assert_int_eq(reyes_scene_add_patch(scene, cp, REYES_RGBA(90, 170, 90), &error), REYES_OK);
}

void reyes_test_add_square(reyes_scene *scene, float x0, float y0, float z, float size)
{
    float cp[4][4][3];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            cp[r][c][0] = x0 + size * (float)c / 3.0f;
            cp[r][c][1] = y0 + size * (float)r / 3.0f;
            cp[r][c][2] = z;
        }
    reyes_error error;
    ck_assert_int_eq(reyes_scene_add_patch(scene, cp, REYES_RGBA(200, 200, 200), &error), REYES_OK);
}

void reyes_test_expect_same_image(const reyes_image *expected, const reyes_image *image, const char *label)
{
    ck_assert_msg(image->width == expected->width && image->height == expected->height,
                  "%s: %ux%u image, expected %ux%u", label, image->width, image->height, expected->width,
                  expected->height);
    size_t pixels = (size_t)image->width * image->height, differ = 0;
    for (size_t k = 0; k < pixels; ++k)
        differ += image->coverage[k] != expected->coverage[k] || memcmp(image->rgb + 3 * k, expected->rgb + 3 * k, 3);
    ck_assert_msg(differ == 0, "%s: %zu of %zu pixels differ", label, differ, pixels);
}

void reyes_test_expect_same_counts(const reyes_stats *expected, const reyes_stats *stats, const char *label)
{
    ck_assert_msg(stats->splits == expected->splits && stats->grids == expected->grids
                      && stats->culled == expected->culled && stats->micropolygons == expected->micropolygons
                      && stats->samples_written == expected->samples_written,
                  "%s: counts differ (splits %llu vs %llu, grids %llu vs %llu, micropolygons %llu vs %llu)", label,
                  (unsigned long long)stats->splits, (unsigned long long)expected->splits,
                  (unsigned long long)stats->grids, (unsigned long long)expected->grids,
                  (unsigned long long)stats->micropolygons, (unsigned long long)expected->micropolygons);
    for (int p = 0; p < REYES_PROC_COUNT; ++p)
        ck_assert_msg(stats->procedures[p].items == expected->procedures[p].items,
                      "%s: %s ran %llu items, expected %llu", label, stats->procedures[p].name,
                      (unsigned long long)stats->procedures[p].items,
                      (unsigned long long)expected->procedures[p].items);
}

void reyes_test_expect_bucket_peaks(const reyes_stats *stats)
{
    size_t count = (size_t)stats->bucket_columns * stats->bucket_rows, largest = 0;
    ck_assert_ptr_nonnull(stats->bucket_peak_queue_bytes);
    for (size_t b = 0; b < count; ++b)
        largest = stats->bucket_peak_queue_bytes[b] > largest ? stats->bucket_peak_queue_bytes[b] : largest;
    ck_assert_uint_eq(largest, stats->peak_queue_bytes);
}

void reyes_test_render(reyes_renderer *renderer, const reyes_scene *scene,
                       const reyes_camera *camera, const reyes_options *options,
                       reyes_image *image, reyes_stats *stats)
{
    reyes_error error;
    reyes_status status = reyes_render(renderer, scene, camera, options, image, stats, &error);
    ck_assert_msg(status == REYES_OK, "render failed: %s", error.message);
}

/* [rotating][work_groups] */
static reyes_renderer *renderers[2][3];

static void destroy_renderers(void)
{
    for (int k = 0; k < 6; ++k)
        reyes_renderer_destroy(renderers[k / 3][k % 3]);
}

static reyes_renderer *cached_renderer(unsigned work_groups, int rotating)
{
    ck_assert_uint_le(work_groups, 2);
    reyes_renderer **r = &renderers[rotating][work_groups];
    if (!*r) {
        static int registered;
        if (!registered++)
            atexit(destroy_renderers);
        reyes_options options;
        reyes_error error;
        reyes_options_init(&options);
        options.work_groups = work_groups;
        options.motion_angle_deg = rotating ? 90.0f : 0.0f;
        reyes_status status = reyes_renderer_create(&options, r, &error);
        ck_assert_msg(status == REYES_OK, "renderer: %s", error.message);
    }
    return *r;
}

reyes_renderer *reyes_test_renderer(unsigned work_groups)
{
    return cached_renderer(work_groups, 0);
}

reyes_renderer *reyes_test_moving_renderer(unsigned work_groups)
{
    return cached_renderer(work_groups, 1);
}

reyes_renderer *reyes_test_renderer_for(const reyes_options *options, unsigned work_groups)
{
    return cached_renderer(work_groups, options->motion_angle_deg != 0.0f);
}

void reyes_test_expect_reference_counts(const reyes_scene *scene, const reyes_camera *camera,
                                        const reyes_options *options, const reyes_stats *stats)
{
    reyes_reference_counts counts;
    reyes_error error;
    reyes_status status = reyes_reference_run(scene, camera, options, &counts, &error);
    ck_assert_msg(status == REYES_OK, "reference: %s", error.message);
    ck_assert_uint_eq(stats->splits, counts.splits);
    ck_assert_uint_eq(stats->culled, counts.culled);
    ck_assert_uint_eq(stats->grids, counts.grids);
    ck_assert_uint_eq(stats->forced_dice, counts.forced_dice);
    ck_assert_uint_eq(stats->micropolygons, counts.micropolygons);
}

void reyes_test_expect_reference_image(const reyes_scene *scene, const reyes_camera *camera,
                                       const reyes_options *options, const reyes_image *image, const char *label)
{
    reyes_image reference;
    reyes_reference_counts counts;
    reyes_error error;
    reyes_status status = reyes_reference_render(scene, camera, options, &reference, &counts, &error);
    ck_assert_msg(status == REYES_OK, "%s: reference: %s", label, error.message);
    ck_assert_msg(image->width == reference.width && image->height == reference.height,
                  "%s: %ux%u image, the reference is %ux%u", label, image->width, image->height, reference.width,
                  reference.height);
    size_t pixels = (size_t)image->width * image->height, differ = 0, far = 0, coverage = 0;
    int largest = 0;
    for (size_t k = 0; k < pixels; ++k) {
        int most = 0;
        for (int c = 0; c < 3; ++c) {
            int d = abs((int)image->rgb[3 * k + c] - (int)reference.rgb[3 * k + c]);
            most = d > most ? d : most;
        }
        int covered = abs((int)image->coverage[k] - (int)reference.coverage[k]);
        differ += most > 0 || covered > 0;
        far += most > 4;
        coverage += covered > 0;
        ck_assert_msg(covered <= 1, "%s: pixel (%zu, %zu) covers %u samples, the reference %u", label,
                      k % image->width, k / image->width, image->coverage[k], reference.coverage[k]);
        largest = most > largest ? most : largest;
    }
    reyes_image_free(&reference);
    fprintf(stderr, "%s: %zu of %zu pixels differ from the C reference's (%zu by more than 4, largest %d; "
                    "%zu in coverage)\n",
            label, differ, pixels, far, largest, coverage);
    ck_assert_msg(differ * 100 <= pixels, "%s: %zu of %zu pixels differ from the C reference's", label, differ,
                  pixels);
    ck_assert_msg(far * 1000 <= pixels, "%s: %zu of %zu pixels differ from the C reference's by more than 4", label,
                  far, pixels);
    ck_assert_msg(coverage * 1000 <= pixels, "%s: %zu of %zu pixels differ from the C reference's in coverage",
                  label, coverage, pixels);
}

/* xorshift32: a fixed sequence of camera positions. */
static float next_unit(uint32_t *state)
{
    uint32_t x = *state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *state = x;
    return (float)(x >> 8) * (1.0f / 16777216.0f);
}

size_t reyes_test_holes_from_random_views(reyes_renderer *renderer, const reyes_scene *scene,
                                          const reyes_options *options,
                                          const reyes_options *reference, unsigned views,
                                          unsigned seed, size_t max_region)
{
    float lo[3], hi[3], center[3], radius = 0.0f;
    ck_assert(reyes_scene_bounds(scene, lo, hi));
    for (int k = 0; k < 3; ++k) {
        center[k] = 0.5f * (lo[k] + hi[k]);
        radius += 0.25f * (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    radius = sqrtf(radius);
    uint32_t state = seed ? seed : 1u;
    size_t holes = 0;
    for (unsigned v = 0; v < views; ++v) {
        /* A uniform direction, a distance, and a target near the center. */
        float z = 2.0f * next_unit(&state) - 1.0f, phi = 6.2831853f * next_unit(&state);
        float r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
        float distance = radius * (2.5f + 3.5f * next_unit(&state));
        reyes_camera camera = { .fov_deg = 40.0f };
        const float direction[3] = { r * cosf(phi), r * sinf(phi), z };
        for (int k = 0; k < 3; ++k) {
            camera.eye[k] = center[k] + distance * direction[k];
            camera.at[k] = center[k] + 0.2f * radius * (next_unit(&state) - 0.5f);
        }
        reyes_image image, truth = {0};
        reyes_test_render(renderer, scene, &camera, options, &image, NULL);
        if (reference)
            reyes_test_render(renderer, scene, &camera, reference, &truth, NULL);
        holes += enclosed_pixels(&image, max_region, 1, reference ? &truth : NULL);
        reyes_image_free(&image);
        reyes_image_free(&truth);
    }
    return holes;
}

int reyes_test_run_suite(Suite *suite)
{
    SRunner *runner = srunner_create(suite);
    srunner_set_fork_status(runner, CK_NOFORK);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed;
}
