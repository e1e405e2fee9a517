/* The look of every render, shared by the renderer and the C reference:
 * the light and its shading weights, and how samples become pixels. */
#ifndef REYES_LOOK_H
#define REYES_LOOK_H

#include "reyes.h"
#include "reyes_shared.h"

/* The unit vector towards the light (REYES_LIGHT_X, _Y, _Z of
 * reyes_shared.h, with the shading weights REYES_AMBIENT ...
 * REYES_SHININESS). */
void reyes_light_direction(float light[3]);

/* The host's copy of reyes_hash (reyes_sample.cl, lowbias32): sample
 * jitter and blur tuples made on the host must match the device's bits. */
static inline uint32_t reyes_hash32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/* Average the spp samples of each pixel of the rectangle [x0,x1) x [y0,y1)
 * (samples: its pixels row by row, spp each) into image; empty samples
 * show `background`; with image->samples (keep_samples) the samples are
 * copied there too.  Returns the covered samples. */
uint64_t reyes_resolve(const uint64_t *samples, unsigned spp, uint32_t background, unsigned x0, unsigned y0,
                       unsigned x1, unsigned y1, reyes_image *image);

#endif
