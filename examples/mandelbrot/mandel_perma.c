/* The perma side: register the procedures, bind the image, seed the root. */
#include <stdlib.h>
#include <string.h>

#include "mandel.h"

/* Threads that share one fill or block item; each takes every 16th pixel. */
enum { AREA_THREADS = 16 };

struct mandel_session {
    perma_runtime *rt;
    perma_proc split;
    mandel_params params;
    uint32_t *counts;
};

/* Device item types, mirrored for seeding. */
typedef struct device_rect {
    uint32_t x0, y0, x1, y1, border_known;
} device_rect;

static mandel_status fail(mandel_session *s, const char *step, char *message, size_t size)
{
    snprintf(message, size, "perma-mandelbrot: %s: %s", step, perma_errmsg(s->rt));
    return MANDEL_ERR_RUNTIME;
}

static perma_status register_procedures(mandel_session *s)
{
    perma_runtime *rt = s->rt;
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
        (st = perma_register(rt, &split, &s->split)) != PERMA_OK ||
        (st = perma_register(rt, &fill, &fill_id)) != PERMA_OK ||
        (st = perma_register(rt, &block, &block_id)) != PERMA_OK)
        return st;
    return PERMA_OK;
}

mandel_status mandel_session_create(const mandel_params *p, const mandel_run_options *options,
                                    uint32_t *counts, mandel_session **out,
                                    char *message, size_t size)
{
    *out = NULL;
    mandel_session *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(message, size, "perma-mandelbrot: out of memory for the session");
        return MANDEL_ERR_RUNTIME;
    }
    s->params = *p;
    s->counts = counts;
    perma_config config;
    perma_config_init(&config);
    config.schedule = options->schedule;
    config.work_groups = options->work_groups;
    perma_error error;
    if (perma_create(&config, &s->rt, &error) != PERMA_OK) {
        snprintf(message, size, "perma-mandelbrot: perma_create: %s", error.message);
        free(s);
        return MANDEL_ERR_RUNTIME;
    }
    size_t bytes = (size_t)p->width * p->height * sizeof *counts;
    if (register_procedures(s) != PERMA_OK) {
        mandel_status st = fail(s, "registering procedures", message, size);
        mandel_session_destroy(s);
        return st;
    }
    if (perma_bind_host(s->rt, "params", "__global const struct mandel_params *", &s->params,
                        sizeof s->params, PERMA_READ) != PERMA_OK ||
        perma_bind_host(s->rt, "counts", "__global uint *", counts, bytes, PERMA_READ_WRITE) != PERMA_OK) {
        mandel_status st = fail(s, "binding buffers", message, size);
        mandel_session_destroy(s);
        return st;
    }
    if (perma_build(s->rt) != PERMA_OK) {
        mandel_status st = fail(s, "building the program", message, size);
        mandel_session_destroy(s);
        return st;
    }
    *out = s;
    return MANDEL_OK;
}

mandel_status mandel_session_run(mandel_session *s, char *message, size_t size)
{
    /* A pixel nothing wrote would keep this value and show up in tests. */
    memset(s->counts, 0xff, (size_t)s->params.width * s->params.height * sizeof *s->counts);
    device_rect root = { 0, 0, s->params.width - 1, s->params.height - 1, 0 };
    if (perma_seed(s->rt, s->split, &root, 1) != PERMA_OK)
        return fail(s, "seeding", message, size);
    if (perma_run(s->rt) != PERMA_OK)
        return fail(s, "running", message, size);
    return MANDEL_OK;
}

perma_runtime *mandel_session_runtime(mandel_session *s)
{
    return s->rt;
}

void mandel_session_destroy(mandel_session *s)
{
    if (!s)
        return;
    perma_destroy(s->rt);
    free(s);
}

mandel_status mandel_render_perma(const mandel_params *p, const mandel_run_options *options,
                                  uint32_t *counts, char *message, size_t size)
{
    mandel_session *s;
    mandel_status st = mandel_session_create(p, options, counts, &s, message, size);
    if (st != MANDEL_OK)
        return st;
    st = mandel_session_run(s, message, size);
    mandel_session_destroy(s);
    return st;
}
