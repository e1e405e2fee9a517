/*
 * A brute-force reference renderer for the tests, independent of the
 * Reyes pipeline: every patch is tessellated uniformly (no bounding,
 * splitting, culling or dicing decisions), its triangles are sampled at
 * the renderer's sample positions with perspective-correct depth and
 * (u,v), and each covered sample is shaded at the exact surface point of
 * its nearest patch (deferred, with the renderer's light and weights).
 * What it renders is what the scene, camera and samples say the image is;
 * rendered images are held against it sample by sample (coverage, which
 * surface) and pixel by pixel (colour).
 */
#ifndef REYES_BRUTE_H
#define REYES_BRUTE_H

#include "reyes.h"

typedef struct reyes_brute_image {
    unsigned width, height, spp;
    float *depth;       /* per sample (pixels row by row, spp each): view depth, INFINITY if empty */
    uint32_t *rgba;     /* per sample: the shaded colour, or the background */
    uint8_t *rgb;       /* pixels: the samples' average, as the renderer resolves them */
    uint8_t *coverage;  /* per pixel: covered samples */
    uint32_t *patch;    /* per sample: the patch seen (UINT32_MAX: none) */
    uint8_t *facing;    /* per sample: 1 the surface's front (its normal towards the eye), 2 its back, 0 empty */
    float *slant;       /* per sample: |cos| of the angle between the surface's normal and the ray (0: empty) */
} reyes_brute_image;

#define REYES_BRUTE_MAX_TESSELLATION 128u
/* The slant below which a surface is seen at a grazing angle (about 84
 * degrees from facing the eye): the cracks are not counted there. */
#define REYES_BRUTE_GRAZING 0.1f

/* Render scene through camera at options' width, height, spp and
 * background, tessellating every patch into tessellation x tessellation
 * quads (64 is plenty for the models at 512 px: its chords miss the
 * surface by hundredths of a pixel), or with tessellation 0 into as many
 * as make its quads at most half a pixel long in space at its nearest
 * depth (4 .. REYES_BRUTE_MAX_TESSELLATION; the most for a patch reaching
 * the near plane): as exact, and far faster for models of many small
 * patches.  Triangles with a vertex at or behind
 * the near plane are left out, as the renderer drops such micropolygons:
 * hold views that cross the near plane elsewhere. */
reyes_status reyes_brute_render(const reyes_scene *scene, const reyes_camera *camera,
                                const reyes_options *options, unsigned tessellation,
                                reyes_brute_image *out, reyes_error *error);
void reyes_brute_free(reyes_brute_image *image);

/* The converged image of the view, adaptively tessellated (tessellation
 * 0) and sampled on a side x side regular lattice per pixel (1..8)
 * instead of the renderer's sample positions: what a render's pixels
 * approximate, sampling noise and all. */
reyes_status reyes_brute_render_truth(const reyes_scene *scene, const reyes_camera *camera,
                                      const reyes_options *options, unsigned side, reyes_brute_image *out,
                                      reyes_error *error);

/* A render held against the reference.  A sample or pixel is *near an
 * edge* when the reference's 3x3 pixels around it have both covered and
 * empty samples, depths more than 2 % apart (a silhouette, one surface in
 * front of another), both sides of a surface (a fold, an open rim) or two
 * patches (a seam, maybe a crease): there the two tessellations may
 * legitimately see different things within a fraction of a pixel.
 * Elsewhere (the *interior*) they must agree. */
typedef struct reyes_brute_comparison {
    size_t samples;              /* width * height * spp */
    size_t reference_covered;    /* samples the reference covers */
    size_t edge_samples;         /* samples near an edge */
    /* Coverage: covered in the render only (extra) or in the reference only (missing). */
    size_t extra, missing;
    size_t interior_extra, interior_missing;
    /* Covered in both but by another surface (depths more than 1 % apart). */
    size_t other_surface, interior_other_surface;
    /* Cracks: samples that show a surface more than 1 % farther than
     * any the reference shows in the 3x3 pixels around them (see-through)
     * or the background where the reference shows none there (holes),
     * where the reference's surface there faces the eye (|cos| of the
     * angle to the ray at least REYES_BRUTE_GRAZING).  What a tessellation
     * may legitimately see past a silhouette within a pixel the reference
     * shows nearby too, and where a fold or a rim is seen edge-on its
     * chords cut the contour (silhouette errors, in the colour and FLIP
     * figures, not cracks). */
    size_t see_through, holes;
    /* Colour per pixel channel, in levels (0..255), over the pixels
     * either covers (`pixels`): mean, largest, and pixels whose largest
     * channel error is over 8 and over 32 levels; the same over those of
     * them away from edges. */
    double mean_error, interior_mean_error;
    unsigned max_error, interior_max_error;
    size_t pixels_over_8, pixels_over_32, interior_pixels_over_8;
    size_t pixels, interior_pixels;
} reyes_brute_comparison;

/* Compare a render made with reyes_options.keep_samples (image->samples)
 * with the reference of the same size and spp. */
reyes_status reyes_brute_compare(const reyes_image *image, const reyes_brute_image *reference,
                                 reyes_brute_comparison *out, reyes_error *error);

/* Per pixel: 2 near a silhouette, fold, rim or one surface in front of
 * another, 1 near a seam between patches only, else 0 (interior). */
void reyes_brute_edge_map(const reyes_brute_image *reference, uint8_t *map);

/* One line of the comparison's numbers (for the test logs and docs). */
void reyes_brute_print(FILE *out, const char *label, const reyes_brute_comparison *c);

#endif
