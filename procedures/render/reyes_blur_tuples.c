/* The pool of (u,v,t) tuples of a blurred render (reyes_blur_tuples.h).
 * Made once per render on the host: hashing and the concentric map per
 * pass in the rasterizer took about half of its time. */
#include <math.h>

#include "reyes_blur_tuples.h"
#include "reyes_look.h"
#include "reyes_shared.h"

/* A hashed number in [0,1) for (tuple index, dimension). */
static float jitter(uint32_t index, uint32_t dimension)
{
    uint32_t h = reyes_hash32(index * 0x9e3779b9u ^ reyes_hash32(dimension + 0x27d4eb2fu));
    return (float)(h >> 8) * (1.0f / 16777216.0f);
}

/* Shirley and Chiu's concentric map of [-1,1]^2 onto the unit disk:
 * uniform, and neighbouring points stay neighbours. */
static void concentric_disk(float a, float b, float *x, float *y)
{
    const float quarter_pi = 0.785398163f;
    float r = 0.0f, phi = 0.0f;
    if (a == 0.0f && b == 0.0f) {
        *x = *y = 0.0f;
        return;
    }
    if (fabsf(a) > fabsf(b)) {
        r = a;
        phi = quarter_pi * (b / a);
    } else {
        r = b;
        phi = 2.0f * quarter_pi - quarter_pi * (a / b);
    }
    *x = r * cosf(phi);
    *y = r * sinf(phi);
}

size_t reyes_blur_pool_size(unsigned algo, unsigned tile, unsigned spp)
{
    if (algo == REYES_BLUR_SIMPLE)
        return spp;
    if (algo == REYES_BLUR_INTERLEAVED)
        return (size_t)tile * tile * spp;
    return (size_t)REYES_BLUR_BBOX_PERIOD * REYES_BLUR_BBOX_PERIOD * spp;
}

void reyes_blur_fill_tuples(reyes_blur_tuple *tuples, size_t count, unsigned spp, unsigned strata)
{
    for (size_t i = 0; i < count; ++i) {
        uint32_t index = (uint32_t)i;
        unsigned stratum = (unsigned)(i % spp) % strata;
        reyes_blur_tuple *u = &tuples[i];
        u->t = ((float)stratum + jitter(index, 1u)) / (float)strata;
        concentric_disk(2.0f * jitter(index, 2u) - 1.0f, 2.0f * jitter(index, 3u) - 1.0f, &u->lens_x,
                        &u->lens_y);
        u->pad = 0.0f;
    }
}
