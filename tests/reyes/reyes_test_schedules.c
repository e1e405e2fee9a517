/* The scheduling configurations the Reyes tests render under. */
#include <check.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "reyes_test_util.h"

/* On top of every schedule (perma_schedule_all, the victims under one
 * stealing strategy): a local front queue and a small batch limit. */
static const char *const with_options[] = { "megakernel/shared+local64", "bounded-batches/p=64" };
#define WITH_OPTIONS (sizeof with_options / sizeof with_options[0])
#define MAX_SCHEDULES 32

static char labels[MAX_SCHEDULES][64];
static unsigned label_count;

static void list_schedules(void)
{
    perma_schedule s;
    while (label_count < MAX_SCHEDULES && perma_schedule_all(PERMA_SCHEDULES_VICTIMS_ONCE, label_count, &s) == PERMA_OK) {
        ck_assert_int_gt(perma_schedule_format(&s, labels[label_count], sizeof labels[0]), 0);
        ++label_count;
    }
    for (unsigned i = 0; i < WITH_OPTIONS && label_count < MAX_SCHEDULES; ++i)
        snprintf(labels[label_count++], sizeof labels[0], "%s", with_options[i]);
}

unsigned reyes_test_schedule_count(void)
{
    if (!label_count)
        list_schedules();
    return label_count;
}

const char *reyes_test_schedule(unsigned index)
{
    ck_assert_uint_lt(index, reyes_test_schedule_count());
    return labels[index];
}

void reyes_test_apply_schedule(const char *label, unsigned work_groups, reyes_options *o)
{
    perma_schedule s;
    perma_error error;
    ck_assert_msg(perma_schedule_parse(label, &s, &error) == PERMA_OK, "%s", error.message);
    o->schedule = s;
    o->work_groups = work_groups;
}

/* A local front queue (+localN) holds N items of every procedure in
 * __local memory: a whole diced grid for some Reyes stages, so how many fit
 * depends on the device (PoCL on a CPU reports its L2 cache size, 256 KiB
 * to several MiB; PERMA_LOCAL_MEMORY_LIMIT caps it).  When the runtime
 * says N does not fit, the render is retried with N / 2, saying so: every
 * such schedule still renders with a local queue on any device that holds
 * one item of each. */
static bool local_queue_too_large(const reyes_options *options, const reyes_error *error)
{
    return options->schedule.local_queue_items > 1 &&
           strstr(error->message, "config.schedule.local_queue_items") &&
           strstr(error->message, "of __local memory, more than the");
}

void reyes_test_render_once(const reyes_scene *scene, const reyes_camera *camera,
                            const reyes_options *options, reyes_image *image, reyes_stats *stats)
{
    reyes_options fitted = *options;
    for (;;) {
        reyes_renderer *renderer;
        reyes_error error;
        reyes_status status = reyes_renderer_create(&fitted, &renderer, &error);
        ck_assert_msg(status == REYES_OK, "renderer: %s", error.message);
        status = reyes_render(renderer, scene, camera, &fitted, image, stats, &error);
        reyes_renderer_destroy(renderer);
        if (status != REYES_OK && local_queue_too_large(&fitted, &error)) {
            printf("%s; retrying with a local queue of %u items\n", error.message,
                   fitted.schedule.local_queue_items / 2);
            fitted.schedule.local_queue_items /= 2;
            continue;
        }
        ck_assert_msg(status == REYES_OK, "render: %s", error.message);
        return;
    }
}
