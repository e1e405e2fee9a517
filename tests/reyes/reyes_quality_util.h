/*
 * Holding renders against the brute-force reference (reyes_brute.h) for
 * the quality of shading-rate dicing: cracks per sample at 1 sample per
 * pixel, the FLIP error (reyes_flip.h) against the converged image and
 * against the reference at the render's own samples, the colour error,
 * and the micropolygons' density and areas.  Shared by the tests and the
 * reyes-quality tool.
 */
#ifndef REYES_QUALITY_UTIL_H
#define REYES_QUALITY_UTIL_H

#include "reyes_brute.h"

/* A camera orbiting a framed one: turned about its target by azimuth
 * degrees (about z), raised to elevation degrees above the target's
 * horizontal plane, at distance times its distance. */
typedef struct reyes_quality_view {
    float azimuth, elevation, distance;
} reyes_quality_view;

/* A view of a sweep: the orbit, its field of view divided by zoom (a
 * telephoto view from afar), and the target moved by aim (fractions of
 * the framed distance, world axes: a near view of a part of the model). */
typedef struct reyes_quality_shot {
    reyes_quality_view view;
    float zoom, aim[3];
} reyes_quality_shot;

/* Random view k of a sweep with this seed: a quarter each framed
 * (distance 0.7 to 2), near (0.2 to 0.5, aimed up to 0.3 away from the
 * target), telephoto (4 to 12, zoomed to about the framed size) and
 * grazing (elevation within 4 degrees of the horizon, distance 0.6 to
 * 1.5); azimuth and the other elevations uniform. */
reyes_quality_shot reyes_quality_random_shot(unsigned seed, unsigned k);
reyes_camera reyes_quality_shoot(const reyes_camera *framed, reyes_quality_shot shot);

reyes_camera reyes_quality_orbit(const reyes_camera *framed, reyes_quality_view view);

/* The references of one view, adaptively tessellated: at 1 sample per
 * pixel for the cracks, at the options' samples per pixel (the render's
 * sample positions) and the converged image (4 x 4 regular samples per
 * pixel), each made when asked for (REYES_QUALITY_*). */
enum { REYES_QUALITY_CRACKS = 1, REYES_QUALITY_SAMPLES = 2, REYES_QUALITY_TRUTH = 4 };

typedef struct reyes_quality_reference {
    reyes_brute_image one, many, truth;
    unsigned made;
} reyes_quality_reference;

reyes_status reyes_quality_reference_make(const reyes_scene *scene, const reyes_camera *camera,
                                          const reyes_options *options, unsigned what,
                                          reyes_quality_reference *out, reyes_error *error);
void reyes_quality_reference_free(reyes_quality_reference *reference);

typedef struct reyes_quality_result {
    /* At 1 sample per pixel: see-through samples and holes (reyes_brute_comparison). */
    size_t see_through, holes;
    /* At the options' samples per pixel, against the reference at the
     * render's samples: the comparison, the mean FLIP and its parts from
     * pixels near silhouettes and near seams only (reyes_brute_edge_map). */
    reyes_brute_comparison colour;
    double flip, flip_silhouettes, flip_seams;
    double flip_truth;               /* mean FLIP against the converged image */
    double micropolygons_per_pixel;  /* micropolygons / pixels with any covered sample */
    double area_mean;                /* square pixels (stats) */
    double area_percentile[4];       /* 10th, 50th, 90th and 99th */
    uint64_t micropolygons, grids;
    size_t covered_pixels;
} reyes_quality_result;

/* Render the view with options at 1 sample per pixel and count its
 * cracks against the reference (see_through, holes). */
reyes_status reyes_quality_cracks(reyes_renderer *renderer, const reyes_scene *scene, const reyes_camera *camera,
                                  const reyes_options *options, const reyes_quality_reference *reference,
                                  reyes_quality_result *out, reyes_error *error);

/* Render the view with options and measure the micropolygons and, for
 * the references made, the colour and FLIP errors (the other fields).
 * With `dump` (may be NULL) and the reference at the render's samples
 * also write DUMP.png, DUMP-reference.png and DUMP-error.png (the
 * differences times 8). */
reyes_status reyes_quality_colour(reyes_renderer *renderer, const reyes_scene *scene, const reyes_camera *camera,
                                  const reyes_options *options, const reyes_quality_reference *reference,
                                  const char *dump, reyes_quality_result *out, reyes_error *error);

#endif
