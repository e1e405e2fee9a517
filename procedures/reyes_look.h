/* The look of every render, shared by the renderer and the C reference:
 * the light and its shading weights, and how samples become pixels. */
#ifndef REYES_LOOK_H
#define REYES_LOOK_H

#include "reyes.h"

/* A sample nothing covered: the buffers start all ones, and a covered
 * sample holds its depth's bits above its packed colour. */
#define REYES_EMPTY_SAMPLE_VALUE UINT64_MAX

/* Blinn-Phong weights (reyes_params.ambient ... shininess). */
#define REYES_AMBIENT 0.18f
#define REYES_DIFFUSE 0.82f
#define REYES_SPECULAR 0.35f
#define REYES_SHININESS 40.0f

/* The unit vector towards the light: from the upper left behind the
 * viewer, in world space (z up). */
void reyes_light_direction(float light[3]);

/* Average the spp samples of each pixel of the rectangle [x0,x1) x [y0,y1)
 * (samples: its pixels row by row, spp each) into image; empty samples
 * show `background`.  Returns the covered samples. */
uint64_t reyes_resolve(const uint64_t *samples, unsigned spp, uint32_t background, unsigned x0, unsigned y0,
                       unsigned x1, unsigned y1, reyes_image *image);

#endif
