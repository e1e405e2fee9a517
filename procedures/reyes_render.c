/* One render: bind the scene, seed bound, run, resolve the samples. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_blur_tuples.h"
#include "reyes_render_stats.h"
#include "reyes_renderer_internal.h"
#include "reyes_look.h"
#include "reyes_stitch_plan.h"
#include "reyes_shared.h"

/* The per-render buffers handed to perma_bind_host. */
typedef struct render_buffers {
    struct reyes_params params;
    uint32_t counters[REYES_COUNTERS];
    struct reyes_subpatch *seeds;   /* one per base patch */
    /* Crack stitching: the leaves of the first pass, the plan, and the
     * seeds of one bucket (dice: leaves, stitch: items). */
    int stitched;
    struct reyes_leaf *leaves;
    size_t leaf_count, leaf_capacity;
    reyes_stitch_plan plan;
    struct reyes_subpatch *dice_seeds;
    struct reyes_stitch *stitch_seeds;
    size_t dice_seed_count, stitch_seed_count;
    reyes_gray_map map;             /* displacement map (or none) */
    reyes_blur_tuple *tuples;       /* motion blur and defocus (or none) */
    size_t tuple_count;
} render_buffers;

static void free_buffers(render_buffers *b)
{
    free(b->seeds);
    free(b->leaves);
    free(b->dice_seeds);
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

/* A bucket: pixels [x0,x1) x [y0,y1) of the image. */
typedef struct tile {
    unsigned x0, y0, x1, y1;
} tile;

/* Motion blur and depth of field in clip space: the motion's clip-space
 * delta (the matrix without translation) and the lens radius in clip x
 * and y units (rows 0 and 1 scale the camera's right and up vectors).
 * Off, and the unblurred code path, when both are zero. */
/* (R - I) for the rotation by `deg` degrees about `axis` (Rodrigues),
 * in double: the part of a vertex's motion that depends on its position. */
static void rotation_minus_identity(const float axis[3], float deg, double out[9])
{
    double a[3], length = 0.0;
    for (int k = 0; k < 3; ++k)
        length += (double)axis[k] * axis[k];
    length = sqrt(length);
    for (int k = 0; k < 3; ++k)
        a[k] = axis[k] / length;
    double theta = deg * (3.14159265358979323846 / 180.0), c = cos(theta), s = sin(theta);
    const double cross[9] = {0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0};
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k)
            out[r * 3 + k] = (c - 1.0) * (r == k) + s * cross[r * 3 + k] + (1.0 - c) * a[r] * a[k];
}

/* A vertex at world p moves by (R - I)(p - target) + motion over the
 * shutter, clip-space motion M3 (R - I) p + M3 (motion - (R - I) target)
 * (M3 the matrix without translation; rows x, y, w): an affine map of p,
 * motion_rows.  Without a rotation its linear part is 0 and the constant
 * column is the uniform motion, computed as before. */
static void set_motion(const reyes_camera *camera, const reyes_options *o, struct reyes_params *p)
{
    const float *m = p->view_proj;
    double rot[9] = {0};
    p->motion_rotates = o->motion_angle_deg != 0.0f;
    if (p->motion_rotates)
        rotation_minus_identity(o->motion_axis, o->motion_angle_deg, rot);
    float d[3];
    for (int k = 0; k < 3; ++k) {
        double moved = rot[k * 3] * camera->at[0] + rot[k * 3 + 1] * camera->at[1]
                       + rot[k * 3 + 2] * camera->at[2];
        d[k] = (float)(o->motion[k] - moved);
    }
    const int rows[3] = {0, 1, 3};
    for (int r = 0; r < 3; ++r) {
        const float *row = m + rows[r] * 4;
        for (int k = 0; k < 3; ++k)
            p->motion_rows[r * 4 + k] = (float)(row[0] * rot[k] + row[1] * rot[3 + k] + row[2] * rot[6 + k]);
        p->motion_rows[r * 4 + 3] = row[0] * d[0] + row[1] * d[1] + row[2] * d[2];
    }
}

static void set_blur(const reyes_camera *camera, const reyes_options *o, struct reyes_params *p)
{
    const float *m = p->view_proj, *d = o->motion;
    p->blur = d[0] != 0.0f || d[1] != 0.0f || d[2] != 0.0f || o->aperture != 0.0f
              || o->motion_angle_deg != 0.0f;
    if (!p->blur)
        return;
    p->time_samples = o->time_samples ? o->time_samples : o->spp;
    p->blur_algo = o->blur_algo;
    p->blur_tile = o->blur_tile;
    p->blur_permutations = o->blur_permutations;
    set_motion(camera, o, p);
    p->lens_x = o->aperture * sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    p->lens_y = o->aperture * sqrtf(m[4] * m[4] + m[5] * m[5] + m[6] * m[6]);
    float target = 0.0f;
    for (int k = 0; k < 3; ++k)
        target += (camera->at[k] - camera->eye[k]) * (camera->at[k] - camera->eye[k]);
    p->focus = o->focus > 0.0f ? o->focus : sqrtf(target);
    if (!(p->focus > 0.0f))
        p->focus = 1.0f;
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

static reyes_status fill_params(const reyes_scene *scene, const reyes_camera *camera,
                                const reyes_options *o,
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
    reyes_light_direction(p->light_dir);
    p->width = (float)o->width;
    p->height = (float)o->height;
    p->bound_px = o->bound_px;
    p->subdivision = o->subdivision;
    p->flat_epsilon = o->flat_epsilon;
    p->flat_lambda = o->flat_lambda;
    p->flat_cap_px = o->flat_bound_px > 0.0f ? o->flat_bound_px : (float)(o->grid - 1u);
    p->wedges = o->crack_fix == REYES_CRACK_FIX_WEDGE ? 1u : 0u;
    p->cull_margin = o->cull_margin;
    p->ambient = REYES_AMBIENT;
    p->diffuse = REYES_DIFFUSE;
    p->specular = REYES_SPECULAR;
    p->shininess = REYES_SHININESS;
    p->max_depth = o->max_depth;
    p->grid = o->grid;
    p->shading_rate = o->shading_rate;
    p->show_grid_sizes = o->show_grid_sizes ? 1u : 0u;
    p->spp = o->spp;
    p->backface_cull = o->backface_cull ? 1u : 0u;
    p->stages = o->stages;
    set_blur(camera, o, p);
    return REYES_OK;
}

/* Point the parameters at one tile: its pixel rectangle and its
 * sub-frustum in normalised device coordinates (exactly -1 and 1 at the
 * image borders, so the whole image culls as without buckets). */
static void set_tile(struct reyes_params *p, const reyes_options *o, tile t)
{
    p->tile_x0 = (float)t.x0;
    p->tile_y0 = (float)t.y0;
    p->tile_x1 = (float)t.x1;
    p->tile_y1 = (float)t.y1;
    p->ndc_left = (float)(2.0 * t.x0 / o->width - 1.0);
    p->ndc_right = (float)(2.0 * t.x1 / o->width - 1.0);
    p->ndc_top = (float)(1.0 - 2.0 * t.y0 / o->height);
    p->ndc_bottom = (float)(1.0 - 2.0 * t.y1 / o->height);
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
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for a %ux%u image", o->width,
                          o->height);
    memset(b->counters, 0, sizeof b->counters);
    for (size_t i = 0; i < scene->patch_count; ++i)
        b->seeds[i] = (struct reyes_subpatch){ .patch = (uint32_t)i, .depth = 0,
                                               .u0 = 0.0f, .v0 = 0.0f, .u1 = 1.0f, .v1 = 1.0f };
    return REYES_OK;
}

static size_t tile_samples(const reyes_options *o, tile t)
{
    return (size_t)(t.x1 - t.x0) * (t.y1 - t.y0) * o->spp;
}

/* Bind every buffer for a run (unused ones get a dummy). */
static perma_status bind_buffers(reyes_renderer *r, const reyes_scene *scene, render_buffers *b)
{
    static struct reyes_leaf no_leaf;
    static struct reyes_stitch_piece no_piece;
    perma_runtime *rt = r->rt;
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
    /* The first pass of stitching rasterizes nothing (its tile, the whole
     * image, may be larger than the sample buffer). */
    int recording = b->params.record_leaves != 0;
    if (s == PERMA_OK)
        s = perma_bind_cl(rt, "samples", "__global ulong *", r->samples);
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "leaves", "__global struct reyes_leaf *",
                            recording ? (void *)b->leaves : (void *)&no_leaf,
                            recording ? b->leaf_capacity * sizeof *b->leaves : sizeof no_leaf,
                            recording ? PERMA_WRITE : PERMA_READ);
    static uint8_t no_map;
    int has_map = b->map.gray != NULL;
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "displacement_map", "__global const uchar *",
                            has_map ? (void *)b->map.gray : (void *)&no_map,
                            has_map ? (size_t)b->map.width * b->map.height : 1, PERMA_READ);
    static reyes_blur_tuple no_tuple;
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "blur_tuples", "__global const float4 *",
                            b->tuples ? (void *)b->tuples : (void *)&no_tuple,
                            b->tuples ? b->tuple_count * sizeof *b->tuples : sizeof no_tuple, PERMA_READ);
    int pieces = b->plan.piece_count > 0;
    if (s == PERMA_OK)
        s = perma_bind_host(rt, "pieces", "__global const struct reyes_stitch_piece *",
                            pieces ? (void *)b->plan.pieces : (void *)&no_piece,
                            pieces ? b->plan.piece_count * sizeof *b->plan.pieces : sizeof no_piece,
                            PERMA_READ);
    return s;
}

/* Seed the run: bound with every base patch, or (stitched) dice with the
 * bucket's leaves and stitch with its items. */
static perma_status seed(reyes_renderer *r, const reyes_scene *scene, render_buffers *b)
{
    if (!b->stitched || b->params.record_leaves)
        return perma_seed(r->rt, r->procs[REYES_PROC_BOUND], b->seeds, scene->patch_count);
    perma_status s = PERMA_OK;
    if (b->dice_seed_count)
        s = perma_seed(r->rt, r->procs[REYES_PROC_DICE], b->dice_seeds, b->dice_seed_count);
    if (s == PERMA_OK && b->stitch_seed_count)
        s = perma_seed(r->rt, r->procs[REYES_PROC_STITCH], b->stitch_seeds, b->stitch_seed_count);
    return s;
}

/* Add the last run's runtime statistics to *stats; *peak_bytes: its peak
 * queue memory. */
static perma_status add_run_stats(reyes_renderer *r, reyes_stats *stats, size_t *peak_bytes)
{
    perma_stats run;
    perma_procedure_stats procedures[REYES_PROC_COUNT];
    perma_status s = perma_get_stats(r->rt, &run);
    for (int p = 0; p < REYES_PROC_COUNT && s == PERMA_OK; ++p)
        s = perma_get_procedure_stats(r->rt, r->procs[p], &procedures[p]);
    if (s == PERMA_OK) {
        reyes_stats_add_run(stats, &run, procedures);
        *peak_bytes = run.peak_queue_bytes;
    }
    return s;
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
    stats->split_bound = b->counters[REYES_COUNT_SPLIT_BOUND];
    stats->split_edge = b->counters[REYES_COUNT_SPLIT_EDGE];
    stats->split_inner = b->counters[REYES_COUNT_SPLIT_INNER];
    stats->split_near = b->counters[REYES_COUNT_SPLIT_NEAR];
    stats->stitches = stats->procedures[REYES_PROC_STITCH].items;
}

/* One perma run over the tile in b->params with the seeds of the current
 * mode; adds its statistics.  *call names what failed. */
static perma_status run_tile(reyes_renderer *r, const reyes_scene *scene, render_buffers *b, reyes_stats *stats,
                             size_t *peak_bytes, const char **call)
{
    *call = "binding the scene";
    perma_status ps = bind_buffers(r, scene, b);
    if (ps == PERMA_OK)
        ps = seed(r, scene, b);
    if (ps == PERMA_OK) {
        *call = "perma_run";
        ps = perma_run(r->rt);
    }
    if (ps == PERMA_OK) {
        *call = "reading the statistics";
        ps = add_run_stats(r, stats, peak_bytes);
    }
    return ps;
}

/* First pass of crack stitching, over the whole image: bound and split
 * record the sub-patches to dice (retrying with a larger buffer if they
 * did not fit), then the stitch plan is built from them. */
static reyes_status subdivide_and_plan(reyes_renderer *r, const reyes_scene *scene,
                                       const reyes_options *o, render_buffers *b,
                                       reyes_stats *stats, reyes_error *error)
{
    tile whole = { 0, 0, o->width, o->height };
    set_tile(&b->params, o, whole);
    b->params.record_leaves = 1;
    b->leaf_capacity = scene->patch_count * 16 + 1024;
    /* This pass (bound and split only) starts from the initial capacities,
     * not from what an earlier render's last run grew them to (the whole
     * pipeline, perhaps over the whole image): its peak queue memory is its
     * own, so a bucketed render's peak_queue_bytes is its largest bucket's
     * whenever the buckets need more than this pass. */
    perma_forget_capacities(r->rt);
    for (;;) {
        struct reyes_leaf *grown = realloc(b->leaves, b->leaf_capacity * sizeof *grown);
        if (!grown)
            return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu grids",
                              b->leaf_capacity);
        b->leaves = grown;
        b->params.leaf_capacity = (uint32_t)b->leaf_capacity;
        memset(b->counters, 0, sizeof b->counters);
        reyes_stats attempt = *stats;
        const char *call = "";
        size_t peak;
        perma_status ps = run_tile(r, scene, b, &attempt, &peak, &call);
        if (ps != PERMA_OK)
            return reyes_runtime_error(r, call, ps, error);
        size_t recorded = b->counters[REYES_COUNT_LEAVES];
        if (recorded <= b->leaf_capacity) {
            *stats = attempt;
            b->leaf_count = recorded;
            break;
        }
        b->leaf_capacity = recorded;
    }
    b->params.record_leaves = 0;
    /* The buckets need much smaller queues than this pass over the whole
     * image: let them grow their own. */
    perma_forget_capacities(r->rt);
    reyes_leaves_sort(b->leaves, b->leaf_count);
    b->dice_seeds = malloc((b->leaf_count ? b->leaf_count : 1) * sizeof *b->dice_seeds);
    if (!b->dice_seeds)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu grids", b->leaf_count);
    reyes_status status = reyes_stitch_plan_build(scene, b->leaves, b->leaf_count, &b->plan, error);
    if (status != REYES_OK)
        return status;
    b->stitch_seeds = malloc((b->plan.item_count ? b->plan.item_count : 1) * sizeof *b->stitch_seeds);
    if (!b->stitch_seeds)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory for %zu stitches",
                          b->plan.item_count);
    return REYES_OK;
}

/* 1 if screen box (lo_x, lo_y, hi_x, hi_y) reaches tile t widened by the
 * cull margin; always 1 without buckets. */
static int box_meets_tile(const reyes_options *o, tile t, float lo_x, float lo_y, float hi_x,
                          float hi_y)
{
    if (o->bucket_width == 0)
        return 1;
    float mx = o->cull_margin * 0.5f * (float)o->width, my = o->cull_margin * 0.5f * (float)o->height;
    return hi_x >= (float)t.x0 - mx && lo_x <= (float)t.x1 + mx && hi_y >= (float)t.y0 - my
           && lo_y <= (float)t.y1 + my;
}

/* The stitched seeds of tile t: leaves and stitch items whose screen box
 * reaches it; the leaves left out count as culled. */
static void select_stitched_seeds(const reyes_options *o, tile t, render_buffers *b)
{
    b->dice_seed_count = b->stitch_seed_count = 0;
    for (size_t l = 0; l < b->leaf_count; ++l) {
        const struct reyes_leaf *leaf = &b->leaves[l];
        if (box_meets_tile(o, t, leaf->lo_x, leaf->lo_y, leaf->hi_x, leaf->hi_y))
            b->dice_seeds[b->dice_seed_count++] = leaf->sp;
        else
            ++b->counters[REYES_COUNT_CULLED];
    }
    for (size_t k = 0; k < b->plan.item_count; ++k) {
        const float *box = b->plan.item_boxes[k];
        if (box_meets_tile(o, t, box[0], box[1], box[2], box[3]))
            b->stitch_seeds[b->stitch_seed_count++] = b->plan.items[k];
    }
}

/* The renderer's sample buffer, at least `bytes` long. */
static reyes_status reserve_samples(reyes_renderer *r, size_t bytes, reyes_error *error)
{
    if (r->samples && r->samples_bytes >= bytes)
        return REYES_OK;
    if (r->samples)
        clReleaseMemObject(r->samples);
    r->samples_bytes = 0;
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
    set_tile(&b->params, o, t);
    if (b->stitched)
        select_stitched_seeds(o, t, b);
    int work = b->stitched ? b->dice_seed_count + b->stitch_seed_count > 0 : scene->patch_count > 0;
    *peak_bytes = 0;
    if (work) {
        const char *call = "";
        perma_status ps = run_tile(r, scene, b, stats, peak_bytes, &call);
        if (ps != PERMA_OK)
            return reyes_runtime_error(r, call, ps, error);
    }
    return resolve_samples(r, o, t, image, stats, error);
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
        reyes_status status = subdivide_and_plan(r, scene, o, b, stats, error);
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
    status = fill_params(scene, camera, options, &b.params, error);
    if (status == REYES_OK)
        status = set_displacement(scene, options, &b, error);
    if (status == REYES_OK)
        status = make_blur_tuples(options, &b, error);
    if (status == REYES_OK)
        status = allocate(scene, options, &b, image, error);
    if (status == REYES_OK)
        status = render_buckets(r, scene, options, &b, image, stats, error);
    free_buffers(&b);
    if (status != REYES_OK)
        reyes_image_free(image);
    if (status != REYES_OK || stats == &local)
        reyes_stats_free(stats);
    return status;
}
