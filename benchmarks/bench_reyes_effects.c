/* perma-bench reyes: the effect workloads, each a side-by-side comparison
 * within one run (the machine is shared and noisy: ratios of times taken
 * together drift much less than absolute times):
 *
 *   displace  plain against bumps displacement, per model and size;
 *   blur      unblurred against the simple, interleaved and bbox blur
 *             algorithms at 16, 25 and 64 samples per pixel (killeroo at
 *             800x600, a moderate motion and aperture);
 *   buckets   no buckets against 256, 128, 64 and 32 pixel buckets: peak
 *             queue memory and time, per model, size and technique.
 *
 * The configurations of a comparison are rendered in turn, --repeat
 * rounds after an untimed render of the first, and each reports its best
 * perma_run time (and best wall time around reyes_render).  Every image is hashed: a row's check is that all
 * its rounds gave the same image, and for buckets that it is the image
 * without buckets. */
#include "bench_reyes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "reyes.h"

#define MAX_CONFIGS 8
#define BLUR_SPPS 3
#define BUCKET_SIZES 5

/* One configuration of a comparison and what its rounds measured. */
typedef struct effect_config {
    char label[64];
    reyes_options options;
    int ran;                /* every round rendered */
    char message[PERMA_MESSAGE_MAX + 64];
    double seconds, wall;   /* best perma_run time (summed over buckets), best wall time */
    uint64_t hash;          /* the first round's image */
    int consistent;         /* every round gave that image */
    reyes_stats stats;      /* the last round's counts (no per-bucket list) */
} effect_config;

/* A comparison: a title, a renderer and its configurations, the first
 * being the baseline. */
typedef struct comparison {
    char title[128];       /* rows keep the first 63 characters */
    reyes_renderer *renderer;
    const reyes_scene *scene;
    reyes_camera camera;
    effect_config configs[MAX_CONFIGS];
    unsigned count;
} comparison;

/* FNV-1a over the colors and the coverage. */
static uint64_t image_hash(const reyes_image *image)
{
    uint64_t h = 1469598103934665603ull;
    size_t pixels = (size_t)image->width * image->height;
    for (size_t k = 0; k < 3 * pixels; ++k)
        h = (h ^ image->rgb[k]) * 1099511628211ull;
    for (size_t k = 0; k < pixels; ++k)
        h = (h ^ image->coverage[k]) * 1099511628211ull;
    return h;
}

static effect_config *add_config(comparison *c, const char *label, const reyes_options *o)
{
    effect_config *config = &c->configs[c->count++];
    memset(config, 0, sizeof *config);
    snprintf(config->label, sizeof config->label, "%s", label);
    config->options = *o;
    return config;
}

/* One round of one configuration. */
static void render_round(comparison *c, effect_config *config, unsigned round)
{
    reyes_image image;
    reyes_stats stats;
    reyes_error error;
    bench_status_show(c->title, config->label);
    double start = bench_now();
    if (reyes_render(c->renderer, c->scene, &c->camera, &config->options, &image, &stats, &error)
        != REYES_OK) {
        config->ran = 0;
        snprintf(config->message, sizeof config->message, "%s", error.message);
        return;
    }
    double wall = bench_now() - start;
    uint64_t hash = image_hash(&image);
    reyes_image_free(&image);
    if (round == 0)
        config->hash = hash;
    config->consistent &= hash == config->hash;
    config->seconds = fmin(config->seconds, stats.seconds);
    config->wall = fmin(config->wall, wall);
    config->stats = stats;
    config->stats.bucket_peak_queue_bytes = NULL;
    reyes_stats_free(&stats);
}

/* The configurations in turn, `rounds` times, after one untimed render
 * of the baseline: queues grown to this image size (a relaunch) and the
 * first-touch costs of its buffers are then paid by nobody's time. */
static void measure(comparison *c, unsigned rounds)
{
    reyes_image image;
    reyes_error error;
    if (reyes_render(c->renderer, c->scene, &c->camera, &c->configs[0].options, &image, NULL, &error)
        == REYES_OK)
        reyes_image_free(&image);
    for (unsigned k = 0; k < c->count; ++k) {
        c->configs[k].ran = 1;
        c->configs[k].consistent = 1;
        c->configs[k].seconds = c->configs[k].wall = INFINITY;
    }
    for (unsigned r = 0; r < rounds; ++r)
        for (unsigned k = 0; k < c->count; ++k)
            if (c->configs[k].ran)
                render_round(c, &c->configs[k], r);
}

/* One row per configuration; same_as_first: the check also wants the
 * baseline's image (buckets). */
static void add_rows(bench_report *report, const comparison *c, int same_as_first)
{
    bench_report_workload(report, c->title);
    for (unsigned k = 0; k < c->count; ++k) {
        const effect_config *config = &c->configs[k];
        bench_row row;
        bench_row_init(&row, c->title, config->label, "quads");
        row.ran = config->ran;
        if (!config->ran) {
            snprintf(row.message, sizeof row.message, "%s", config->message);
            bench_report_add(report, &row, k == 0);
            continue;
        }
        const reyes_stats *s = &config->stats;
        row.seconds = config->seconds;
        row.wall_seconds = config->wall;
        row.work_groups = s->run.work_groups;
        row.group_size = s->run.group_size;
        row.units = (double)s->micropolygons;
        row.count = s->grids;
        row.expected = c->configs[0].stats.grids;
        int same = config->consistent && (!same_as_first || config->hash == c->configs[0].hash);
        row.check = same ? BENCH_CHECK_PASS : BENCH_CHECK_FAIL;
        row.peak_queue_bytes = s->peak_queue_bytes;
        row.steals = s->run.steals;
        row.donations = s->run.donations;
        row.spills = s->run.spills;
        snprintf(row.message, sizeof row.message,
                 "wall %.3f s; splits %llu grids %llu micropolygons %llu samples %llu; buckets %u; "
                 "launches %u", config->wall, (unsigned long long)s->splits,
                 (unsigned long long)s->grids, (unsigned long long)s->micropolygons,
                 (unsigned long long)s->samples_written, s->bucket_columns * s->bucket_rows,
                 s->run.launches);
        bench_report_add(report, &row, k == 0);
    }
}

/* Time of configuration k over the baseline's (0 if either did not run). */
static double cost(const comparison *c, unsigned k)
{
    const effect_config *base = &c->configs[0], *config = &c->configs[k];
    return base->ran && config->ran && base->seconds > 0.0 ? config->seconds / base->seconds : 0.0;
}

/* ---- scenes and renderers ---- */

/* The scene of a workload: a model from the models directory, or with
 * --quick the built-in scene.  0 (with a message) if the model is
 * missing; -1 if it failed to load. */
static int load_scene(const reyes_bench_args *a, const bench_options *options, const char *model,
                      reyes_scene *scene)
{
    reyes_error error;
    reyes_scene_init(scene);
    if (options->quick)
        return reyes_scene_add_builtin(scene, &error) == REYES_OK ? 1 : -1;
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.bpt", a->models_dir, model);
    if (!reyes_bench_file_exists(path)) {
        printf("reyes: skipping %s: %s is missing (the models are in ../shared/models; "
               "pass --models DIR)\n", model, path);
        return 0;
    }
    if (reyes_scene_load_bpt(scene, path, reyes_model_color(0), &error) != REYES_OK) {
        fprintf(stderr, "perma-bench reyes: %s\n", error.message);
        return -1;
    }
    return 1;
}

static float scene_radius(const reyes_scene *scene)
{
    float lo[3], hi[3], r2 = 0.0f;
    if (!reyes_scene_bounds(scene, lo, hi))
        return 1.0f;
    for (int k = 0; k < 3; ++k)
        r2 += 0.25f * (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return sqrtf(r2);
}

/* A renderer for variant v, warmed up with a small render so that the
 * program's compilation is not timed; NULL (message printed) if refused. */
static reyes_renderer *create_renderer(const reyes_bench_args *a, const bench_options *options,
                                       const bench_variant *v)
{
    reyes_options o = reyes_bench_render_options(a, options, v, 64, 64);
    reyes_renderer *renderer;
    reyes_error error;
    if (reyes_renderer_create(&o, &renderer, &error) != REYES_OK) {
        printf("reyes: %s: n/a: %s\n", v->label, error.message);
        return NULL;
    }
    reyes_scene scene;
    reyes_camera camera;
    reyes_image image;
    reyes_scene_init(&scene);
    if (reyes_scene_add_builtin(&scene, &error) == REYES_OK
        && reyes_camera_frame(&scene, 40.0f, 1.0f, &camera, &error) == REYES_OK
        && reyes_render(renderer, &scene, &camera, &o, &image, NULL, &error) == REYES_OK)
        reyes_image_free(&image);
    reyes_scene_free(&scene);
    return renderer;
}

/* The first variant --only selects (megakernel/shared by default) into
 * *out; 0 if none. */
static int first_selected(const bench_options *options, bench_variant *out)
{
    for (unsigned v = 0; v < bench_variant_count(); ++v)
        if (bench_variant_select(options, bench_variant_label(v), out))
            return 1;
    return 0;
}

static int frame(comparison *c, unsigned width, unsigned height)
{
    reyes_error error;
    if (reyes_camera_frame(c->scene, 40.0f, (float)width / (float)height, &c->camera, &error) != REYES_OK) {
        printf("reyes: %s: %s\n", c->title, error.message);
        return 0;
    }
    return 1;
}

/* ---- displace ---- */

static void displace_comparison(bench_report *report, const reyes_bench_args *a,
                                const bench_options *options, const bench_variant *v,
                                reyes_renderer *renderer, const char *model, const reyes_scene *scene,
                                unsigned width, unsigned height)
{
    comparison c = { .renderer = renderer, .scene = scene };
    /* Bumps of a hundredth of the scene's radius. */
    float amplitude = 0.01f * scene_radius(scene);
    snprintf(c.title, sizeof c.title, "displace: %s %ux%u bumps:%.3g", model, width, height,
             (double)amplitude);
    if (!frame(&c, width, height))
        return;
    reyes_options o = reyes_bench_render_options(a, options, v, width, height);
    add_config(&c, "plain", &o);
    o.displace_mode = REYES_DISPLACE_BUMPS;
    o.displace_amplitude = amplitude;
    add_config(&c, "bumps", &o);
    measure(&c, options->repeat);
    add_rows(report, &c, 0);
    printf("  displacement cost: %+.1f %% over plain (perma_run time, best of %u)\n",
           100.0 * (cost(&c, 1) - 1.0), options->repeat);
}

/* ---- blur ---- */

/* Screen distance in pixels that `motion` moves the scene's center. */
static float motion_pixels(const reyes_scene *scene, const reyes_camera *camera, unsigned width,
                           unsigned height, const float motion[3])
{
    float lo[3], hi[3], from[3], to[3], m[16], x0, y0, x1, y1, depth;
    reyes_error error;
    if (!reyes_scene_bounds(scene, lo, hi)
        || reyes_camera_matrix(camera, (float)width / (float)height, 1e-3f, m, &error) != REYES_OK)
        return 0.0f;
    for (int k = 0; k < 3; ++k) {
        from[k] = 0.5f * (lo[k] + hi[k]);
        to[k] = from[k] + motion[k];
    }
    if (!reyes_camera_project(m, width, height, from, &x0, &y0, &depth)
        || !reyes_camera_project(m, width, height, to, &x1, &y1, &depth))
        return 0.0f;
    return hypotf(x1 - x0, y1 - y0);
}

static void blur_comparisons(bench_report *report, const reyes_bench_args *a,
                             const bench_options *options, const bench_variant *v,
                             reyes_renderer *renderer, const char *model, const reyes_scene *scene)
{
    const unsigned spps[BLUR_SPPS] = {16, 25, 64};
    unsigned spp_count = options->quick ? 1 : BLUR_SPPS;
    unsigned width = a->sizes_given ? a->widths[0] : options->quick ? 96 : 800;
    unsigned height = a->sizes_given ? a->heights[0] : options->quick ? 72 : 600;
    /* Moderate: the motion a hundredth of the scene's radius across, a
     * lens of about a thousandth of it, focused at the target. */
    float radius = scene_radius(scene);
    const float motion[3] = {0.01f * radius, 0.0f, 0.0f};
    float aperture = 0.0012f * radius;
    double costs[BLUR_SPPS][4] = {{0.0}};
    double base_seconds[BLUR_SPPS] = {0.0};
    float pixels = 0.0f;
    for (unsigned k = 0; k < spp_count; ++k) {
        comparison c = { .renderer = renderer, .scene = scene };
        unsigned spp = options->quick ? 4 : spps[k];
        snprintf(c.title, sizeof c.title, "blur: %s %ux%u %u spp", model, width, height, spp);
        if (!frame(&c, width, height))
            return;
        pixels = motion_pixels(scene, &c.camera, width, height, motion);
        reyes_options o = reyes_bench_render_options(a, options, v, width, height);
        o.spp = spp;
        add_config(&c, "unblurred", &o);
        memcpy(o.motion, motion, sizeof o.motion);
        o.aperture = aperture;
        for (unsigned algo = 0; reyes_blur_algo_name(algo); ++algo) {
            o.blur_algo = algo;
            add_config(&c, reyes_blur_algo_name(algo), &o);
        }
        measure(&c, options->repeat);
        add_rows(report, &c, 0);
        base_seconds[k] = c.configs[0].ran ? c.configs[0].seconds : 0.0;
        for (unsigned i = 1; i < c.count && i < 4; ++i)
            costs[k][i] = cost(&c, i);
    }
    printf("\n  blur cost, %s %ux%u, motion %.3g (about %.1f px at the center), aperture %.3g "
           "(time / unblurred at the same spp, best of %u):\n", model, width, height,
           (double)motion[0], (double)pixels, (double)aperture, options->repeat);
    printf("  %5s %12s %8s %12s %8s\n", "spp", "unblurred", "simple", "interleaved", "bbox");
    for (unsigned k = 0; k < spp_count; ++k)
        printf("  %5u %10.3f s %7.2fx %11.2fx %7.2fx\n", options->quick ? 4 : spps[k], base_seconds[k],
               costs[k][1], costs[k][2], costs[k][3]);
}

/* ---- buckets ---- */

static void bucket_comparison(bench_report *report, const reyes_bench_args *a,
                              const bench_options *options, const bench_variant *v,
                              reyes_renderer *renderer, const char *model, const reyes_scene *scene,
                              unsigned width, unsigned height)
{
    const unsigned sides[BUCKET_SIZES] = {0, 256, 128, 64, 32};
    comparison c = { .renderer = renderer, .scene = scene };
    snprintf(c.title, sizeof c.title, "buckets: %s %ux%u %s", model, width, height, v->label);
    if (!frame(&c, width, height))
        return;
    for (unsigned k = 0; k < BUCKET_SIZES; ++k) {
        /* A bucket as large as the image is no bucket. */
        if (sides[k] >= width && sides[k] >= height)
            continue;
        reyes_options o = reyes_bench_render_options(a, options, v, width, height);
        o.bucket_width = o.bucket_height = sides[k];
        char label[64];
        if (sides[k])
            snprintf(label, sizeof label, "bucket %ux%u", sides[k], sides[k]);
        else
            snprintf(label, sizeof label, "no buckets");
        add_config(&c, label, &o);
    }
    measure(&c, options->repeat);
    add_rows(report, &c, 1);
    const effect_config *base = &c.configs[0];
    printf("\n  %s (best of %u): %-14s %7s %14s %9s %10s %8s %10s %8s\n", c.title, options->repeat,
           "bucket", "buckets", "peak queue B", "vs none", "perma_run", "vs none", "wall", "vs none");
    for (unsigned k = 0; k < c.count; ++k) {
        const effect_config *config = &c.configs[k];
        if (!config->ran || !base->ran)
            continue;
        printf("  %-14s %7u %14zu %8.3fx %8.3f s %7.2fx %8.3f s %7.2fx\n", config->label,
               config->stats.bucket_columns * config->stats.bucket_rows, config->stats.peak_queue_bytes,
               (double)config->stats.peak_queue_bytes / (double)base->stats.peak_queue_bytes,
               config->seconds, cost(&c, k), config->wall, config->wall / base->wall);
    }
}

/* ---- the workloads ---- */

typedef void (*size_comparison)(bench_report *, const reyes_bench_args *, const bench_options *,
                                const bench_variant *, reyes_renderer *, const char *,
                                const reyes_scene *, unsigned, unsigned);

/* Run `compare` for every model and size with each renderer.  Returns 0,
 * or 1 if a model failed to load. */
static int per_model_and_size(bench_report *report, const reyes_bench_args *a, const bench_options *options,
                              const bench_variant *const *variants, reyes_renderer *const *renderers,
                              unsigned variant_count, size_comparison compare)
{
    const char *models[] = { "teapot", "killeroo" };
    unsigned model_count = options->quick ? 1 : 2;
    for (unsigned m = 0; m < model_count; ++m) {
        const char *name = options->quick ? "built-in" : models[m];
        reyes_scene scene;
        int loaded = load_scene(a, options, models[m], &scene);
        for (unsigned s = 0; loaded > 0 && s < a->size_count; ++s) {
            unsigned width = options->quick && !a->sizes_given ? 128 : a->widths[s];
            unsigned height = options->quick && !a->sizes_given ? 96 : a->heights[s];
            for (unsigned v = 0; v < variant_count; ++v)
                if (renderers[v])
                    compare(report, a, options, variants[v], renderers[v], name, &scene, width, height);
        }
        reyes_scene_free(&scene);
        if (loaded < 0)
            return 1;
    }
    return 0;
}

int reyes_bench_effects(bench_report *report, const reyes_bench_args *a, const bench_options *options)
{
    int status = 0;
    bench_variant selected;
    const bench_variant *primary = first_selected(options, &selected) ? &selected : NULL;
    if (primary)
        bench_variant_use_device(options, 0, &selected); /* --devices: the first one */
    if (a->workloads & (REYES_BENCH_DISPLACE | REYES_BENCH_BLUR) && !primary)
        printf("reyes: --only '%s' selects no variant: no displace or blur rows\n", options->only);
    reyes_renderer *renderer = NULL;
    if (primary && a->workloads & (REYES_BENCH_DISPLACE | REYES_BENCH_BLUR))
        renderer = create_renderer(a, options, primary);
    if (renderer && a->workloads & REYES_BENCH_DISPLACE)
        status |= per_model_and_size(report, a, options, &primary, &renderer, 1, displace_comparison);
    if (renderer && a->workloads & REYES_BENCH_BLUR) {
        reyes_scene scene;
        int loaded = load_scene(a, options, "killeroo", &scene);
        if (loaded > 0)
            blur_comparisons(report, a, options, primary, renderer,
                             options->quick ? "built-in" : "killeroo", &scene);
        status |= loaded < 0;
        reyes_scene_free(&scene);
    }
    reyes_renderer_destroy(renderer);
    if (a->workloads & REYES_BENCH_BUCKETS) {
        /* Megakernel/shared keeps its queues small anyway; kernel-per-
         * procedure holds a breadth-first level, which buckets bound. */
        const char *labels[2] = { bench_variant_label(0), NULL };
        for (unsigned v = 0; v < bench_variant_count(); ++v) {
            perma_schedule s;
            if (perma_schedule_parse(bench_variant_label(v), &s, NULL) == PERMA_OK
                && s.technique == PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE)
                labels[1] = bench_variant_label(v);
        }
        bench_variant parsed[2];
        const bench_variant *variants[2] = { &parsed[0], &parsed[1] };
        reyes_renderer *renderers[2] = { NULL, NULL };
        for (unsigned v = 0; v < 2; ++v)
            if (labels[v] && bench_variant_select(options, labels[v], &parsed[v]))
                renderers[v] = create_renderer(a, options, &parsed[v]);
        status |= per_model_and_size(report, a, options, variants, renderers, 2, bucket_comparison);
        for (unsigned v = 0; v < 2; ++v)
            reyes_renderer_destroy(renderers[v]);
    }
    return status;
}
