/* The C reference's pieces: subdivision (reyes_reference.c), dicing and
 * shading (reyes_reference_dice.c), sampling (reyes_reference_sample.c)
 * and the hull's tests against the samples (reyes_reference_occlusion.c). */
#ifndef REYES_REFERENCE_INTERNAL_H
#define REYES_REFERENCE_INTERNAL_H

#include <time.h>

#include "reyes_look.h"
#include "reyes_reference.h"
#include "reyes_shared.h"

#define REFERENCE_MAX_VERTICES (REYES_MAX_GRID * REYES_MAX_GRID)
/* The sampling sets up a grid row's quads in this many lanes, reading that
 * far past the row's first vertex: the arrays' padding. */
#define REFERENCE_ROW_LANES REYES_MAX_GRID
#define REFERENCE_GRID_ARRAY (REFERENCE_MAX_VERTICES + REFERENCE_ROW_LANES + 1)

/* One diced grid, structure of arrays (vertex j * n + i), and padding. */
typedef struct reference_grid {
    unsigned columns, rows; /* vertices along u and v */
    float sx[REFERENCE_GRID_ARRAY], sy[REFERENCE_GRID_ARRAY]; /* pixels, y down */
    float w[REFERENCE_MAX_VERTICES];                              /* clip w, the depth */
    uint32_t rgba[REFERENCE_MAX_VERTICES];
    float color[3][REFERENCE_MAX_VERTICES];                       /* rgba's channels in [0,1] */
    unsigned char front[REFERENCE_GRID_ARRAY];                  /* in front of the near plane */
    /* Scratch of the shading. */
    float x[3][REFERENCE_MAX_VERTICES], normal[3][REFERENCE_MAX_VERTICES];
    float diffuse[REFERENCE_MAX_VERTICES], specular[REFERENCE_MAX_VERTICES];
} reference_grid;

/* What a full render samples into: every sample of the image (spp per
 * pixel, rows top down) and the columns x rows lattice of strata that
 * places them (reyes_sample.cl). */
typedef struct reference_samples {
    uint64_t *values;
    unsigned width, height, spp, columns, rows;
    int concurrent; /* 1: threads share values (atomic minimum) */
} reference_samples;

/* A projected control hull's octagon (reyes_hull_octagon,
 * reyes_occlusion.cl): its screen box cut by the extremes of x + y (sum)
 * and x - y (difference), each side moved out by REYES_SAMPLE_BOX_MARGIN. */
typedef struct reference_octagon {
    float lo_x, lo_y, hi_x, hi_y, sum_lo, sum_hi, difference_lo, difference_hi;
} reference_octagon;

/* A sub-patch to dice later, and what ordering and testing it needs. */
typedef struct reference_leaf {
    struct reyes_subpatch sp;
    uint32_t order; /* its place among its base patch's leaves: near_w's ties */
    float near_w;   /* its control hull's nearest clip w: the front-to-back order */
    /* Occlusion culling: the depth every sample in the octagon must be
     * nearer than for the grid to be skipped; 0: not tested (kept). */
    float limit;
    reference_octagon octagon;
} reference_leaf;

/* Sub-patches to dice later (the OpenMP driver's first phase, and both
 * drivers' when culling hidden grids). */
typedef struct reference_leaves {
    reference_leaf *items;
    size_t count, capacity;
    int failed; /* out of memory */
} reference_leaves;

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
    /* Non-NULL: bound records the sub-patches to dice here instead of
     * dicing them. */
    reference_leaves *leaves;
    uint32_t patch_leaves; /* leaves recorded of the base patch in hand */
    /* 1: occlusion culling (reyes_options.occlusion_cull in a full render
     * at a shading rate): the leaves are recorded, sorted front to back
     * and each tested against the samples before it is diced, as the
     * renderer's dice does (reyes_occlusion.cl). */
    int occlusion;
} reference_context;

/* Check the options (the C reference's limits too) and set up the
 * context's camera, light and counts (cleared); no grid, no samples. */
reyes_status reference_begin(reference_context *c, const reyes_scene *scene, const reyes_camera *camera,
                             const reyes_options *options, reyes_reference_counts *out, reyes_error *error);
/* The context's grid scratch (free c->grid). */
reyes_status reference_grid_alloc(reference_context *c, reyes_error *error);
/* Bound base patch `patch`, split and dice (or record) depth-first. */
void reference_subdivide_patch(reference_context *c, uint32_t patch);
void reference_leaves_add(reference_leaves *leaves, const reference_leaf *leaf);
void reference_leaves_free(reference_leaves *leaves);
/* The octagon of the projected hull (sx, sy)[16] with screen box lo..hi. */
reference_octagon reference_hull_octagon(const float sx[16], const float sy[16], float lo_x, float lo_y, float hi_x,
                                         float hi_y);
/* As reyes_hull_has_sample (reyes_bound.cl): 0 only when no sample
 * position of a width x height image at spp samples per pixel lies in
 * the octagon; 1 also for octagons over more than REYES_SAMPLE_BOX_PIXELS
 * pixels (not searched). */
int reference_hull_has_sample(unsigned width, unsigned height, unsigned spp, const reference_octagon *o);
/* Occlusion culling (reyes_occlusion.cl): set leaf->limit for the hull
 * (sx, sy)[16] with octagon leaf->octagon, nearest clip w leaf->near_w
 * and largest |x| + |y| + |z| of a control point `largest` (0 where the
 * octagon is off the image or over more than REYES_OCCLUSION_PIXELS
 * pixels); and whether the samples already hide the leaf's grid: every
 * sample in its octagon nearer than its limit. */
void reference_occlusion_setup(const reference_context *c, reference_leaf *leaf, float largest);
int reference_leaf_occluded(const reference_context *c, const reference_leaf *leaf);
/* Front to back: by near_w, ties by base patch and order (the same order
 * however the leaves were gathered). */
void reference_leaves_sort(reference_leaf *items, size_t count);
int reference_leaf_before(const reference_leaf *a, const reference_leaf *b);
/* Dice a recorded leaf, or with occlusion culling skip it (counted in
 * occluded) when the samples already hide it. */
void reference_dice_leaf(reference_context *c, const reference_leaf *leaf);
double reference_seconds_since(const struct timespec *start);
/* The serial drivers' body: allocate c's grid, subdivide every patch of
 * the scene in order, and time it into out->seconds. */
reyes_status reference_subdivide_all(reference_context *c, const reyes_scene *scene,
                                     reyes_reference_counts *out, reyes_error *error);

/* A full render's set-up, shared by the single-threaded and OpenMP
 * drivers (reyes_reference_render.c): the options checked (no motion,
 * lens or displacement either), the context begun for *full (the options
 * with every stage), the samples (concurrent: for several threads) and
 * the image allocated.  reference_render_end resolves the samples into the
 * image (on success) and frees what begin allocated. */
reyes_status reference_render_begin(reference_context *c, reyes_options *full, reference_samples *samples,
                                    const reyes_scene *scene, const reyes_camera *camera,
                                    const reyes_options *options, int concurrent, reyes_image *image,
                                    reyes_reference_counts *out, reyes_error *error);
reyes_status reference_render_end(reyes_status status, reference_samples *samples, const reyes_options *options,
                                  reyes_image *image, reyes_reference_counts *out);

/* The C reference's vector loops (dice and shading, the quads' set-up and
 * tests) run at the machine's vector width, as the OpenCL device compiles
 * the procedures for the CPU it runs on: on x86-64 with GCC 12 or later
 * the two functions that hold them get AVX-512 and AVX2 clones besides
 * the baseline's (function multiversioning: the loader picks one by the
 * CPU; the attribute goes on their definitions only).  The clones compute
 * the same bits: no contractions in ISO C. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12 && defined(__ELF__)
#define REFERENCE_MACHINE_CLONES __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define REFERENCE_MACHINE_CLONES
#endif
/* A helper with vector loops: inlined into every clone (a function of its
 * own would be built for the baseline only). */
#ifdef __GNUC__
#define REFERENCE_VECTOR_HELPER static inline __attribute__((always_inline))
#else
#define REFERENCE_VECTOR_HELPER static inline
#endif

/* fminf and fmaxf would be library calls (their NaN rules); these are not. */
static inline float min_f(float a, float b)
{
    return a < b ? a : b;
}

static inline float max_f(float a, float b)
{
    return a > b ? a : b;
}

/* The position of the sample in stratum (sx, sy) of the image's lattice:
 * pixel (*px, *py), index *k (>= spp: the stratum holds no sample), as
 * reyes_sample_xy.  The quotients are exact in float (sx + 1/2 lies at
 * least 1 / (2 columns) from a multiple of columns, far more than the
 * rounding error below 2^20), so this vectorises. */
REFERENCE_VECTOR_HELPER void reference_stratum_sample(int sx, int sy, int columns, int rows, float *x, float *y,
                                                      int *px, int *py, int *k)
{
    int pixel_x = (int)(((float)sx + 0.5f) / (float)columns), pixel_y = (int)(((float)sy + 0.5f) / (float)rows);
    int cell_x = sx - pixel_x * columns, cell_y = sy - pixel_y * rows;
    *k = cell_y * columns + cell_x;
    uint32_t h = reyes_hash32((uint32_t)pixel_x * 0x9e3779b9u
                              ^ reyes_hash32((uint32_t)pixel_y * 0x85ebca6bu ^ reyes_hash32((uint32_t)*k)));
    float jx = (float)(int)(h & 0xffffu) * (1.0f / 65536.0f), jy = (float)(int)(h >> 16) * (1.0f / 65536.0f);
    *x = (float)pixel_x + ((float)cell_x + jx) / (float)columns;
    *y = (float)pixel_y + ((float)cell_y + jy) / (float)rows;
    *px = pixel_x;
    *py = pixel_y;
}

/* Dice sub-patch sp: evaluate its grid, count the visible quads and, in a
 * full render, shade and sample them. */
void reference_dice(reference_context *c, const struct reyes_subpatch *sp);

/* Sample the visible quads of a diced grid; returns how many there are. */
uint64_t reference_sample_grid(const reference_context *c, const reference_grid *g);

/* Allocate the samples of a width x height image (cleared to empty);
 * concurrent: written by several threads.
 * Free with reference_samples_free (also after a failure). */
reyes_status reference_samples_create(reference_samples *s, unsigned width, unsigned height, unsigned spp,
                                      int concurrent, reyes_error *error);
void reference_samples_free(reference_samples *s);

#endif
