/* The scheduling configurations the Reyes tests render under. */
#include <check.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "reyes_test_util.h"

/* test_reyes_blur uses entries 1 (stealing) and 6 (kernel-per-procedure). */
const char *const reyes_test_schedules[] = {
    "megakernel/shared",
    "megakernel/stealing/random",
    "megakernel/stealing/round-robin",
    "megakernel/donation",
    "megakernel/stealing-donation/random",
    "megakernel/shared+local64",
    "kernel-per-procedure",
    "bounded-batches",
    "bounded-batches/p=64",
};
const unsigned reyes_test_schedule_count = sizeof reyes_test_schedules / sizeof reyes_test_schedules[0];

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
