/* Quality measurements against the brute-force reference (reyes_quality_util.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_flip.h"
#include "reyes_quality_util.h"

reyes_camera reyes_quality_orbit(const reyes_camera *framed, reyes_quality_view view)
{
    reyes_quality_shot shot = { view, 1.0f, {0.0f, 0.0f, 0.0f} };
    return reyes_quality_shoot(framed, shot);
}

reyes_camera reyes_quality_shoot(const reyes_camera *framed, reyes_quality_shot shot)
{
    reyes_quality_view view = shot.view;
    float d[3], length = 0.0f;
    for (int k = 0; k < 3; ++k) {
        d[k] = framed->eye[k] - framed->at[k];
        length += d[k] * d[k];
    }
    float framed_length = sqrtf(length);
    length = framed_length * view.distance;
    float a = atan2f(d[1], d[0]) + view.azimuth * 0.017453293f, e = view.elevation * 0.017453293f;
    reyes_camera camera = *framed;
    for (int k = 0; k < 3; ++k)
        camera.at[k] = framed->at[k] + shot.aim[k] * framed_length;
    camera.eye[0] = camera.at[0] + length * cosf(e) * cosf(a);
    camera.eye[1] = camera.at[1] + length * cosf(e) * sinf(a);
    camera.eye[2] = camera.at[2] + length * sinf(e);
    if (shot.zoom != 1.0f)
        camera.fov_deg = 2.0f * atanf(tanf(framed->fov_deg * 0.008726646f) / shot.zoom) / 0.008726646f;
    return camera;
}

/* A uniform number in [0, 1) from (seed, k, n): a fixed hash. */
static float uniform(unsigned seed, unsigned k, unsigned n)
{
    uint32_t h = seed * 0x9e3779b9u ^ k * 0x85ebca6bu ^ n * 0xc2b2ae35u;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return (float)(h >> 8) / 16777216.0f;
}

reyes_quality_shot reyes_quality_random_shot(unsigned seed, unsigned k)
{
    reyes_quality_shot shot = { { 360.0f * uniform(seed, k, 0), 170.0f * uniform(seed, k, 1) - 85.0f, 1.0f }, 1.0f,
                                {0.0f, 0.0f, 0.0f} };
    reyes_quality_view *v = &shot.view;
    float r = uniform(seed, k, 2);
    switch (k % 4) {
    case 0: /* framed */
        v->distance = 0.7f + 1.3f * r;
        break;
    case 1: /* near, aimed at a part */
        v->distance = 0.2f + 0.3f * r;
        for (int i = 0; i < 3; ++i)
            shot.aim[i] = 0.6f * uniform(seed, k, 3 + (unsigned)i) - 0.3f;
        break;
    case 2: /* telephoto: from afar, zoomed back to about the framed size */
        v->distance = 4.0f + 8.0f * r;
        shot.zoom = v->distance * (0.7f + 0.6f * uniform(seed, k, 3));
        break;
    default: /* grazing */
        v->elevation = 8.0f * uniform(seed, k, 3) - 4.0f;
        v->distance = 0.6f + 0.9f * r;
        break;
    }
    return shot;
}

reyes_status reyes_quality_reference_make(const reyes_scene *scene, const reyes_camera *camera,
                                          const reyes_options *options, unsigned what,
                                          reyes_quality_reference *out, reyes_error *error)
{
    memset(out, 0, sizeof *out);
    reyes_options o = *options;
    o.spp = 1;
    reyes_status status = REYES_OK;
    if (what & REYES_QUALITY_CRACKS)
        status = reyes_brute_render(scene, camera, &o, 0, &out->one, error);
    if (status == REYES_OK && (what & REYES_QUALITY_SAMPLES))
        status = reyes_brute_render(scene, camera, options, 0, &out->many, error);
    if (status == REYES_OK && (what & REYES_QUALITY_TRUTH))
        status = reyes_brute_render_truth(scene, camera, options, 4, &out->truth, error);
    out->made = what;
    if (status != REYES_OK)
        reyes_quality_reference_free(out);
    return status;
}

void reyes_quality_reference_free(reyes_quality_reference *reference)
{
    reyes_brute_free(&reference->one);
    reyes_brute_free(&reference->many);
    reyes_brute_free(&reference->truth);
}

/* Render with keep_samples at `spp` samples per pixel. */
static reyes_status render_kept(reyes_renderer *renderer, const reyes_scene *scene, const reyes_camera *camera,
                                const reyes_options *options, unsigned spp, reyes_image *image, reyes_stats *stats,
                                reyes_error *error)
{
    reyes_options o = *options;
    o.keep_samples = 1;
    o.area_stats = 1;
    o.spp = spp;
    return reyes_render(renderer, scene, camera, &o, image, stats, error);
}

reyes_status reyes_quality_cracks(reyes_renderer *renderer, const reyes_scene *scene, const reyes_camera *camera,
                                  const reyes_options *options, const reyes_quality_reference *reference,
                                  reyes_quality_result *out, reyes_error *error)
{
    reyes_image image;
    reyes_brute_comparison c;
    reyes_status status = render_kept(renderer, scene, camera, options, 1, &image, NULL, error);
    if (status != REYES_OK)
        return status;
    status = reyes_brute_compare(&image, &reference->one, &c, error);
    reyes_image_free(&image);
    out->see_through = c.see_through;
    out->holes = c.holes;
    return status;
}

/* PREFIX.png (the render), PREFIX-reference.png and PREFIX-error.png
 * (each channel's difference times 8). */
static reyes_status dump_images(const char *prefix, const reyes_image *image, const reyes_brute_image *reference,
                                reyes_error *error)
{
    char path[1024];
    snprintf(path, sizeof path, "%s.png", prefix);
    reyes_status status = reyes_write_png(path, image, error);
    reyes_image copy = *image;
    size_t n = (size_t)image->width * image->height * 3;
    uint8_t *difference = malloc(n);
    if (!difference)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory");
    for (size_t k = 0; k < n; ++k) {
        int d = abs((int)image->rgb[k] - (int)reference->rgb[k]) * 8;
        difference[k] = (uint8_t)(d > 255 ? 255 : d);
    }
    copy.samples = NULL;
    copy.rgb = reference->rgb;
    snprintf(path, sizeof path, "%s-reference.png", prefix);
    if (status == REYES_OK)
        status = reyes_write_png(path, &copy, error);
    copy.rgb = difference;
    snprintf(path, sizeof path, "%s-error.png", prefix);
    if (status == REYES_OK)
        status = reyes_write_png(path, &copy, error);
    free(difference);
    return status;
}

/* The FLIP error against the reference at the render's samples, and its
 * parts from pixels near silhouettes and near seams only. */
static reyes_status flip_at_samples(const reyes_image *image, const reyes_brute_image *reference,
                                    reyes_quality_result *out, reyes_error *error)
{
    size_t n = (size_t)image->width * image->height;
    float *map = malloc(n * sizeof *map);
    uint8_t *edges = malloc(n);
    out->flip = map && edges ? reyes_flip_mean(reference->rgb, image->rgb, image->width, image->height,
                                               REYES_FLIP_DEFAULT_PPD, map)
                             : -1.0;
    if (out->flip >= 0.0) {
        reyes_brute_edge_map(reference, edges);
        double silhouettes = 0.0, seams = 0.0;
        for (size_t k = 0; k < n; ++k) {
            silhouettes += edges[k] == 2 ? map[k] : 0.0f;
            seams += edges[k] == 1 ? map[k] : 0.0f;
        }
        out->flip_silhouettes = silhouettes / (double)n;
        out->flip_seams = seams / (double)n;
    }
    free(map);
    free(edges);
    if (out->flip < 0.0)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for FLIP at %ux%u", image->width,
                          image->height);
    return REYES_OK;
}

reyes_status reyes_quality_colour(reyes_renderer *renderer, const reyes_scene *scene, const reyes_camera *camera,
                                  const reyes_options *options, const reyes_quality_reference *reference,
                                  const char *dump, reyes_quality_result *out, reyes_error *error)
{
    reyes_image image;
    reyes_stats stats;
    reyes_status status = render_kept(renderer, scene, camera, options, options->spp, &image, &stats, error);
    if (status != REYES_OK)
        return status;
    if (reference->made & REYES_QUALITY_SAMPLES) {
        status = reyes_brute_compare(&image, &reference->many, &out->colour, error);
        if (status == REYES_OK && dump)
            status = dump_images(dump, &image, &reference->many, error);
        if (status == REYES_OK)
            status = flip_at_samples(&image, &reference->many, out, error);
    }
    if (status == REYES_OK && (reference->made & REYES_QUALITY_TRUTH)) {
        out->flip_truth = reyes_flip_mean(reference->truth.rgb, image.rgb, image.width, image.height,
                                          REYES_FLIP_DEFAULT_PPD, NULL);
        if (out->flip_truth < 0.0)
            status = reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for FLIP at %ux%u", image.width,
                                image.height);
    }
    size_t covered = 0;
    for (size_t k = 0; k < (size_t)image.width * image.height; ++k)
        covered += image.coverage[k] > 0;
    out->covered_pixels = covered;
    out->micropolygons = stats.micropolygons;
    out->grids = stats.grids;
    out->micropolygons_per_pixel = covered ? (double)stats.micropolygons / (double)covered : 0.0;
    out->area_mean = reyes_stats_area_mean(&stats);
    const double fractions[4] = {0.10, 0.50, 0.90, 0.99};
    for (int k = 0; k < 4; ++k)
        out->area_percentile[k] = reyes_stats_area_percentile(&stats, fractions[k]);
    reyes_image_free(&image);
    reyes_stats_free(&stats);
    return status;
}
