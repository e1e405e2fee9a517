/* The (u,v,t) tuples of motion blur and depth of field, made on the host
 * and read by the rasterizer (reyes_blur.cl; docs/reyes-effects.md). */
#ifndef REYES_BLUR_TUPLES_H
#define REYES_BLUR_TUPLES_H

#include <stddef.h>

/* One tuple: time in [0,1), lens position on the unit disk, padding (a
 * float4 on the device). */
typedef struct reyes_blur_tuple {
    float t, lens_x, lens_y, pad;
} reyes_blur_tuple;

/* Tuples the algorithm draws from, N = spp per block: simple N,
 * interleaved tile * tile * N, bbox REYES_BLUR_BBOX_PERIOD^2 * N. */
size_t reyes_blur_pool_size(unsigned algo, unsigned tile, unsigned spp);

/* Fill tuples[0..count): tuple i has its time in stratum (i mod spp) mod
 * strata, jittered, and its lens position from the concentric map of two
 * more jitters; all are hashes of i, so a pool is a prefix of any larger
 * one (interleaved with 1x1 tiles uses exactly simple's tuples). */
void reyes_blur_fill_tuples(reyes_blur_tuple *tuples, size_t count, unsigned spp, unsigned strata);

#endif
