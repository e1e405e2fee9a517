/*
 * perma-image-compare: two PNG images of the same size, pixel by pixel.
 *
 *     perma-image-compare EXPECTED.png ACTUAL.png [--tolerance N] [--fraction F]
 *
 * A pixel differs when one of its red, green and blue values differs by
 * more than N/255 (default 2); the images agree when at most a fraction F
 * of the pixels differ (default 0.001).  The GPU check (docs/gpu.md)
 * compares a GPU's renders with the ones PoCL made here.  Prints one line:
 *
 *     teapot.png vs gpu-teapot.png: 640x360, 12 of 230400 pixels (0.0052%) differ by more than 2/255
 *     (worst 9/255, mean difference 0.0031/255): agree
 *
 * Exit status: 0 the images agree, 1 they do not (or differ in size, or
 * one cannot be read), 2 bad usage.
 */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "perma_cli.h"

typedef struct rgb_image {
    unsigned width, height;
    unsigned char *pixels; /* width * height * 3 */
} rgb_image;

/* Read `path` as 8-bit RGB; 0, or 1 with the reason said. */
static int read_rgb(const char *path, rgb_image *out)
{
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    out->pixels = NULL;
    if (!png_image_begin_read_from_file(&image, path)) {
        fprintf(stderr, "perma-image-compare: %s: %s\n", path, image.message);
        return 1;
    }
    image.format = PNG_FORMAT_RGB;
    out->width = image.width;
    out->height = image.height;
    out->pixels = malloc(PNG_IMAGE_SIZE(image));
    if (!out->pixels) {
        png_image_free(&image);
        fprintf(stderr, "perma-image-compare: %s: out of memory for %ux%u pixels\n", path, image.width,
                image.height);
        return 1;
    }
    if (!png_image_finish_read(&image, NULL, out->pixels, 0, NULL)) {
        fprintf(stderr, "perma-image-compare: %s: %s\n", path, image.message);
        free(out->pixels);
        out->pixels = NULL;
        return 1;
    }
    return 0;
}

/* The operands, in order (max_operands keeps them to two). */
typedef struct image_paths {
    const char *path[2];
    size_t count;
} image_paths;

static int add_path(const perma_cli_option *option, const char *value, char *complaint, size_t size)
{
    (void)complaint;
    (void)size;
    image_paths *paths = option->target;
    paths->path[paths->count++] = value;
    return 0;
}

int main(int argc, char **argv)
{
    unsigned tolerance = 2;
    double fraction = 0.001;
    image_paths images = { { NULL, NULL }, 0 };
    size_t operands = 0;
    const perma_cli_option rows[] = {
        { PERMA_CLI_WHOLE("tolerance", "N", &tolerance, 0, 255,
                          "a pixel differs when a channel differs by more than N/255 (default 2)") },
        { PERMA_CLI_DOUBLE("fraction", "F", &fraction, 0.0, 1.0,
                           "the images agree when at most this fraction of the pixels differ (default 0.001)") },
    };
    const perma_cli_table table = { "options", rows, sizeof rows / sizeof rows[0] };
    const perma_cli_option operand = { PERMA_CLI_CUSTOM(NULL, "PNG", add_path, &images, NULL) };
    const perma_cli cli = {
        .program = "perma-image-compare",
        .synopsis = "EXPECTED.png ACTUAL.png [options]",
        .about = "Compare two PNG images of the same size pixel by pixel (8-bit red, green, blue).",
        .tables = &table,
        .table_count = 1,
        .operand = &operand,
        .max_operands = 2,
        .operand_count = &operands,
        .notes = "exit status: 0 the images agree, 1 they do not (or differ in size, or one cannot be read), "
                 "2 bad usage",
    };
    char message[PERMA_CLI_MESSAGE_MAX];
    perma_cli_status status = perma_cli_parse(&cli, argc, argv, message, sizeof message);
    if (status == PERMA_CLI_OK && operands != 2)
        status = perma_cli_fail(&cli, message, sizeof message, "expected two images, EXPECTED.png ACTUAL.png");
    if (status != PERMA_CLI_OK)
        return perma_cli_exit_status(status);

    const char *const *paths = images.path;
    rgb_image a, b;
    if (read_rgb(paths[0], &a))
        return 1;
    if (read_rgb(paths[1], &b)) {
        free(a.pixels);
        return 1;
    }
    int result = 1;
    if (a.width != b.width || a.height != b.height) {
        printf("%s vs %s: %ux%u and %ux%u: differ in size\n", paths[0], paths[1], a.width, a.height, b.width,
               b.height);
    } else {
        size_t pixels = (size_t)a.width * a.height, differing = 0;
        unsigned long long total = 0;
        unsigned worst = 0;
        for (size_t i = 0; i < pixels; ++i) {
            unsigned most = 0;
            for (int c = 0; c < 3; ++c) {
                int d = (int)a.pixels[3 * i + c] - (int)b.pixels[3 * i + c];
                unsigned diff = (unsigned)(d < 0 ? -d : d);
                total += diff;
                most = diff > most ? diff : most;
            }
            differing += most > tolerance;
            worst = most > worst ? most : worst;
        }
        double share = pixels ? (double)differing / (double)pixels : 0.0;
        result = share <= fraction ? 0 : 1;
        printf("%s vs %s: %ux%u, %zu of %zu pixels (%.4f%%) differ by more than %u/255 (worst %u/255, mean "
               "difference %.4f/255): %s\n", paths[0], paths[1], a.width, a.height, differing, pixels,
               100.0 * share, tolerance, worst, pixels ? (double)total / (3.0 * (double)pixels) : 0.0,
               result == 0 ? "agree" : "disagree");
    }
    free(a.pixels);
    free(b.pixels);
    return result;
}
