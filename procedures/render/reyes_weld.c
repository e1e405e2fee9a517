/* Welding base patch seams (reyes_weld.h). */
#include <stdlib.h>
#include <string.h>

#include "reyes_shared.h"
#include "reyes_stitch_glue.h"
#include "reyes_weld.h"

/* The control point index of corner c (0..3: cp[0], cp[3], cp[12], cp[15]). */
static const int corner_point[4] = { 0, 3, 12, 15 };

/* The corners (0..3) at the start and end of a boundary, in increasing
 * parameter, and its inner control points. */
static void boundary_corners(uint32_t boundary, int *start, int *end, int inner[2])
{
    switch (boundary) {
    case REYES_EDGE_V0: *start = 0, *end = 1, inner[0] = 1, inner[1] = 2; break;
    case REYES_EDGE_V1: *start = 2, *end = 3, inner[0] = 13, inner[1] = 14; break;
    case REYES_EDGE_U0: *start = 0, *end = 2, inner[0] = 4, inner[1] = 8; break;
    default: *start = 1, *end = 3, inner[0] = 7, inner[1] = 11; break;
    }
}

static size_t find(size_t *parent, size_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static void join(size_t *parent, size_t a, size_t b)
{
    a = find(parent, a);
    b = find(parent, b);
    if (a != b)
        parent[a < b ? b : a] = a < b ? a : b;
}

typedef struct corner_key {
    float x, y, z;
    size_t index;
} corner_key;

static int compare_corner_keys(const void *pa, const void *pb)
{
    const corner_key *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    if (a->z != b->z)
        return a->z < b->z ? -1 : 1;
    return a->index < b->index ? -1 : a->index > b->index;
}

static void set_point(float *points, size_t patch, int k, const double value[3], size_t *moved)
{
    float *p = points + patch * 64 + (size_t)k * 4;
    int changed = 0;
    for (int c = 0; c < 3; ++c) {
        float v = (float)value[c];
        changed |= p[c] != v;
        p[c] = v;
    }
    *moved += (size_t)changed;
}

reyes_status reyes_weld_points(const reyes_scene *scene, float **out, size_t *moved, reyes_error *error)
{
    size_t n = scene->patch_count, corners = 4 * n;
    *out = NULL;
    *moved = 0;
    float *points = malloc((n ? n : 1) * 64 * sizeof *points);
    boundary_link *links = malloc((n ? n : 1) * 4 * sizeof *links);
    size_t *parent = malloc((corners ? corners : 1) * sizeof *parent);
    corner_key *keys = malloc((corners ? corners : 1) * sizeof *keys);
    double (*sum)[4] = calloc(corners ? corners : 1, sizeof *sum);
    if (!points || !links || !parent || !keys || !sum) {
        free(points), free(links), free(parent), free(keys), free(sum);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory welding %zu patches", n);
    }
    memcpy(points, scene->points, n * 64 * sizeof *points);
    reyes_status status = reyes_glue_boundaries(scene, 1, links, error);
    if (status != REYES_OK) {
        free(points), free(links), free(parent), free(keys), free(sum);
        return status;
    }
    for (size_t i = 0; i < corners; ++i) {
        parent[i] = i;
        const float *p = scene->points + (i / 4) * 64 + (size_t)corner_point[i % 4] * 4;
        keys[i] = (corner_key){ p[0], p[1], p[2], i };
    }
    /* Corners at the same point, then the ends of every glued seam. */
    qsort(keys, corners, sizeof *keys, compare_corner_keys);
    for (size_t i = 1; i < corners; ++i)
        if (keys[i].x == keys[i - 1].x && keys[i].y == keys[i - 1].y && keys[i].z == keys[i - 1].z)
            join(parent, keys[i].index, keys[i - 1].index);
    for (size_t b = 0; b < 4 * n; ++b) {
        const boundary_link *l = &links[b];
        if (l->patch < 0)
            continue;
        int start, end, inner[2], other_start, other_end, other_inner[2];
        boundary_corners((uint32_t)(b % 4), &start, &end, inner);
        boundary_corners(l->boundary, &other_start, &other_end, other_inner);
        size_t a = b / 4, o = (size_t)l->patch;
        join(parent, a * 4 + (size_t)start, o * 4 + (size_t)(l->reversed ? other_end : other_start));
        join(parent, a * 4 + (size_t)end, o * 4 + (size_t)(l->reversed ? other_start : other_end));
    }
    for (size_t i = 0; i < corners; ++i) {
        size_t root = find(parent, i);
        const float *p = scene->points + (i / 4) * 64 + (size_t)corner_point[i % 4] * 4;
        for (int c = 0; c < 3; ++c)
            sum[root][c] += p[c];
        sum[root][3] += 1.0;
    }
    for (size_t i = 0; i < corners; ++i) {
        size_t root = find(parent, i);
        double mean[3];
        for (int c = 0; c < 3; ++c)
            mean[c] = sum[root][c] / sum[root][3];
        set_point(points, i / 4, corner_point[i % 4], mean, moved);
    }
    /* Each glued pair's inner points, once (from the lower boundary). */
    for (size_t b = 0; b < 4 * n; ++b) {
        const boundary_link *l = &links[b];
        size_t other = (size_t)l->patch * 4 + l->boundary;
        if (l->patch < 0 || other < b)
            continue;
        int start, end, inner[2], other_start, other_end, other_inner[2];
        boundary_corners((uint32_t)(b % 4), &start, &end, inner);
        boundary_corners(l->boundary, &other_start, &other_end, other_inner);
        for (int k = 0; k < 2; ++k) {
            int ko = other_inner[l->reversed ? 1 - k : k];
            const float *p = scene->points + (b / 4) * 64 + (size_t)inner[k] * 4;
            const float *q = scene->points + (size_t)l->patch * 64 + (size_t)ko * 4;
            double mean[3];
            for (int c = 0; c < 3; ++c)
                mean[c] = 0.5 * ((double)p[c] + (double)q[c]);
            set_point(points, b / 4, inner[k], mean, moved);
            set_point(points, (size_t)l->patch, ko, mean, moved);
        }
    }
    /* The boundaries glued to none, a bit each in the w of the first
     * control point (reyes_polyline.cl dices them finer). */
    for (size_t patch = 0; patch < n; ++patch) {
        unsigned open = 0;
        for (unsigned b = 0; b < 4; ++b)
            open |= (links[patch * 4 + b].patch < 0 ? 1u : 0u) << b;
        points[patch * 64 + 3] = (float)open;
    }
    free(links), free(parent), free(keys), free(sum);
    *out = points;
    return REYES_OK;
}

uint64_t reyes_points_hash(const reyes_scene *scene)
{
    /* Four independent chains (a patch is 32 words), then mixed. */
    uint64_t h[4] = { 0x9e3779b97f4a7c15u ^ (uint64_t)scene->patch_count, 1, 2, 3 };
    size_t words = scene->patch_count * 64 * sizeof(float) / sizeof(uint64_t);
    const unsigned char *bytes = (const unsigned char *)scene->points;
    for (size_t i = 0; i < words; i += 4)
        for (int k = 0; k < 4; ++k) {
            uint64_t w;
            memcpy(&w, bytes + (i + (size_t)k) * sizeof w, sizeof w);
            h[k] = (h[k] ^ w) * 0x100000001b3u;
            h[k] ^= h[k] >> 29;
        }
    return ((h[0] * 31u + h[1]) * 31u + h[2]) * 31u + h[3];
}
