/* Gluing base patch boundaries for the crack stitches (reyes_stitch_glue.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_shared.h"
#include "reyes_stitch_glue.h"

static int compare_float(float a, float b)
{
    return a < b ? -1 : a > b ? 1 : 0;
}

/* Control points of a patch boundary in increasing parameter order. */
static void boundary_points(const reyes_scene *scene, uint32_t patch, uint32_t boundary, float out[12])
{
    const float *p = scene->points + (size_t)patch * 64;
    for (int k = 0; k < 4; ++k) {
        int row = boundary == REYES_EDGE_V0 ? 0 : boundary == REYES_EDGE_V1 ? 3 : k;
        int col = boundary == REYES_EDGE_U0 ? 0 : boundary == REYES_EDGE_U1 ? 3 : k;
        memcpy(&out[k * 3], &p[(row * 4 + col) * 4], 3 * sizeof(float));
    }
}

typedef struct boundary_key {
    float points[12];   /* the lexicographically smaller orientation */
    uint32_t patch, boundary, flipped;
} boundary_key;

static int compare_keys(const void *pa, const void *pb)
{
    const boundary_key *a = pa, *b = pb;
    for (int k = 0; k < 12; ++k) {
        int c = compare_float(a->points[k], b->points[k]);
        if (c)
            return c;
    }
    if (a->patch != b->patch)
        return a->patch < b->patch ? -1 : 1;
    return a->boundary < b->boundary ? -1 : a->boundary > b->boundary;
}

static int same_points(const float a[12], const float b[12])
{
    for (int k = 0; k < 12; ++k)
        if (a[k] != b[k])
            return 0;
    return 1;
}

/* Glue the boundaries with identical control points (in either order;
 * exactly two patches per curve). */
static void glue_exactly(boundary_key *keys, size_t used, boundary_link *links)
{
    qsort(keys, used, sizeof *keys, compare_keys);
    for (size_t i = 0; i < used;) {
        size_t j = i + 1;
        while (j < used && same_points(keys[j].points, keys[i].points))
            ++j;
        if (j - i == 2) {
            const boundary_key *a = &keys[i], *b = &keys[i + 1];
            uint32_t reversed = a->flipped != b->flipped;
            links[a->patch * 4 + a->boundary] = (boundary_link){ (int32_t)b->patch, b->boundary, reversed };
            links[b->patch * 4 + b->boundary] = (boundary_link){ (int32_t)a->patch, a->boundary, reversed };
        }
        i = j;
    }
}

/* The largest distance between corresponding control points of two
 * boundary curves, each as 12 floats in the same direction. */
static float curve_distance(const float a[12], const float b[12])
{
    float most = 0.0f;
    for (int k = 0; k < 4; ++k) {
        float dx = a[3 * k] - b[3 * k], dy = a[3 * k + 1] - b[3 * k + 1], dz = a[3 * k + 2] - b[3 * k + 2];
        most = fmaxf(most, sqrtf(dx * dx + dy * dy + dz * dz));
    }
    return most;
}

static float polygon_length(const float a[12])
{
    float length = 0.0f;
    for (int k = 0; k < 3; ++k) {
        float dx = a[3 * k + 3] - a[3 * k], dy = a[3 * k + 4] - a[3 * k + 1], dz = a[3 * k + 5] - a[3 * k + 2];
        length += sqrtf(dx * dx + dy * dy + dz * dz);
    }
    return length;
}

/* Boundaries nearly glued: how far apart their control points may be, as
 * a fraction of the curve's control polygon length. */
#define NEAR_GLUE 0.02f

/* A boundary not glued exactly, for the near gluing: its key, the
 * smallest x of its end points (the same in either direction, so nearly
 * equal curves sort close together), its length and its best match. */
typedef struct loose_end {
    const boundary_key *key;
    float x, length;
    long best;
    float best_distance;
    uint32_t best_reversed;
} loose_end;

static int compare_loose(const void *pa, const void *pb)
{
    const loose_end *a = pa, *b = pb;
    int c = compare_float(a->x, b->x);
    if (c)
        return c;
    return compare_keys(a->key, b->key);
}

/* Glue the boundaries left unglued that are each other's nearest, within
 * NEAR_GLUE of the shorter one's length. */
static reyes_status glue_nearly(const boundary_key *keys, size_t used, boundary_link *links, reyes_error *error)
{
    loose_end *ends = malloc((used ? used : 1) * sizeof *ends);
    if (!ends)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory gluing %zu patch boundaries", used);
    size_t count = 0;
    for (size_t i = 0; i < used; ++i) {
        if (links[keys[i].patch * 4 + keys[i].boundary].patch >= 0)
            continue;
        const float *p = keys[i].points;
        ends[count++] = (loose_end){ &keys[i], fminf(p[0], p[9]), polygon_length(p), -1, INFINITY, 0 };
    }
    qsort(ends, count, sizeof *ends, compare_loose);
    for (size_t i = 0; i < count; ++i) {
        float reach = NEAR_GLUE * ends[i].length;
        for (size_t j = i + 1; j < count && ends[j].x - ends[i].x <= reach; ++j) {
            float tolerance = NEAR_GLUE * fminf(ends[i].length, ends[j].length);
            float forward[12], backward[12];
            memcpy(forward, ends[j].key->points, sizeof forward);
            for (int k = 0; k < 4; ++k)
                memcpy(&backward[k * 3], &forward[(3 - k) * 3], 3 * sizeof(float));
            float same = curve_distance(ends[i].key->points, forward);
            float reverse = curve_distance(ends[i].key->points, backward);
            float distance = fminf(same, reverse);
            if (!(distance <= tolerance) || ends[i].key->patch == ends[j].key->patch)
                continue;
            uint32_t reversed = (reverse < same) != (ends[i].key->flipped != ends[j].key->flipped);
            if (distance < ends[i].best_distance) {
                ends[i].best = (long)j;
                ends[i].best_distance = distance;
                ends[i].best_reversed = reversed;
            }
            if (distance < ends[j].best_distance) {
                ends[j].best = (long)i;
                ends[j].best_distance = distance;
                ends[j].best_reversed = reversed;
            }
        }
    }
    for (size_t i = 0; i < count; ++i) {
        long j = ends[i].best;
        if (j <= (long)i || ends[j].best != (long)i)
            continue; /* each pair once, and only mutual nearest */
        const boundary_key *a = ends[i].key, *b = ends[j].key;
        uint32_t reversed = ends[i].best_reversed;
        links[a->patch * 4 + a->boundary] = (boundary_link){ (int32_t)b->patch, b->boundary, reversed };
        links[b->patch * 4 + b->boundary] = (boundary_link){ (int32_t)a->patch, a->boundary, reversed };
    }
    free(ends);
    return REYES_OK;
}

reyes_status reyes_glue_boundaries(const reyes_scene *scene, int near, boundary_link *links, reyes_error *error)
{
    size_t n = scene->patch_count * 4, used = 0;
    boundary_key *keys = malloc((n ? n : 1) * sizeof *keys);
    if (!keys)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory linking %zu patches",
                          scene->patch_count);
    for (size_t i = 0; i < n; ++i) {
        links[i] = (boundary_link){ .patch = -1 };
        float forward[12], backward[12];
        boundary_points(scene, (uint32_t)(i / 4), (uint32_t)(i % 4), forward);
        for (int k = 0; k < 4; ++k)
            memcpy(&backward[k * 3], &forward[(3 - k) * 3], 3 * sizeof(float));
        if (same_points(forward, backward))
            continue; /* a point (pole) or a symmetric curve: orientation unknown */
        int flipped = 0;
        for (int k = 0; k < 12 && !flipped; ++k) {
            if (forward[k] != backward[k]) {
                flipped = backward[k] < forward[k];
                break;
            }
        }
        boundary_key *key = &keys[used++];
        memcpy(key->points, flipped ? backward : forward, sizeof key->points);
        key->patch = (uint32_t)(i / 4);
        key->boundary = (uint32_t)(i % 4);
        key->flipped = (uint32_t)flipped;
    }
    glue_exactly(keys, used, links);
    reyes_status status = near ? glue_nearly(keys, used, links, error) : REYES_OK;
    free(keys);
    return status;
}
