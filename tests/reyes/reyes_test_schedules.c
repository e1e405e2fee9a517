/* The scheduling configurations the Reyes tests render under. */
#include <check.h>
#include <stdio.h>

#include "reyes_test_util.h"

#define MK PERMA_TECHNIQUE_MEGAKERNEL
#define RANDOM PERMA_VICTIM_RANDOM

const reyes_test_schedule reyes_test_schedules[] = {
    { MK, PERMA_STRATEGY_SHARED, RANDOM, 0, 0 },
    { MK, PERMA_STRATEGY_STEALING, RANDOM, 0, 0 },
    { MK, PERMA_STRATEGY_STEALING, PERMA_VICTIM_ROUND_ROBIN, 0, 0 },
    { MK, PERMA_STRATEGY_DONATION, RANDOM, 0, 0 },
    { MK, PERMA_STRATEGY_STEALING_DONATION, RANDOM, 0, 0 },
    { MK, PERMA_STRATEGY_SHARED, RANDOM, 64, 0 },
    { PERMA_TECHNIQUE_KERNEL_PER_PROCEDURE, PERMA_STRATEGY_SHARED, RANDOM, 0, 0 },
    { PERMA_TECHNIQUE_BOUNDED_BATCHES, PERMA_STRATEGY_SHARED, RANDOM, 0, 0 },
    { PERMA_TECHNIQUE_BOUNDED_BATCHES, PERMA_STRATEGY_SHARED, RANDOM, 0, 64 },
};
const unsigned reyes_test_schedule_count = sizeof reyes_test_schedules / sizeof reyes_test_schedules[0];

void reyes_test_schedule_label(const reyes_test_schedule *s, char *out, size_t size)
{
    int stealing = s->strategy == PERMA_STRATEGY_STEALING || s->strategy == PERMA_STRATEGY_STEALING_DONATION;
    snprintf(out, size, "%s/%s%s%s local=%u p=%u", perma_technique_name(s->technique),
             perma_strategy_name(s->strategy), stealing ? "/" : "",
             stealing ? perma_victim_name(s->victim) : "", s->local_queue_items, s->batch_limit);
}

void reyes_test_apply_schedule(const reyes_test_schedule *s, unsigned work_groups, reyes_options *o)
{
    o->technique = s->technique;
    o->strategy = s->strategy;
    o->victim = s->victim;
    o->local_queue_items = s->local_queue_items;
    o->batch_limit = s->batch_limit;
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
