/* Colour map of escape counts and PNG output through libpng. */
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include "mandel.h"

/* Points in the set are black; escaping points run along a gradient by
 * sqrt(count / max_iter), which spreads out the many low counts. */
static void colour(uint32_t count, uint32_t max_iter, png_byte rgb[3])
{
    static const double stops[][3] = {
        { 0, 7, 100 }, { 32, 107, 203 }, { 237, 255, 255 }, { 255, 170, 0 }, { 80, 20, 0 },
    };
    const int last = (int)(sizeof stops / sizeof stops[0]) - 1;
    if (count >= max_iter) {
        rgb[0] = rgb[1] = rgb[2] = 0;
        return;
    }
    double t = sqrt((double)count / max_iter) * last;
    int k = (int)t;
    if (k >= last)
        k = last - 1;
    double f = t - k;
    for (int c = 0; c < 3; ++c)
        rgb[c] = (png_byte)lround(stops[k][c] + f * (stops[k + 1][c] - stops[k][c]));
}

/* libpng reports errors by longjmp; the row buffer is owned by the caller. */
static int encode(FILE *f, const mandel_params *p, const uint32_t *counts, png_bytep row)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    if (!png)
        return 0;
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, info ? &info : NULL);
        return 0;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, p->width, p->height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (uint32_t y = 0; y < p->height; ++y) {
        for (uint32_t x = 0; x < p->width; ++x)
            colour(counts[(size_t)y * p->width + x], p->max_iter, row + 3 * (size_t)x);
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return 1;
}

mandel_status mandel_write_png(const char *path, const mandel_params *p, const uint32_t *counts,
                               char *message, size_t size)
{
    png_bytep row = malloc(3 * (size_t)p->width);
    if (!row) {
        snprintf(message, size, "%s: out of memory for a row", path);
        return MANDEL_ERR_RUNTIME;
    }
    /* Whole or not at all: a failed write leaves no partial file. */
    perma_output *out;
    perma_error error;
    if (perma_output_open(path, &out, &error) != PERMA_OK) {
        snprintf(message, size, "%s", error.message);
        free(row);
        return MANDEL_ERR_RUNTIME;
    }
    int ok = encode(perma_output_stream(out), p, counts, row);
    free(row);
    if (perma_output_finish(out, &error) != PERMA_OK) {
        snprintf(message, size, "%s", error.message);
        return MANDEL_ERR_RUNTIME;
    }
    if (!ok) {
        perma_output_discard(out);
        snprintf(message, size, "%s: libpng failed to encode the image", path);
        return MANDEL_ERR_RUNTIME;
    }
    if (perma_output_commit(out, &error) != PERMA_OK) {
        snprintf(message, size, "%s", error.message);
        return MANDEL_ERR_RUNTIME;
    }
    return MANDEL_OK;
}
