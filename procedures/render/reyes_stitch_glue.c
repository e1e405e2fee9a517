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
 * smallest x of its end points (the order below: nearly equal curves
 * sort close together), its length, the centroid of its control points
 * (the same in either direction, and within the curves' distance of a
 * nearly equal curve's), the level of the index it is in, and its best
 * match so far. */
typedef struct loose_end {
    const boundary_key *key;
    float x, length;
    double centroid[3];
    int level;
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

/* The near gluing finds, for every loose boundary, the one nearest to it
 * within the tolerance (ties: the first in the order above), and glues
 * the pairs that are each other's nearest.  Comparing every pair took
 * minutes for tens of thousands of touching patches; an index of the
 * centroids finds the candidates.  A boundary's level is the cell size
 * of the index it is in, a power of two 2^level at least 1.5 times its
 * reach (NEAR_GLUE times its length): two boundaries within the tolerance
 * of the shorter one have centroids in neighbouring cells at the level of
 * either.  Their lengths differ by at most 6 times their distance (each
 * of the 3 legs of the control polygon by twice it), so by a factor below
 * 1/0.88, and their levels by at most one. */
typedef struct index_cell {
    int level;
    int64_t cell[3];
    long end;           /* the loose end it holds */
} index_cell;

static int compare_cells(const void *pa, const void *pb)
{
    const index_cell *a = pa, *b = pb;
    if (a->level != b->level)
        return a->level < b->level ? -1 : 1;
    for (int k = 0; k < 3; ++k)
        if (a->cell[k] != b->cell[k])
            return a->cell[k] < b->cell[k] ? -1 : 1;
    return a->end < b->end ? -1 : a->end > b->end;
}

static void cell_of(const double centroid[3], int level, int64_t cell[3])
{
    for (int k = 0; k < 3; ++k) {
        double c = floor(ldexp(centroid[k], -level));
        cell[k] = c < -4e18 ? (int64_t)-4e18 : c > 4e18 ? (int64_t)4e18 : (int64_t)c;
    }
}

/* The first entry of the sorted index at or after (level, cell). */
static size_t lower_bound(const index_cell *index, size_t count, int level, const int64_t cell[3])
{
    const index_cell key = { level, { cell[0], cell[1], cell[2] }, -1 };
    size_t lo = 0, hi = count;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (compare_cells(&index[mid], &key) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Consider end `j` as the match of end `i`: within the tolerance, of
 * another patch, and nearer than (or as near and before) the best so far. */
static void consider(loose_end *ends, size_t i, size_t j)
{
    loose_end *a = &ends[i];
    const loose_end *b = &ends[j];
    if (i == j || a->key->patch == b->key->patch)
        return;
    float tolerance = NEAR_GLUE * fminf(a->length, b->length);
    float forward[12], backward[12];
    memcpy(forward, b->key->points, sizeof forward);
    for (int k = 0; k < 4; ++k)
        memcpy(&backward[k * 3], &forward[(3 - k) * 3], 3 * sizeof(float));
    float same = curve_distance(a->key->points, forward);
    float reverse = curve_distance(a->key->points, backward);
    float distance = fminf(same, reverse);
    if (!(distance <= tolerance))
        return;
    if (distance < a->best_distance || (distance == a->best_distance && (long)j < a->best)) {
        a->best = (long)j;
        a->best_distance = distance;
        a->best_reversed = (reverse < same) != (a->key->flipped != b->key->flipped);
    }
}

/* Runs of identical boundaries (three or more patches on one curve): the
 * nearest of each is another of its run, at distance 0, so their matches
 * are known without a search.  The first of a run (`first`) and the first
 * of another patch than its (`other`) are the only ones another boundary
 * can match (ties go to the earlier), so only they go in the index.
 * in_index[i] says whether end i does; ends matched here have best set. */
static void match_identical_runs(loose_end *ends, size_t count, unsigned char *in_index)
{
    for (size_t i = 0; i < count;) {
        size_t j = i + 1;
        while (j < count && same_points(ends[j].key->points, ends[i].key->points))
            ++j;
        size_t first = i, other = j;
        for (size_t k = i + 1; k < j && other == j; ++k)
            if (ends[k].key->patch != ends[first].key->patch)
                other = k;
        in_index[first] = 1;
        if (other < j)
            in_index[other] = 1;
        for (size_t k = i; k < j && other < j; ++k) {
            size_t match = ends[k].key->patch != ends[first].key->patch ? first : other;
            ends[k].best = (long)match;
            ends[k].best_distance = 0.0f;
            ends[k].best_reversed = ends[k].key->flipped != ends[match].key->flipped;
        }
        i = j;
    }
}

/* The centroid and index level of each end. */
static void place_ends(loose_end *ends, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        const float *p = ends[i].key->points;
        for (int k = 0; k < 3; ++k)
            ends[i].centroid[k] = ((double)p[k] + p[3 + k] + p[6 + k] + p[9 + k]) * 0.25;
        int level;
        frexp(1.5 * (double)NEAR_GLUE * ends[i].length, &level);
        ends[i].level = level;
    }
}

/* Glue the boundaries left unglued that are each other's nearest, within
 * NEAR_GLUE of the shorter one's length. */
static reyes_status glue_nearly(const boundary_key *keys, size_t used, boundary_link *links, reyes_error *error)
{
    loose_end *ends = malloc((used ? used : 1) * sizeof *ends);
    index_cell *index = malloc((used ? used : 1) * sizeof *index);
    unsigned char *in_index = calloc(used ? used : 1, 1);
    if (!ends || !index || !in_index) {
        free(ends), free(index), free(in_index);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory gluing %zu patch boundaries", used);
    }
    size_t count = 0;
    for (size_t i = 0; i < used; ++i) {
        if (links[keys[i].patch * 4 + keys[i].boundary].patch >= 0)
            continue;
        const float *p = keys[i].points;
        ends[count++] = (loose_end){ .key = &keys[i], .x = fminf(p[0], p[9]), .length = polygon_length(p),
                                     .best = -1, .best_distance = INFINITY };
    }
    qsort(ends, count, sizeof *ends, compare_loose);
    place_ends(ends, count);
    match_identical_runs(ends, count, in_index);
    size_t cells = 0;
    for (size_t i = 0; i < count; ++i) {
        if (!in_index[i])
            continue;
        index[cells] = (index_cell){ .level = ends[i].level, .end = (long)i };
        cell_of(ends[i].centroid, ends[i].level, index[cells++].cell);
    }
    qsort(index, cells, sizeof *index, compare_cells);
    /* Each end not matched in its run looks in the 27 cells around its
     * centroid at its level and the two beside it. */
    for (size_t i = 0; i < count; ++i) {
        if (ends[i].best >= 0 && ends[i].best_distance == 0.0f)
            continue;
        for (int level = ends[i].level - 1; level <= ends[i].level + 1; ++level) {
            int64_t at[3], cell[3];
            cell_of(ends[i].centroid, level, at);
            for (int d = 0; d < 27; ++d) {
                cell[0] = at[0] + d % 3 - 1;
                cell[1] = at[1] + d / 3 % 3 - 1;
                cell[2] = at[2] + d / 9 - 1;
                for (size_t c = lower_bound(index, cells, level, cell); c < cells && index[c].level == level
                     && index[c].cell[0] == cell[0] && index[c].cell[1] == cell[1] && index[c].cell[2] == cell[2]; ++c)
                    consider(ends, i, (size_t)index[c].end);
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
    free(ends), free(index), free(in_index);
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
