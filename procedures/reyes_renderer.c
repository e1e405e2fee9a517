/* Create a perma runtime and register the Reyes procedures on it. */
#include <stdlib.h>
#include <string.h>

#include "reyes_renderer_internal.h"
#include "reyes_shared.h"
#include "reyes_sources.h"

#define DEFAULT_GROUP_SIZE 64u
#define DICE_THREADS_MAX 64u

reyes_status reyes_runtime_error(const struct reyes_renderer *r, const char *call,
                                 perma_status status, reyes_error *error)
{
    return reyes_fail(error, REYES_ERR_RUNTIME, "%s failed (%s): %s", call,
                      perma_status_name(status), r->rt ? perma_errmsg(r->rt) : "");
}

static perma_status register_all(struct reyes_renderer *r)
{
    const char *item = "struct reyes_subpatch";
    const size_t item_size = sizeof(struct reyes_subpatch);
    /* Dice emits its grid's quads and, with wedges, a strip per edge. */
    unsigned quads = (r->grid - 1) * (r->grid - 1) + 4 * (r->grid - 1);
    /* Per-vertex motion: larger micropolygons and dice vertices, chosen
     * here because item types are fixed when the program is built. */
    const char *raster_item = r->vertex_motion ? "struct reyes_moving_quad" : "struct reyes_quad";
    size_t raster_size = r->vertex_motion ? sizeof(struct reyes_moving_quad) : sizeof(struct reyes_quad);
    size_t vertex_bytes = r->vertex_motion ? REYES_DICE_MOVING_VERTEX_BYTES : REYES_DICE_VERTEX_BYTES;
    /* Bound and split emit into each other: bound is served before split
     * (it culls and dices, split doubles), and consumers before producers
     * keeps the queues short. */
    const perma_procedure procedures[REYES_PROC_COUNT] = {
        [REYES_PROC_BOUND] = { .name = "bound", .item_type = item, .item_size = item_size,
            .threads_per_item = 1, .source = reyes_bound_cl_source,
            .source_file = "reyes_bound.cl", .function = "reyes_bound",
            .emits = { { "split_u", 1 }, { "split_v", 1 }, { "dice", 1 } }, .priority = 2 },
        [REYES_PROC_SPLIT_U] = { .name = "split_u", .item_type = item, .item_size = item_size,
            .threads_per_item = 1, .source = reyes_split_u_cl_source,
            .source_file = "reyes_split_u.cl", .function = "reyes_split_u",
            .emits = { { "bound", 2 } }, .priority = 1 },
        [REYES_PROC_SPLIT_V] = { .name = "split_v", .item_type = item, .item_size = item_size,
            .threads_per_item = 1, .source = reyes_split_v_cl_source,
            .source_file = "reyes_split_v.cl", .function = "reyes_split_v",
            .emits = { { "bound", 2 } }, .priority = 1 },
        [REYES_PROC_DICE] = { .name = "dice", .item_type = item, .item_size = item_size,
            .threads_per_item = r->dice_threads, .source = reyes_dice_cl_source,
            .source_file = "reyes_dice.cl", .function = "reyes_dice",
            .local_bytes_per_item = (size_t)r->grid * r->grid * vertex_bytes,
            .cooperative = 1, .emits = { { "rasterize", quads } }, .priority = 3 },
        [REYES_PROC_RASTERIZE] = { .name = "rasterize", .item_type = raster_item,
            .item_size = raster_size, .threads_per_item = 1,
            .source = reyes_rasterize_cl_source, .source_file = "reyes_rasterize.cl",
            .function = "reyes_rasterize", .priority = 4 },
        [REYES_PROC_STITCH] = { .name = "stitch", .item_type = "struct reyes_stitch",
            .item_size = sizeof(struct reyes_stitch), .threads_per_item = 1,
            .source = reyes_stitch_cl_source, .source_file = "reyes_stitch.cl",
            .function = "reyes_stitch", .priority = 4 },
    };
    perma_status status = PERMA_OK;
    if (r->vertex_motion)
        status = perma_add_source(r->rt, "#define REYES_VERTEX_MOTION 1\n", "reyes_vertex_motion.h");
    if (status == PERMA_OK)
        status = perma_add_source(r->rt, reyes_shared_h_source, "reyes_shared.h");
    if (status == PERMA_OK)
        status = perma_add_source(r->rt, reyes_common_cl_source, "reyes_common.cl");
    if (status == PERMA_OK)
        status = perma_add_source(r->rt, reyes_flatness_cl_source, "reyes_flatness.cl");
    if (status == PERMA_OK)
        status = perma_add_source(r->rt, reyes_sample_cl_source, "reyes_sample.cl");
    if (status == PERMA_OK)
        status = perma_add_source(r->rt, reyes_blur_cl_source, "reyes_blur.cl");
    if (status == PERMA_OK)
        status = perma_add_source(r->rt, reyes_displace_cl_source, "reyes_displace.cl");
    if (status == PERMA_OK)
        status = perma_add_source(r->rt, reyes_surface_cl_source, "reyes_surface.cl");
    for (int p = 0; p < REYES_PROC_COUNT && status == PERMA_OK; ++p)
        status = perma_register(r->rt, &procedures[p], &r->procs[p]);
    return status;
}

reyes_status reyes_renderer_create(const reyes_options *options, reyes_renderer **out,
                                   reyes_error *error)
{
    *out = NULL;
    reyes_status checked = reyes_options_check(options, error);
    if (checked != REYES_OK)
        return checked;
    struct reyes_renderer *r = calloc(1, sizeof *r);
    if (!r)
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "out of memory");
    unsigned group_size = options->group_size ? options->group_size : DEFAULT_GROUP_SIZE;
    r->grid = options->grid;
    r->vertex_motion = options->motion_angle_deg != 0.0f;
    r->dice_threads = group_size < DICE_THREADS_MAX ? group_size : DICE_THREADS_MAX;

    perma_config config;
    perma_config_init(&config);
    config.work_groups = options->work_groups;
    config.group_size = group_size;
    config.schedule = options->schedule;
    config.time_limit = options->time_limit;
    if (options->device)
        perma_config_set_device(&config, options->device);
    perma_error perr;
    perma_status status = perma_create(&config, &r->rt, &perr);
    if (status != PERMA_OK) {
        free(r);
        return reyes_fail(error, REYES_ERR_RUNTIME, "perma_create failed (%s): %s",
                          perma_status_name(status), perr.message);
    }
    /* The program is built by the first run, once the buffers are bound. */
    status = register_all(r);
    if (status != PERMA_OK) {
        reyes_runtime_error(r, "registering the Reyes procedures", status, error);
        reyes_renderer_destroy(r);
        return REYES_ERR_RUNTIME;
    }
    *out = r;
    return REYES_OK;
}

void reyes_renderer_destroy(reyes_renderer *renderer)
{
    if (!renderer)
        return;
    perma_destroy(renderer->rt);
    free(renderer);
}

const char *reyes_renderer_device(const reyes_renderer *renderer)
{
    return perma_device_summary(renderer->rt);
}
