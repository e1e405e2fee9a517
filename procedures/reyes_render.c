/* One render: bind the scene, seed bound, run, resolve the samples. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_renderer_internal.h"
#include "reyes_shared.h"

#define EMPTY_SAMPLE UINT64_MAX

void reyes_image_free(reyes_image *image)
{
    if (!image)
        return;
    free(image->rgb);
    free(image->coverage);
    memset(image, 0, sizeof *image);
}

/* The per-render buffers handed to perma_bind_host. */
typedef struct render_buffers {
    struct reyes_params params;
    uint32_t counters[REYES_COUNTERS];
    uint64_t *samples;
    struct reyes_subpatch *seeds;
} render_buffers;

static reyes_status fill_params(const reyes_scene *scene, const reyes_camera *camera,
                                const reyes_options *o, unsigned dice_threads,
                                struct reyes_params *p, reyes_error *error)
{
    memset(p, 0, sizeof *p);
    /* Nothing closer than this is projected; patches crossing it are split. */
    p->near_w = reyes_near_plane(scene);
    reyes_status status = reyes_camera_matrix(camera, (float)o->width / (float)o->height, p->near_w,
                                              p->view_proj, error);
    if (status != REYES_OK)
        return status;
    for (int k = 0; k < 3; ++k)
        p->eye[k] = camera->eye[k];
    /* Light from the upper left behind the viewer, in world space (z up). */
    const float light[3] = {-0.4f, -0.5f, 0.77f};
    float length = sqrtf(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    for (int k = 0; k < 3; ++k)
        p->light_dir[k] = light[k] / length;
    p->width = (float)o->width;
    p->height = (float)o->height;
    p->bound_px = o->bound_px;
    p->cull_margin = o->cull_margin;
    p->ambient = 0.18f;
    p->diffuse = 0.82f;
    p->specular = 0.35f;
    p->shininess = 40.0f;
    p->max_depth = o->max_depth;
    p->grid = o->grid;
    p->spp = o->spp;
    p->backface_cull = o->backface_cull ? 1u : 0u;
    p->dice_threads = dice_threads;
    p->stages = o->stages;
    return REYES_OK;
}

static reyes_status allocate(const reyes_scene *scene, const reyes_options *o, render_buffers *b,
                             reyes_image *image, reyes_error *error)
{
    size_t pixels = (size_t)o->width * o->height;
    size_t samples = pixels * o->spp;
    b->samples = malloc(samples * sizeof *b->samples);
    b->seeds = malloc((scene->patch_count ? scene->patch_count : 1) * sizeof *b->seeds);
    image->width = o->width;
    image->height = o->height;
    image->rgb = malloc(pixels * 3);
    image->coverage = malloc(pixels);
    if (!b->samples || !b->seeds || !image->rgb || !image->coverage)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a %ux%u image", o->width,
                          o->height);
    memset(b->samples, 0xff, samples * sizeof *b->samples);
    memset(b->counters, 0, sizeof b->counters);
    for (size_t i = 0; i < scene->patch_count; ++i)
        b->seeds[i] = (struct reyes_subpatch){ .patch = (uint32_t)i, .depth = 0,
                                               .u0 = 0.0f, .v0 = 0.0f, .u1 = 1.0f, .v1 = 1.0f };
    return REYES_OK;
}

static perma_status bind_and_seed(reyes_renderer *r, const reyes_scene *scene,
                                  const reyes_options *o, render_buffers *b)
{
    perma_runtime *rt = r->rt;
    size_t samples = (size_t)o->width * o->height * o->spp;
    perma_status s = perma_bind_host(rt, "patches", "__global const float4 *", scene->points,
                                     scene->patch_count * 64 * sizeof(float), PERMA_READ);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "colors", "__global const uint *", scene->colors,
                            scene->patch_count * sizeof(uint32_t), PERMA_READ);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "params", "__global const struct reyes_params *", &b->params,
                            sizeof b->params, PERMA_READ);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "counters", "__global uint *", b->counters, sizeof b->counters,
                            PERMA_READ_WRITE);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "samples", "__global ulong *", b->samples,
                            samples * sizeof *b->samples, PERMA_READ_WRITE);
    if (s == PERMA_OK)
        s = perma_seed(rt, r->procs[REYES_PROC_BOUND], b->seeds, scene->patch_count);
    return s;
}

/* Average the samples of each pixel; empty samples show the background. */
static uint64_t resolve(const uint64_t *samples, const reyes_options *o, reyes_image *image)
{
    uint64_t written = 0;
    size_t pixels = (size_t)o->width * o->height;
    for (size_t px = 0; px < pixels; ++px) {
        unsigned sum[3] = {0, 0, 0}, hits = 0;
        for (unsigned s = 0; s < o->spp; ++s) {
            uint64_t sample = samples[px * o->spp + s];
            uint32_t rgba = o->background;
            if (sample != EMPTY_SAMPLE) {
                rgba = (uint32_t)sample;
                ++hits;
            }
            for (int c = 0; c < 3; ++c)
                sum[c] += (rgba >> (8 * c)) & 255u;
        }
        for (int c = 0; c < 3; ++c)
            image->rgb[px * 3 + c] = (uint8_t)((sum[c] + o->spp / 2) / o->spp);
        image->coverage[px] = (uint8_t)hits;
        written += hits;
    }
    return written;
}

static perma_status collect_stats(reyes_renderer *r, const reyes_scene *scene,
                                  const render_buffers *b, uint64_t written, reyes_stats *stats)
{
    memset(stats, 0, sizeof *stats);
    stats->patches_in = scene->patch_count;
    stats->splits = b->counters[REYES_COUNT_SPLITS];
    stats->culled = b->counters[REYES_COUNT_CULLED];
    stats->grids = b->counters[REYES_COUNT_GRIDS];
    stats->forced_dice = b->counters[REYES_COUNT_FORCED_DICE];
    stats->micropolygons = b->counters[REYES_COUNT_MICROPOLYGONS];
    stats->samples_written = written;
    for (int p = 0; p < REYES_PROC_COUNT; ++p)
        stats->procedures[p].name = "";
    if (scene->patch_count == 0)
        return PERMA_OK; /* nothing ran */
    perma_status s = perma_get_stats(r->rt, &stats->run);
    for (int p = 0; p < REYES_PROC_COUNT && s == PERMA_OK; ++p)
        s = perma_get_procedure_stats(r->rt, r->procs[p], &stats->procedures[p]);
    stats->peak_queue_bytes = stats->run.peak_queue_bytes;
    stats->seconds = stats->run.seconds;
    return s;
}

reyes_status reyes_render(reyes_renderer *r, const reyes_scene *scene, const reyes_camera *camera,
                          const reyes_options *options, reyes_image *image, reyes_stats *stats,
                          reyes_error *error)
{
    memset(image, 0, sizeof *image);
    reyes_status status = reyes_options_check(options, error);
    if (status != REYES_OK)
        return status;
    if (options->grid != r->grid)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "grid %u differs from the renderer's grid %u (create a new renderer)",
                          options->grid, r->grid);
    render_buffers b = {0};
    status = fill_params(scene, camera, options, r->dice_threads, &b.params, error);
    if (status == REYES_OK)
        status = allocate(scene, options, &b, image, error);
    perma_status ps = PERMA_OK;
    const char *call = "binding the scene";
    if (status == REYES_OK && scene->patch_count > 0) {
        ps = bind_and_seed(r, scene, options, &b);
        if (ps == PERMA_OK) {
            call = "perma_run";
            ps = perma_run(r->rt);
        }
        if (ps != PERMA_OK)
            status = reyes_runtime_error(r, call, ps, error);
    }
    if (status == REYES_OK) {
        uint64_t written = resolve(b.samples, options, image);
        reyes_stats local;
        ps = collect_stats(r, scene, &b, written, stats ? stats : &local);
        if (ps != PERMA_OK)
            status = reyes_runtime_error(r, "reading the statistics", ps, error);
    }
    free(b.samples);
    free(b.seeds);
    if (status != REYES_OK)
        reyes_image_free(image);
    return status;
}
