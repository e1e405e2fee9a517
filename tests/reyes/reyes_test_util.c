/* Helpers for the Reyes rendering tests. */
#include <check.h>
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

size_t reyes_test_hole_pixels(const reyes_image *image, size_t max_region)
{
    size_t w = image->width, h = image->height, holes = 0;
    size_t *stack = malloc(w * h * sizeof *stack);
    uint8_t *seen = calloc(w * h, 1);
    ck_assert(stack && seen);
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
            ++size;
            touches_border |= x == 0 || y == 0 || x == w - 1 || y == h - 1;
            size_t next[4] = {x > 0 ? p - 1 : p, x + 1 < w ? p + 1 : p, y > 0 ? p - w : p,
                              y + 1 < h ? p + w : p};
            for (int k = 0; k < 4; ++k) {
                if (!seen[next[k]] && !image->coverage[next[k]]) {
                    seen[next[k]] = 1;
                    stack[top++] = next[k];
                }
            }
        }
        if (!touches_border && size < max_region)
            holes += size;
    }
    free(stack);
    free(seen);
    return holes;
}

void reyes_test_render(reyes_renderer *renderer, const reyes_scene *scene,
                       const reyes_camera *camera, const reyes_options *options,
                       reyes_image *image, reyes_stats *stats)
{
    reyes_error error;
    reyes_status status = reyes_render(renderer, scene, camera, options, image, stats, &error);
    ck_assert_msg(status == REYES_OK, "render failed: %s", error.message);
}

static reyes_renderer *renderers[3];

static void destroy_renderers(void)
{
    for (int k = 0; k < 3; ++k)
        reyes_renderer_destroy(renderers[k]);
}

reyes_renderer *reyes_test_renderer(unsigned work_groups)
{
    ck_assert_uint_le(work_groups, 2);
    if (!renderers[work_groups]) {
        static int registered;
        if (!registered++)
            atexit(destroy_renderers);
        reyes_options options;
        reyes_error error;
        reyes_options_init(&options);
        options.work_groups = work_groups;
        reyes_status status = reyes_renderer_create(&options, &renderers[work_groups], &error);
        ck_assert_msg(status == REYES_OK, "renderer: %s", error.message);
    }
    return renderers[work_groups];
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
