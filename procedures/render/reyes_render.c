/* One render: the buckets, each one perma run (reyes_render_tile.c), their
 * samples resolved into the image. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_render_stats.h"
#include "reyes_render_internal.h"
#include "reyes_renderer_internal.h"
#include "reyes_look.h"
#include "reyes_weld.h"

static void free_buffers(render_buffers *b)
{
    free(b->seeds);
    free(b->leaves);
    free(b->dice_seeds);
    free(b->near_order);
    free(b->stitch_seeds);
    reyes_stitch_plan_free(&b->plan);
    reyes_gray_map_free(&b->map);
    free(b->tuples);
}

/* Displacement parameters; reads the map.  Amplitude 0 is no displacement
 * (the very code path and image of an undisplaced render). */
static reyes_status set_displacement(const reyes_scene *scene, const reyes_options *o,
                                     render_buffers *b, reyes_error *error)
{
    struct reyes_params *p = &b->params;
    p->displace_mode = o->displace_amplitude == 0.0f ? REYES_DISPLACE_NONE : o->displace_mode;
    p->displace_amplitude = o->displace_amplitude;
    float lo[3], hi[3], radius = 0.0f;
    if (reyes_scene_bounds(scene, lo, hi))
        for (int k = 0; k < 3; ++k)
            radius = fmaxf(radius, 0.5f * (hi[k] - lo[k]));
    /* About twenty noise cells across the scene's half-size. */
    p->displace_frequency = radius > 0.0f ? 20.0f / radius : 1.0f;
    if (p->displace_mode != REYES_DISPLACE_MAP)
        return REYES_OK;
    reyes_status status = reyes_read_gray_png(o->displace_map, &b->map, error);
    p->map_width = b->map.width;
    p->map_height = b->map.height;
    return status;
}

/* The pool of (time, lens) tuples the blur algorithm draws from. */
static reyes_status make_blur_tuples(const reyes_options *o, render_buffers *b, reyes_error *error)
{
    const struct reyes_params *p = &b->params;
    if (!p->blur)
        return REYES_OK;
    b->tuple_count = reyes_blur_pool_size(p->blur_algo, p->blur_tile, p->spp);
    b->tuples = malloc(b->tuple_count * sizeof *b->tuples);
    if (!b->tuples)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu blur samples (%s)",
                          b->tuple_count, reyes_blur_algo_name(o->blur_algo));
    reyes_blur_fill_tuples(b->tuples, b->tuple_count, p->spp, p->time_samples);
    return REYES_OK;
}

static unsigned bucket_side(unsigned bucket, unsigned image)
{
    return bucket == 0 || bucket > image ? image : bucket;
}

static reyes_status allocate(const reyes_scene *scene, const reyes_options *o, render_buffers *b,
                             reyes_image *image, reyes_error *error)
{
    size_t pixels = (size_t)o->width * o->height;
    b->seeds = malloc((scene->patch_count ? scene->patch_count : 1) * sizeof *b->seeds);
    image->width = o->width;
    image->height = o->height;
    image->rgb = calloc(pixels, 3); /* 0 where a bucket source leaves buckets out */
    image->coverage = calloc(pixels, 1);
    image->spp = o->spp;
    if (o->keep_samples) {
        image->samples = malloc(pixels * o->spp * sizeof *image->samples);
        if (image->samples)
            memset(image->samples, 0xff, pixels * o->spp * sizeof *image->samples);
    }
    if (!b->seeds || !image->rgb || !image->coverage || (o->keep_samples && !image->samples))
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a %ux%u image (%zu bytes)", o->width,
                          o->height, pixels * (4 + (o->keep_samples ? o->spp * sizeof *image->samples : 0)));
    memset(b->counters, 0, sizeof b->counters);
    for (size_t i = 0; i < scene->patch_count; ++i)
        b->seeds[i] = (struct reyes_subpatch){ .patch = (uint32_t)i, .depth = 0,
                                               .u0 = 0.0f, .v0 = 0.0f, .u1 = 1.0f, .v1 = 1.0f,
                                               .edge_levels = 0xffffffffu }; /* unsettled edges */
    return REYES_OK;
}

static size_t tile_samples(const reyes_options *o, tile t)
{
    return (size_t)(t.x1 - t.x0) * (t.y1 - t.y0) * o->spp;
}

static void count_stats(const reyes_scene *scene, const render_buffers *b, reyes_stats *stats)
{
    stats->patches_in = scene->patch_count;
    stats->splits = b->counters[REYES_COUNT_SPLITS];
    stats->culled = b->counters[REYES_COUNT_CULLED];
    stats->grids = b->counters[REYES_COUNT_GRIDS];
    stats->forced_dice = b->counters[REYES_COUNT_FORCED_DICE];
    stats->micropolygons = b->counters[REYES_COUNT_MICROPOLYGONS];
    stats->fillers = b->counters[REYES_COUNT_FILLERS];
    stats->occluded = b->counters[REYES_COUNT_OCCLUDED];
    stats->split_bound = b->counters[REYES_COUNT_SPLIT_BOUND];
    stats->split_edge = b->counters[REYES_COUNT_SPLIT_EDGE];
    stats->split_inner = b->counters[REYES_COUNT_SPLIT_INNER];
    stats->split_near = b->counters[REYES_COUNT_SPLIT_NEAR];
    uint64_t units;
    memcpy(&units, &b->counters[REYES_COUNT_AREA_SUM], sizeof units);
    stats->micropolygon_area = (double)units / (double)REYES_AREA_UNITS;
    for (unsigned k = 0; k < REYES_AREA_BINS; ++k)
        stats->micropolygon_area_bins[k] = b->counters[REYES_COUNT_AREA_BINS + k];
    stats->stitches = stats->procedures[REYES_PROC_STITCH].items;
}

/* The renderer's sample buffer, at least `bytes` long. */
static reyes_status reserve_samples(reyes_renderer *r, size_t bytes, reyes_error *error)
{
    if (r->samples && r->samples_bytes >= bytes)
        return REYES_OK;
    if (r->samples)
        clReleaseMemObject(r->samples);
    r->samples = NULL;
    r->samples_bytes = 0;
    /* Checked here: the driver may not survive the allocation failing inside it. */
    if (perma_check_memory(r->rt, bytes, "the sample buffer") != PERMA_OK)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "%s", perma_errmsg(r->rt));
    cl_int err;
    r->samples = clCreateBuffer(perma_cl_context(r->rt), CL_MEM_READ_WRITE, bytes, NULL, &err);
    if (err != CL_SUCCESS) {
        r->samples = NULL;
        return reyes_fail(error, REYES_ERR_RUNTIME, "clCreateBuffer for %zu bytes of samples failed (%d)", bytes,
                          (int)err);
    }
    r->samples_bytes = bytes;
    return REYES_OK;
}

/* Set the first `bytes` of the samples to REYES_EMPTY_SAMPLE (on the
 * device, before the run's clock starts). */
static reyes_status clear_samples(reyes_renderer *r, size_t bytes, reyes_error *error)
{
    const uint64_t empty = UINT64_MAX;
    cl_command_queue queue = perma_cl_queue(r->rt);
    cl_int err = clEnqueueFillBuffer(queue, r->samples, &empty, sizeof empty, 0, bytes, 0, NULL, NULL);
    if (err == CL_SUCCESS)
        err = clFinish(queue);
    if (err != CL_SUCCESS)
        return reyes_fail(error, REYES_ERR_RUNTIME, "clearing the samples failed (OpenCL error %d)", (int)err);
    return REYES_OK;
}

/* Resolve tile t's samples into the image (read where they are on a CPU
 * device: mapping copies nothing there). */
static reyes_status resolve_samples(reyes_renderer *r, const reyes_options *o, tile t, reyes_image *image,
                                    reyes_stats *stats, reyes_error *error)
{
    size_t bytes = tile_samples(o, t) * sizeof(uint64_t);
    cl_command_queue queue = perma_cl_queue(r->rt);
    cl_int err;
    const uint64_t *samples = clEnqueueMapBuffer(queue, r->samples, CL_TRUE, CL_MAP_READ, 0, bytes, 0, NULL, NULL,
                                                 &err);
    if (err != CL_SUCCESS)
        return reyes_fail(error, REYES_ERR_RUNTIME, "reading the samples failed (OpenCL error %d)", (int)err);
    stats->samples_written += reyes_resolve(samples, o->spp, o->background, t.x0, t.y0, t.x1, t.y1, image);
    err = clEnqueueUnmapMemObject(queue, r->samples, (void *)samples, 0, NULL, NULL);
    if (err == CL_SUCCESS)
        err = clFinish(queue);
    if (err != CL_SUCCESS)
        return reyes_fail(error, REYES_ERR_RUNTIME, "releasing the samples failed (OpenCL error %d)", (int)err);
    return REYES_OK;
}

/* Render one tile: a perma run (unless there is nothing to seed), then
 * resolve. */
static reyes_status render_tile(reyes_renderer *r, const reyes_scene *scene, const reyes_options *o, tile t,
                                render_buffers *b, reyes_image *image, reyes_stats *stats, size_t *peak_bytes,
                                reyes_error *error)
{
    reyes_status status = clear_samples(r, tile_samples(o, t) * sizeof(uint64_t), error);
    if (status != REYES_OK)
        return status;
    render_set_tile(&b->params, o, t);
    if (b->stitched)
        render_select_stitched_seeds(o, t, b);
    int work = b->stitched ? b->dice_seed_count + b->stitch_seed_count > 0 : scene->patch_count > 0;
    *peak_bytes = 0;
    if (work) {
        const char *call = "";
        perma_status ps = render_run_tile(r, scene, b, stats, peak_bytes, &call);
        if (ps != PERMA_OK)
            return reyes_runtime_error(r, call, ps, error);
    }
    return resolve_samples(r, o, t, image, stats, error);
}

/* The points the run reads: with polylines the scene's welded (made once
 * per scene and kept in the renderer), else the scene's own. */
static reyes_status choose_points(reyes_renderer *r, const reyes_scene *scene, const reyes_options *o,
                                  render_buffers *b, reyes_error *error)
{
    b->points = scene->points;
    if (o->crack_fix != REYES_CRACK_FIX_POLYLINE || scene->patch_count == 0)
        return REYES_OK;
    uint64_t hash = reyes_points_hash(scene);
    if (!r->welded || r->welded_from != scene->points || r->welded_count != scene->patch_count
        || r->welded_hash != hash) {
        free(r->welded);
        r->welded = NULL;
        size_t moved;
        reyes_status status = reyes_weld_points(scene, &r->welded, &moved, error);
        if (status != REYES_OK)
            return status;
        r->welded_from = scene->points;
        r->welded_count = scene->patch_count;
        r->welded_hash = hash;
    }
    b->points = r->welded;
    return REYES_OK;
}

/* Seeds front to back for occlusion culling in one pass (polylines, no
 * crack fix): each base patch by its control points' nearest clip w, in
 * REYES_SEED_BINS bins between the scene's nearest and farthest (a
 * counting sort, stable: patch order within a bin), those reaching the
 * near plane first.  Small patches (the killeroo's) are diced whole, in
 * about this order, so the near ones are drawn before the far ones they
 * hide are tested (reyes_occlusion.cl); the image does not depend on it. */
#define REYES_SEED_BINS 4096u
static reyes_status order_seeds_front_to_back(const reyes_scene *scene, render_buffers *b, reyes_error *error)
{
    size_t n = scene->patch_count;
    if (!b->params.occlusion_cull || n < 2)
        return REYES_OK;
    float *near = malloc(n * sizeof *near);
    uint32_t *count = calloc(REYES_SEED_BINS + 1, sizeof *count);
    struct reyes_subpatch *sorted = malloc(n * sizeof *sorted);
    if (!near || !count || !sorted) {
        free(near), free(count), free(sorted);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory ordering %zu patches", n);
    }
    const float *m = b->params.view_proj + 12;
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; ++i) {
        const float *cp = b->points + i * 64;
        float w = INFINITY;
        for (int k = 0; k < 16; ++k)
            w = fminf(w, m[0] * cp[4 * k] + m[1] * cp[4 * k + 1] + m[2] * cp[4 * k + 2] + m[3]);
        near[i] = w > b->params.near_w ? w : -INFINITY;
        if (near[i] > -INFINITY) {
            lo = fminf(lo, w);
            hi = fmaxf(hi, w);
        }
    }
    float scale = hi > lo ? (float)(REYES_SEED_BINS - 1) / (hi - lo) : 0.0f;
    for (size_t i = 0; i < n; ++i) {
        uint32_t bin = near[i] == -INFINITY ? 0u : 1u + (uint32_t)((near[i] - lo) * scale);
        near[i] = (float)bin;
        ++count[bin < REYES_SEED_BINS ? bin : REYES_SEED_BINS];
    }
    for (uint32_t k = 1; k <= REYES_SEED_BINS; ++k)
        count[k] += count[k - 1];
    for (size_t i = n; i-- > 0;) {
        uint32_t bin = (uint32_t)near[i];
        sorted[--count[bin < REYES_SEED_BINS ? bin : REYES_SEED_BINS]] = b->seeds[i];
    }
    memcpy(b->seeds, sorted, n * sizeof *sorted);
    free(near), free(count), free(sorted);
    return REYES_OK;
}

/* Render every bucket, row by row (one bucket: the whole image). */
static reyes_status render_buckets(reyes_renderer *r, const reyes_scene *scene,
                                   const reyes_options *o, render_buffers *b, reyes_image *image,
                                   reyes_stats *stats, reyes_error *error)
{
    unsigned bw = bucket_side(o->bucket_width, o->width);
    unsigned bh = bucket_side(o->bucket_height, o->height);
    stats->bucket_columns = (o->width + bw - 1) / bw;
    stats->bucket_rows = (o->height + bh - 1) / bh;
    size_t count = (size_t)stats->bucket_columns * stats->bucket_rows;
    reyes_status reserved = reserve_samples(r, (size_t)bw * bh * o->spp * sizeof(uint64_t), error);
    if (reserved != REYES_OK)
        return reserved;
    if (o->bucket_width > 0) {
        stats->bucket_peak_queue_bytes = calloc(count, sizeof *stats->bucket_peak_queue_bytes);
        if (!stats->bucket_peak_queue_bytes)
            return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu buckets", count);
    }
    b->stitched = o->crack_fix == REYES_CRACK_FIX_STITCH && o->stages == REYES_STAGES_ALL
                  && scene->patch_count > 0;
    if (b->stitched) {
        reyes_status status = render_subdivide_and_plan(r, scene, o, b, stats, error);
        if (status != REYES_OK)
            return status;
    } else {
        reyes_status status = order_seeds_front_to_back(scene, b, error);
        if (status != REYES_OK)
            return status;
    }
    const reyes_bucket_source *source = o->bucket_source;
    for (size_t next = 0;; ++next) {
        unsigned bucket = (unsigned)next;
        if (source ? !source->next(source->user, &bucket) : next >= count)
            break;
        if (bucket >= count)
            return reyes_fail(error, REYES_ERR_ARGUMENT, "the bucket source gave bucket %u of %zu",
                              bucket, count);
        size_t k = bucket;
        unsigned column = (unsigned)(k % stats->bucket_columns);
        unsigned row = (unsigned)(k / stats->bucket_columns);
        tile t = { column * bw, row * bh, 0, 0 };
        t.x1 = t.x0 + bw < o->width ? t.x0 + bw : o->width;
        t.y1 = t.y0 + bh < o->height ? t.y0 + bh : o->height;
        size_t peak;
        reyes_status tiled = render_tile(r, scene, o, t, b, image, stats, &peak, error);
        if (tiled != REYES_OK)
            return tiled;
        if (stats->bucket_peak_queue_bytes)
            stats->bucket_peak_queue_bytes[k] = peak;
        reyes_status status = source && source->done
                                  ? source->done(source->user, bucket, image, t.x0, t.y0, t.x1, t.y1, error)
                                  : REYES_OK;
        if (status != REYES_OK)
            return status;
    }
    count_stats(scene, b, stats);
    return REYES_OK;
}

reyes_status reyes_render(reyes_renderer *r, const reyes_scene *scene, const reyes_camera *camera,
                          const reyes_options *options, reyes_image *image, reyes_stats *stats,
                          reyes_error *error)
{
    memset(image, 0, sizeof *image);
    reyes_stats local;
    if (!stats)
        stats = &local;
    memset(stats, 0, sizeof *stats);
    for (int p = 0; p < REYES_PROC_COUNT; ++p)
        stats->procedures[p].name = "";
    reyes_status status = reyes_options_check(options, error);
    if (status != REYES_OK)
        return status;
    if (options->grid != r->grid)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "grid %u differs from the renderer's grid %u (create a new renderer)",
                          options->grid, r->grid);
    if (options->motion_angle_deg != 0.0f && !r->vertex_motion)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "a motion rotation needs a renderer created with one (per-vertex motion; "
                          "create a new renderer)");
    render_buffers b = {0};
    status = render_fill_params(scene, camera, options, &b.params, error);
    if (status == REYES_OK)
        status = set_displacement(scene, options, &b, error);
    if (status == REYES_OK)
        status = make_blur_tuples(options, &b, error);
    if (status == REYES_OK)
        status = allocate(scene, options, &b, image, error);
    if (status == REYES_OK)
        status = choose_points(r, scene, options, &b, error);
    if (status == REYES_OK)
        status = render_buckets(r, scene, options, &b, image, stats, error);
    free_buffers(&b);
    if (status != REYES_OK)
        reyes_image_free(image);
    if (status != REYES_OK || stats == &local)
        reyes_stats_free(stats);
    return status;
}
