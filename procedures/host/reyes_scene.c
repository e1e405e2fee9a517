/* Scene storage: a growable array of patches with a color each. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes.h"

#define FLOATS_PER_PATCH 64 /* 16 points x (x y z w) */

void reyes_scene_init(reyes_scene *scene)
{
    memset(scene, 0, sizeof *scene);
}

void reyes_scene_free(reyes_scene *scene)
{
    if (!scene)
        return;
    free(scene->points);
    free(scene->colors);
    reyes_scene_init(scene);
}

static reyes_status grow(reyes_scene *scene, reyes_error *error)
{
    if (scene->patch_count >= REYES_MAX_PATCHES)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "scene has more than %u patches",
                          REYES_MAX_PATCHES);
    size_t capacity = scene->capacity ? scene->capacity * 2 : 64;
    float *points = realloc(scene->points, capacity * FLOATS_PER_PATCH * sizeof *points);
    if (!points)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu patches", capacity);
    scene->points = points;
    uint32_t *colors = realloc(scene->colors, capacity * sizeof *colors);
    if (!colors)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu patches", capacity);
    scene->colors = colors;
    scene->capacity = capacity;
    return REYES_OK;
}

reyes_status reyes_scene_add_patch(reyes_scene *scene, const float cp[4][4][3], uint32_t rgba,
                                   reyes_error *error)
{
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 3; ++k)
                if (!isfinite(cp[r][c][k]))
                    return reyes_fail(error, REYES_ERR_ARGUMENT, "control point is not finite");
    if (scene->patch_count == scene->capacity) {
        reyes_status status = grow(scene, error);
        if (status != REYES_OK)
            return status;
    }
    float *out = scene->points + scene->patch_count * FLOATS_PER_PATCH;
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            float *p = out + (r * 4 + c) * 4;
            p[0] = cp[r][c][0];
            p[1] = cp[r][c][1];
            p[2] = cp[r][c][2];
            p[3] = 1.0f;
        }
    }
    scene->colors[scene->patch_count++] = rgba;
    return REYES_OK;
}

int reyes_scene_bounds(const reyes_scene *scene, float lo[3], float hi[3])
{
    if (scene->patch_count == 0)
        return 0;
    for (int k = 0; k < 3; ++k) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < scene->patch_count * 16; ++i) {
        const float *p = scene->points + i * 4;
        for (int k = 0; k < 3; ++k) {
            lo[k] = fminf(lo[k], p[k]);
            hi[k] = fmaxf(hi[k], p[k]);
        }
    }
    return 1;
}

uint32_t reyes_model_color(unsigned n)
{
    static const uint32_t palette[] = {
        REYES_RGBA(222, 184, 135), /* tan */
        REYES_RGBA(70, 130, 200),  /* blue */
        REYES_RGBA(200, 70, 60),   /* red */
        REYES_RGBA(90, 170, 90),   /* green */
        REYES_RGBA(220, 190, 60),  /* gold */
        REYES_RGBA(160, 100, 190), /* violet */
    };
    return palette[n % (sizeof palette / sizeof palette[0])];
}
