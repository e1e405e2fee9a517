/* Crack-free subdivision: a closed sphere of patches seen from random
 * views at 1 sample per pixel shows no holes with stitching.  Coarse grids
 * (4x4 vertices) and a large bound make the cracks between grids diced at
 * different rates wide enough to catch samples. */
#include <check.h>
#include <stdio.h>
#include <stdlib.h>

#include "reyes_shared.h"
#include "reyes_test_util.h"

#define VIEWS 24
#define SEED 12345u
#define MAX_HOLE 48
#define GRID 4
#define BOUND_PX 16.0f

static void crack_options(reyes_options *o, unsigned crack_fix)
{
    reyes_options_init(o);
    o->width = 128;
    o->height = 128;
    o->spp = 1;
    o->crack_fix = crack_fix;
    o->grid = GRID;
    o->bound_px = BOUND_PX;
}

START_TEST(test_sphere_watertight)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    const float center[3] = {0.3f, -0.2f, 0.1f};
    ck_assert_int_eq(reyes_scene_add_sphere(&scene, center, 1.0f, REYES_RGBA(200, 200, 200), &error),
                     REYES_OK);
    reyes_options o;
    crack_options(&o, REYES_CRACK_FIX_NONE);
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    size_t without = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                        SEED, MAX_HOLE);
    crack_options(&o, REYES_CRACK_FIX_STITCH);
    size_t with = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                     SEED, MAX_HOLE);
    printf("sphere, %d views at 1 spp: %zu hole pixels without crack fix, %zu with stitching\n",
           VIEWS, without, with);
    ck_assert_uint_eq(with, 0);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

/* The same with the tiered subdivision criterion: sub-patches of the
 * sphere are split to different depths by curvature, not only by size.
 * Its micropolygons are at most about a pixel (bound <= grid - 1 px), so
 * unstitched cracks are narrow and seldom catch a sample: the count
 * without the fix is printed, the count with it must be 0. */
START_TEST(test_sphere_watertight_tiered)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    const float center[3] = {-0.2f, 0.1f, 0.3f};
    ck_assert_int_eq(reyes_scene_add_sphere(&scene, center, 1.0f, REYES_RGBA(200, 200, 200), &error),
                     REYES_OK);
    reyes_options o;
    crack_options(&o, REYES_CRACK_FIX_NONE);
    o.subdivision = REYES_SUBDIVISION_TIERED;
    o.grid = 8; /* sub-patches up to 7 px, split further where curved */
    o.flat_epsilon = 0.5f;
    reyes_renderer *renderer;
    ck_assert_int_eq(reyes_renderer_create(&o, &renderer, &error), REYES_OK);
    size_t without = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                        SEED + 1, MAX_HOLE);
    o.crack_fix = REYES_CRACK_FIX_STITCH;
    size_t with = reyes_test_holes_from_random_views(renderer, &scene, &o, NULL, VIEWS,
                                                     SEED + 1, MAX_HOLE);
    printf("sphere, tiered criterion, %d views at 1 spp: %zu hole pixels without crack fix, "
           "%zu with stitching\n", VIEWS, without, with);
    ck_assert_uint_eq(with, 0);
    reyes_renderer_destroy(renderer);
    reyes_scene_free(&scene);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_cracks");
    TCase *tc = tcase_create("cracks");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_sphere_watertight);
    tcase_add_test(tc, test_sphere_watertight_tiered);
    suite_add_tcase(s, tc);
    SRunner *runner = srunner_create(s);
    srunner_set_fork_status(runner, CK_NOFORK);
    srunner_run_all(runner, CK_NORMAL);
    int failed = srunner_ntests_failed(runner);
    srunner_free(runner);
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
