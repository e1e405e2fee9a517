/* The perma Mandelbrot image equals a brute-force image computed on the
 * host, pixel for pixel, under the technique and strategy of the test's
 * variant.  Exact equality holds because host and device run the same
 * float operations in the same order without contraction (mandel_escape.h);
 * a difference is a bug, not rounding. */
#include "example_test.h"

#include <stdlib.h>
#include <string.h>

#include "mandel.h"
#include "mandel_options.h"

/* Small images that still subdivide a few levels; the second is a zoom into
 * the filaments of the seahorse valley, where fills and blocks interleave. */
static const struct {
    unsigned width, height, max_iter, min_size;
    double region[4];
} cases[] = {
    { 192, 144, 256, 8, { -2.2, 0.8, -1.125, 1.125 } },
    { 160, 160, 400, 6, { -0.80, -0.70, 0.05, 0.15 } },
};

static void assert_same_image(const mandel_params *p, const uint32_t *got, const uint32_t *want)
{
    size_t differ = 0, first = 0;
    for (size_t i = 0; i < (size_t)p->width * p->height; ++i)
        if (got[i] != want[i] && differ++ == 0)
            first = i;
    ck_assert_msg(differ == 0, "%zu pixels differ; first (%zu, %zu): perma %u, host %u", differ,
                  first % p->width, first / p->width, got[first], want[first]);
}

START_TEST(perma_equals_brute_force)
{
    mandel_params p;
    mandel_params_init(&p, cases[_i].width, cases[_i].height, cases[_i].region[0], cases[_i].region[1],
                       cases[_i].region[2], cases[_i].region[3], cases[_i].max_iter, cases[_i].min_size);
    size_t pixels = (size_t)p.width * p.height;
    uint32_t *want = malloc(pixels * sizeof *want), *got = malloc(pixels * sizeof *got);
    ck_assert(want && got);
    mandel_brute_force(&p, want);
    example_run_options run = { .work_groups = 0 };
    example_test_variant(&run.schedule);
    char message[2048];
    mandel_status st = mandel_render_perma(&p, &run, got, message, sizeof message);
    ck_assert_msg(st == MANDEL_OK, "%s", message);
    assert_same_image(&p, got, want);
    free(want);
    free(got);
}
END_TEST

/* The sequential subdivision agrees too, so --compare compares like with like. */
START_TEST(sequential_equals_brute_force)
{
    mandel_params p;
    mandel_params_init(&p, cases[_i].width, cases[_i].height, cases[_i].region[0], cases[_i].region[1],
                       cases[_i].region[2], cases[_i].region[3], cases[_i].max_iter, cases[_i].min_size);
    size_t pixels = (size_t)p.width * p.height;
    uint32_t *want = malloc(pixels * sizeof *want), *got = malloc(pixels * sizeof *got);
    ck_assert(want && got);
    mandel_brute_force(&p, want);
    ck_assert_int_eq(mandel_sequential(&p, got), 0);
    assert_same_image(&p, got, want);
    free(want);
    free(got);
}
END_TEST

/* Degenerate images (one row, one column, one pixel) have no interior. */
START_TEST(thin_images)
{
    static const unsigned sizes[][2] = { { 1, 1 }, { 37, 1 }, { 1, 23 }, { 3, 3 } };
    mandel_params p;
    mandel_params_init(&p, sizes[_i][0], sizes[_i][1], -2.0, 0.5, -1.0, 1.0, 100, 2);
    uint32_t want[64], got[64];
    mandel_brute_force(&p, want);
    example_run_options run = { .work_groups = 0 };
    example_test_variant(&run.schedule);
    char message[2048];
    mandel_status st = mandel_render_perma(&p, &run, got, message, sizeof message);
    ck_assert_msg(st == MANDEL_OK, "%s", message);
    assert_same_image(&p, got, want);
}
END_TEST

START_TEST(bad_options_are_usage_errors)
{
    static const char *const bad[][3] = {
        { "mandelbrot", "--size", "0x10" }, { "mandelbrot", "--region", "1,0,0,1" },
        { "mandelbrot", "--max-iter", "x" }, { "mandelbrot", "--technique", "warp" },
        { "mandelbrot", "--strategy", "greedy" }, { "mandelbrot", "--bogus", "1" },
    };
    mandel_options o;
    char message[512];
    perma_cli_status st = mandel_parse_options(3, (char **)bad[_i], &o, message, sizeof message);
    ck_assert_int_eq(st, PERMA_CLI_USAGE);
    ck_assert_msg(strstr(message, bad[_i][1]) != NULL, "message does not name %s: %s", bad[_i][1], message);
}
END_TEST

START_TEST(good_options)
{
    char *argv[] = { "mandelbrot", "--size", "64x32", "--region", "-1,1,-0.5,0.5", "--max-iter", "50",
                     "--technique", "bounded-batches", "--groups", "3", "-o", "x.png", NULL };
    mandel_options o;
    char message[512];
    ck_assert_int_eq(mandel_parse_options(13, argv, &o, message, sizeof message), PERMA_CLI_OK);
    ck_assert_uint_eq(o.size[0], 64);
    ck_assert_uint_eq(o.size[1], 32);
    ck_assert_uint_eq(o.max_iter, 50);
    ck_assert_uint_eq(o.common.run.work_groups, 3);
    ck_assert_int_eq(o.common.run.schedule.technique, PERMA_TECHNIQUE_BOUNDED_BATCHES);
    ck_assert_str_eq(o.output, "x.png");
}
END_TEST

int main(void)
{
    Suite *s = suite_create("mandelbrot");
    TCase *tc = tcase_create("mandelbrot");
    tcase_set_timeout(tc, EXAMPLE_TEST_TIMEOUT);
    const int ncases = (int)(sizeof cases / sizeof cases[0]);
    tcase_add_loop_test(tc, perma_equals_brute_force, 0, ncases);
    tcase_add_loop_test(tc, sequential_equals_brute_force, 0, ncases);
    tcase_add_loop_test(tc, thin_images, 0, 4);
    tcase_add_loop_test(tc, bad_options_are_usage_errors, 0, 6);
    tcase_add_test(tc, good_options);
    suite_add_tcase(s, tc);
    return example_test_run(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
