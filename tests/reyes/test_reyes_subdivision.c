/* The tiered subdivision criterion (options.subdivision): exact grid counts
 * for a flat square, the effect of lambda on a geometrically flat but
 * unevenly parametrised patch, the inner tier on a bulge, epsilon on a
 * sphere, and the same decisions as the C reference throughout. */
#include <check.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reyes_shared.h"
#include "reyes_test_util.h"

#define PI 3.14159265358979323846
#define SIZE 256
#define DISTANCE 3.5f

/* The square [-1,1]^2 at z = 0 with its control points at the given
 * fractions along each side (uniform: 0, 1/3, 2/3, 1) and the four inner
 * ones raised by `bulge`. */
static void add_square(reyes_scene *scene, const float fractions[4], float bulge)
{
    float cp[4][4][3];
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            cp[r][c][0] = -1.0f + 2.0f * fractions[c];
            cp[r][c][1] = -1.0f + 2.0f * fractions[r];
            cp[r][c][2] = (r == 1 || r == 2) && (c == 1 || c == 2) ? bulge : 0.0f;
        }
    }
    reyes_error error;
    ck_assert_int_eq(reyes_scene_add_patch(scene, cp, REYES_RGBA(220, 220, 220), &error), REYES_OK);
}

static const float uniform[4] = {0.0f, 1.0f / 3.0f, 2.0f / 3.0f, 1.0f};
static const float uneven[4] = {0.0f, 0.05f, 0.1f, 1.0f};

/* Looking straight down at the square from DISTANCE above its center. */
static const reyes_camera above = { .eye = {0.0f, 0.0f, DISTANCE}, .at = {0.0f, 0.0f, 0.0f},
                                    .fov_deg = 40.0f };

static void square_options(reyes_options *o, unsigned subdivision, float lambda)
{
    reyes_options_init(o);
    o->width = SIZE;
    o->height = SIZE;
    o->spp = 1;
    o->subdivision = subdivision;
    o->flat_lambda = lambda;
}

/* Render and check the decisions against the C reference and the split
 * reasons against the split count. */
static void render_checked(const reyes_scene *scene, const reyes_camera *camera,
                           const reyes_options *o, reyes_image *image, reyes_stats *stats)
{
    reyes_test_render(reyes_test_renderer(0), scene, camera, o, image, stats);
    reyes_test_expect_reference_counts(scene, camera, o, stats);
    ck_assert_uint_eq(stats->split_bound + stats->split_edge + stats->split_inner
                          + stats->split_near,
                      stats->splits);
    ck_assert_uint_eq(stats->grids, stats->splits + stats->patches_in - stats->culled);
}

/* Halvings of `size` pixels until at most `limit`. */
static unsigned halvings(float size, float limit)
{
    unsigned n = 0;
    while (size > limit) {
        size *= 0.5f;
        ++n;
    }
    return n;
}

/* A flat, uniformly parametrised square seen face-on is split by its
 * screen size only: to 8 px with the bound criterion, to grid - 1 = 15 px
 * with the tiered one (it is flat at every level), so 4^halvings grids. */
START_TEST(test_flat_square_counts)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    add_square(&scene, uniform, 0.0f);
    float m[16], x0, y0, x1, y1, depth;
    reyes_error error;
    ck_assert_int_eq(reyes_camera_matrix(&above, 1.0f, reyes_near_plane(&scene, &above), m, &error), REYES_OK);
    const float low[3] = {-1.0f, -1.0f, 0.0f}, high[3] = {1.0f, 1.0f, 0.0f};
    ck_assert(reyes_camera_project(m, SIZE, SIZE, low, &x0, &y0, &depth));
    ck_assert(reyes_camera_project(m, SIZE, SIZE, high, &x1, &y1, &depth));
    float side = fabsf(x1 - x0);
    ck_assert_float_eq_tol(side, fabsf(y1 - y0), 1e-3f);
    /* Keep clear of the thresholds: 201 px -> 6.3 px after 5 halvings,
     * 12.6 px after 4. */
    ck_assert(side > 190.0f && side < 220.0f);
    unsigned bound_halvings = halvings(side, 8.0f), tiered_halvings = halvings(side, 15.0f);
    ck_assert_uint_eq(bound_halvings, 5);
    ck_assert_uint_eq(tiered_halvings, 4);

    reyes_options o;
    reyes_image image;
    reyes_stats stats;
    square_options(&o, REYES_SUBDIVISION_BOUND, 0.5f);
    render_checked(&scene, &above, &o, &image, &stats);
    ck_assert_uint_eq(stats.grids, 1u << (2 * bound_halvings));
    ck_assert_uint_eq(stats.split_bound, stats.splits);
    uint64_t bound_covered = reyes_test_covered_samples(&image);
    reyes_image_free(&image);
    /* Shape and parametrisation are exact: lambda changes nothing. */
    for (int lambda = 0; lambda <= 1; ++lambda) {
        square_options(&o, REYES_SUBDIVISION_TIERED, (float)lambda);
        render_checked(&scene, &above, &o, &image, &stats);
        ck_assert_uint_eq(stats.grids, 1u << (2 * tiered_halvings));
        ck_assert_uint_eq(stats.split_bound, stats.splits);
        ck_assert_uint_eq(stats.split_edge + stats.split_inner, 0);
        /* Fewer, larger grids cover the same square (up to samples on
         * the grid lines, which both renders count once). */
        ck_assert_uint_eq(reyes_test_covered_samples(&image), bound_covered);
        reyes_image_free(&image);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* A flat square whose control points bunch up at one side: its shape is
 * flat (lambda 0: no tier splits), its parametrisation is far from
 * uniform (lambda 1: the edge tier splits it further). */
START_TEST(test_lambda_weighs_parametric_distance)
{
    reyes_scene scene;
    reyes_scene_init(&scene);
    add_square(&scene, uneven, 0.0f);
    reyes_options o;
    reyes_image image;
    reyes_stats geometric, parametric;
    square_options(&o, REYES_SUBDIVISION_TIERED, 0.0f);
    render_checked(&scene, &above, &o, &image, &geometric);
    ck_assert_uint_eq(geometric.split_edge + geometric.split_inner, 0);
    uint64_t covered = reyes_test_covered_samples(&image);
    reyes_image_free(&image);

    square_options(&o, REYES_SUBDIVISION_TIERED, 1.0f);
    render_checked(&scene, &above, &o, &image, &parametric);
    ck_assert_uint_gt(parametric.split_edge, 0);
    ck_assert_uint_gt(parametric.grids, geometric.grids);
    /* The same square either way, only diced differently: coverage
     * agrees up to samples on grid edges. */
    uint64_t covered_parametric = reyes_test_covered_samples(&image);
    ck_assert_uint_le(covered > covered_parametric ? covered - covered_parametric
                                                   : covered_parametric - covered,
                      SIZE);
    printf("uneven square: %llu grids at lambda 0, %llu at lambda 1 (%llu edge-tier splits)\n",
           (unsigned long long)geometric.grids, (unsigned long long)parametric.grids,
           (unsigned long long)parametric.split_edge);
    reyes_image_free(&image);
    reyes_scene_free(&scene);
}
END_TEST

/* A square with straight, uniform edges and a raised middle, small on
 * screen (under grid - 1 pixels, so its size asks for no split): it passes
 * the edge tier and fails the inner one; flat, it is one grid. */
START_TEST(test_inner_tier)
{
    const reyes_camera far_above = { .eye = {0.0f, 0.0f, 50.0f}, .at = {0.0f, 0.0f, 0.0f},
                                     .fov_deg = 40.0f };
    for (int raised = 0; raised <= 1; ++raised) {
        reyes_scene scene;
        reyes_scene_init(&scene);
        add_square(&scene, uniform, raised ? 0.3f : 0.0f);
        reyes_options o;
        reyes_image image;
        reyes_stats stats;
        square_options(&o, REYES_SUBDIVISION_TIERED, 0.5f);
        render_checked(&scene, &far_above, &o, &image, &stats);
        ck_assert_uint_gt(reyes_test_covered_samples(&image), 150);
        ck_assert_uint_eq(stats.split_bound, 0);
        if (raised) {
            ck_assert_uint_ge(stats.split_inner, 1);
        } else {
            ck_assert_uint_eq(stats.splits, 0);
            ck_assert_uint_eq(stats.grids, 1);
        }
        reyes_image_free(&image);
        reyes_scene_free(&scene);
    }
}
END_TEST

/* A sphere at three tolerances: smaller epsilon, more grids; the covered
 * area stays pi r^2 within 1% and there are no holes. */
START_TEST(test_epsilon_on_sphere)
{
    reyes_scene scene;
    reyes_error error;
    reyes_scene_init(&scene);
    const float center[3] = {0, 0, 0};
    ck_assert_int_eq(reyes_scene_add_sphere(&scene, center, 1.0f, REYES_RGBA(200, 200, 200), &error),
                     REYES_OK);
    const float distance = 5.0f, fov = 35.0f;
    reyes_camera camera = { .eye = {0, -distance, 0}, .at = {0, 0, 0}, .fov_deg = fov };
    double focal = 80.0 / tan(0.5 * fov * PI / 180.0);
    double radius_px = focal * tan(asin(1.0 / distance));
    double expected = PI * radius_px * radius_px;
    const float epsilons[] = {4.0f, 1.0f, 0.25f};
    uint64_t previous = 0;
    for (int k = 0; k < 3; ++k) {
        reyes_options o;
        reyes_options_init(&o);
        o.width = o.height = 160;
        o.subdivision = REYES_SUBDIVISION_TIERED;
        o.flat_epsilon = epsilons[k];
        reyes_image image;
        reyes_stats stats;
        render_checked(&scene, &camera, &o, &image, &stats);
        double area = (double)reyes_test_covered_samples(&image) / o.spp;
        ck_assert_msg(fabs(area - expected) < 0.01 * expected, "epsilon %g: area %g, expected %g",
                      (double)epsilons[k], area, expected);
        ck_assert_uint_eq(reyes_test_hole_pixels(&image, 64), 0);
        ck_assert_uint_eq(stats.forced_dice, 0);
        ck_assert_msg(stats.grids > previous, "epsilon %g: %llu grids, not more than %llu",
                      (double)epsilons[k], (unsigned long long)stats.grids,
                      (unsigned long long)previous);
        printf("sphere, epsilon %g px: %llu grids\n", (double)epsilons[k],
               (unsigned long long)stats.grids);
        previous = stats.grids;
        reyes_image_free(&image);
    }
    reyes_scene_free(&scene);
}
END_TEST

/* Out-of-range criterion options are refused with a message naming them. */
START_TEST(test_option_checks)
{
    struct { unsigned subdivision; float epsilon, lambda; const char *needle; } cases[] = {
        { 2, 0.5f, 0.5f, "subdivision 2 is not 0 (bound) or 1 (tiered)" },
        { REYES_SUBDIVISION_TIERED, 0.0f, 0.5f, "flatness epsilon 0 px is not in 0.01..1000" },
        { REYES_SUBDIVISION_TIERED, NAN, 0.5f, "flatness epsilon" },
        { REYES_SUBDIVISION_TIERED, 0.5f, 1.5f, "flatness lambda 1.5 is not in 0..1" },
        { REYES_SUBDIVISION_TIERED, 0.5f, -INFINITY, "flatness lambda" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        reyes_options o;
        reyes_error error;
        reyes_options_init(&o);
        o.subdivision = cases[i].subdivision;
        o.flat_epsilon = cases[i].epsilon;
        o.flat_lambda = cases[i].lambda;
        ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
        ck_assert_msg(strstr(error.message, cases[i].needle) != NULL, "case %zu: '%s' lacks '%s'",
                      i, error.message, cases[i].needle);
    }
    reyes_options o;
    reyes_error error;
    reyes_options_init(&o);
    o.subdivision = REYES_SUBDIVISION_TIERED;
    o.flat_bound_px = 0.25f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "tiered bound 0.25 px is not 0 or in 0.5..1e6");
    o.flat_bound_px = 0.0f;
    o.crack_fix = REYES_CRACK_FIX_WEDGE;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_OK);
    o.displace_mode = REYES_DISPLACE_BUMPS;
    o.displace_amplitude = 0.1f;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "crack fix wedge cannot be combined with displacement yet");
    o.displace_amplitude = 0.0f;
    o.subdivision = REYES_SUBDIVISION_BOUND;
    ck_assert_int_eq(reyes_options_check(&o, &error), REYES_ERR_ARGUMENT);
    ck_assert_str_eq(error.message, "crack fix wedge needs the tiered subdivision criterion");
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reyes_subdivision");
    TCase *tc = tcase_create("subdivision");
    tcase_set_timeout(tc, 300);
    tcase_add_test(tc, test_option_checks);
    tcase_add_test(tc, test_flat_square_counts);
    tcase_add_test(tc, test_lambda_weighs_parametric_distance);
    tcase_add_test(tc, test_inner_tier);
    tcase_add_test(tc, test_epsilon_on_sphere);
    suite_add_tcase(s, tc);
    return reyes_test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
