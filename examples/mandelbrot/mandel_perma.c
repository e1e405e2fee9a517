/* The perma program: register the procedures, bind the image, seed the
 * root (run by example_session.h). */
#include <string.h>

#include "mandel.h"

/* Threads that share one fill or block item; each takes every 16th pixel. */
enum { AREA_THREADS = 16 };

/* Device item types, mirrored for seeding. */
typedef struct device_rect {
    uint32_t x0, y0, x1, y1, border_known;
} device_rect;

static perma_status register_procedures(perma_runtime *rt, mandel_run *run)
{
    const char *source = mandel_device_procedures();
    perma_procedure split = {
        .name = "split", .item_type = "struct mandel_rect", .item_size = sizeof(device_rect),
        .threads_per_item = 1, .source = source, .source_file = "mandel_procedures.cl",
        .function = "mandel_split",
        .emits = { { "split", 4 }, { "fill", 1 }, { "block", 1 } },
    };
    perma_procedure fill = {
        .name = "fill", .item_type = "struct mandel_area", .item_size = 20,
        .threads_per_item = AREA_THREADS, .source = source, .source_file = "mandel_procedures.cl",
        .function = "mandel_fill",
    };
    perma_procedure block = fill;
    block.name = "block";
    block.function = "mandel_block";
    perma_proc fill_id, block_id;
    perma_status st;
    if ((st = perma_add_source(rt, mandel_device_types(), "mandel_types.cl")) != PERMA_OK ||
        (st = perma_register(rt, &split, &run->split)) != PERMA_OK ||
        (st = perma_register(rt, &fill, &fill_id)) != PERMA_OK ||
        (st = perma_register(rt, &block, &block_id)) != PERMA_OK)
        return st;
    return PERMA_OK;
}

static perma_status build(perma_runtime *rt, void *data, const char **step)
{
    mandel_run *run = data;
    size_t bytes = (size_t)run->params.width * run->params.height * sizeof *run->counts;
    perma_status st = register_procedures(rt, run);
    if (st != PERMA_OK)
        return st;
    *step = "binding buffers";
    if ((st = perma_bind_host(rt, "params", "__global const struct mandel_params *", &run->params,
                              sizeof run->params, PERMA_READ)) != PERMA_OK ||
        (st = perma_bind_host(rt, "counts", "__global uint *", run->counts, bytes, PERMA_READ_WRITE)) != PERMA_OK)
        return st;
    return PERMA_OK;
}

static perma_status seed(perma_runtime *rt, void *data)
{
    mandel_run *run = data;
    /* A pixel nothing wrote would keep this value and show up in tests. */
    memset(run->counts, 0xff, (size_t)run->params.width * run->params.height * sizeof *run->counts);
    device_rect root = { 0, 0, run->params.width - 1, run->params.height - 1, 0 };
    return perma_seed(rt, run->split, &root, 1);
}

const example_program mandel_program = { "perma-mandelbrot", build, seed };

mandel_status mandel_render_perma(const mandel_params *p, const example_run_options *options,
                                  uint32_t *counts, char *message, size_t size)
{
    mandel_run run = { *p, counts, 0 };
    return example_session_once(&mandel_program, &run, options, NULL, 0, message, size) ? MANDEL_ERR_RUNTIME
                                                                                        : MANDEL_OK;
}
