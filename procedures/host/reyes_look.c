/* The look of every render: the light, and the box filter from samples
 * to pixels. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_look.h"

void reyes_light_direction(float light[3])
{
    const float towards[3] = {REYES_LIGHT_X, REYES_LIGHT_Y, REYES_LIGHT_Z};
    float length = sqrtf(towards[0] * towards[0] + towards[1] * towards[1] + towards[2] * towards[2]);
    for (int k = 0; k < 3; ++k)
        light[k] = towards[k] / length;
}

uint64_t reyes_resolve(const uint64_t *samples, unsigned spp, uint32_t background, unsigned x0, unsigned y0,
                       unsigned x1, unsigned y1, reyes_image *image)
{
    uint64_t written = 0;
    size_t tile_width = x1 - x0;
    for (unsigned y = y0; y < y1; ++y) {
        for (unsigned x = x0; x < x1; ++x) {
            const uint64_t *pixel = samples + ((size_t)(y - y0) * tile_width + (x - x0)) * spp;
            size_t px = (size_t)y * image->width + x;
            unsigned sum[3] = {0, 0, 0}, hits = 0;
            for (unsigned s = 0; s < spp; ++s) {
                uint32_t rgba = background;
                if (pixel[s] != REYES_EMPTY_SAMPLE) {
                    rgba = (uint32_t)pixel[s];
                    ++hits;
                }
                for (int c = 0; c < 3; ++c)
                    sum[c] += (rgba >> (8 * c)) & 255u;
            }
            for (int c = 0; c < 3; ++c)
                image->rgb[px * 3 + c] = (uint8_t)((sum[c] + spp / 2) / spp);
            image->coverage[px] = (uint8_t)hits;
            written += hits;
            if (image->samples) /* reyes_options.keep_samples */
                memcpy(image->samples + px * spp, pixel, spp * sizeof *pixel);
        }
    }
    return written;
}

void reyes_image_free(reyes_image *image)
{
    if (!image)
        return;
    free(image->rgb);
    free(image->coverage);
    free(image->samples);
    memset(image, 0, sizeof *image);
}
