/* The C reference's pieces: subdivision (reyes_reference.c), dicing and
 * shading (reyes_reference_dice.c) and sampling (reyes_reference_sample.c). */
#ifndef REYES_REFERENCE_INTERNAL_H
#define REYES_REFERENCE_INTERNAL_H

#include <time.h>

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

/* Sub-patches to dice later (the OpenMP driver's first phase). */
typedef struct reference_leaves {
    struct reyes_subpatch *items;
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
} reference_context;

/* Check the options (the C reference's limits too) and set up the
 * context's camera, light and counts (cleared); no grid, no samples. */
reyes_status reference_begin(reference_context *c, const reyes_scene *scene, const reyes_camera *camera,
                             const reyes_options *options, reyes_reference_counts *out, reyes_error *error);
/* The context's grid scratch (free c->grid). */
reyes_status reference_grid_alloc(reference_context *c, reyes_error *error);
/* Bound base patch `patch`, split and dice (or record) depth-first. */
void reference_subdivide_patch(reference_context *c, uint32_t patch);
void reference_leaves_add(reference_leaves *leaves, const struct reyes_subpatch *sp);
int reference_hull_has_sample(unsigned width, unsigned height, unsigned spp, const float sx[16], const float sy[16],
                              float lo_x, float lo_y, float hi_x, float hi_y);
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
