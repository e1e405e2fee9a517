/*
 * The C reference's tests of a projected control hull against the sample
 * positions and the samples: bound's sampleless test (a grid that covers
 * no sample is not diced) and occlusion culling (a grid whose every sample
 * already holds a nearer surface is not diced), as reyes_bound.cl and
 * reyes_occlusion.cl make them, with the constants of reyes_shared.h; and
 * the front-to-back order that lets the near grids hide the far ones.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "reyes_reference_internal.h"

reference_octagon reference_hull_octagon(const float sx[16], const float sy[16], float lo_x, float lo_y, float hi_x,
                                         float hi_y)
{
    const float margin = REYES_SAMPLE_BOX_MARGIN;
    reference_octagon o = { lo_x - margin, lo_y - margin, hi_x + margin, hi_y + margin,
                            INFINITY,      -INFINITY,     INFINITY,      -INFINITY };
    for (int k = 0; k < 16; ++k) {
        o.sum_lo = min_f(o.sum_lo, sx[k] + sy[k]);
        o.sum_hi = max_f(o.sum_hi, sx[k] + sy[k]);
        o.difference_lo = min_f(o.difference_lo, sx[k] - sy[k]);
        o.difference_hi = max_f(o.difference_hi, sx[k] - sy[k]);
    }
    o.sum_lo -= 2.0f * margin;
    o.sum_hi += 2.0f * margin;
    o.difference_lo -= 2.0f * margin;
    o.difference_hi += 2.0f * margin;
    return o;
}

/* The pixels of a width x height image that the octagon's box reaches:
 * first and last column and row in range[4], and how many (0 when the box
 * is off the image or NaN). */
static float octagon_pixels(const reference_octagon *o, unsigned width, unsigned height, int range[4])
{
    if (!(o->hi_x >= 0.0f && o->hi_y >= 0.0f && o->lo_x < (float)width && o->lo_y < (float)height))
        return 0.0f;
    float first_x = max_f(floorf(o->lo_x), 0.0f), first_y = max_f(floorf(o->lo_y), 0.0f);
    float last_x = min_f(floorf(o->hi_x), (float)width - 1.0f), last_y = min_f(floorf(o->hi_y), (float)height - 1.0f);
    range[0] = (int)first_x;
    range[1] = (int)first_y;
    range[2] = (int)last_x;
    range[3] = (int)last_y;
    return (last_x - first_x + 1.0f) * (last_y - first_y + 1.0f);
}

/* Whether sample k of pixel (px, py) of an image at spp samples per
 * pixel in a columns x rows lattice lies in the octagon. */
static int octagon_contains_sample(const reference_octagon *o, int px, int py, int k, int columns, int rows)
{
    float x, y;
    int pixel_x, pixel_y, index;
    reference_stratum_sample(px * columns + k % columns, py * rows + k / columns, columns, rows, &x, &y, &pixel_x,
                             &pixel_y, &index);
    return x >= o->lo_x && x <= o->hi_x && y >= o->lo_y && y <= o->hi_y && x + y >= o->sum_lo && x + y <= o->sum_hi
           && x - y >= o->difference_lo && x - y <= o->difference_hi;
}

/* Whether a sample position of the pixels in range[4] lies in the
 * octagon and, when s is not NULL, holds a depth of limit_bits or more
 * (farther than the limit, or empty).  With samples the depth is read
 * first: a sample nearer than the limit does not matter wherever it
 * lies, so a hidden grid's test makes no sample position at all. */
static int octagon_finds(const reference_octagon *o, const int range[4], unsigned spp,
                         const reference_samples *s, uint32_t limit_bits)
{
    int columns = 1;
    while ((unsigned)(columns * columns) < spp)
        ++columns;
    int rows = ((int)spp + columns - 1) / columns;
    for (int py = range[1]; py <= range[3]; ++py)
        for (int px = range[0]; px <= range[2]; ++px)
            for (int k = 0; k < (int)spp; ++k) {
                if (s) {
                    const uint64_t *slot = s->values + ((size_t)py * s->width + (size_t)px) * spp + (size_t)k;
                    /* Other threads lower the samples as this reads them
                     * (store_nearer's atomic minimum).  A value only ever
                     * decreases, so a stale read is a depth too far, never
                     * too near: it can only keep a grid that could have
                     * been skipped, never skip one that shows. */
                    uint64_t value = s->concurrent ? __atomic_load_n(slot, __ATOMIC_RELAXED) : *slot;
                    if ((uint32_t)(value >> 32) < limit_bits)
                        continue;
                }
                if (octagon_contains_sample(o, px, py, k, columns, rows))
                    return 1;
            }
    return 0;
}

int reference_hull_has_sample(unsigned width, unsigned height, unsigned spp, const reference_octagon *o)
{
    int range[4];
    float pixels = octagon_pixels(o, width, height, range);
    if (!(pixels > 0.0f) || pixels > (float)REYES_SAMPLE_BOX_PIXELS)
        return 1; /* off the image (the frustum test's business) or too big to search */
    return octagon_finds(o, range, spp, NULL, 0);
}

void reference_occlusion_setup(const reference_context *c, reference_leaf *leaf, float largest)
{
    int range[4];
    float pixels = octagon_pixels(&leaf->octagon, c->o->width, c->o->height, range);
    leaf->limit = 0.0f;
    if (!(pixels > 0.0f) || pixels > (float)REYES_OCCLUSION_PIXELS)
        return;
    /* The margin of reyes_grid_occluded: a part of the nearest w, and float
     * steps of the w of points of the size of the scene's coordinates. */
    const float *m = c->m;
    float row_w = fabsf(m[12]) + fabsf(m[13]) + fabsf(m[14]);
    float slack = leaf->near_w * REYES_OCCLUSION_RELATIVE
                  + REYES_OCCLUSION_ULPS * FLT_EPSILON * (largest * row_w + fabsf(m[15]));
    float limit = leaf->near_w - slack;
    leaf->limit = limit > 0.0f ? limit : 0.0f;
}

int reference_leaf_occluded(const reference_context *c, const reference_leaf *leaf)
{
    if (!(leaf->limit > 0.0f))
        return 0;
    int range[4];
    octagon_pixels(&leaf->octagon, c->o->width, c->o->height, range);
    union { float f; uint32_t u; } limit = { leaf->limit }; /* depths >= 0 order like their bits */
    return !octagon_finds(&leaf->octagon, range, c->o->spp, c->samples, limit.u);
}

void reference_dice_leaf(reference_context *c, const reference_leaf *leaf)
{
    if (c->occlusion && reference_leaf_occluded(c, leaf))
        ++c->counts->occluded;
    else
        reference_dice(c, &leaf->sp);
}

int reference_leaf_before(const reference_leaf *a, const reference_leaf *b)
{
    if (a->near_w != b->near_w)
        return a->near_w < b->near_w;
    if (a->sp.patch != b->sp.patch)
        return a->sp.patch < b->sp.patch;
    return a->order < b->order;
}

static int compare_leaves(const void *pa, const void *pb)
{
    const reference_leaf *a = pa, *b = pb;
    return reference_leaf_before(a, b) ? -1 : reference_leaf_before(b, a) ? 1 : 0;
}

void reference_leaves_sort(reference_leaf *items, size_t count)
{
    if (count > 1)
        qsort(items, count, sizeof *items, compare_leaves);
}
