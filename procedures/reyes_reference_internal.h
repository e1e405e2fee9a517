/* The C reference's pieces: subdivision (reyes_reference.c), dicing and
 * shading (reyes_reference_dice.c) and sampling (reyes_reference_sample.c). */
#ifndef REYES_REFERENCE_INTERNAL_H
#define REYES_REFERENCE_INTERNAL_H

#include "reyes_reference.h"
#include "reyes_shared.h"

#define REFERENCE_MAX_VERTICES (REYES_MAX_GRID * REYES_MAX_GRID)

/* One diced grid, structure of arrays (vertex j * n + i). */
typedef struct reference_grid {
    unsigned n;
    float sx[REFERENCE_MAX_VERTICES], sy[REFERENCE_MAX_VERTICES]; /* pixels, y down */
    float w[REFERENCE_MAX_VERTICES];                              /* clip w, the depth */
    uint32_t rgba[REFERENCE_MAX_VERTICES];
    float color[3][REFERENCE_MAX_VERTICES];                       /* rgba's channels in [0,1] */
    unsigned char front[REFERENCE_MAX_VERTICES];                  /* in front of the near plane */
    /* Scratch of the shading. */
    float x[3][REFERENCE_MAX_VERTICES], normal[3][REFERENCE_MAX_VERTICES];
    float diffuse[REFERENCE_MAX_VERTICES], specular[REFERENCE_MAX_VERTICES];
} reference_grid;

/* What a full render samples into: every sample of the image (spp per
 * pixel, rows top down) and its position (x, y pairs; reyes_sample.cl's
 * jittered positions, computed once per render instead of once per quad
 * that covers the pixel). */
typedef struct reference_samples {
    uint64_t *values;
    float *positions;
    unsigned width, height, spp;
} reference_samples;

typedef struct reference_context {
    const reyes_scene *scene;
    const reyes_options *o;
    float m[16];
    float near_w;
    reyes_reference_counts *counts;
    /* A full render: the camera, the light and the samples (NULL
     * otherwise: dice only counts the visible quads). */
    float eye[3], light[3];
    reference_samples *samples;
    reference_grid *grid;
} reference_context;

/* Dice sub-patch sp: evaluate its grid, count the visible quads and, in a
 * full render, shade and sample them. */
void reference_dice(reference_context *c, const struct reyes_subpatch *sp);

/* Sample the visible quads of a diced grid; returns how many there are. */
uint64_t reference_sample_grid(const reference_context *c, const reference_grid *g);

/* Point a sample buffer at its arrays and fill in the positions. */
void reference_samples_init(reference_samples *s, unsigned width, unsigned height, unsigned spp,
                            uint64_t *values, float *positions);

#endif
