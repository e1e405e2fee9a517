/* The scheduling configurations the Reyes tests render under. */
#include <check.h>

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

void reyes_test_render_once(const reyes_scene *scene, const reyes_camera *camera,
                            const reyes_options *options, reyes_image *image, reyes_stats *stats)
{
    reyes_renderer *renderer;
    reyes_error error;
    reyes_status status = reyes_renderer_create(options, &renderer, &error);
    ck_assert_msg(status == REYES_OK, "renderer: %s", error.message);
    status = reyes_render(renderer, scene, camera, options, image, stats, &error);
    reyes_renderer_destroy(renderer);
    ck_assert_msg(status == REYES_OK, "render: %s", error.message);
}
