/* PNG output, and grayscale PNG input (displacement maps), through libpng. */
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include "reyes.h"

/* libpng's message (instead of its default printing to stderr), then its
 * longjmp back to write_rows. */
static void png_failed(png_structp png, png_const_charp message)
{
    snprintf((char *)png_get_error_ptr(png), 256, "%s", message);
    png_longjmp(png, 1);
}

/* libpng reports errors by longjmp; keep the stream outside the jump. */
static int write_rows(FILE *f, const reyes_image *image, char message[256])
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, message, png_failed, NULL);
    if (!png) {
        snprintf(message, 256, "png_create_write_struct failed");
        return 0;
    }
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, info ? &info : NULL);
        if (!info)
            snprintf(message, 256, "png_create_info_struct failed");
        return 0;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, image->width, image->height, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (unsigned y = 0; y < image->height; ++y)
        png_write_row(png, image->rgb + (size_t)y * image->width * 3);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return 1;
}

reyes_status reyes_png_writer(FILE *out, const void *data, reyes_error *error)
{
    const reyes_image *image = data;
    char message[256] = "";
    if (!write_rows(out, image, message))
        return reyes_fail(error, REYES_ERR_IO, "libpng failed to encode the image: %s", message);
    return REYES_OK;
}

reyes_status reyes_write_png(const char *path, const reyes_image *image, reyes_error *error)
{
    if (!image->rgb || image->width == 0 || image->height == 0)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "%s: empty image", path);
    const reyes_output_file file = { path, reyes_png_writer, image };
    return reyes_write_outputs(&file, 1, error);
}

reyes_status reyes_read_gray_png(const char *path, reyes_gray_map *map, reyes_error *error)
{
    memset(map, 0, sizeof *map);
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path))
        return reyes_fail(error, REYES_ERR_IO, "%s: cannot read as PNG: %s", path, image.message);
    image.format = PNG_FORMAT_GRAY;
    size_t bytes = PNG_IMAGE_SIZE(image);
    if (image.width == 0 || image.height == 0 || image.width > REYES_MAX_SIZE
        || image.height > REYES_MAX_SIZE) {
        png_image_free(&image);
        return reyes_fail(error, REYES_ERR_FORMAT, "%s: %ux%u is not in 1..%u per side", path,
                          image.width, image.height, REYES_MAX_SIZE);
    }
    map->gray = malloc(bytes);
    if (!map->gray) {
        png_image_free(&image);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "%s: out of memory for %zu bytes", path, bytes);
    }
    if (!png_image_finish_read(&image, NULL, map->gray, 0, NULL)) {
        reyes_status status = reyes_fail(error, REYES_ERR_FORMAT, "%s: %s", path, image.message);
        reyes_gray_map_free(map);
        png_image_free(&image);
        return status;
    }
    map->width = image.width;
    map->height = image.height;
    return REYES_OK;
}

void reyes_gray_map_free(reyes_gray_map *map)
{
    free(map->gray);
    memset(map, 0, sizeof *map);
}
