/*
 * LDR-FLIP (Andersson et al., "FLIP: A Difference Evaluator for
 * Alternating Images", HPG 2020), written here from the paper's
 * description: the perceived difference between a reference and a test
 * image, per pixel in [0, 1], for an observer at `pixels_per_degree`
 * (67.0 for the paper's default: a 0.7 m wide 4K monitor seen from
 * 0.7 m).  Colour: both images in the opponent space YCxCz, each channel
 * filtered by its contrast sensitivity function, clamped to the RGB cube,
 * compared in Hunt-adjusted L*a*b* by the HyAB distance and compressed to
 * [0, 1]; features: edges and points of the achromatic channel, whose
 * difference raises the colour error to a power below 1.  Used by the
 * tests to hold renders against the brute-force reference (reyes_brute.h).
 */
#ifndef REYES_FLIP_H
#define REYES_FLIP_H

#include <stddef.h>
#include <stdint.h>

#define REYES_FLIP_DEFAULT_PPD 67.0206f

/* Mean FLIP error of `test` against `reference`, both width x height RGB8
 * (rows top to bottom, sRGB).  With `map` (may be NULL) also the error of
 * every pixel.  Returns a negative value when out of memory. */
double reyes_flip_mean(const uint8_t *reference, const uint8_t *test, unsigned width, unsigned height,
                       float pixels_per_degree, float *map);

#endif
