/*
 * Adaptive Mandelbrot (Mariani-Silver) on perma: shared types and the
 * functions of the example's small library (used by the program and tests).
 *
 * Every function that can fail returns a mandel_status and writes a message
 * naming the file, option or OpenCL step into a caller's buffer.
 */
#ifndef MANDEL_H
#define MANDEL_H

#include <perma.h>
#include <stddef.h>
#include <stdint.h>

#include "example_session.h"

/* Exit codes of the program follow the README: 0 ok, 1 runtime failure, 2 bad usage. */
typedef enum mandel_status {
    MANDEL_OK = 0,
    MANDEL_ERR_RUNTIME = 1,
    MANDEL_ERR_USAGE = 2
} mandel_status;

enum {
    MANDEL_MAX_SIZE = 16384,       /* widest or tallest image */
    MANDEL_MAX_ITER = 1000000,
    MANDEL_DEFAULT_MIN_SIZE = 16   /* interiors this small are computed per pixel */
};

/* The image and the plane it samples.  Pixel (px, py) samples
 * c = (x0 + px * dx, y0 + py * dy), evaluated in float in exactly that
 * order on host and device (mandel_escape.h); (x0, y0) is the top-left
 * corner and dy is negative.  The layout matches struct mandel_params of
 * the device source. */
typedef struct mandel_params {
    uint32_t width, height;
    uint32_t max_iter;
    uint32_t min_size;
    float x0, y0, dx, dy;
} mandel_params;

/* Fill *p for a width x height image of the rectangle
 * [x_min, x_max] x [y_min, y_max] of the complex plane. */
void mandel_params_init(mandel_params *p, unsigned width, unsigned height,
                        double x_min, double x_max, double y_min, double y_max,
                        unsigned max_iter, unsigned min_size);

/* Host versions.  `counts` holds width*height escape counts, row-major. */
void mandel_brute_force(const mandel_params *p, uint32_t *counts);
/* The same Mariani-Silver subdivision as the perma procedures, sequential;
 * returns 0, or -1 when out of memory. */
int mandel_sequential(const mandel_params *p, uint32_t *counts);

/* The perma program (mandel_perma.c) of one image: each run writes the
 * escape counts into `counts` (the caller's, width*height words).  The
 * build sets `split`. */
typedef struct mandel_run {
    mandel_params params; /* bound to the device: lives as long as the session */
    uint32_t *counts;
    perma_proc split;
} mandel_run;

extern const example_program mandel_program;

/* Render once with a fresh session (build included). */
mandel_status mandel_render_perma(const mandel_params *p, const example_run_options *options,
                                  uint32_t *counts, char *message, size_t size);

/* Device source of the procedures (split, fill, block) and their types. */
const char *mandel_device_types(void);
const char *mandel_device_procedures(void);

/* Colour-map the escape counts and write an RGB PNG. */
mandel_status mandel_write_png(const char *path, const mandel_params *p, const uint32_t *counts,
                               char *message, size_t size);

/* --compare: time the sequential C version and every technique/strategy,
 * print a table with ratios to `out`. */
mandel_status mandel_compare(const mandel_params *p, unsigned work_groups, unsigned repeats,
                             FILE *out, char *message, size_t size);

#endif
