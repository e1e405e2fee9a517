/* Create a perma runtime and register the Reyes procedures on it. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_renderer_internal.h"
#include "reyes_shared.h"

#define DEFAULT_GROUP_SIZE 64u
#define DEFAULT_CPU_GROUP_SIZE 8u

reyes_status reyes_runtime_error(const struct reyes_renderer *r, const char *call,
                                 perma_status status, reyes_error *error)
{
    return reyes_fail(error, REYES_ERR_RUNTIME, "%s failed (%s): %s", call,
                      perma_status_name(status), r->rt ? perma_errmsg(r->rt) : "");
}

/* Bytes of a diced grid for the renderer's grid size. */
size_t reyes_grid_item_bytes(unsigned grid, int vertex_motion)
{
    size_t words = vertex_motion ? REYES_GRID_MOVING_VERTEX_WORDS : REYES_GRID_VERTEX_WORDS;
    return 4 * (REYES_GRID_HEADER_WORDS + words * REYES_GRID_ARRAY(grid));
}

/* Bytes of dice's scratch (struct reyes_dice_scratch, reyes_dice.cl): the
 * grid and the wedge strips, rasterized from there. */
static size_t dice_scratch_bytes(const struct reyes_renderer *r)
{
    return 2 * reyes_grid_item_bytes(r->grid, r->vertex_motion);
}

/* The definitions the procedures' sources take from the renderer. */
static perma_status add_definitions(struct reyes_renderer *r)
{
    char text[256];
    snprintf(text, sizeof text,
             "#define REYES_GRID_VERTICES %uu\n"
             "#define REYES_MAX_SPP_CHUNKS %u\n"
             "%s",
             REYES_GRID_ARRAY(r->grid), (REYES_MAX_SPP + 3) / 4,
             r->vertex_motion ? "#define REYES_VERTEX_MOTION 1\n" : "");
    return perma_add_source(r->rt, text, "reyes_renderer.h");
}

/* The embedded sources (meson.build makes them from the stage table). */
#define DECLARE_LIBRARY_SOURCE(stem, ext) extern const char reyes_##stem##_##ext##_source[];
#define DECLARE_PROCEDURE_SOURCE(e, name, item, priority, emits) extern const char reyes_##name##_cl_source[];
REYES_LIBRARY_SOURCES(DECLARE_LIBRARY_SOURCE)
REYES_PROCEDURES(DECLARE_PROCEDURE_SOURCE)

/* The library sources of the stage table, in its order. */
static const struct {
    const char *text, *file;
} library_sources[] = {
#define LIBRARY_SOURCE(stem, ext) { reyes_##stem##_##ext##_source, "reyes_" #stem "." #ext },
    REYES_LIBRARY_SOURCES(LIBRARY_SOURCE)
#undef LIBRARY_SOURCE
};

/* Register the stage table's procedures, after the renderer's definitions
 * and the library sources. */
static perma_status register_all(struct reyes_renderer *r)
{
    perma_procedure procedures[REYES_PROC_COUNT] = {
#define PROCEDURE(e, proc, item, prio, emit_list)                                                    \
    [REYES_PROC_##e] = { .name = #proc, .item_type = #item, .item_size = sizeof(item),               \
                         .threads_per_item = 1, .source = reyes_##proc##_cl_source,                  \
                         .source_file = "reyes_" #proc ".cl", .function = "reyes_" #proc,            \
                         .emits = { emit_list }, .priority = prio },
        REYES_PROCEDURES(PROCEDURE)
#undef PROCEDURE
    };
    procedures[REYES_PROC_DICE].local_bytes_per_item = dice_scratch_bytes(r);
    perma_status status = add_definitions(r);
    for (size_t s = 0; s < sizeof library_sources / sizeof *library_sources && status == PERMA_OK; ++s)
        status = perma_add_source(r->rt, library_sources[s].text, library_sources[s].file);
    for (int p = 0; p < REYES_PROC_COUNT && status == PERMA_OK; ++p)
        status = perma_register(r->rt, &procedures[p], &r->procs[p]);
    return status;
}

/* Create the runtime with the scheduling fields of the options and
 * `group_size` work-items per group. */
static perma_status create_runtime(const reyes_options *options, unsigned group_size, perma_runtime **rt,
                                   perma_error *perr)
{
    perma_config config;
    perma_config_init(&config);
    config.work_groups = options->work_groups;
    config.group_size = group_size;
    config.schedule = options->schedule;
    config.time_limit = options->time_limit;
    config.progress = options->progress;
    config.progress_user = options->progress_user;
    config.progress_interval = options->progress_interval;
    config.trace_path = options->trace_path;
    if (options->device)
        perma_config_set_device(&config, options->device);
    return perma_create(&config, rt, perr);
}

/* Whether the runtime's device is a CPU. */
static int on_cpu(perma_runtime *rt)
{
    cl_device_type type = 0;
    return clGetDeviceInfo(perma_cl_device(rt), CL_DEVICE_TYPE, sizeof type, &type, NULL) == CL_SUCCESS
           && (type & CL_DEVICE_TYPE_CPU);
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
    perma_error perr;
    perma_status status = create_runtime(options, group_size, &r->rt, &perr);
    if (status == PERMA_OK && options->group_size == 0 && on_cpu(r->rt)) {
        /* A CPU runs a group's work-items one after another, once per
         * stretch between barriers: a small group wastes less on the
         * stretches where few of them have work (dice and rasterize do
         * their own SIMD), which made full renders about a quarter faster. */
        perma_destroy(r->rt);
        r->rt = NULL;
        group_size = DEFAULT_CPU_GROUP_SIZE;
        status = create_runtime(options, group_size, &r->rt, &perr);
    }
    if (status != PERMA_OK) {
        free(r);
        return reyes_fail(error, REYES_ERR_RUNTIME, "perma_create failed (%s): %s",
                          perma_status_name(status), perr.message);
    }
    r->grid = options->grid;
    r->vertex_motion = options->motion_angle_deg != 0.0f;
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
    if (renderer->samples)
        clReleaseMemObject(renderer->samples);
    free(renderer->welded);
    perma_destroy(renderer->rt);
    free(renderer);
}

const char *reyes_renderer_device(const reyes_renderer *renderer)
{
    return perma_device_summary(renderer->rt);
}
