/* The bulk of a scene: its control points without the few far away from
 * the rest (reyes.h, reyes_scene_bulk), and the depth of what lies in
 * front of a camera (the near plane).  Both are robust statistics so that
 * one stray control point 1e6 units from a teapot neither shrinks the
 * framed teapot to a dot nor pushes the near plane past it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes.h"

/* Statistics read at most this many control points, evenly spread
 * (deterministic), so a scene of millions of patches costs little. */
#define SAMPLE_MAX 65536
/* A point farther from the sample's median than this many times the
 * distance within which 90% of the sample lies is left out: framing it
 * would leave the rest less than 1/64 of the view. */
#define FAR_FACTOR 64.0f

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static float median_of(float *values, size_t count)
{
    qsort(values, count, sizeof *values, compare_floats);
    return values[count / 2];
}

static float distance3(const float *a, const float *b)
{
    float d[3] = { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
    return sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

int reyes_scene_bulk(const reyes_scene *scene, reyes_bulk *bulk)
{
    memset(bulk, 0, sizeof *bulk);
    size_t points = scene->patch_count * 16;
    if (points == 0)
        return 0;
    size_t stride = (points + SAMPLE_MAX - 1) / SAMPLE_MAX, samples = (points + stride - 1) / stride;
    float *values = malloc(samples * sizeof *values);
    bulk->keep_radius = INFINITY; /* without the statistics: every point */
    if (values) {
        for (int k = 0; k < 3; ++k) {
            for (size_t s = 0; s < samples; ++s)
                values[s] = scene->points[s * stride * 4 + k];
            bulk->center[k] = median_of(values, samples);
        }
        for (size_t s = 0; s < samples; ++s)
            values[s] = distance3(scene->points + s * stride * 4, bulk->center);
        qsort(values, samples, sizeof *values, compare_floats);
        float r90 = values[samples * 9 / 10 < samples ? samples * 9 / 10 : samples - 1];
        if (r90 > 0.0f && isfinite(FAR_FACTOR * r90))
            bulk->keep_radius = FAR_FACTOR * r90;
        free(values);
    }
    for (int k = 0; k < 3; ++k) {
        bulk->lo[k] = INFINITY;
        bulk->hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < points; ++i) {
        const float *p = scene->points + i * 4;
        if (!reyes_bulk_holds(bulk, p)) {
            if (bulk->left_out++ == 0)
                bulk->first_left_out = i;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            bulk->lo[k] = fminf(bulk->lo[k], p[k]);
            bulk->hi[k] = fmaxf(bulk->hi[k], p[k]);
        }
    }
    return 1;
}

int reyes_bulk_holds(const reyes_bulk *bulk, const float point[3])
{
    return !(distance3(point, bulk->center) > bulk->keep_radius);
}

float reyes_near_plane(const reyes_scene *scene, const reyes_camera *camera)
{
    float lo[3], hi[3], radius = 1.0f;
    if (reyes_scene_bounds(scene, lo, hi)) {
        float d[3] = { hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2] };
        radius = fmaxf(0.5f * sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), 1e-3f);
    }
    /* The median depth of the control points in front of the camera, to a
     * power of two (a histogram of exponents: one pass, no sorting). */
    float forward[3] = { camera->at[0] - camera->eye[0], camera->at[1] - camera->eye[1],
                         camera->at[2] - camera->eye[2] };
    float length = sqrtf(forward[0] * forward[0] + forward[1] * forward[1] + forward[2] * forward[2]);
    enum { EXPONENTS = 300, OFFSET = 160 }; /* frexpf exponents of positive floats: -148..128 */
    size_t histogram[EXPONENTS] = { 0 }, in_front = 0;
    for (size_t i = 0; length > 0.0f && i < scene->patch_count * 16; ++i) {
        const float *p = scene->points + i * 4;
        float depth = ((p[0] - camera->eye[0]) * forward[0] + (p[1] - camera->eye[1]) * forward[1]
                       + (p[2] - camera->eye[2]) * forward[2]) / length;
        int exponent;
        if (!(depth > 0.0f) || !isfinite(depth))
            continue;
        frexpf(depth, &exponent);
        histogram[exponent + OFFSET]++;
        in_front++;
    }
    float scale = radius;
    for (size_t e = 0, seen = 0; in_front > 0 && e < EXPONENTS; ++e) {
        seen += histogram[e];
        if (2 * seen > in_front) {
            scale = fminf(radius, ldexpf(0.5f, (int)e - OFFSET)); /* the bin's lower end */
            break;
        }
    }
    /* Nothing closer than this is projected: far below anything a camera
     * shows of the geometry in front of it, however far the rest reaches. */
    return 1e-4f * scale;
}
