/* Render options: defaults and range checks. */
#include <math.h>
#include <string.h>

#include "reyes.h"
#include "reyes_shared.h"

void reyes_options_init(reyes_options *options)
{
    memset(options, 0, sizeof *options);
    options->width = 512;
    options->height = 512;
    options->bound_px = 8.0f;
    options->grid = 16;
    options->subdivision = REYES_SUBDIVISION_BOUND;
    options->flat_epsilon = 0.5f;
    options->flat_lambda = 0.5f;
    options->spp = 4;
    options->max_depth = 20;
    options->backface_cull = 0;
    options->occlusion_cull = 1;
    options->cull_margin = 0.05f;
    options->background = REYES_RGBA(24, 26, 32);
    options->crack_fix = REYES_CRACK_FIX_STITCH;
    options->blur_algo = REYES_BLUR_INTERLEAVED;
    options->blur_tile = 4;
    options->blur_permutations = 8;
    options->motion_axis[2] = 1.0f;
}

static const char *const blur_algo_names[] = { "simple", "interleaved", "bbox" };

const char *reyes_blur_algo_name(unsigned algo)
{
    return algo < sizeof blur_algo_names / sizeof blur_algo_names[0] ? blur_algo_names[algo] : NULL;
}

int reyes_blur_algo_parse(const char *name, unsigned *algo)
{
    for (unsigned a = 0; reyes_blur_algo_name(a); ++a) {
        if (strcmp(name, reyes_blur_algo_name(a)) == 0) {
            *algo = a;
            return 1;
        }
    }
    return 0;
}

/* The blur sampling fields (checked whether or not anything moves). */
static reyes_status check_blur_algo(const reyes_options *o, reyes_error *error)
{
    if (!reyes_blur_algo_name(o->blur_algo))
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "blur_algo %u is not %u (simple), %u (interleaved) or %u (bbox)",
                          o->blur_algo, REYES_BLUR_SIMPLE, REYES_BLUR_INTERLEAVED, REYES_BLUR_BBOX);
    if (o->blur_tile < 1 || o->blur_tile > REYES_MAX_BLUR_TILE)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "blur_tile %u is not in 1..%u", o->blur_tile,
                          REYES_MAX_BLUR_TILE);
    if (o->blur_permutations < 1 || o->blur_permutations > REYES_MAX_BLUR_PERMUTATIONS)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "blur_permutations %u is not in 1..%u",
                          o->blur_permutations, REYES_MAX_BLUR_PERMUTATIONS);
    return REYES_OK;
}

/* The rotation over the shutter: a finite axis, not zero-length when
 * anything rotates, and an angle within a turn (a vertex moves linearly
 * between its open and close positions, so more turns add nothing). */
static reyes_status check_rotation(const reyes_options *o, reyes_error *error)
{
    const float *a = o->motion_axis;
    double length = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (!isfinite(a[k]) || fabsf(a[k]) > 1e6f)
            return reyes_fail(error, REYES_ERR_ARGUMENT,
                              "motion rotation axis %g is not finite and within 1e6", (double)a[k]);
        length += (double)a[k] * a[k];
    }
    float angle = o->motion_angle_deg;
    if (!isfinite(angle) || fabsf(angle) > REYES_MAX_MOTION_ANGLE)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "motion rotation angle %g is not finite and within -%g..%g degrees",
                          (double)angle, (double)REYES_MAX_MOTION_ANGLE, (double)REYES_MAX_MOTION_ANGLE);
    if (angle != 0.0f && !(length > 0.0))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "motion rotation axis is zero-length");
    return REYES_OK;
}

reyes_status reyes_options_check(const reyes_options *o, reyes_error *error)
{
    if (o->width < 1 || o->height < 1 || o->width > REYES_MAX_SIZE || o->height > REYES_MAX_SIZE)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "image size %ux%u is not in 1..%u", o->width,
                          o->height, REYES_MAX_SIZE);
    if (!(o->bound_px >= 0.5f && o->bound_px <= 1e6f))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "bound %g px is not in 0.5..1e6",
                          (double)o->bound_px);
    if (o->grid < 2 || o->grid > REYES_MAX_GRID)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "grid %u is not in 2..%u", o->grid,
                          REYES_MAX_GRID);
    if (o->subdivision > REYES_SUBDIVISION_TIERED)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "subdivision %u is not %u (bound) or %u (tiered)",
                          o->subdivision, REYES_SUBDIVISION_BOUND, REYES_SUBDIVISION_TIERED);
    if (!(o->flat_epsilon >= 0.01f && o->flat_epsilon <= REYES_MAX_EPSILON))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "flatness epsilon %g px is not in 0.01..%g",
                          (double)o->flat_epsilon, (double)REYES_MAX_EPSILON);
    if (!(o->flat_bound_px == 0.0f || (o->flat_bound_px >= 0.5f && o->flat_bound_px <= 1e6f)))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "tiered bound %g px is not 0 or in 0.5..1e6",
                          (double)o->flat_bound_px);
    if (!(o->flat_lambda >= 0.0f && o->flat_lambda <= 1.0f))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "flatness lambda %g is not in 0..1",
                          (double)o->flat_lambda);
    if (o->spp < 1 || o->spp > REYES_MAX_SPP)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "samples per pixel %u is not in 1..%u", o->spp,
                          REYES_MAX_SPP);
    if (o->max_depth > REYES_MAX_DEPTH)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "max depth %u is not in 0..%u", o->max_depth,
                          REYES_MAX_DEPTH);
    if (!(o->cull_margin >= 0.0f && o->cull_margin <= 10.0f))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "cull margin is not in 0..10");
    /* The sample buffer holds one 64-bit word per sample; keep it under 4 GiB
     * and its indices within 32 bits. */
    if ((uint64_t)o->width * o->height * o->spp > (1ull << 29))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "%ux%u at %u samples per pixel is too many samples",
                          o->width, o->height, o->spp);
    if (o->stages > REYES_STAGES_SUBDIVIDE)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "stages %u is not %u..%u", o->stages,
                          REYES_STAGES_ALL, REYES_STAGES_SUBDIVIDE);
    if (o->displace_mode > REYES_DISPLACE_MAP)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "displacement mode %u is not %u..%u",
                          o->displace_mode, REYES_DISPLACE_NONE, REYES_DISPLACE_MAP);
    if (!isfinite(o->displace_amplitude) || fabsf(o->displace_amplitude) > 1e6f)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "displacement amplitude %g is not finite and "
                          "within 1e6", (double)o->displace_amplitude);
    if (o->displace_mode == REYES_DISPLACE_MAP && !o->displace_map)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "map displacement needs a PNG file");
    for (int k = 0; k < 3; ++k)
        if (!isfinite(o->motion[k]) || fabsf(o->motion[k]) > 1e6f)
            return reyes_fail(error, REYES_ERR_ARGUMENT, "motion %g is not finite and within 1e6",
                              (double)o->motion[k]);
    reyes_status rotation_status = check_rotation(o, error);
    if (rotation_status != REYES_OK)
        return rotation_status;
    if (!(o->aperture >= 0.0f && o->aperture <= 1e6f) || !(o->focus >= 0.0f && o->focus <= 1e9f))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "aperture %g and focus %g must be >= 0 and finite",
                          (double)o->aperture, (double)o->focus);
    if (o->time_samples > REYES_MAX_SPP)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "time samples %u is not in 0..%u",
                          o->time_samples, REYES_MAX_SPP);
    reyes_status blur_status = check_blur_algo(o, error);
    if (blur_status != REYES_OK)
        return blur_status;
    if (o->crack_fix > REYES_CRACK_FIX_POLYLINE)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "crack fix %u is not %u (none), %u (stitch), %u (wedge) or %u (polyline)", o->crack_fix,
                          REYES_CRACK_FIX_NONE, REYES_CRACK_FIX_STITCH, REYES_CRACK_FIX_WEDGE,
                          REYES_CRACK_FIX_POLYLINE);
    if (o->crack_fix == REYES_CRACK_FIX_WEDGE && o->subdivision != REYES_SUBDIVISION_TIERED)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "crack fix wedge needs the tiered subdivision criterion");
    if (!(o->shading_rate == 0.0f || (o->shading_rate >= REYES_MIN_SHADING_RATE
                                       && o->shading_rate <= REYES_MAX_SHADING_RATE)))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "shading rate %g px is not 0 (fixed grids) or in %g..%g",
                          (double)o->shading_rate, (double)REYES_MIN_SHADING_RATE,
                          (double)REYES_MAX_SHADING_RATE);
    if (o->crack_fix == REYES_CRACK_FIX_WEDGE && o->shading_rate > 0.0f)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "crack fix wedge needs fixed grids (shading rate 0): its strips assume grid - 1 "
                          "steps along every edge");
    if (o->crack_fix == REYES_CRACK_FIX_POLYLINE && o->shading_rate == 0.0f)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "crack fix polyline needs a shading rate (fixed grids stitch or use wedges)");
    if (o->crack_fix == REYES_CRACK_FIX_POLYLINE && o->displace_mode != REYES_DISPLACE_NONE
        && o->displace_amplitude != 0.0f)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "crack fix polyline cannot be combined with displacement (its polylines are of the "
                          "undisplaced surface; stitch instead)");
    if (o->crack_fix == REYES_CRACK_FIX_WEDGE && o->displace_mode != REYES_DISPLACE_NONE
        && o->displace_amplitude != 0.0f)
        return reyes_fail(error, REYES_ERR_ARGUMENT,
                          "crack fix wedge cannot be combined with displacement yet");
    if (o->occlusion_cull > 1)
        return reyes_fail(error, REYES_ERR_ARGUMENT, "occlusion_cull %u is not 0 (off) or 1 (on)", o->occlusion_cull);
    if ((o->bucket_width == 0) != (o->bucket_height == 0))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "bucket %ux%u: both sides or neither must be 0",
                          o->bucket_width, o->bucket_height);
    if (o->bucket_width > 0) {
        uint64_t columns = (o->width + o->bucket_width - 1) / o->bucket_width;
        uint64_t rows = (o->height + o->bucket_height - 1) / o->bucket_height;
        if (columns * rows > REYES_MAX_BUCKETS)
            return reyes_fail(error, REYES_ERR_ARGUMENT,
                              "bucket %ux%u makes %llu buckets of a %ux%u image, more than %u",
                              o->bucket_width, o->bucket_height, (unsigned long long)(columns * rows),
                              o->width, o->height, REYES_MAX_BUCKETS);
    }
    if (!perma_technique_name(o->schedule.technique) || !perma_strategy_name(o->schedule.strategy)
        || !perma_victim_name(o->schedule.victim))
        return reyes_fail(error, REYES_ERR_ARGUMENT, "unknown technique, strategy or victim value");
    return REYES_OK;
}
