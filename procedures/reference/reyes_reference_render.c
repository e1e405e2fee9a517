/*
 * The C reference's full render on one thread (reyes_reference_render) and
 * the set-up and resolve it shares with the OpenMP driver
 * (reyes_reference_parallel.c).
 */
#include <stdlib.h>
#include <string.h>

#include "reyes_look.h"
#include "reyes_reference_internal.h"

static reyes_status image_alloc(reyes_image *image, unsigned width, unsigned height, reyes_error *error)
{
    size_t pixels = (size_t)width * height;
    image->width = width;
    image->height = height;
    image->rgb = malloc(pixels * 3);
    image->coverage = malloc(pixels);
    if (!image->rgb || !image->coverage)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a %ux%u image", width, height);
    return REYES_OK;
}

reyes_status reference_render_begin(reference_context *c, reyes_options *full, reference_samples *samples,
                                    const reyes_scene *scene, const reyes_camera *camera,
                                    const reyes_options *options, int concurrent, reyes_image *image,
                                    reyes_reference_counts *out, reyes_error *error)
{
    memset(image, 0, sizeof *image);
    memset(samples, 0, sizeof *samples);
    *full = *options;
    full->stages = REYES_STAGES_ALL;
    reyes_status status = reference_begin(c, scene, camera, full, out, error);
    if (status == REYES_OK && (options->motion[0] != 0.0f || options->motion[1] != 0.0f
                               || options->motion[2] != 0.0f || options->motion_angle_deg != 0.0f
                               || options->aperture != 0.0f))
        status = reyes_fail(error, REYES_ERR_ARGUMENT,
                            "the C reference renders without motion blur or depth of field");
    if (status == REYES_OK && options->displace_mode != REYES_DISPLACE_NONE && options->displace_amplitude != 0.0f)
        status = reyes_fail(error, REYES_ERR_ARGUMENT, "the C reference renders without displacement");
    if (status == REYES_OK)
        status = reference_samples_create(samples, options->width, options->height, options->spp, concurrent, error);
    if (status == REYES_OK)
        status = image_alloc(image, options->width, options->height, error);
    c->samples = samples;
    /* As the renderer: only with a shading rate (it refuses displacement
     * and blur, under which a grid leaves its hull). */
    c->occlusion = options->occlusion_cull && options->shading_rate > 0.0f;
    return status;
}

reyes_status reference_render_end(reyes_status status, reference_samples *samples, const reyes_options *options,
                                  reyes_image *image, reyes_reference_counts *out)
{
    if (status == REYES_OK)
        out->samples_written = reyes_resolve(samples->values, options->spp, options->background, 0, 0,
                                             options->width, options->height, image);
    reference_samples_free(samples);
    if (status != REYES_OK)
        reyes_image_free(image);
    return status;
}

reyes_status reyes_reference_render(const reyes_scene *scene, const reyes_camera *camera,
                                    const reyes_options *options, reyes_image *image,
                                    reyes_reference_counts *out, reyes_error *error)
{
    reference_context c;
    reyes_options full;
    reference_samples samples;
    reyes_status status = reference_render_begin(&c, &full, &samples, scene, camera, options, 0, image, out, error);
    if (status == REYES_OK)
        status = reference_subdivide_all(&c, scene, out, error);
    free(c.grid);
    return reference_render_end(status, &samples, options, image, out);
}
